/* A picture's passes in order. (1) The light's maps: the head's depth and the hair's
 * deep opacity map (light_maps.c). (2) Every hair vertex shaded once (hair_shading.c).
 * (3) Per tile of the picture, in parallel: the head rasterised with 2 x 2 samples per
 * pixel (tile_head.c), then the hair's fragments in front of it sorted by depth per
 * pixel and composited front to back (tile_hair.c).
 *
 * The renderer keeps every buffer of these passes for the next picture: a full head
 * needs several hundred MB a picture, and allocating and faulting them in anew for
 * each frame of an animation kept the kernel busy for about 7 % of the run. */
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "render_internal.h"
#include "tile_bins_inline.h"

struct hk_Renderer {
    uint8_t *seg;              /* segment starts */
    hk_RasterPoint *proj;      /* hair points on the picture */
    hk_RasterPoint *head_proj; /* head vertices on the picture */
    float *near;               /* each segment's nearer depth on the picture */
    size_t seg_cap, proj_cap, head_proj_cap, near_cap;
    hk_HairShader shader;
    hk_LightMaps maps;
    hk_TileBins hair_bins, head_bins;
    hk_Canvas picture;
    size_t picture_cap; /* pixels */
    hk_TileBase *bases; /* the head under each tile */
    float *cull;        /* each tile's depth beyond which the head hides all hair */
    size_t bases_cap, cull_cap;
    /* each thread's work space for the tiles */
    hk_TileHead **tile_head;
    hk_TileHair **tile_hair;
    int threads;
};

hk_Status hk_renderer_create(hk_Renderer **out, hk_Error *err)
{
    *out = hk_calloc_array(1, sizeof **out, err);
    return *out ? HK_OK : HK_ERR_NOMEM;
}

void hk_renderer_destroy(hk_Renderer *r)
{
    if (!r) return;
    hk_free(r->seg);
    hk_free(r->proj);
    hk_free(r->head_proj);
    hk_free(r->near);
    hk_hair_shader_free(&r->shader);
    hk_light_maps_free(&r->maps);
    hk_tile_bins_free(&r->hair_bins);
    hk_tile_bins_free(&r->head_bins);
    hk_free(r->picture.rgb);
    hk_free(r->bases);
    hk_free(r->cull);
    for (int t = 0; t < r->threads; t++) {
        free(r->tile_head[t]);
        hk_tile_hair_destroy(r->tile_hair[t]);
    }
    free(r->tile_head);
    free(r->tile_hair);
    hk_free(r);
}

const hk_Canvas *hk_renderer_picture(const hk_Renderer *r) { return &r->picture; }

/* The tiles' work spaces of `threads` threads. */
static hk_Status reserve_tile_work(hk_Renderer *r, int threads, hk_Error *err)
{
    if (threads <= r->threads) return HK_OK;
    hk_TileHead **heads = realloc(r->tile_head, (size_t)threads * sizeof *heads);
    if (heads) r->tile_head = heads;
    hk_TileHair **hairs = realloc(r->tile_hair, (size_t)threads * sizeof *hairs);
    if (hairs) r->tile_hair = hairs;
    if (!heads || !hairs) return hk_error_set(err, HK_ERR_NOMEM, "out of memory for the tiles");
    for (; r->threads < threads; r->threads++) {
        heads[r->threads] = malloc(sizeof **heads);
        hairs[r->threads] = hk_tile_hair_create();
        if (!heads[r->threads] || !hairs[r->threads]) {
            free(heads[r->threads]);
            hk_tile_hair_destroy(hairs[r->threads]);
            return hk_error_set(err, HK_ERR_NOMEM, "out of memory for the tiles");
        }
    }
    return HK_OK;
}

typedef struct BoxCtx {
    const hk_Scene *sc;
    const hk_RasterPoint *proj;
    const uint8_t *seg;
    const int *tri;
    int width, height;
} BoxCtx;

static int segment_box(void *user, uint32_t i, hk_Rect *box)
{
    const BoxCtx *c = user;
    if (!c->seg[i]) return 0;
    const hk_Scene *sc = c->sc;
    const float width = (float)(0.5 * (hk_hair_thickness_at(sc, i) * c->proj[i].px_per_unit +
                                       hk_hair_thickness_at(sc, i + 1) * c->proj[i + 1].px_per_unit));
    return hk_segment_box_inline(c->proj[i], c->proj[i + 1], width, c->width, c->height, box);
}

static int front_triangle_box(void *user, uint32_t t, hk_Rect *box)
{
    const BoxCtx *c = user;
    hk_RasterPoint v[3];
    for (int k = 0; k < 3; k++) v[k] = c->proj[c->tri[3 * (size_t)t + (size_t)k]];
    /* Counter-clockwise from outside; y points down on screen, so front faces have a
     * negative signed area there. */
    const float area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (!(area < 0.0f)) return 0;
    return hk_triangle_box(v, c->width, c->height, box);
}

HK_TILE_BINS_BUILD(bin_segments, segment_box)
HK_TILE_BINS_BUILD(bin_triangles, front_triangle_box)

/* (3a) The head under every tile, and each tile's depth beyond which the hair is
 * hidden by the head in all its pixels (+inf where a sample misses the head), widened
 * by 2^-16 so that no fragment of a segment beyond it passes the per-pixel test (the
 * perspective-correct depth of a fragment is its segment's nearer depth within a few
 * rounding errors). */
static void draw_head(hk_Renderer *r, const hk_TileInput *in)
{
    const int tiles = in->tiles->tiles_x * in->tiles->tiles_y;
#pragma omp parallel num_threads(in->scene->threads)
    {
        hk_TileHead *work = r->tile_head[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 4)
        for (int tile = 0; tile < tiles; tile++) {
            const float far = hk_tile_head(in, tile, work, &r->bases[tile]);
            r->cull[tile] = far < HUGE_VALF ? far * (1.0f + 1.0f / 65536.0f) : HUGE_VALF;
        }
    }
}

/* (3b) Every tile's hair in parallel, over its head. */
static hk_Status draw_tiles(hk_Renderer *r, const hk_TileInput *in, hk_RenderStats *stats, hk_Error *err)
{
    const int tiles = in->hair_bins->tiles_x * in->hair_bins->tiles_y;
    long long fragments = 0;
    int most = 0, failed = 0;
#pragma omp parallel reduction(+ : fragments) reduction(max : most) reduction(| : failed) \
    num_threads(in->scene->threads)
    {
        hk_TileHair *hair = r->tile_hair[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < tiles; k++) {
            const int tile = (int)in->hair_bins->heavy[k];
            if (failed) continue;
            if (!hk_tile_hair(hair, in, tile, &r->bases[tile], &r->picture, &fragments, &most)) failed = 1;
        }
    }
    if (failed) return hk_error_set(err, HK_ERR_NOMEM, "out of memory while drawing the hair");
    stats->hair_fragments = fragments;
    stats->max_depth_complexity = most;
    return HK_OK;
}

static hk_Vec3 direction(double azimuth_deg, double elevation_deg)
{
    const double d = HK_PI / 180.0;
    return hk_v3(sin(azimuth_deg * d) * cos(elevation_deg * d), sin(elevation_deg * d),
                 cos(azimuth_deg * d) * cos(elevation_deg * d));
}

static hk_Status draw(hk_Renderer *r, const hk_HairFile *hair, const hk_Mesh *head, const hk_Visuality *vis,
                      const hk_RenderDef *opt, hk_RenderStats *stats, hk_Error *err)
{
    /* The visuality file's colours are display (sRGB) values, as in the thesis's
     * shaders, which wrote them to the screen unconverted; shading works in linear. */
    const hk_Visuality vis_default = hk_default_visuality();
    if (!vis) vis = &vis_default;
    hk_Visuality vis_linear = *vis;
    vis_linear.ambient = hk_srgb_to_linear(vis->ambient);
    vis_linear.diffuse = hk_srgb_to_linear(vis->diffuse);
    vis_linear.specular = hk_srgb_to_linear(vis->specular);
    hk_Scene sc = {hair,
                   head && head->triangle_count > 0 ? head : NULL,
                   &vis_linear,
                   opt,
                   hk_v3_zero(),
                   hk_v3_zero(),
                   hk_v3_zero(),
                   0.0,
                   0,
                   NULL,
                   0.0,
                   hk_render_threads(opt),
                   1.0};
    sc.light_dir = hk_v3_normalize(direction(opt->light_azimuth_deg, opt->light_elevation_deg));
    hk_Status st = hk_scene_bounds(&sc, err);
    if (st != HK_OK) return st;
    sc.thickness = hk_scene_file_thickness(&sc);
    hk_scene_thickness(&sc, 1);
    const double t0 = omp_get_wtime();
    /* The camera first (it needs only the bounds): the level of detail comes from how
     * wide a strand is in the picture, and the light's maps draw the same strands, k
     * times as wide (their opacity, the mean count of fibres in front, is kept on
     * average; the picture's mean brightness moved by 0.12 % or less on the default
     * head, docs/rendering.md "Speed"). */
    const hk_View cam = hk_camera_frame(&sc);
    const int stride = hk_scene_strand_stride(&sc, &cam);
    hk_scene_thickness(&sc, stride);
    stats->strand_stride = stride;
    if ((st = reserve_tile_work(r, sc.threads, err)) != HK_OK) return st;
    if (!HK_RESERVE(r->seg, r->seg_cap, hair->point_count, err)) return HK_ERR_NOMEM;
    sc.segment_count = hk_segment_starts(hair, stride, r->seg, sc.threads);
    const double t1 = omp_get_wtime();
    if (opt->shadows && (st = hk_light_maps_build(&sc, r->seg, &r->maps, stats, err)) != HK_OK) return st;
    const double t2 = omp_get_wtime();
    if (!HK_RESERVE(r->proj, r->proj_cap, hair->point_count, err) ||
        !HK_RESERVE(r->near, r->near_cap, hair->point_count, err) ||
        (sc.head && !HK_RESERVE(r->head_proj, r->head_proj_cap, (size_t)sc.head->vertex_count, err)))
        return HK_ERR_NOMEM;
    hk_RasterPoint *proj = r->proj, *head_proj = r->head_proj;
    float *near = r->near;
    hk_view_project_points(&cam, hair, proj, sc.threads);
    /* What the tiles sort their segments by, copied into the bins next to the
     * segments (read there in order, rather than from scattered points by every
     * tile). */
    const uint8_t *seg = r->seg;
    /* The smaller by a comparison (fminf is a call into libm); the points are finite
     * (hk_scene_bounds), so there is no NaN for fminf to pass over. */
#pragma omp parallel for schedule(static) num_threads(sc.threads)
    for (long i = 0; i < (long)hair->point_count; i++)
        near[i] = seg[i] ? (proj[i].z < proj[i + 1].z ? proj[i].z : proj[i + 1].z) : 0.0f;
    for (int i = 0; sc.head && i < sc.head->vertex_count; i++)
        head_proj[i] = hk_view_project(&cam, sc.head->positions[i]);
    if ((st = hk_hair_shader_init(&r->shader, &sc, r->seg, opt->shadows ? &r->maps : NULL, &cam, err)) != HK_OK)
        return st;
    const double t3 = omp_get_wtime();
    if (sc.head) {
        BoxCtx hb = {&sc, head_proj, NULL, sc.head->triangles, opt->width, opt->height};
        if ((st = bin_triangles((uint32_t)sc.head->triangle_count, &hb, NULL, NULL, opt->width, opt->height, sc.threads,
                                &r->head_bins, err)) != HK_OK)
            return st;
    }
    hk_TileBins layout;
    memset(&layout, 0, sizeof layout);
    layout.tiles_x = (opt->width + HK_TILE - 1) / HK_TILE, layout.tiles_y = (opt->height + HK_TILE - 1) / HK_TILE;
    const size_t tiles = (size_t)layout.tiles_x * (size_t)layout.tiles_y;
    /* Every pixel is written by its tile. */
    if (!HK_RESERVE(r->picture.rgb, r->picture_cap, 3 * (size_t)opt->width * (size_t)opt->height, err) ||
        !HK_RESERVE(r->bases, r->bases_cap, tiles, err) || !HK_RESERVE(r->cull, r->cull_cap, tiles, err))
        return HK_ERR_NOMEM;
    r->picture.width = opt->width, r->picture.height = opt->height;
    const hk_TileInput in = {&sc,           &cam,      opt->shadows ? &r->maps : NULL, proj,   &r->shader,
                             &r->hair_bins, head_proj, sc.head ? &r->head_bins : NULL, &layout};
    draw_head(r, &in);
    /* A tile's segments are drawn nearest first (by their nearer depth), so those at or
     * beyond the tile's cull depth come last, after every segment that can be seen:
     * leaving them out of the bins leaves the picture as it was (the bytes), and on a
     * full head the hair behind the head is a large part of the tiles' entries. */
    BoxCtx box = {&sc, proj, r->seg, NULL, opt->width, opt->height};
    if ((st = bin_segments(hair->point_count, &box, near, r->cull, opt->width, opt->height, sc.threads, &r->hair_bins,
                           err)) != HK_OK)
        return st;
    if ((st = draw_tiles(r, &in, stats, err)) != HK_OK) return st;
    stats->seconds_light = t2 - t1;
    stats->seconds_camera = (t1 - t0) + (t3 - t2);
    stats->seconds_hair = omp_get_wtime() - t3;
    return HK_OK;
}

hk_Status hk_renderer_draw(hk_Renderer *r, const hk_HairFile *hair, const hk_Mesh *head, const hk_Visuality *vis,
                           const hk_RenderDef *options, hk_RenderStats *stats, hk_Error *err)
{
    r->picture.width = r->picture.height = 0;
    hk_RenderStats st_local;
    if (!stats) stats = &st_local;
    memset(stats, 0, sizeof *stats);
    const hk_RenderDef defaults = hk_default_render_def();
    const hk_RenderDef *opt = options ? options : &defaults;
    hk_Status st = hk_render_check_options(opt, err);
    if (st != HK_OK) return st;
    st = draw(r, hair, head, vis, opt, stats, err);
    if (st != HK_OK) r->picture.width = r->picture.height = 0;
    return st;
}

hk_Status hk_render(const hk_HairFile *hair, const hk_Mesh *head, const hk_Visuality *vis, const hk_RenderDef *opt,
                    hk_Canvas *out, hk_RenderStats *stats, hk_Error *err)
{
    out->rgb = NULL, out->width = out->height = 0;
    hk_Renderer *r;
    hk_Status st = hk_renderer_create(&r, err);
    if (st != HK_OK) return st;
    st = hk_renderer_draw(r, hair, head, vis, opt, stats, err);
    if (st == HK_OK) {
        *out = r->picture; /* handed over */
        r->picture.rgb = NULL;
    }
    hk_renderer_destroy(r);
    return st;
}
