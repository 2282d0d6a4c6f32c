/* Follicles on a head's wick (Piuze et al. 2011 §4.3, Fig. 9): the implicit surface fitted to
 * the wick and the head around it, the wick's boundary as the fixed particles of the
 * scalp contour, and the particle sampling restricted to the wick. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "follicle_internal.h"
#include "hairkit/follicle_sampling.h"

hk_WickSamplingDef hk_default_wick_sampling_def(void)
{
    hk_WickSamplingDef d;
    memset(&d, 0, sizeof d);
    const hk_FollicleSamplingDef s = hk_default_follicle_sampling_def();
    d.spacing = 0.0;
    d.fit_spacing = 0.01;
    d.margin = 0.02;
    d.include_contour = 1;
    d.max_particles = s.max_particles;
    d.max_iterations = s.max_iterations;
    d.relax_iterations = s.relax_iterations;
    d.seed = s.seed;
    return d;
}

static hk_Status check_mesh(const hk_Mesh *m, const char *name, hk_Error *err)
{
    if (m->vertex_count < 0 || m->vertex_count > HK_MAX_MESH_VERTICES || m->triangle_count < 0 ||
        m->triangle_count > HK_MAX_MESH_TRIANGLES || (m->vertex_count && (!m->positions || !m->normals)) ||
        (m->triangle_count && !m->triangles))
        return hk_error_set(err, HK_ERR_INVALID, "the %s mesh is malformed (%d vertices, %d triangles)", name,
                            m->vertex_count, m->triangle_count);
    for (int i = 0; i < 3 * m->triangle_count; i++)
        if (m->triangles[i] < 0 || m->triangles[i] >= m->vertex_count)
            return hk_error_set(err, HK_ERR_INVALID, "%s triangle %d names vertex %d of %d", name, i / 3,
                                m->triangles[i], m->vertex_count);
    for (int i = 0; i < m->vertex_count; i++)
        if (!hk_v3_isfinite(m->positions[i]) || !hk_v3_isfinite(m->normals[i]))
            return hk_error_set(err, HK_ERR_INVALID, "%s vertex %d is not finite", name, i);
    return HK_OK;
}

/* Fit points: the wick's vertices, then the head's vertices within the grid's radius
 * of the wick, thinned greedily in that order (so wick vertices win) to no two closer
 * than fit_spacing: close points with slightly different normals would make the
 * interpolation system needlessly ill-conditioned. The thinning is all-pairs, fine
 * for the few thousand vertices around a wick. */
static hk_Status fit_points(const hk_Mesh *head, const hk_Mesh *wick, const hk_TriangleGrid *near_wick,
                            double fit_spacing, hk_Vec3 **out_p, hk_Vec3 **out_n, int *out_count, hk_Error *err)
{
    const int total = wick->vertex_count + (head ? head->vertex_count : 0);
    hk_Vec3 *p = hk_alloc_array((size_t)total, sizeof *p, err);
    hk_Vec3 *n = hk_alloc_array((size_t)total, sizeof *n, err);
    if (!p || !n) {
        hk_free(p), hk_free(n);
        return HK_ERR_NOMEM;
    }
    int kept = 0;
    const double r2 = fit_spacing * fit_spacing;
    for (int i = 0; i < total; i++) {
        const int from_wick = i < wick->vertex_count;
        const hk_Vec3 x = from_wick ? wick->positions[i] : head->positions[i - wick->vertex_count];
        const hk_Vec3 nx = from_wick ? wick->normals[i] : head->normals[i - wick->vertex_count];
        if (!(hk_v3_norm(nx) > 0.5)) continue; /* a vertex of no face */
        if (!from_wick && !(hk_triangle_grid_distance(near_wick, x, NULL) < near_wick->radius)) continue;
        int close = 0;
        for (int k = 0; k < kept && !close; k++) close = hk_v3_norm2(hk_v3_sub(p[k], x)) < r2;
        if (close) continue;
        if (kept == HK_IMPLICIT_MAX_CONSTRAINTS / 2) {
            hk_free(p), hk_free(n);
            return hk_error_set(err, HK_ERR_INVALID,
                                "more than %d points to fit around the wick at fit_spacing %g m: make it larger",
                                HK_IMPLICIT_MAX_CONSTRAINTS / 2, fit_spacing);
        }
        p[kept] = x, n[kept] = nx;
        kept++;
    }
    *out_p = p, *out_n = n, *out_count = kept;
    return HK_OK;
}

typedef struct Edge {
    int lo, hi; /* vertex indices, lo < hi */
    int from;   /* the directed edge's first vertex */
} Edge;

static int edge_cmp(const void *a, const void *b)
{
    const Edge *x = a, *y = b;
    if (x->lo != y->lo) return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi) return x->hi < y->hi ? -1 : 1;
    return x->from - y->from;
}

/* The scalp contour: the wick's boundary loops (edges of one triangle, followed in the
 * triangles' winding), each resampled at equal arc length steps close to `spacing`. */
static hk_Status contour_points(const hk_Mesh *wick, double spacing, hk_Vec3 **out, int *out_count, hk_Error *err)
{
    *out = NULL, *out_count = 0;
    const int nv = wick->vertex_count, ne = 3 * wick->triangle_count;
    Edge *e = hk_alloc_array((size_t)ne, sizeof *e, err);
    int *next = hk_alloc_array((size_t)nv, sizeof *next, err);
    char *seen = hk_calloc_array((size_t)nv, 1, err);
    hk_Status st = HK_OK;
    if (!e || !next || !seen) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (int t = 0; t < wick->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const int a = wick->triangles[3 * t + c], b = wick->triangles[3 * t + (c + 1) % 3];
            e[3 * t + c] = (Edge){a < b ? a : b, a < b ? b : a, a};
        }
    qsort(e, (size_t)ne, sizeof *e, edge_cmp);
    for (int v = 0; v < nv; v++) next[v] = -1;
    for (int i = 0; i < ne;) {
        int j = i + 1;
        while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        if (j - i == 1 && e[i].lo != e[i].hi) {
            const int a = e[i].from, b = a == e[i].lo ? e[i].hi : e[i].lo;
            if (next[a] >= 0) {
                st = hk_error_set(err, HK_ERR_INVALID, "the wick's boundary is not a set of simple loops at vertex %d",
                                  a + 1);
                goto done;
            }
            next[a] = b;
        }
        i = j;
    }
    /* two passes over the loops: count the points, then place them */
    long total = 0;
    for (int pass = 0; pass < 2; pass++) {
        memset(seen, 0, (size_t)nv);
        int placed = 0;
        for (int v0 = 0; v0 < nv; v0++) {
            if (next[v0] < 0 || seen[v0]) continue;
            double length = 0.0;
            int v = v0, steps = 0;
            do {
                if (next[v] < 0 || steps++ > nv) {
                    st = hk_error_set(err, HK_ERR_INVALID, "the wick's boundary does not close at vertex %d", v + 1);
                    goto done;
                }
                seen[v] = 1;
                length += hk_v3_dist(wick->positions[v], wick->positions[next[v]]);
                v = next[v];
            } while (v != v0);
            const double m_real = fmax(3.0, round(length / spacing));
            if (m_real > (double)HK_SAMPLING_MAX_PARTICLES) {
                st = hk_error_set(err, HK_ERR_INVALID, "a contour of %g m at spacing %g m makes too many particles",
                                  length, spacing);
                goto done;
            }
            const int m = (int)m_real;
            if (pass == 0) {
                total += m;
                if (total > HK_SAMPLING_MAX_PARTICLES) {
                    st = hk_error_set(err, HK_ERR_INVALID, "the wick's contour makes more than %d particles",
                                      HK_SAMPLING_MAX_PARTICLES);
                    goto done;
                }
                continue;
            }
            /* walk again, dropping a point every length / m */
            const double step = length / m;
            double s_edge = 0.0; /* arc length at the start of the current edge */
            v = v0;
            for (int k = 0; k < m; k++) {
                const double target = k * step;
                double el = hk_v3_dist(wick->positions[v], wick->positions[next[v]]);
                while (s_edge + el < target && next[v] != v0) {
                    s_edge += el;
                    v = next[v];
                    el = hk_v3_dist(wick->positions[v], wick->positions[next[v]]);
                }
                const double u = el > 0.0 ? fmin(1.0, (target - s_edge) / el) : 0.0;
                (*out)[placed++] = hk_v3_add(wick->positions[v],
                                             hk_v3_scale(hk_v3_sub(wick->positions[next[v]], wick->positions[v]), u));
            }
        }
        if (pass == 0) {
            *out = hk_alloc_array((size_t)total, sizeof(hk_Vec3), err);
            if (!*out) {
                st = HK_ERR_NOMEM;
                goto done;
            }
        } else {
            *out_count = placed;
        }
    }
done:
    hk_free(e), hk_free(next), hk_free(seen);
    if (st != HK_OK) {
        hk_free(*out);
        *out = NULL, *out_count = 0;
    }
    return st;
}

/* Hair grows where the surface runs over the wick: near a triangle along its normal
 * (the smooth surface bulges off the flat triangles), hardly beyond its edges. */
typedef struct WickMask {
    hk_TriangleGrid grid; /* radius: the normal tolerance */
    double beyond;        /* the tangential tolerance */
} WickMask;

static int on_wick(void *user, hk_Vec3 x)
{
    const WickMask *m = user;
    double tangential;
    return hk_triangle_grid_distance(&m->grid, x, &tangential) < m->grid.radius && tangential < m->beyond;
}

hk_Status hk_wick_follicles(const hk_Mesh *head, const hk_Mesh *wick, const hk_WickSamplingDef *def,
                            hk_FollicleSamples *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    if (!wick) return hk_error_set(err, HK_ERR_INVALID, "wick follicles need a wick");
    hk_WickSamplingDef d = def ? *def : hk_default_wick_sampling_def();
    if (!(d.spacing > 0.0) || !isfinite(d.spacing))
        return hk_error_set(err, HK_ERR_INVALID, "follicle spacing must be > 0, got %g", d.spacing);
    if (!isfinite(d.fit_spacing) || !isfinite(d.margin))
        return hk_error_set(err, HK_ERR_INVALID, "fit_spacing and margin must be finite");
    if (d.fit_spacing <= 0.0) d.fit_spacing = 0.01;
    if (d.margin < 0.0) d.margin = 0.02;
    hk_Status st = check_mesh(wick, "wick", err);
    if (st == HK_OK && head) st = check_mesh(head, "head", err);
    if (st != HK_OK) return st;
    if (wick->triangle_count < 1) return hk_error_set(err, HK_ERR_INVALID, "the wick has no triangles");
    if (d.max_particles < 1 || d.max_particles > HK_SAMPLING_MAX_PARTICLES)
        return hk_error_set(err, HK_ERR_INVALID, "max_particles must be in [1, %d], got %d", HK_SAMPLING_MAX_PARTICLES,
                            d.max_particles);
    /* refuse at once what the cap would cut short after a long run */
    const double expected = hk_mesh_area(wick) / (0.8660254037844386 * d.spacing * d.spacing);
    if (!(expected <= 0.9 * d.max_particles))
        return hk_error_set(err, HK_ERR_INVALID,
                            "a spacing of %g m on the wick's %.4g m^2 makes about %.3g follicles, more than "
                            "max_particles (%d)",
                            d.spacing, hk_mesh_area(wick), expected, d.max_particles);

    hk_TriangleGrid near = {0};
    WickMask mask = {{0}, 0.0};
    hk_Vec3 *fp = NULL, *fn = NULL, *contour = NULL, *contour_n = NULL, *seeds = NULL;
    hk_ImplicitSurface *surface = NULL;
    hk_FollicleSamples free_part = {0};
    int fit_count = 0, contour_count = 0;
    if ((st = hk_triangle_grid_build(&near, wick->positions, wick->triangles, wick->triangle_count,
                                     fmax(d.margin, 1e-9), err)) != HK_OK)
        goto done;
    if ((st = fit_points(d.margin > 0.0 ? head : NULL, wick, &near, d.fit_spacing, &fp, &fn, &fit_count, err)) != HK_OK)
        goto done;
    hk_ImplicitFitDef fit = hk_default_implicit_fit_def();
    fit.threads = d.threads;
    if (d.progress) d.progress(d.progress_user, "surface", 0.0);
    if ((st = hk_implicit_surface_fit(fp, fn, fit_count, &fit, &surface, err)) != HK_OK) goto done;
    if (d.progress) d.progress(d.progress_user, "surface", 1.0);
    const hk_ImplicitFunction f = hk_implicit_surface_function(surface);

    /* How far the wick's flat triangles stray from the smooth surface: the mask must
     * reach beyond that, or follicles on the surface would fall outside it. */
    double stray = 0.0;
    for (int t = 0; t < wick->triangle_count; t++) {
        const int *v = wick->triangles + 3 * t;
        const hk_Vec3 c = hk_v3_scale(
            hk_v3_add(wick->positions[v[0]], hk_v3_add(wick->positions[v[1]], wick->positions[v[2]])), 1.0 / 3.0);
        hk_Vec3 g;
        const double val = hk_implicit_surface_eval(surface, c, &g);
        if (hk_v3_norm(g) > 0.0) stray = fmax(stray, fabs(val) / hk_v3_norm(g));
    }
    if ((st = hk_triangle_grid_build(&mask.grid, wick->positions, wick->triangles, wick->triangle_count,
                                     0.25 * d.spacing + 2.0 * stray, err)) != HK_OK)
        goto done;
    mask.beyond = 0.1 * d.spacing + 2.0 * stray;

    if ((st = contour_points(wick, d.spacing, &contour, &contour_count, err)) != HK_OK) goto done;
    contour_n = hk_alloc_array((size_t)contour_count, sizeof(hk_Vec3), err);
    if (!contour_n) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (int i = 0; i < contour_count; i++)
        if (!hk_implicit_project(f, contour[i], 1e-9 * d.spacing, 0.5 * d.spacing, &contour[i], &contour_n[i])) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "contour point %d cannot be projected onto the fitted surface", i);
            goto done;
        }

    /* seeds: the wick's vertices, every k-th so that they leave room to grow */
    const int stride = wick->vertex_count / d.max_particles + 1;
    int seed_count = 0;
    seeds = hk_alloc_array((size_t)wick->vertex_count, sizeof(hk_Vec3), err);
    if (!seeds) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (int i = 0; i < wick->vertex_count; i += stride) seeds[seed_count++] = wick->positions[i];

    hk_FollicleSamplingDef sd = hk_default_follicle_sampling_def();
    sd.spacing = d.spacing;
    sd.max_particles = d.max_particles;
    sd.max_iterations = d.max_iterations;
    sd.relax_iterations = d.relax_iterations;
    sd.seed = d.seed;
    sd.fixed = contour;
    sd.fixed_count = contour_count;
    sd.inside = on_wick;
    sd.inside_user = &mask;
    sd.threads = d.threads;
    sd.progress = d.progress;
    sd.progress_user = d.progress_user;
    if ((st = hk_sample_follicles(f, seeds, seed_count, &sd, &free_part, err)) != HK_OK) goto done;

    const int extra = d.include_contour ? contour_count : 0;
    *out = free_part;
    memset(&free_part, 0, sizeof free_part);
    if (extra > 0) {
        hk_Vec3 *p = hk_alloc_array((size_t)out->count + (size_t)extra, sizeof(hk_Vec3), err);
        hk_Vec3 *n = hk_alloc_array((size_t)out->count + (size_t)extra, sizeof(hk_Vec3), err);
        if (!p || !n) {
            hk_free(p), hk_free(n);
            st = HK_ERR_NOMEM;
            goto done;
        }
        memcpy(p, out->points, sizeof(hk_Vec3) * (size_t)out->count);
        memcpy(n, out->normals, sizeof(hk_Vec3) * (size_t)out->count);
        memcpy(p + out->count, contour, sizeof(hk_Vec3) * (size_t)extra);
        memcpy(n + out->count, contour_n, sizeof(hk_Vec3) * (size_t)extra);
        hk_free(out->points), hk_free(out->normals);
        out->points = p, out->normals = n;
        out->count += extra;
    }
done:
    hk_triangle_grid_free(&near);
    hk_triangle_grid_free(&mask.grid);
    hk_free(fp), hk_free(fn), hk_free(contour), hk_free(contour_n), hk_free(seeds);
    hk_implicit_surface_destroy(surface);
    hk_follicle_samples_free(&free_part);
    if (st != HK_OK) hk_follicle_samples_free(out);
    return st;
}
