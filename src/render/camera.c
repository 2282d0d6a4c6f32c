/* The camera: a perspective view from the options' azimuth and elevation, at the
 * distance where every hair point and head vertex fits the picture. */
#include <omp.h>

#include "core/linalg.h"
#include "points_avx.h"
#include "render_internal.h"

static const double DEG = HK_PI / 180.0;

/* Unit vector from azimuth (about +y, 0 = +z, positive towards +x) and elevation. */
static hk_Vec3 direction(double azimuth_deg, double elevation_deg)
{
    const double az = azimuth_deg * DEG, el = elevation_deg * DEG;
    return hk_v3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
}

/* The fit's two passes over a point: the distance it needs (its projection inside the
 * picture's margins, and in front of the eye), and where it lands on the picture at
 * the distance found (x and y over depth). */
typedef struct Fit {
    hk_Vec3 target, origin, forward, right, up;
    double tx, ty;
} Fit;

static inline double needed(const Fit *f, hk_Vec3 p)
{
    const hk_Vec3 r = hk_v3_sub(p, f->target);
    const double w = hk_v3_dot(r, f->forward);
    const double need_x = fabs(hk_v3_dot(r, f->right)) / f->tx - w, need_y = fabs(hk_v3_dot(r, f->up)) / f->ty - w;
    const double need = need_x > need_y ? need_x : need_y;
    const double front = 1e-3 - w; /* everything in front of the eye */
    return need > front ? need : front;
}

typedef struct Spread {
    double xlo, xhi, ylo, yhi;
} Spread;

static inline void spread_add(const Fit *f, hk_Vec3 p, Spread *s)
{
    const hk_Vec3 d = hk_v3_sub(p, f->origin);
    const double z = hk_v3_dot(d, f->forward);
    const double x = hk_v3_dot(d, f->right) / z, y = hk_v3_dot(d, f->up) / z;
    if (x < s->xlo) s->xlo = x;
    if (x > s->xhi) s->xhi = x;
    if (y < s->ylo) s->ylo = y;
    if (y > s->yhi) s->yhi = y;
}

#ifdef HK_POINTS_AVX
/* needed() and spread_add() of hair points i .. while four remain before hi, lane by
 * lane: the maxima and minima are exact whatever the order (the same result). Return
 * where they stopped. */
__attribute__((target("avx"))) static size_t needed_avx(const Fit *f, const float *p, size_t i, size_t hi, double *dist)
{
    const __m256d cx = _mm256_set1_pd(f->target.x), cy = _mm256_set1_pd(f->target.y), cz = _mm256_set1_pd(f->target.z);
    const __m256d tx = _mm256_set1_pd(f->tx), ty = _mm256_set1_pd(f->ty), eye = _mm256_set1_pd(1e-3);
    const __m256d sign = _mm256_set1_pd(-0.0);
    __m256d most = _mm256_set1_pd(*dist);
    for (; i + 4 <= hi; i += 4) {
        __m256d x, y, z;
        hk_load4_points_avx(p, i, &x, &y, &z);
        x = _mm256_sub_pd(x, cx), y = _mm256_sub_pd(y, cy), z = _mm256_sub_pd(z, cz);
        const __m256d w = hk_dot4_avx(x, y, z, f->forward);
        const __m256d need_x =
            _mm256_sub_pd(_mm256_div_pd(_mm256_andnot_pd(sign, hk_dot4_avx(x, y, z, f->right)), tx), w);
        const __m256d need_y = _mm256_sub_pd(_mm256_div_pd(_mm256_andnot_pd(sign, hk_dot4_avx(x, y, z, f->up)), ty), w);
        /* max_pd(a, b) is a > b ? a : b, as the scalar's */
        const __m256d d = _mm256_max_pd(_mm256_max_pd(need_x, need_y), _mm256_sub_pd(eye, w));
        most = _mm256_max_pd(d, most);
    }
    *dist = hk_max4_avx(most);
    return i;
}

__attribute__((target("avx"))) static size_t spread_avx(const Fit *f, const float *p, size_t i, size_t hi, Spread *s)
{
    const __m256d ox = _mm256_set1_pd(f->origin.x), oy = _mm256_set1_pd(f->origin.y), oz = _mm256_set1_pd(f->origin.z);
    __m256d xlo = _mm256_set1_pd(s->xlo), xhi = _mm256_set1_pd(s->xhi);
    __m256d ylo = _mm256_set1_pd(s->ylo), yhi = _mm256_set1_pd(s->yhi);
    for (; i + 4 <= hi; i += 4) {
        __m256d x, y, z;
        hk_load4_points_avx(p, i, &x, &y, &z);
        x = _mm256_sub_pd(x, ox), y = _mm256_sub_pd(y, oy), z = _mm256_sub_pd(z, oz);
        const __m256d depth = hk_dot4_avx(x, y, z, f->forward);
        const __m256d px = _mm256_div_pd(hk_dot4_avx(x, y, z, f->right), depth);
        const __m256d py = _mm256_div_pd(hk_dot4_avx(x, y, z, f->up), depth);
        /* min_pd(a, b) is a < b ? a : b: a NaN keeps the bound, as the scalar's */
        xlo = _mm256_min_pd(px, xlo), xhi = _mm256_max_pd(px, xhi);
        ylo = _mm256_min_pd(py, ylo), yhi = _mm256_max_pd(py, yhi);
    }
    s->xlo = hk_min4_avx(xlo), s->xhi = hk_max4_avx(xhi), s->ylo = hk_min4_avx(ylo), s->yhi = hk_max4_avx(yhi);
    return i;
}
#endif

/* The largest distance the scene's points need (at least 1e-6). */
static double fit_distance(const hk_Scene *scene, const Fit *f)
{
    const hk_HairFile *h = scene->hair;
    const size_t n = h->point_count;
#ifdef HK_POINTS_AVX
    const int avx = hk_avx_path();
#endif
    double dist = 1e-6;
    /* max is exact: the same result whatever the threads and lanes. */
#pragma omp parallel reduction(max : dist) num_threads(scene->threads)
    {
        size_t i, hi;
        hk_points_part(n, &i, &hi);
#ifdef HK_POINTS_AVX
        if (avx) i = needed_avx(f, h->points, i, hi, &dist);
#endif
        for (; i < hi; i++) {
            const double d = needed(f, hk_hair_point(h, (uint32_t)i));
            if (d > dist) dist = d;
        }
    }
    for (int i = 0; scene->head && i < scene->head->vertex_count; i++) {
        const double d = needed(f, scene->head->positions[i]);
        if (d > dist) dist = d;
    }
    return dist;
}

/* The extent of the points' projections, seen from f->origin. */
static Spread fit_spread(const hk_Scene *scene, const Fit *f)
{
    const hk_HairFile *h = scene->hair;
    const size_t n = h->point_count;
#ifdef HK_POINTS_AVX
    const int avx = hk_avx_path();
#endif
    double xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;
#pragma omp parallel reduction(min : xlo, ylo) reduction(max : xhi, yhi) num_threads(scene->threads)
    {
        size_t i, hi;
        hk_points_part(n, &i, &hi);
        Spread s = {xlo, xhi, ylo, yhi};
#ifdef HK_POINTS_AVX
        if (avx) i = spread_avx(f, h->points, i, hi, &s);
#endif
        for (; i < hi; i++) spread_add(f, hk_hair_point(h, (uint32_t)i), &s);
        xlo = s.xlo, xhi = s.xhi, ylo = s.ylo, yhi = s.yhi;
    }
    Spread s = {xlo, xhi, ylo, yhi};
    for (int i = 0; scene->head && i < scene->head->vertex_count; i++) spread_add(f, scene->head->positions[i], &s);
    return s;
}

hk_View hk_camera_frame(const hk_Scene *scene)
{
    const hk_RenderDef *o = scene->opt;
    hk_View v;
    v.perspective = 1;
    v.width = o->width;
    v.height = o->height;
    v.depth_offset = 0.0;
    v.forward = hk_v3_neg(direction(o->azimuth_deg, o->elevation_deg));
    hk_Vec3 side = hk_v3_cross(v.forward, hk_v3(0, 1, 0));
    if (hk_v3_norm(side) < 1e-9) side = hk_v3(1, 0, 0); /* looking straight up or down */
    v.right = hk_v3_normalize(side);
    v.up = hk_v3_cross(v.right, v.forward);
    const double ty = tan(0.5 * o->fov_deg * DEG) * 0.92; /* 4% margin on each side */
    const double tx = ty * (double)o->width / (double)o->height;
    v.focal = 0.5 * o->height / tan(0.5 * o->fov_deg * DEG);
    if (o->camera_distance > 0.0) {
        v.target = o->camera_target;
        v.distance = o->camera_distance;
        v.origin = hk_v3_madd(v.target, v.forward, -v.distance);
        return v;
    }
    hk_Vec3 target = hk_v3_scale(hk_v3_add(scene->lo, scene->hi), 0.5);
    /* Distance so that every point fits, then centre the picture on the points'
     * projection and fit again. */
    Fit f = {target, hk_v3_zero(), v.forward, v.right, v.up, tx, ty};
    for (int pass = 0; pass < 2; pass++) {
        f.target = target;
        const double dist = fit_distance(scene, &f);
        v.origin = hk_v3_madd(target, v.forward, -dist);
        v.target = target;
        v.distance = dist;
        if (pass == 1) break;
        f.origin = v.origin;
        const Spread s = fit_spread(scene, &f);
        if (!(s.xlo <= s.xhi)) break; /* no points */
        /* Move the target sideways by the offset of the projection's centre, at the
         * target's depth. */
        target = hk_v3_madd(target, v.right, 0.5 * (s.xlo + s.xhi) * dist);
        target = hk_v3_madd(target, v.up, 0.5 * (s.ylo + s.yhi) * dist);
    }
    return v;
}
