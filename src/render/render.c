/* hk_render: the passes in order. (1) The light's maps: the head's depth and the
 * hair's deep opacity map (light_maps.c). (2) Every hair vertex shaded once
 * (hair_shading.c). (3) Per tile of the picture, in parallel: the head rasterised
 * with 2 x 2 samples per pixel (tile_head.c), then the hair's fragments in front of
 * it sorted by depth per pixel and composited front to back (tile_hair.c). */
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "render_internal.h"

hk_RenderOptions hk_default_render_options(void)
{
    hk_RenderOptions o;
    memset(&o, 0, sizeof o);
    o.width = 1200;
    o.height = 900;
    o.threads = 0;
    o.shadows = 1;
    o.shading = HK_SHADING_KAJIYA_KAY;
    o.azimuth_deg = 35.0;
    o.elevation_deg = 12.0;
    o.fov_deg = 30.0;
    o.camera_target = hk_v3_zero();
    o.camera_distance = 0.0; /* fit */
    o.light_azimuth_deg = -30.0;
    o.light_elevation_deg = 40.0;
    o.light_intensity = 1.0;
    o.ambient_intensity = 0.2;
    o.shadow_map_size = 512;
    o.opacity_layers = 4;
    o.layer_size = 0.0;
    o.scatter_floor = 0.25;
    o.hair_thickness = 0.0;
    o.strand_variation = 0.15;
    o.background_top = hk_v3(0.32, 0.34, 0.38);
    o.background_bottom = hk_v3(0.05, 0.05, 0.06);
    o.skin = hk_v3(0.61, 0.40, 0.28);
    return o;
}

static hk_Status check_options(const hk_RenderOptions *o, hk_Error *err)
{
    if (o->width < 8 || o->height < 8 || o->width > 16384 || o->height > 16384)
        return hk_error_set(err, HK_ERR_INVALID, "picture size %dx%d: each side must be 8 to 16384 pixels",
                            o->width, o->height);
    if (o->shadows && (o->shadow_map_size < 16 || o->shadow_map_size > 8192))
        return hk_error_set(err, HK_ERR_INVALID, "shadow map size %d: must be 16 to 8192", o->shadow_map_size);
    if (o->shadows && (o->opacity_layers < 1 || o->opacity_layers > HK_MAX_OPACITY_LAYERS))
        return hk_error_set(err, HK_ERR_INVALID, "opacity layers %d: must be 1 to %d", o->opacity_layers,
                            HK_MAX_OPACITY_LAYERS);
    if (!isfinite(o->camera_distance) || !hk_v3_isfinite(o->camera_target))
        return hk_error_set(err, HK_ERR_INVALID, "camera target and distance must be finite");
    if (!(o->fov_deg >= 1.0 && o->fov_deg <= 150.0))
        return hk_error_set(err, HK_ERR_INVALID, "field of view %g degrees: must be 1 to 150", o->fov_deg);
    if (!isfinite(o->azimuth_deg) || !isfinite(o->elevation_deg) || !isfinite(o->light_azimuth_deg) ||
        !isfinite(o->light_elevation_deg) || !(o->light_intensity >= 0.0) || !(o->ambient_intensity >= 0.0) ||
        !(o->scatter_floor >= 0.0 && o->scatter_floor <= 1.0) || !isfinite(o->layer_size) ||
        !isfinite(o->hair_thickness) || !(o->strand_variation >= 0.0 && o->strand_variation < 1.0))
        return hk_error_set(err, HK_ERR_INVALID, "render options out of range (angles, intensities, floor in [0, 1])");
    return HK_OK;
}

uint8_t *hk_segment_starts(const hk_HairFile *hair, uint32_t *count, hk_Error *err)
{
    uint8_t *s = hk_calloc_array(hair->point_count ? hair->point_count : 1, 1, err);
    if (!s) return NULL;
    uint32_t n = 0;
    for (uint32_t k = 0; k < hair->strand_count; k++)
        for (uint32_t i = hair->first_point[k]; i + 1 < hair->first_point[k + 1]; i++) s[i] = 1, n++;
    *count = n;
    return s;
}

/* Bounding box of hair and head; non-finite coordinates are refused. */
static hk_Status scene_bounds(hk_Scene *sc, hk_Error *err)
{
    sc->lo = hk_v3(DBL_MAX, DBL_MAX, DBL_MAX), sc->hi = hk_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    const hk_HairFile *h = sc->hair;
    /* In parallel (millions of points): min and max do not depend on the order. */
    double lx = DBL_MAX, ly = DBL_MAX, lz = DBL_MAX, hx = -DBL_MAX, hy = -DBL_MAX, hz = -DBL_MAX;
    long bad = LONG_MAX;
#pragma omp parallel for schedule(static) reduction(min : lx, ly, lz, bad) reduction(max : hx, hy, hz)
    for (long i = 0; i < (long)h->point_count; i++) {
        hk_Vec3 p = hk_hair_point(h, (uint32_t)i);
        if (!hk_v3_isfinite(p)) {
            if (i < bad) bad = i;
            continue;
        }
        lx = fmin(lx, p.x), ly = fmin(ly, p.y), lz = fmin(lz, p.z);
        hx = fmax(hx, p.x), hy = fmax(hy, p.y), hz = fmax(hz, p.z);
    }
    if (bad != LONG_MAX) return hk_error_set(err, HK_ERR_INVALID, "hair point %ld is not finite", bad);
    sc->lo = hk_v3(lx, ly, lz), sc->hi = hk_v3(hx, hy, hz);
    for (int i = 0; sc->head && i < sc->head->vertex_count; i++) {
        hk_Vec3 p = sc->head->positions[i];
        if (!hk_v3_isfinite(p)) return hk_error_set(err, HK_ERR_INVALID, "head vertex %d is not finite", i + 1);
        sc->lo = hk_v3(fmin(sc->lo.x, p.x), fmin(sc->lo.y, p.y), fmin(sc->lo.z, p.z));
        sc->hi = hk_v3(fmax(sc->hi.x, p.x), fmax(sc->hi.y, p.y), fmax(sc->hi.z, p.z));
    }
    if (sc->lo.x > sc->hi.x) return hk_error_set(err, HK_ERR_INVALID, "nothing to render: no hair and no head");
    return HK_OK;
}

static hk_Vec3 direction(double azimuth_deg, double elevation_deg)
{
    const double d = 3.14159265358979323846 / 180.0;
    return hk_v3(sin(azimuth_deg * d) * cos(elevation_deg * d), sin(elevation_deg * d),
                 cos(azimuth_deg * d) * cos(elevation_deg * d));
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
    return hk_segment_box(c->proj[i], c->proj[i + 1], width, c->width, c->height, box);
}

static int front_triangle_box(void *user, uint32_t t, hk_Rect *box)
{
    const BoxCtx *c = user;
    hk_RasterPoint v[3];
    for (int k = 0; k < 3; k++) v[k] = c->proj[c->tri[3 * (size_t)t + k]];
    /* Counter-clockwise from outside; y points down on screen, so front faces have a
     * negative signed area there. */
    const float area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (!(area < 0.0f)) return 0;
    return hk_triangle_box(v, c->width, c->height, box);
}

/* (3) Every tile in parallel: head, then hair over it. */
static hk_Status draw_tiles(const hk_TileInput *in, hk_Canvas *image, hk_RenderStats *stats, hk_Error *err)
{
    const int tiles = in->hair_bins->tiles_x * in->hair_bins->tiles_y;
    long long fragments = 0;
    int most = 0, failed = 0;
#pragma omp parallel reduction(+ : fragments) reduction(max : most) reduction(| : failed)
    {
        hk_TileHead *head = malloc(sizeof *head);
        hk_TileHair *hair = hk_tile_hair_create();
        if (!head || !hair) failed = 1;
#pragma omp for schedule(dynamic, 1)
        for (int tile = 0; tile < tiles; tile++) {
            if (failed) continue;
            hk_tile_head(in, tile, head);
            if (!hk_tile_hair(hair, in, tile, head, image, &fragments, &most)) failed = 1;
        }
        free(head);
        hk_tile_hair_destroy(hair);
    }
    if (failed) return hk_error_set(err, HK_ERR_NOMEM, "out of memory while drawing the hair");
    stats->hair_fragments = fragments;
    stats->max_depth_complexity = most;
    return HK_OK;
}

hk_Status hk_render_fit_camera(const hk_HairFile *hair, const hk_Mesh *head,
                               const hk_RenderOptions *opt, hk_Vec3 *target, double *distance,
                               hk_Error *err)
{
    hk_Status st = check_options(opt, err);
    if (st != HK_OK) return st;
    hk_RenderOptions fit = *opt;
    fit.camera_distance = 0.0;
    hk_Scene sc = {hair, head && head->triangle_count > 0 ? head : NULL, NULL, &fit, hk_v3_zero(), hk_v3_zero(),
                   hk_v3_zero(), 0.0, 0};
    if ((st = scene_bounds(&sc, err)) != HK_OK) return st;
    const hk_View cam = hk_camera_frame(&sc);
    *target = cam.target;
    *distance = cam.distance;
    return HK_OK;
}

hk_Status hk_render(const hk_HairFile *hair, const hk_Mesh *head, const hk_VisualityDef *vis,
                    const hk_RenderOptions *opt, hk_Canvas *out, hk_RenderStats *stats, hk_Error *err)
{
    out->rgb = NULL, out->width = out->height = 0;
    hk_RenderStats st_local;
    if (!stats) stats = &st_local;
    memset(stats, 0, sizeof *stats);
    hk_Status st = check_options(opt, err);
    if (st != HK_OK) return st;
    const int saved_threads = omp_get_max_threads();
    if (opt->threads > 0) omp_set_num_threads(opt->threads);
    /* The visuality file's colours are display (sRGB) values, as in the thesis's
     * shaders, which wrote them to the screen unconverted; shading works in linear. */
    hk_VisualityDef vis_linear = *vis;
    vis_linear.ambient = hk_srgb_to_linear(vis->ambient);
    vis_linear.diffuse = hk_srgb_to_linear(vis->diffuse);
    vis_linear.specular = hk_srgb_to_linear(vis->specular);
    hk_Scene sc = {hair, head && head->triangle_count > 0 ? head : NULL, &vis_linear, opt, hk_v3_zero(), hk_v3_zero(),
                   hk_v3_zero(), 0.0, 0};
    sc.light_dir = hk_v3_normalize(direction(opt->light_azimuth_deg, opt->light_elevation_deg));
    uint8_t *seg = NULL;
    hk_RasterPoint *proj = NULL, *head_proj = NULL;
    hk_HairShader shader;
    memset(&shader, 0, sizeof shader);
    hk_LightMaps maps;
    memset(&maps, 0, sizeof maps);
    hk_TileBins hair_bins, head_bins;
    memset(&hair_bins, 0, sizeof hair_bins), memset(&head_bins, 0, sizeof head_bins);
    if ((st = scene_bounds(&sc, err)) != HK_OK) goto done;
    sc.thickness = hair->default_thickness > 0.0f ? hair->default_thickness : 1e-3 * hk_v3_dist(sc.lo, sc.hi);
    if (!(seg = hk_segment_starts(hair, &sc.segment_count, err))) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    const double t0 = omp_get_wtime();
    if (opt->shadows && (st = hk_light_maps_build(&sc, seg, &maps, stats, err)) != HK_OK) goto done;
    const double t1 = omp_get_wtime();
    const hk_View cam = hk_camera_frame(&sc);
    proj = hk_alloc_array(hair->point_count ? hair->point_count : 1, sizeof *proj, err);
    if (sc.head) head_proj = hk_alloc_array((size_t)sc.head->vertex_count, sizeof *head_proj, err);
    if (!proj || (sc.head && !head_proj)) {
        st = HK_ERR_NOMEM;
        goto done;
    }
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)hair->point_count; i++) proj[i] = hk_view_project(&cam, hk_hair_point(hair, (uint32_t)i));
    for (int i = 0; sc.head && i < sc.head->vertex_count; i++) head_proj[i] = hk_view_project(&cam, sc.head->positions[i]);
    if ((st = hk_hair_shader_init(&shader, &sc, seg, opt->shadows ? &maps : NULL, &cam, err)) != HK_OK) goto done;
    const double t2 = omp_get_wtime();
    BoxCtx box = {&sc, proj, seg, NULL, opt->width, opt->height};
    if ((st = hk_tile_bins_build(hair->point_count, segment_box, &box, opt->width, opt->height, &hair_bins, err)) !=
        HK_OK)
        goto done;
    if (sc.head) {
        BoxCtx hb = {&sc, head_proj, NULL, sc.head->triangles, opt->width, opt->height};
        if ((st = hk_tile_bins_build((uint32_t)sc.head->triangle_count, front_triangle_box, &hb, opt->width,
                                     opt->height, &head_bins, err)) != HK_OK)
            goto done;
    }
    if ((st = hk_canvas_create(opt->width, opt->height, hk_v3_zero(), out, err)) != HK_OK) goto done;
    const hk_TileInput in = {&sc, &cam, opt->shadows ? &maps : NULL, proj, &shader, &hair_bins,
                             head_proj, sc.head ? &head_bins : NULL};
    if ((st = draw_tiles(&in, out, stats, err)) != HK_OK) {
        hk_canvas_destroy(out);
        goto done;
    }
    stats->seconds_light = t1 - t0;
    stats->seconds_camera = t2 - t1;
    stats->seconds_hair = omp_get_wtime() - t2;
done:
    hk_tile_bins_free(&hair_bins);
    hk_tile_bins_free(&head_bins);
    hk_light_maps_free(&maps);
    hk_free(seg);
    hk_free(proj);
    hk_free(head_proj);
    hk_hair_shader_free(&shader);
    if (opt->threads > 0) omp_set_num_threads(saved_threads);
    return st;
}
