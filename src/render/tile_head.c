/* The head in one tile of the picture (thesis head shader, §4.1.5): rasterised with
 * 2 x 2 samples per pixel and a depth test, each sample shaded with Lambert's law
 * (plus a faint sheen) and the light reaching it through the head's shadow map and
 * the hair's deep opacity map. */
#include <float.h>

#include "raster_inline.h"
#include "render_internal.h"

static void head_sample(void *user, int x, int y, int s, float l0, float l1, float l2)
{
    hk_TileHead *w = user;
    /* Depth is affine in screen space for 1/z: perspective-correct. */
    const float inv_z = l0 / w->tv[0].z + l1 / w->tv[1].z + l2 / w->tv[2].z;
    const float z = 1.0f / inv_z;
    const size_t k = ((size_t)(y - w->r.y0) * HK_TILE + (size_t)(x - w->r.x0)) * 4 + (size_t)s;
    if (z < w->sample_z[k]) {
        w->sample_z[k] = z;
        w->sample_tri[k] = w->tri;
        w->sample_l[k][0] = l0 / w->tv[0].z / inv_z;
        w->sample_l[k][1] = l1 / w->tv[1].z / inv_z;
    }
}

static hk_Vec3 shade_skin(const hk_TileInput *in, int tri, float b0, float b1)
{
    const hk_Mesh *m = in->scene->head;
    const hk_RenderDef *o = in->scene->opt;
    const int *v = m->triangles + 3 * (size_t)tri;
    const double b2 = 1.0 - b0 - b1;
    hk_Vec3 p = hk_v3_scale(m->positions[v[0]], b0);
    p = hk_v3_madd(p, m->positions[v[1]], b1), p = hk_v3_madd(p, m->positions[v[2]], b2);
    hk_Vec3 n = hk_v3_scale(m->normals[v[0]], b0);
    n = hk_v3_madd(n, m->normals[v[1]], b1), n = hk_v3_madd(n, m->normals[v[2]], b2);
    n = hk_v3_norm(n) > 0.0 ? hk_v3_normalize(n) : hk_v3(0, 1, 0);
    double visible = 1.0;
    if (in->maps) {
        /* Looked up a texel and a half off the surface along its normal ("normal
         * offset"), so that a lit surface never shadows itself. */
        double head_visible, opacity;
        hk_light_lookup(in->maps, hk_v3_madd(p, n, 1.5 * in->maps->texel), &head_visible, &opacity);
        visible = head_visible * exp(-opacity);
    }
    /* Lambert (thesis head shader) plus a faint Blinn-Phong sheen. */
    const hk_Vec3 l = in->scene->light_dir, e = hk_v3_normalize(hk_v3_sub(in->camera->origin, p));
    /* fmax(0, .) by comparisons (fmax is a call into libm, three a sample): the same
     * values, NaN included; a -0.0 becomes +0.0, which adds and powers alike. */
    const double nl = hk_v3_dot(n, l), diffuse = nl > 0.0 ? nl : 0.0;
    const hk_Vec3 h = hk_v3_normalize(hk_v3_add(l, e));
    const double nh = hk_v3_dot(n, h);
    const double sheen = diffuse > 0.0 ? 0.04 * pow(nh > 0.0 ? nh : 0.0, 40.0) : 0.0;
    const double ambient = 2.0 * o->ambient_intensity; /* skin is not in the visuality file */
    return hk_v3_add(hk_v3_scale(o->skin, ambient + o->light_intensity * visible * diffuse),
                     hk_v3_scale(hk_v3(1, 1, 1), o->light_intensity * visible * sheen));
}

float hk_tile_head(const hk_TileInput *in, int tile, hk_TileHead *w, hk_TileBase *out)
{
    const int npx = HK_TILE * HK_TILE;
    for (int k = 0; k < npx * 4; k++) w->sample_z[k] = FLT_MAX;
    const hk_Mesh *m = in->scene->head;
    const hk_TileBins *bins = in->head_bins;
    w->r = hk_tile_rect(in->tiles, tile, in->scene->opt->width, in->scene->opt->height);
    if (m && bins)
        for (uint32_t k = bins->start[tile]; k < bins->start[tile + 1]; k++) {
            const uint32_t t = bins->items[k];
            hk_RasterPoint v[3];
            for (int c = 0; c < 3; c++) v[c] = in->head_proj[m->triangles[3 * (size_t)t + (size_t)c]];
            w->tri = (int)t, w->tv = v;
            hk_raster_triangle(v, w->r, 2, head_sample, w);
        }
    const hk_RenderDef *o = in->scene->opt;
    float farthest = 0.0f;
    for (int y = w->r.y0; y < w->r.y1; y++) {
        const double f = o->height > 1 ? (double)y / (o->height - 1) : 0.0;
        const hk_Vec3 bg = hk_v3_add(hk_v3_scale(o->background_top, 1.0 - f), hk_v3_scale(o->background_bottom, f));
        for (int x = w->r.x0; x < w->r.x1; x++) {
            const int p = (y - w->r.y0) * HK_TILE + (x - w->r.x0);
            hk_Vec3 sum = hk_v3_zero();
            float far = 0.0f;
            for (int s = 0; s < 4; s++) {
                const int k = 4 * p + s;
                if (w->sample_z[k] == FLT_MAX) {
                    sum = hk_v3_add(sum, bg), far = FLT_MAX;
                    continue;
                }
                sum = hk_v3_add(sum, shade_skin(in, w->sample_tri[k], w->sample_l[k][0], w->sample_l[k][1]));
                far = maxf(far, w->sample_z[k]); /* a number: kept only below FLT_MAX */
            }
            out->base[p][0] = (float)(0.25 * sum.x), out->base[p][1] = (float)(0.25 * sum.y);
            out->base[p][2] = (float)(0.25 * sum.z);
            out->cutoff[p] = far; /* hair behind every sample of the head is hidden */
            farthest = maxf(farthest, far);
        }
    }
    return farthest < FLT_MAX ? farthest : HUGE_VALF;
}
