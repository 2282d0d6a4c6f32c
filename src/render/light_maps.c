/* The light's view: a depth map of the head (its shadow on itself and on the hair)
 * and the deep opacity map of the hair (Yuksel & Keyser, "Deep Opacity Maps", 2008;
 * Lansink 2010 §4.1.6 and the opacity and hair shaders of Appendix A). The map is built
 * per tile from the hair's fragments as seen from the light: z0, the depth where the
 * hair begins in each texel, then the opacity of every fragment added to the layer it
 * falls in, layers starting at z0 and growing deeper. Lookups interpolate between the
 * layers' opacities; points beyond the last layer take its value. (The thesis's
 * fragment shader tests zi.z twice, so its fourth layer is never interpolated; here
 * every layer is.) Work is split into tiles of the map, each filled in segment order,
 * so the sums are the same whatever the thread count. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "raster_inline.h"
#include "render_internal.h"
#include "tile_bins_inline.h"

/* One fragment of the hair in the light's view, kept per tile until the tile's z0 is
 * known. */
typedef struct LightFragment {
    float z, alpha;
    uint32_t texel;
} LightFragment;

typedef struct LightPass {
    const hk_Scene *scene;
    hk_LightMaps *maps;
    const hk_RasterPoint *proj; /* hair points in the light's view */
    const uint8_t *segment_start;
    LightFragment *frag;
    size_t count, cap;
    int failed;
} LightPass;

static inline __attribute__((always_inline)) float segment_width(const hk_Scene *s, const hk_RasterPoint *proj,
                                                                 uint32_t i)
{
    return (float)(0.5 * (hk_hair_thickness_at(s, i) + hk_hair_thickness_at(s, i + 1))) * proj[i].px_per_unit;
}

/* The texels the thin rasteriser can reach (not the wide one's box, a texel and a half
 * wider on every side: segments were binned into twice as many tiles as they drew in). */
static int hair_box(void *user, uint32_t i, hk_Rect *box)
{
    const LightPass *lp = user;
    if (!lp->segment_start[i]) return 0;
    return hk_segment_box_thin_inline(lp->proj[i], lp->proj[i + 1], lp->maps->size, lp->maps->size, box);
}

HK_TILE_BINS_BUILD(bin_hair, hair_box)

/* Where a tile's segments put their fragments: a local of opacity_tile's, so that the
 * compiler keeps it in registers (through the LightPass, the stores of the fragments'
 * floats might have changed the segment's depths, which were loaded again for each).
 * z0 is the map's: each fragment lowers its texel's z0 as it is made (the tile owns its
 * texels), rather than in a pass over the tile's fragments afterwards. */
typedef struct LightSink {
    LightFragment *frag;
    size_t count;
    float az, dz; /* the segment's depth at its start, and its change to the end */
    uint32_t size;
    float *z0;
} LightSink;

/* The room is made before each segment (opacity_tile), not tested for each fragment: a
 * segment gives a tile at most one fragment a column of the tile. */
HK_FRAGMENT_INLINE void hair_fragment(void *user, int x, int y, float t, float alpha)
{
    LightSink *k = user;
    LightFragment *f = &k->frag[k->count++];
    const float z = k->az + t * k->dz; /* orthographic: depth is linear */
    const uint32_t texel = (uint32_t)y * k->size + (uint32_t)x;
    f->z = z;
    f->alpha = alpha;
    f->texel = texel;
    if (z < k->z0[texel]) k->z0[texel] = z;
}

/* Each fragment's opacity added to its layer (layers: m->layers). */
static inline __attribute__((always_inline)) void add_to_layers(LightPass *lp, const int layers)
{
    hk_LightMaps *m = lp->maps;
    const LightFragment *frag = lp->frag;
    const float *z0 = m->hair_z0;
    float *opacity = m->opacity;
    float end[HK_MAX_OPACITY_LAYERS]; /* a copy, which the sums cannot change: kept in registers */
    memcpy(end, m->layer_end, sizeof end);
    for (size_t f = 0; f < lp->count; f++) {
        const float d = frag[f].z - z0[frag[f].texel];
        /* The layer: how many of the increasing layer ends lie at or before d (the
         * last layer takes everything beyond), counted without branches, which the
         * fragments' scattered depths mispredicted. */
        int k = 0;
        for (int j = 0; j < layers - 1; j++) k += d >= end[j];
        opacity[(size_t)frag[f].texel * (size_t)layers + (size_t)k] += frag[f].alpha;
    }
}

/* One tile of the map: draw its segments (finding z0), add each fragment to its
 * layer, and turn the layers into running sums. */
static void opacity_tile(LightPass *lp, const hk_TileBins *bins, int tile)
{
    hk_LightMaps *m = lp->maps;
    const hk_Rect r = hk_tile_rect(bins, tile, m->size, m->size);
    LightSink sink = {lp->frag, 0, 0.0f, 0.0f, (uint32_t)m->size, m->hair_z0};
    size_t cap = lp->cap;
    int failed = 0;
    const hk_RasterPoint *proj = lp->proj;
    const hk_Scene *scene = lp->scene;
    const uint32_t end = bins->start[tile + 1];
    for (uint32_t k = bins->start[tile]; k < end; k++) {
        const uint32_t i = bins->items[k];
        /* The tile's segments are scattered over the projected points: fetch ahead. */
        if (k + 16 < end) __builtin_prefetch(&proj[bins->items[k + 16]]);
        if (cap - sink.count < HK_TILE) {
            LightFragment *grown = hk_grow_fragments(sink.frag, &cap, sizeof *grown);
            if (!grown) {
                failed = 1;
                break;
            }
            sink.frag = grown;
        }
        const hk_RasterPoint a = proj[i], b = proj[i + 1];
        sink.az = a.z, sink.dz = b.z - a.z;
        hk_raster_segment_thin(a, b, segment_width(scene, proj, i), r, hair_fragment, &sink);
    }
    lp->frag = sink.frag, lp->cap = cap, lp->count = sink.count;
    if (failed) {
        lp->failed = 1;
        return;
    }
    if (m->layers == 4) /* the default: the count of layers known, its loop unrolled */
        add_to_layers(lp, 4);
    else
        add_to_layers(lp, m->layers);
    for (int y = r.y0; y < r.y1; y++)
        for (int x = r.x0; x < r.x1; x++) {
            float *o = m->opacity + ((size_t)y * (size_t)m->size + (size_t)x) * (size_t)m->layers;
            for (int k = 1; k < m->layers; k++) o[k] += o[k - 1];
        }
}

typedef struct HeadPass {
    hk_LightMaps *maps;
    const hk_RasterPoint *proj;
    const int *tri;
    const hk_RasterPoint *v; /* the current triangle */
} HeadPass;

static int head_box(void *user, uint32_t t, hk_Rect *box)
{
    const HeadPass *hp = user;
    hk_RasterPoint v[3];
    for (int k = 0; k < 3; k++) v[k] = hp->proj[hp->tri[3 * (size_t)t + (size_t)k]];
    return hk_triangle_box(v, hp->maps->size, hp->maps->size, box);
}

HK_TILE_BINS_BUILD(bin_head, head_box)

static void head_sample(void *user, int x, int y, int sample, float l0, float l1, float l2)
{
    (void)sample;
    HeadPass *hp = user;
    const float z = l0 * hp->v[0].z + l1 * hp->v[1].z + l2 * hp->v[2].z;
    float *d = &hp->maps->head_depth[(size_t)y * (size_t)hp->maps->size + (size_t)x];
    if (z < *d) *d = z;
}

static hk_Status head_depth_map(const hk_Scene *scene, hk_LightMaps *m, hk_Error *err)
{
    const hk_Mesh *head = scene->head;
    if (!head || head->triangle_count == 0) return HK_OK;
    if (!HK_RESERVE(m->proj, m->proj_cap, (size_t)head->vertex_count, err)) return HK_ERR_NOMEM;
    hk_RasterPoint *proj = m->proj;
    for (int i = 0; i < head->vertex_count; i++) proj[i] = hk_view_project(&m->view, head->positions[i]);
    HeadPass hp = {m, proj, head->triangles, NULL};
    hk_TileBins *bins = &m->bins;
    hk_Status st =
        bin_head((uint32_t)head->triangle_count, &hp, NULL, NULL, m->size, m->size, scene->threads, bins, err);
    if (st != HK_OK) return st;
    const int tiles = bins->tiles_x * bins->tiles_y;
#pragma omp parallel for schedule(dynamic, 1) firstprivate(hp) num_threads(scene->threads)
    for (int k = 0; k < tiles; k++) {
        const int tile = (int)bins->heavy[k];
        const hk_Rect r = hk_tile_rect(bins, tile, m->size, m->size);
        for (uint32_t at = bins->start[tile]; at < bins->start[tile + 1]; at++) {
            const uint32_t t = bins->items[at];
            hk_RasterPoint v[3];
            for (int c = 0; c < 3; c++) v[c] = proj[head->triangles[3 * (size_t)t + (size_t)c]];
            hp.v = v;
            hk_raster_triangle(v, r, 1, head_sample, &hp);
        }
    }
    return HK_OK;
}

static hk_Status hair_opacity_map(const hk_Scene *scene, const uint8_t *segment_start, hk_LightMaps *m,
                                  long long *fragments, hk_Error *err)
{
    const hk_HairFile *hair = scene->hair;
    if (hair->point_count == 0) return HK_OK;
    if (!HK_RESERVE(m->proj, m->proj_cap, hair->point_count, err)) return HK_ERR_NOMEM;
    hk_RasterPoint *proj = m->proj;
    hk_view_project_points(&m->view, hair, proj, scene->threads);
    /* Each thread's fragment buffer, kept for the next picture. */
    const int threads = scene->threads;
    if (threads > m->frag_threads) {
        hk_ThreadBuffer *f = realloc(m->frag, (size_t)threads * sizeof *f);
        if (!f) return hk_error_set(err, HK_ERR_NOMEM, "out of memory in the deep opacity map");
        for (int t = m->frag_threads; t < threads; t++) f[t].data = NULL, f[t].cap = 0;
        m->frag = f, m->frag_threads = threads;
    }
    LightPass lp;
    memset(&lp, 0, sizeof lp);
    lp.scene = scene, lp.maps = m, lp.proj = proj, lp.segment_start = segment_start;
    const hk_TileBins *bins = &m->bins;
    hk_Status st = bin_hair(hair->point_count, &lp, NULL, NULL, m->size, m->size, scene->threads, &m->bins, err);
    if (st != HK_OK) return st;
    long long total = 0;
    int failed = 0;
    const int tiles = bins->tiles_x * bins->tiles_y;
#pragma omp parallel firstprivate(lp) reduction(+ : total) reduction(| : failed) num_threads(threads)
    {
        hk_ThreadBuffer *mine = &m->frag[omp_get_thread_num()];
        lp.frag = mine->data, lp.cap = mine->cap;
#pragma omp for schedule(dynamic, 1)
        for (int k = 0; k < tiles; k++) {
            if (lp.failed) continue;
            opacity_tile(&lp, bins, (int)bins->heavy[k]);
            total += (long long)lp.count;
        }
        failed |= lp.failed;
        mine->data = lp.frag, mine->cap = lp.cap;
    }
    *fragments = total;
    if (failed) return hk_error_set(err, HK_ERR_NOMEM, "out of memory in the deep opacity map");
    return HK_OK;
}

hk_Status hk_light_maps_build(const hk_Scene *scene, const uint8_t *segment_start, hk_LightMaps *m,
                              hk_RenderStats *stats, hk_Error *err)
{
    const hk_RenderDef *o = scene->opt;
    m->size = hk_render_shadow_map_texels(o);
    m->layers = o->opacity_layers;
    const double first = o->layer_size > 0.0 ? o->layer_size : 0.002;
    double end = 0.0;
    memset(m->layer_end, 0, sizeof m->layer_end);
    for (int k = 0; k < m->layers; k++) m->layer_end[k] = (float)(end += first * ldexp(1.0, k));
    /* Orthographic along the light, covering the scene's bounding sphere. */
    hk_View *v = &m->view;
    memset(v, 0, sizeof *v);
    v->perspective = 0;
    v->width = v->height = m->size;
    v->forward = hk_v3_neg(scene->light_dir);
    hk_Vec3 side = hk_v3_cross(v->forward, hk_v3(0, 1, 0));
    if (hk_v3_norm(side) < 1e-9) side = hk_v3(1, 0, 0);
    v->right = hk_v3_normalize(side);
    v->up = hk_v3_cross(v->right, v->forward);
    v->origin = hk_v3_scale(hk_v3_add(scene->lo, scene->hi), 0.5);
    const double radius = fmax(0.5 * hk_v3_dist(scene->lo, scene->hi), 1e-6) * 1.02;
    v->focal = 0.5 * m->size / radius;
    v->depth_offset = radius;
    m->texel = 1.0 / v->focal;
    const size_t texels = (size_t)m->size * (size_t)m->size;
    if (!HK_RESERVE(m->head_depth, m->head_depth_cap, texels, err) ||
        !HK_RESERVE(m->hair_z0, m->hair_z0_cap, texels, err) ||
        !HK_RESERVE(m->opacity, m->opacity_cap, texels * (size_t)m->layers, err)) {
        hk_light_maps_free(m);
        return HK_ERR_NOMEM;
    }
    memset(m->opacity, 0, texels * (size_t)m->layers * sizeof *m->opacity);
    for (size_t i = 0; i < texels; i++) m->head_depth[i] = m->hair_z0[i] = FLT_MAX;
    long long fragments = 0;
    hk_Status st = head_depth_map(scene, m, err);
    if (st == HK_OK) st = hair_opacity_map(scene, segment_start, m, &fragments, err);
    if (st != HK_OK) {
        hk_light_maps_free(m);
        return st;
    }
    if (stats) stats->light_fragments = fragments;
    return HK_OK;
}

void hk_light_maps_free(hk_LightMaps *m)
{
    hk_free(m->head_depth);
    hk_free(m->hair_z0);
    hk_free(m->opacity);
    hk_free(m->proj);
    hk_tile_bins_free(&m->bins);
    for (int t = 0; t < m->frag_threads; t++) free(m->frag[t].data);
    free(m->frag);
    memset(m, 0, sizeof *m);
}

/* Opacity in front of depth z in one texel: zero in front of the hair, then linear
 * within each layer between the running sums at its two ends. */
static double texel_opacity(const hk_LightMaps *m, size_t texel, float z)
{
    const float z0 = m->hair_z0[texel];
    if (z0 == FLT_MAX || z <= z0) return 0.0;
    const float d = z - z0;
    const float *o = m->opacity + texel * (size_t)m->layers;
    float start = 0.0f, before = 0.0f;
    for (int k = 0; k < m->layers; k++) {
        if (d < m->layer_end[k]) return before + (o[k] - before) * (d - start) / (m->layer_end[k] - start);
        start = m->layer_end[k], before = o[k];
    }
    return o[m->layers - 1];
}

void hk_light_lookup(const hk_LightMaps *m, hk_Vec3 p, double *head_visible, double *opacity)
{
    const hk_RasterPoint q = hk_view_project(&m->view, p);
    const int n = m->size;
    /* Both maps are read at the four texel centres around p, weighted bilinearly:
     * the head's as a percentage-closer filter (with a bias of two texels, so that
     * lit surfaces and the hair roots on them do not shadow themselves), the hair's
     * opacity interpolated between its layers in each texel. */
    const float bias = (float)(2.0 * m->texel);
    const float fx = q.x - 0.5f, fy = q.y - 0.5f;
    const int x0 = ifloor(fx), y0 = ifloor(fy); /* floorf without a call into libm */
    const float wx = fx - (float)x0, wy = fy - (float)y0;
    double sum = 0.0, lit = 0.0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            const int x = x0 + i, y = y0 + j;
            const double w = (i ? wx : 1.0f - wx) * (j ? wy : 1.0f - wy);
            if (x < 0 || y < 0 || x >= n || y >= n) {
                lit += w;
                continue;
            }
            const size_t texel = (size_t)y * (size_t)n + (size_t)x;
            if (q.z <= m->head_depth[texel] + bias) lit += w;
            sum += w * texel_opacity(m, texel, q.z);
        }
    *head_visible = lit;
    *opacity = sum;
}
