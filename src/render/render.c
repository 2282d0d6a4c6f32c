/* The renderer's options and their checks, the scene's bounds and the camera's fit
 * (the passes of a picture: renderer.c). */
#include <float.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "core/core_internal.h"
#include "points_avx.h"
#include "render_internal.h"

hk_RenderDef hk_default_render_def(void)
{
    hk_RenderDef o;
    memset(&o, 0, sizeof o);
    o.width = 1200;
    o.height = 900;
    o.threads = 0;
    o.shadows = 1;
    o.shading = HK_SHADING_KAJIYA_KAY;
    o.scattering = HK_SCATTERING_DUAL;
    o.azimuth_deg = 35.0;
    o.elevation_deg = 12.0;
    o.fov_deg = 30.0;
    o.camera_target = hk_v3_zero();
    o.camera_distance = 0.0; /* fit */
    o.light_azimuth_deg = -30.0;
    o.light_elevation_deg = 40.0;
    o.light_intensity = 1.0;
    o.ambient_intensity = 0.2;
    o.shadow_map_size = 0; /* from the picture's size */
    o.opacity_layers = 4;
    o.layer_size = 0.0;
    o.scatter_floor = 0.25;
    o.hair_thickness = 0.0;
    o.strand_variation = 0.15;
    o.strand_lod = 1;
    o.background_top = hk_v3(0.32, 0.34, 0.38);
    o.background_bottom = hk_v3(0.05, 0.05, 0.06);
    o.skin = hk_v3(0.61, 0.40, 0.28);
    return o;
}

/* The light's maps (deep opacity maps, Yuksel & Keyser 2008; Lansink 2010 §4.1.6) of a
 * picture of the default 1200 x 900 have 512 texels a side, as they always had; a
 * smaller picture gets a map as much smaller, so that a texel stays about as many of
 * its pixels wide: shadow detail finer than a pixel does not show, and filling the
 * 512 map (15 million fragments on the default head) was a third of a 64 x 48
 * thumbnail's time (issue 18, item 4). Larger pictures keep 512: their pictures are
 * those of before, and a larger map costs more than it shows (docs/rendering.md). */
enum { FULL_MAP = 512, FULL_WIDTH = 1200, FULL_HEIGHT = 900, SMALLEST_MAP = 64, MAP_STEP = 32 };

int hk_render_shadow_map_texels(const hk_RenderDef *o)
{
    if (o->shadow_map_size > 0) return o->shadow_map_size;
    const double scale = fmax((double)o->width / FULL_WIDTH, (double)o->height / FULL_HEIGHT);
    if (scale >= 1.0) return FULL_MAP;
    const int steps = (int)ceil(FULL_MAP * scale / MAP_STEP - 1e-9);
    const int texels = steps * MAP_STEP;
    return texels < SMALLEST_MAP ? SMALLEST_MAP : texels;
}

hk_Status hk_render_check_options(const hk_RenderDef *o, hk_Error *err)
{
    if (o->width < 8 || o->height < 8 || o->width > 16384 || o->height > 16384)
        return hk_error_set(err, HK_ERR_INVALID, "picture size %dx%d: each side must be 8 to 16384 pixels", o->width,
                            o->height);
    if (o->shadows && o->shadow_map_size != 0 && (o->shadow_map_size < 16 || o->shadow_map_size > 8192))
        return hk_error_set(err, HK_ERR_INVALID, "shadow map size %d: must be 16 to 8192 (or 0: from the picture)",
                            o->shadow_map_size);
    if (o->shadows && (o->opacity_layers < 1 || o->opacity_layers > HK_MAX_OPACITY_LAYERS))
        return hk_error_set(err, HK_ERR_INVALID, "opacity layers %d: must be 1 to %d", o->opacity_layers,
                            HK_MAX_OPACITY_LAYERS);
    if (o->shading != HK_SHADING_KAJIYA_KAY && o->shading != HK_SHADING_MARSCHNER)
        return hk_error_set(err, HK_ERR_INVALID, "shading model %d: must be Kajiya-Kay or Marschner", (int)o->shading);
    if (o->scattering != HK_SCATTERING_SINGLE && o->scattering != HK_SCATTERING_DUAL)
        return hk_error_set(err, HK_ERR_INVALID, "scattering %d: must be single or dual", (int)o->scattering);
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

int hk_render_threads(const hk_RenderDef *options)
{
    return options->threads > 0 ? options->threads : omp_get_max_threads();
}

/* Whether strand k is among the one in `stride` drawn: by a hash of its index (the
 * finaliser of MurmurHash3), so that the strands kept are spread over the groom
 * whatever order its strands come in (a groom's strands often come guide by guide). */
static int strand_drawn(uint32_t k, int stride)
{
    if (stride <= 1) return 1;
    uint32_t h = k;
    h ^= h >> 16, h *= 0x85ebca6bu, h ^= h >> 13, h *= 0xc2b2ae35u, h ^= h >> 16;
    return h % (uint32_t)stride == 0;
}

uint32_t hk_segment_starts(const hk_HairFile *hair, int stride, uint8_t *s, int threads)
{
    uint32_t n = 0;
#pragma omp parallel for schedule(static) reduction(+ : n) num_threads(threads)
    for (long k = 0; k < (long)hair->strand_count; k++) {
        const uint32_t first = hair->first_point[k], end = hair->first_point[k + 1];
        const int drawn = strand_drawn((uint32_t)k, stride);
        for (uint32_t i = first; i < end; i++) s[i] = drawn && i + 1 < end;
        n += drawn && end > first ? end - first - 1 : 0;
    }
    for (uint32_t i = hair->first_point[hair->strand_count]; i < hair->point_count; i++) s[i] = 0;
    return n;
}

/* Bounding box of hair and head; non-finite coordinates are refused. */
hk_Status hk_scene_bounds(hk_Scene *sc, hk_Error *err)
{
    sc->lo = hk_v3(DBL_MAX, DBL_MAX, DBL_MAX), sc->hi = hk_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    const hk_HairFile *h = sc->hair;
    /* In parallel (millions of points): min and max do not depend on the order. In the
     * file's floats: their min and max are those of the doubles they convert to
     * (exactly), at a fraction of the work (every frame of an animation pays for it). */
    float lx = HUGE_VALF, ly = HUGE_VALF, lz = HUGE_VALF, hx = -HUGE_VALF, hy = -HUGE_VALF, hz = -HUGE_VALF;
    int nonfinite = 0;
#pragma omp parallel reduction(min                                                                                     \
                               : lx, ly, lz) reduction(max                                                             \
                                                       : hx, hy, hz) reduction(|                                       \
                                                                               : nonfinite) num_threads(sc->threads)
    {
        size_t i, hi;
        hk_points_part(h->point_count, &i, &hi);
        float lo[3], up[3];
        if (hi > i) { /* (no points: h->points may be NULL) */
            nonfinite |= hk_float_points_bounds(h->points + 3 * i, hi - i, lo, up);
            lx = lo[0], ly = lo[1], lz = lo[2], hx = up[0], hy = up[1], hz = up[2];
        }
    }
    for (long i = 0; nonfinite && i < (long)h->point_count; i++)
        if (!hk_v3_isfinite(hk_hair_point(h, (uint32_t)i)))
            return hk_error_set(err, HK_ERR_INVALID, "hair point %ld is not finite", i);
    if (lx < HUGE_VALF) /* else no hair point: the empty box above */
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

/* Level of detail (hk_render_strand_stride): a strand under a quarter of a pixel wide
 * at the camera's target is drawn as one of k, k times as wide, up to a quarter pixel;
 * at most 64, and at least 5,000 strands kept (with 1,000 the 11,400 strands of Sintel
 * at 320 x 240 were drawn one in 7, their streaks visibly coarser: RMSE 1.25 %). */
enum { LOD_MOST = 64, LOD_FEWEST_STRANDS = 5000 };
#define LOD_WIDTH 0.25 /* pixels */

int hk_scene_strand_stride(const hk_Scene *sc, const hk_View *cam)
{
    if (!sc->opt->strand_lod || !(cam->distance > 0.0)) return 1;
    /* The diameter: the one value, or the mean of the file's array over every 64th
     * point (in order: the same bits whatever the threads). */
    double diameter = sc->thickness_fixed;
    if (sc->thickness_point && sc->hair->point_count > 0) {
        double sum = 0.0;
        long count = 0;
        for (uint32_t i = 0; i < sc->hair->point_count; i += 64, count++) sum += sc->thickness_point[i];
        diameter = sum / (double)count;
    }
    const double pixels = diameter * cam->focal / cam->distance;
    if (!(pixels > 0.0) || pixels >= LOD_WIDTH) return 1;
    double k = floor(LOD_WIDTH / pixels);
    k = fmin(k, (double)LOD_MOST);
    k = fmin(k, floor((double)sc->hair->strand_count / LOD_FEWEST_STRANDS));
    return k > 1.0 ? (int)k : 1;
}

/* The scene the camera frames (hk_camera_frame), for the questions asked of it without
 * drawing: options checked, bounds, the strands' width (every strand drawn). */
static hk_Status camera_scene(const hk_HairFile *hair, const hk_Mesh *head, const hk_RenderDef *opt, hk_Scene *sc,
                              hk_Error *err)
{
    hk_Status st = hk_render_check_options(opt, err);
    if (st != HK_OK) return st;
    memset(sc, 0, sizeof *sc);
    sc->hair = hair, sc->head = head && head->triangle_count > 0 ? head : NULL, sc->opt = opt;
    sc->threads = hk_render_threads(opt);
    if ((st = hk_scene_bounds(sc, err)) != HK_OK) return st;
    sc->thickness = hk_scene_file_thickness(sc);
    hk_scene_thickness(sc, 1);
    return HK_OK;
}

int hk_render_strand_stride(const hk_HairFile *hair, const hk_Mesh *head, const hk_RenderDef *opt, hk_Error *err)
{
    const hk_RenderDef defaults = hk_default_render_def();
    hk_Scene sc;
    if (camera_scene(hair, head, opt ? opt : &defaults, &sc, err) != HK_OK) return 0;
    const hk_View cam = hk_camera_frame(&sc);
    return hk_scene_strand_stride(&sc, &cam);
}

hk_Status hk_render_fit_camera(const hk_HairFile *hair, const hk_Mesh *head, const hk_RenderDef *opt, hk_Vec3 *target,
                               double *distance, hk_Error *err)
{
    hk_RenderDef fit = opt ? *opt : hk_default_render_def();
    hk_Status st = hk_render_check_options(&fit, err); /* the camera's own values too */
    if (st != HK_OK) return st;
    fit.camera_distance = 0.0;
    hk_Scene sc;
    if ((st = camera_scene(hair, head, &fit, &sc, err)) != HK_OK) return st;
    const hk_View cam = hk_camera_frame(&sc);
    *target = cam.target;
    *distance = cam.distance;
    return HK_OK;
}
