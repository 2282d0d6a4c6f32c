/* Variational implicit surface through points with normals (Piuze et al. 2011 §4.3 after Turk
 * & O'Brien, "Modelling with implicit surfaces that interpolate", ACM TOG 2002):
 * the function of least thin-plate energy taking 0 on the surface points and +1 (and
 * -1) a little way out (and in) along the normals; in 3D that function is
 * sum_j w_j |x - c_j|^3 + a linear polynomial (Duchon 1977). */
#include <float.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "follicle_internal.h"
#include "hairkit/follicle_sampling.h"

struct hk_ImplicitSurface {
    int n;                /* centres = constraints */
    double *cx, *cy, *cz; /* centres in normalised coordinates, (x - origin) / scale */
    double *w;            /* kernel weights */
    double p[4];          /* polynomial p0 + p1 x + p2 y + p3 z in normalised coordinates */
    hk_Vec3 origin;
    double scale;
    double offset; /* normal offset used (m) */
};

hk_ImplicitFitDef hk_default_implicit_fit_def(void)
{
    hk_ImplicitFitDef d = {0.0, 0, 0};
    return d;
}

void hk_implicit_surface_destroy(hk_ImplicitSurface *s)
{
    if (!s) return;
    hk_free(s->cx);
    hk_free(s->cy);
    hk_free(s->cz);
    hk_free(s->w);
    hk_free(s);
}

double hk_implicit_surface_offset(const hk_ImplicitSurface *s) { return s->offset; }
int hk_implicit_surface_constraint_count(const hk_ImplicitSurface *s) { return s->n; }

double hk_implicit_surface_eval(const hk_ImplicitSurface *s, hk_Vec3 x, hk_Vec3 *grad)
{
    const double inv = 1.0 / s->scale;
    const double x0 = (x.x - s->origin.x) * inv, y0 = (x.y - s->origin.y) * inv, z0 = (x.z - s->origin.z) * inv;
    /* Two interleaved sums: more instructions in flight, the same order every call. */
    double f0 = 0.0, f1 = 0.0, gx0 = 0.0, gx1 = 0.0, gy0 = 0.0, gy1 = 0.0, gz0 = 0.0, gz1 = 0.0;
    const int n = s->n;
    int j = 0;
    for (; j + 2 <= n; j += 2) {
        const double dx0 = x0 - s->cx[j], dy0 = y0 - s->cy[j], dz0 = z0 - s->cz[j];
        const double dx1 = x0 - s->cx[j + 1], dy1 = y0 - s->cy[j + 1], dz1 = z0 - s->cz[j + 1];
        const double r20 = dx0 * dx0 + dy0 * dy0 + dz0 * dz0, r21 = dx1 * dx1 + dy1 * dy1 + dz1 * dz1;
        const double wr0 = s->w[j] * sqrt(r20), wr1 = s->w[j + 1] * sqrt(r21);
        f0 += wr0 * r20;
        f1 += wr1 * r21;
        gx0 += wr0 * dx0, gy0 += wr0 * dy0, gz0 += wr0 * dz0;
        gx1 += wr1 * dx1, gy1 += wr1 * dy1, gz1 += wr1 * dz1;
    }
    for (; j < n; j++) {
        const double dx = x0 - s->cx[j], dy = y0 - s->cy[j], dz = z0 - s->cz[j];
        const double r2 = dx * dx + dy * dy + dz * dz;
        const double wr = s->w[j] * sqrt(r2);
        f0 += wr * r2;
        gx0 += wr * dx, gy0 += wr * dy, gz0 += wr * dz;
    }
    const double f = (f0 + f1) + (s->p[0] + s->p[1] * x0 + s->p[2] * y0 + s->p[3] * z0);
    /* d/dx |x - c|^3 = 3 |x - c| (x - c) */
    if (grad)
        *grad = hk_v3((3.0 * (gx0 + gx1) + s->p[1]) * inv, (3.0 * (gy0 + gy1) + s->p[2]) * inv,
                      (3.0 * (gz0 + gz1) + s->p[3]) * inv);
    return f;
}

static double eval_adapter(const void *user, hk_Vec3 x, hk_Vec3 *grad)
{
    return hk_implicit_surface_eval((const hk_ImplicitSurface *)user, x, grad);
}

hk_ImplicitFunction hk_implicit_surface_function(const hk_ImplicitSurface *s)
{
    hk_ImplicitFunction fn = {eval_adapter, s};
    return fn;
}

/* Coincident constraints make the system singular; name them instead of failing in
 * the factorisation. Sorting along x keeps this O(n log n) for spread-out points. */
typedef struct Keyed {
    double x;
    int i;
} Keyed;

static int keyed_cmp(const void *a, const void *b)
{
    const Keyed *ka = a, *kb = b;
    if (ka->x != kb->x) return ka->x < kb->x ? -1 : 1;
    return ka->i - kb->i;
}

static int find_coincident(const hk_Vec3 *c, int n, double tol, Keyed *keys, int *a, int *b)
{
    for (int i = 0; i < n; i++) keys[i].x = c[i].x, keys[i].i = i;
    qsort(keys, (size_t)n, sizeof *keys, keyed_cmp);
    for (int i = 0; i < n; i++)
        for (int k = i + 1; k < n && keys[k].x - keys[i].x <= tol; k++)
            if (hk_v3_dist(c[keys[i].i], c[keys[k].i]) <= tol) {
                *a = keys[i].i < keys[k].i ? keys[i].i : keys[k].i;
                *b = keys[i].i < keys[k].i ? keys[k].i : keys[i].i;
                return 1;
            }
    return 0;
}

hk_Status hk_implicit_surface_fit(const hk_Vec3 *points, const hk_Vec3 *normals, int count,
                                  const hk_ImplicitFitDef *def, hk_ImplicitSurface **out, hk_Error *err)
{
    *out = NULL;
    const hk_ImplicitFitDef d = def ? *def : hk_default_implicit_fit_def();
    if (count <= 0 || !points || !normals)
        return hk_error_set(err, HK_ERR_INVALID, "the implicit surface needs points with normals, got %d", count);
    const int per_point = d.both_sides ? 3 : 2;
    if (count > HK_IMPLICIT_MAX_CONSTRAINTS / per_point)
        return hk_error_set(err, HK_ERR_INVALID,
                            "too many points for the implicit surface: %d (limit %d, i.e. %d constraints with "
                            "%d per point: the dense solve grows as n^3); thin the points first",
                            count, HK_IMPLICIT_MAX_CONSTRAINTS / per_point, HK_IMPLICIT_MAX_CONSTRAINTS, per_point);
    if (!isfinite(d.normal_offset)) return hk_error_set(err, HK_ERR_INVALID, "the normal offset is not finite");
    hk_Vec3 lo = hk_v3(DBL_MAX, DBL_MAX, DBL_MAX), hi = hk_v3(-DBL_MAX, -DBL_MAX, -DBL_MAX);
    for (int i = 0; i < count; i++) {
        if (!hk_v3_isfinite(points[i]) || !hk_v3_isfinite(normals[i]))
            return hk_error_set(err, HK_ERR_INVALID, "point %d or its normal is not finite", i);
        if (!(hk_v3_norm(normals[i]) > 1e-12))
            return hk_error_set(err, HK_ERR_INVALID, "point %d has a zero normal", i);
        lo = hk_v3(fmin(lo.x, points[i].x), fmin(lo.y, points[i].y), fmin(lo.z, points[i].z));
        hi = hk_v3(fmax(hi.x, points[i].x), fmax(hi.y, points[i].y), fmax(hi.z, points[i].z));
    }
    const double diag = hk_v3_dist(lo, hi);
    if (!(diag > 0.0) || !isfinite(diag))
        return hk_error_set(err, HK_ERR_INVALID, "the implicit surface's points span no space (diagonal %g)", diag);
    const double offset = d.normal_offset > 0.0 ? d.normal_offset : 0.01 * diag;

    const int n = count * per_point;
    hk_ImplicitSurface *s = hk_calloc_array(1, sizeof *s, err);
    hk_Vec3 *c = hk_alloc_array((size_t)n, sizeof *c, err);
    double *h = hk_alloc_array((size_t)n, sizeof *h, err);
    Keyed *keys = hk_alloc_array((size_t)n, sizeof *keys, err);
    hk_Status st = HK_OK;
    if (!s || !c || !h || !keys) {
        st = HK_ERR_NOMEM;
        goto fail;
    }
    s->n = n;
    s->offset = offset;
    /* Normalised coordinates keep the matrix entries of order one; the interpolant
     * does not change (the spline space is invariant under similarity). */
    s->origin = hk_v3_scale(hk_v3_add(lo, hi), 0.5);
    s->scale = 0.5 * diag;
    const double inv = 1.0 / s->scale;
    for (int i = 0; i < count; i++) {
        const hk_Vec3 nrm = hk_v3_normalize(normals[i]);
        const hk_Vec3 q = hk_v3_scale(hk_v3_sub(points[i], s->origin), inv);
        c[i] = q, h[i] = 0.0;
        c[count + i] = hk_v3_madd(q, nrm, offset * inv), h[count + i] = 1.0;
        if (d.both_sides) c[2 * count + i] = hk_v3_madd(q, nrm, -offset * inv), h[2 * count + i] = -1.0;
    }
    int ia, ib;
    if (find_coincident(c, n, 1e-10, keys, &ia, &ib)) {
        const char *kind[3] = {"point", "outer offset of point", "inner offset of point"};
        st = hk_error_set(err, HK_ERR_INVALID,
                          "implicit surface constraints coincide: %s %d and %s %d (duplicate points, or a "
                          "normal offset of %g m reaching another point)",
                          kind[ia / count], ia % count, kind[ib / count], ib % count, offset);
        goto fail;
    }
    s->cx = hk_alloc_array((size_t)n, sizeof(double), err);
    s->cy = hk_alloc_array((size_t)n, sizeof(double), err);
    s->cz = hk_alloc_array((size_t)n, sizeof(double), err);
    s->w = hk_alloc_array((size_t)n, sizeof(double), err);
    if (!s->cx || !s->cy || !s->cz || !s->w) {
        st = HK_ERR_NOMEM;
        goto fail;
    }
    for (int i = 0; i < n; i++) s->cx[i] = c[i].x, s->cy[i] = c[i].y, s->cz[i] = c[i].z;
    st = hk_rbf_solve(n, c, h, d.threads > 0 ? d.threads : omp_get_max_threads(), s->w, s->p, err);
    if (st != HK_OK) goto fail;
    hk_free(c), hk_free(h), hk_free(keys);
    *out = s;
    return HK_OK;
fail:
    hk_free(c), hk_free(h), hk_free(keys);
    hk_implicit_surface_destroy(s);
    return st;
}

int hk_implicit_project(hk_ImplicitFunction fn, hk_Vec3 x, double tol, double max_step, hk_Vec3 *out_point,
                        hk_Vec3 *out_normal)
{
    for (int it = 0; it < 50; it++) {
        hk_Vec3 g;
        const double f = fn.eval(fn.user, x, &g);
        const double g2 = hk_v3_norm2(g);
        if (!isfinite(f) || !(g2 > 0.0) || !isfinite(g2)) return 0;
        const double dist = fabs(f) / sqrt(g2);
        if (dist <= tol) {
            *out_point = x;
            *out_normal = hk_v3_scale(g, 1.0 / sqrt(g2));
            return 1;
        }
        double t = f / g2;
        /* far from the surface the linearisation overshoots: cap the step */
        if (max_step > 0.0 && dist > max_step) t *= max_step / dist;
        x = hk_v3_madd(x, g, -t);
    }
    return 0;
}
