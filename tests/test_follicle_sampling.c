/* Follicle sampling (Piuze et al. 2011 §4.3): the variational implicit surface interpolates
 * its constraints and recovers a sphere; particles end on the surface, evenly spaced,
 * in the expected number, away from fixed particles and inside the mask; the same
 * seed gives the same bytes with 1 or 2 threads; the wick of the project's head;
 * bad input gives errors. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/follicle_sampling.h"
#include "follicles/follicle_internal.h"

#define PI       HK_PI
#define HEX_AREA 0.8660254037844386 /* area per point of a hexagonal packing of spacing 1 */

/* Fibonacci points on a sphere: near-uniform and deterministic. */
static void sphere_points(int n, hk_Vec3 centre, double radius, hk_Vec3 *p, hk_Vec3 *nrm)
{
    for (int i = 0; i < n; i++) {
        const double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z), phi = 2.399963229728653 * i;
        nrm[i] = hk_v3(r * cos(phi), r * sin(phi), z);
        p[i] = hk_v3_madd(centre, nrm[i], radius);
    }
}

static hk_Vec3 random_unit(void)
{
    const double z = 2.0 * hk_test_uniform() - 1.0, phi = 2.0 * PI * hk_test_uniform(), r = sqrt(1.0 - z * z);
    return hk_v3(r * cos(phi), r * sin(phi), z);
}

/* ---- implicit surface ----------------------------------------------------------- */

static void test_fit_interpolates_constraints(void **state)
{
    (void)state;
    /* an irregular closed shape: a sphere squashed into an ellipsoid with a bump */
    enum { N = 150 };
    hk_Vec3 p[N], n[N];
    sphere_points(N, hk_v3_zero(), 1.0, p, n);
    for (int i = 0; i < N; i++) {
        const hk_Vec3 u = n[i];
        const double bump = 1.0 + 0.2 * exp(-8.0 * hk_v3_norm2(hk_v3_sub(u, hk_v3(0, 0, 1))));
        p[i] = hk_v3(0.12 * u.x * bump, 0.08 * u.y * bump, 0.1 * u.z * bump);
        n[i] = hk_v3(u.x / 0.12, u.y / 0.08, u.z / 0.1); /* the ellipsoid's normal, close enough */
    }
    for (int both = 0; both <= 1; both++) {
        hk_ImplicitFitDef def = hk_default_implicit_fit_def();
        def.both_sides = both;
        hk_ImplicitSurface *s;
        hk_Error err;
        assert_int_equal(hk_implicit_surface_fit(p, n, N, &def, &s, &err), HK_OK);
        assert_int_equal(hk_implicit_surface_constraint_count(s), (both ? 3 : 2) * N);
        const double off = hk_implicit_surface_offset(s);
        /* default: 1% of the bounding box diagonal */
        assert_true(off > 0.001 && off < 0.01);
        for (int i = 0; i < N; i++) {
            const hk_Vec3 u = hk_v3_normalize(n[i]);
            hk_assert_near(hk_implicit_surface_eval(s, p[i], NULL), 0.0, 1e-8);
            hk_assert_near(hk_implicit_surface_eval(s, hk_v3_madd(p[i], u, off), NULL), 1.0, 1e-8);
            if (both) hk_assert_near(hk_implicit_surface_eval(s, hk_v3_madd(p[i], u, -off), NULL), -1.0, 1e-8);
        }
        /* inside negative, outside positive */
        assert_true(hk_implicit_surface_eval(s, hk_v3_zero(), NULL) < 0.0);
        assert_true(hk_implicit_surface_eval(s, hk_v3(0.5, 0.1, 0.2), NULL) > 0.0);
        hk_implicit_surface_destroy(s);
    }
}

static void test_fit_recovers_sphere(void **state)
{
    (void)state;
    /* 200 points on a sphere of radius R: on 2000 random points of the true sphere the
     * distance to the zero set, |f| / |grad f|, stays below 2e-5 R and grad f is
     * radial within 2e-4 rad (measured: 7e-6 R and 7e-5 rad). */
    enum { N = 200 };
    const double R = 0.1;
    const hk_Vec3 c = hk_v3(0.01, 0.2, -0.03);
    hk_Vec3 p[N], n[N];
    sphere_points(N, c, R, p, n);
    hk_ImplicitFitDef def = hk_default_implicit_fit_def();
    def.normal_offset = 0.1 * R;
    hk_ImplicitSurface *s;
    hk_Error err;
    assert_int_equal(hk_implicit_surface_fit(p, n, N, &def, &s, &err), HK_OK);
    hk_assert_near(hk_implicit_surface_offset(s), 0.1 * R, 1e-15);
    double worst_d = 0.0, worst_a = 0.0;
    for (int k = 0; k < 2000; k++) {
        const hk_Vec3 u = random_unit();
        hk_Vec3 g;
        const double f = hk_implicit_surface_eval(s, hk_v3_madd(c, u, R), &g);
        worst_d = fmax(worst_d, fabs(f) / hk_v3_norm(g));
        worst_a = fmax(worst_a, acos(fmin(1.0, hk_v3_dot(hk_v3_normalize(g), u))));
    }
    assert_true(worst_d < 2e-5 * R);
    assert_true(worst_a < 2e-4);
    hk_implicit_surface_destroy(s);
}

static void test_gradient_is_analytic(void **state)
{
    (void)state;
    enum { N = 60 };
    hk_Vec3 p[N], n[N];
    sphere_points(N, hk_v3(1, 2, 3), 0.5, p, n);
    hk_ImplicitSurface *s;
    hk_Error err;
    assert_int_equal(hk_implicit_surface_fit(p, n, N, NULL, &s, &err), HK_OK);
    for (int k = 0; k < 50; k++) {
        const hk_Vec3 x = hk_v3_add(hk_v3(1, 2, 3), hk_v3_scale(random_unit(), 0.8 * hk_test_uniform()));
        hk_Vec3 g;
        hk_implicit_surface_eval(s, x, &g);
        const double h = 1e-6;
        for (int a = 0; a < 3; a++) {
            hk_Vec3 xp = x, xm = x;
            hk_v3_set(&xp, a, hk_v3_get(x, a) + h);
            hk_v3_set(&xm, a, hk_v3_get(x, a) - h);
            const double fd = (hk_implicit_surface_eval(s, xp, NULL) - hk_implicit_surface_eval(s, xm, NULL)) / (2 * h);
            /* central differences: truncation ~h^2, rounding ~1e-16 |terms| / h */
            hk_assert_near(hk_v3_get(g, a), fd, 1e-6 * hk_v3_norm(g));
        }
    }
    hk_implicit_surface_destroy(s);
}

static void test_fit_same_bytes_any_threads(void **state)
{
    (void)state;
    enum { N = 400 }; /* 800 constraints: the factorisation runs in parallel */
    hk_Vec3 *p = malloc(sizeof *p * N), *n = malloc(sizeof *n * N);
    sphere_points(N, hk_v3_zero(), 1.0, p, n);
    for (int i = 0; i < N; i++) p[i].y *= 0.7; /* not a sphere, so no symmetry hides a difference */
    double f[2][20];
    for (int t = 1; t <= 2; t++) {
        hk_ImplicitFitDef def = hk_default_implicit_fit_def();
        def.threads = t;
        hk_ImplicitSurface *s;
        hk_Error err;
        assert_int_equal(hk_implicit_surface_fit(p, n, N, &def, &s, &err), HK_OK);
        for (int k = 0; k < 20; k++)
            f[t - 1][k] = hk_implicit_surface_eval(s, hk_v3(0.1 * k - 1.0, 0.05 * k, 0.3), NULL);
        hk_implicit_surface_destroy(s);
    }
    assert_memory_equal(f[0], f[1], sizeof f[0]);
    free(p), free(n);
}

static void test_fit_bad_input(void **state)
{
    (void)state;
    enum { N = 20 };
    hk_Vec3 p[N], n[N];
    sphere_points(N, hk_v3_zero(), 1.0, p, n);
    hk_ImplicitSurface *s = (hk_ImplicitSurface *)p; /* must come back NULL */
    hk_Error err;
    assert_int_equal(hk_implicit_surface_fit(p, n, 0, NULL, &s, &err), HK_ERR_INVALID);
    assert_null(s);
    assert_int_equal(hk_implicit_surface_fit(NULL, n, N, NULL, &s, &err), HK_ERR_INVALID);
    /* NaN in a point, in a normal; a zero normal */
    hk_Vec3 q[N], m[N];
    memcpy(q, p, sizeof q), memcpy(m, n, sizeof m);
    q[3].y = NAN;
    assert_int_equal(hk_implicit_surface_fit(q, n, N, NULL, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 3");
    m[5].z = INFINITY;
    assert_int_equal(hk_implicit_surface_fit(p, m, N, NULL, &s, &err), HK_ERR_INVALID);
    memcpy(m, n, sizeof m);
    m[7] = hk_v3_zero();
    assert_int_equal(hk_implicit_surface_fit(p, m, N, NULL, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "zero normal");
    /* duplicate points */
    memcpy(q, p, sizeof q);
    q[9] = q[4];
    assert_int_equal(hk_implicit_surface_fit(q, n, N, NULL, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "coincide");
    /* a normal offset landing on another point: a thin sheet's two sides */
    const hk_Vec3 sheet[4] = {{0, 0, 0}, {0, 0.01, 0}, {1, 0, 0}, {0, 0, 1}};
    const hk_Vec3 up[4] = {{0, 1, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}};
    hk_ImplicitFitDef def = hk_default_implicit_fit_def();
    def.normal_offset = 0.01;
    assert_int_equal(hk_implicit_surface_fit(sheet, up, 4, &def, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "offset");
    /* all constraints in one plane: a circle with in-plane normals */
    for (int i = 0; i < N; i++) {
        q[i] = hk_v3(cos(2 * PI * i / N), sin(2 * PI * i / N), 0);
        m[i] = q[i];
    }
    assert_int_equal(hk_implicit_surface_fit(q, m, N, NULL, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "one plane");
    /* absurd sizes are refused before anything is allocated */
    assert_int_equal(hk_implicit_surface_fit(p, n, HK_IMPLICIT_MAX_CONSTRAINTS, NULL, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "too many points");
    assert_int_equal(hk_implicit_surface_fit(p, n, 2000000000, NULL, &s, &err), HK_ERR_INVALID);
    def.normal_offset = NAN;
    assert_int_equal(hk_implicit_surface_fit(p, n, N, &def, &s, &err), HK_ERR_INVALID);
    assert_null(s);
}

/* ---- sampling ------------------------------------------------------------------- */

static double unit_sphere(const void *user, hk_Vec3 x, hk_Vec3 *grad)
{
    (void)user;
    const double r = hk_v3_norm(x);
    *grad = r > 0.0 ? hk_v3_scale(x, 1.0 / r) : hk_v3_zero();
    return r - 1.0;
}

static const hk_ImplicitFunction sphere_fn = {unit_sphere, NULL};

typedef struct Spacing {
    double mean, cv, min;
} Spacing;

/* Nearest-neighbour distances among the points (and to the extra points, if any). */
static Spacing nearest_neighbours(const hk_Vec3 *p, int n, const hk_Vec3 *extra, int extra_count)
{
    double s = 0.0, s2 = 0.0, mn = 1e300;
    for (int i = 0; i < n; i++) {
        double best = 1e300;
        for (int j = 0; j < n; j++)
            if (j != i) best = fmin(best, hk_v3_dist(p[i], p[j]));
        for (int j = 0; j < extra_count; j++) best = fmin(best, hk_v3_dist(p[i], extra[j]));
        s += best, s2 += best * best, mn = fmin(mn, best);
    }
    Spacing r;
    r.mean = s / n;
    r.cv = sqrt(fmax(0.0, s2 / n - r.mean * r.mean)) / r.mean;
    r.min = mn;
    return r;
}

/* Progress reports: fractions that never go back, ending at 1. */
typedef struct Progress {
    int calls, backwards;
    double last;
} Progress;

static void record_progress(void *user, const char *stage, double fraction)
{
    Progress *p = user;
    assert_string_equal(stage, "follicles");
    if (fraction < p->last) p->backwards++;
    p->last = fraction;
    p->calls++;
}

static void test_sphere_from_one_seed(void **state)
{
    (void)state;
    /* One seed grows by fission over the whole unit sphere. Expected count: the area
     * over a hexagonal packing's sqrt(3)/2 d^2 (645 for d = 0.15); measured 638, nearest
     * neighbours 0.92 d on average with a coefficient of variation 0.027. */
    const double d = 0.15;
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = d;
    const hk_Vec3 seed = hk_v3(0.3, 1.2, 0.1);
    hk_FollicleSamples out;
    hk_Error err;
    Progress progress = {0, 0, 0.0};
    def.progress = record_progress;
    def.progress_user = &progress;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_OK);
    assert_int_equal(progress.calls, out.iterations + 1); /* one per iteration, and the end */
    assert_int_equal(progress.backwards, 0);
    hk_assert_near(progress.last, 1.0, 0.0);
    const double expected = 4.0 * PI / (HEX_AREA * d * d);
    assert_true(fabs(out.count / expected - 1.0) < 0.05);
    assert_true(out.births >= out.count - 1);
    for (int i = 0; i < out.count; i++) {
        hk_assert_near(hk_v3_norm(out.points[i]), 1.0, 1e-6); /* on the surface */
        hk_assert_near(hk_v3_dot(out.normals[i], out.points[i]), 1.0, 1e-6);
    }
    const Spacing sp = nearest_neighbours(out.points, out.count, NULL, 0);
    assert_true(sp.cv < 0.1);
    assert_true(sp.mean > 0.85 * d && sp.mean < 1.0 * d);
    assert_true(sp.min > 0.7 * d);
    assert_true(out.iterations <= def.max_iterations);
    hk_follicle_samples_free(&out);
}

static void test_fitted_sphere(void **state)
{
    (void)state;
    /* the whole chain: fit a sphere of radius 0.1 from 100 points, sample at 3 cm */
    enum { N = 100 };
    const double R = 0.1, d = 0.03;
    hk_Vec3 p[N], n[N];
    sphere_points(N, hk_v3_zero(), R, p, n);
    hk_ImplicitFitDef fit = hk_default_implicit_fit_def();
    fit.normal_offset = 0.1 * R;
    hk_ImplicitSurface *s;
    hk_Error err;
    assert_int_equal(hk_implicit_surface_fit(p, n, N, &fit, &s, &err), HK_OK);
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = d;
    hk_FollicleSamples out;
    assert_int_equal(hk_sample_follicles(hk_implicit_surface_function(s), p, 4, &def, &out, &err), HK_OK);
    const double expected = 4.0 * PI * R * R / (HEX_AREA * d * d);
    assert_true(fabs(out.count / expected - 1.0) < 0.1);
    for (int i = 0; i < out.count; i++) {
        hk_Vec3 g;
        const double f = hk_implicit_surface_eval(s, out.points[i], &g);
        assert_true(fabs(f) / hk_v3_norm(g) < 1e-6 * R);        /* on the fitted surface */
        hk_assert_near(hk_v3_norm(out.points[i]), R, 1e-4 * R); /* hence on the sphere */
        assert_true(hk_v3_dot(out.normals[i], hk_v3_normalize(out.points[i])) > 1.0 - 1e-6);
    }
    assert_true(nearest_neighbours(out.points, out.count, NULL, 0).cv < 0.1);
    hk_follicle_samples_free(&out);
    hk_implicit_surface_destroy(s);
}

static int upper_half(void *user, hk_Vec3 x) { return x.y > *(const double *)user; }

static void test_fixed_contour_and_mask(void **state)
{
    (void)state;
    /* The upper hemisphere with fixed particles every d along the equator (the
     * paper's scalp contour). Expected count: the hemisphere less the half row the
     * contour owns, (2 pi - 2 pi sqrt(3)/4 d) / (sqrt(3)/2 d^2) = 301; measured 297. */
    const double d = 0.15, level = 0.0;
    enum { M = 42 }; /* 2 pi / d */
    hk_Vec3 fixed[M], copy[M];
    for (int i = 0; i < M; i++) fixed[i] = hk_v3(cos(2 * PI * i / M), 0.0, sin(2 * PI * i / M));
    memcpy(copy, fixed, sizeof copy);
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = d;
    def.fixed = fixed;
    def.fixed_count = M;
    def.inside = upper_half;
    def.inside_user = (void *)&level;
    const hk_Vec3 seeds[3] = {{0, 1, 0}, {0.5, 0.5, 0}, {0, -1, 0}}; /* the last is outside: dropped */
    hk_FollicleSamples out;
    hk_Error err;
    assert_int_equal(hk_sample_follicles(sphere_fn, seeds, 3, &def, &out, &err), HK_OK);
    assert_memory_equal(fixed, copy, sizeof copy); /* the fixed particles did not move */
    const double expected = (2.0 * PI - 2.0 * PI * sqrt(3.0) / 4.0 * d) / (HEX_AREA * d * d);
    assert_true(fabs(out.count / expected - 1.0) < 0.08);
    for (int i = 0; i < out.count; i++) {
        assert_true(out.points[i].y > level); /* the mask holds */
        hk_assert_near(hk_v3_norm(out.points[i]), 1.0, 1e-6);
    }
    /* the contour repels: nobody comes closer to it than to each other */
    const Spacing sp = nearest_neighbours(out.points, out.count, fixed, M);
    assert_true(sp.min > 0.7 * d);
    assert_true(sp.cv < 0.1);
    hk_follicle_samples_free(&out);
}

static void test_mask_alone(void **state)
{
    (void)state;
    /* A cap y > 0.5 with no fixed particles: the mask holds; without a contour the
     * particles crowd its edge a little (measured: 271 for the cap's area / hex = 252). */
    const double d = 0.12, level = 0.5;
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = d;
    def.inside = upper_half;
    def.inside_user = (void *)&level;
    def.max_iterations = 300;
    const hk_Vec3 seed = hk_v3(0, 1, 0);
    hk_FollicleSamples out;
    hk_Error err;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_OK);
    for (int i = 0; i < out.count; i++) assert_true(out.points[i].y > level);
    const double expected = 2.0 * PI * (1.0 - level) / (HEX_AREA * d * d);
    assert_true(out.count > 0.9 * expected && out.count < 1.3 * expected);
    assert_true(nearest_neighbours(out.points, out.count, NULL, 0).min > 0.4 * d);
    hk_follicle_samples_free(&out);
}

static void test_max_particles(void **state)
{
    (void)state;
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = 0.05; /* would be ~5800 */
    def.max_particles = 60;
    def.max_iterations = 100;
    def.relax_iterations = 20;
    const hk_Vec3 seed = hk_v3(0, 0, 1);
    hk_FollicleSamples out;
    hk_Error err;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_OK);
    assert_true(out.count <= 60 && out.count > 30);
    assert_true(out.iterations <= 100);
    hk_follicle_samples_free(&out);
}

static void sample_sphere(uint64_t seed, int threads, hk_FollicleSamples *out)
{
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    def.spacing = 0.3;
    def.seed = seed;
    def.threads = threads;
    const hk_Vec3 seeds[2] = {{0, 0, 1}, {0.1, 0.9, 0}};
    hk_Error err;
    assert_int_equal(hk_sample_follicles(sphere_fn, seeds, 2, &def, out, &err), HK_OK);
}

static void test_same_bytes(void **state)
{
    (void)state;
    hk_FollicleSamples a, b, c, e;
    sample_sphere(7, 1, &a);
    sample_sphere(7, 2, &b);
    sample_sphere(7, 2, &c);
    assert_int_equal(a.count, b.count);
    assert_int_equal(a.count, c.count);
    assert_memory_equal(a.points, b.points, sizeof(hk_Vec3) * (size_t)a.count);
    assert_memory_equal(a.normals, b.normals, sizeof(hk_Vec3) * (size_t)a.count);
    assert_memory_equal(b.points, c.points, sizeof(hk_Vec3) * (size_t)a.count);
    /* another seed: other points, about as many */
    sample_sphere(8, 2, &e);
    assert_true(abs(e.count - a.count) < a.count / 10);
    assert_true(e.count != a.count || memcmp(e.points, a.points, sizeof(hk_Vec3) * (size_t)a.count) != 0);
    hk_follicle_samples_free(&a), hk_follicle_samples_free(&b), hk_follicle_samples_free(&c);
    hk_follicle_samples_free(&e);
}

static double flat_fn(const void *user, hk_Vec3 x, hk_Vec3 *grad)
{
    (void)user, (void)x;
    *grad = hk_v3_zero(); /* no surface to project on */
    return 1.0;
}

static void test_sampling_bad_input(void **state)
{
    (void)state;
    const hk_Vec3 seed = hk_v3(0, 0, 1);
    hk_FollicleSamples out;
    hk_Error err;
    hk_FollicleSamplingDef def = hk_default_follicle_sampling_def();
    /* spacing unset, negative, NaN */
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "spacing");
    def.spacing = -1.0;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.spacing = NAN;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.spacing = 0.2;
    /* no seeds, a NaN seed, a seed that cannot reach a surface */
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 0, &def, &out, &err), HK_ERR_INVALID);
    assert_int_equal(hk_sample_follicles(sphere_fn, NULL, 1, &def, &out, &err), HK_ERR_INVALID);
    const hk_Vec3 nan_seed = hk_v3(0, NAN, 1);
    assert_int_equal(hk_sample_follicles(sphere_fn, &nan_seed, 1, &def, &out, &err), HK_ERR_INVALID);
    const hk_ImplicitFunction flat = {flat_fn, NULL};
    assert_int_equal(hk_sample_follicles(flat, &seed, 1, &def, &out, &err), HK_ERR_NUMERIC);
    hk_assert_contains(err.message, "projected");
    /* absurd sizes */
    def.max_particles = 0;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.max_particles = 2000000000;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.max_particles = 100;
    def.fixed_count = -3;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.fixed_count = 5; /* and fixed == NULL */
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    const hk_Vec3 bad_fixed[2] = {{1, 0, 0}, {0, INFINITY, 0}};
    def.fixed = bad_fixed;
    def.fixed_count = 2;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "fixed particle 1");
    def.fixed = NULL, def.fixed_count = 0;
    def.max_iterations = 0;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.max_iterations = 10, def.relax_iterations = 11;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    def.relax_iterations = 5;
    /* every seed outside the mask */
    const double level = 2.0;
    def.inside = upper_half;
    def.inside_user = (void *)&level;
    assert_int_equal(hk_sample_follicles(sphere_fn, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "outside");
    assert_int_equal(out.count, 0);
    assert_null(out.points);
    /* no function */
    const hk_ImplicitFunction none = {NULL, NULL};
    def.inside = NULL;
    assert_int_equal(hk_sample_follicles(none, &seed, 1, &def, &out, &err), HK_ERR_INVALID);
}

/* ---- helpers: projection, grids, closest points --------------------------------- */

static void test_projection(void **state)
{
    (void)state;
    hk_Vec3 p, n;
    assert_int_equal(hk_implicit_project(sphere_fn, hk_v3(3, 4, 0), 1e-12, 0.0, &p, &n), 1);
    hk_assert_near(p.x, 0.6, 1e-12);
    hk_assert_near(p.y, 0.8, 1e-12);
    hk_assert_near(n.x, 0.6, 1e-12);
    /* capped steps still get there */
    assert_int_equal(hk_implicit_project(sphere_fn, hk_v3(0, 0, 9), 1e-12, 0.5, &p, &n), 1);
    hk_assert_near(p.z, 1.0, 1e-12);
    /* no gradient at the centre, none anywhere for a constant */
    assert_int_equal(hk_implicit_project(sphere_fn, hk_v3_zero(), 1e-12, 0.0, &p, &n), 0);
    const hk_ImplicitFunction flat = {flat_fn, NULL};
    assert_int_equal(hk_implicit_project(flat, hk_v3(1, 2, 3), 1e-12, 0.0, &p, &n), 0);
}

typedef struct Visits {
    int count;
    int seen[400];
} Visits;

static void count_visit(void *user, int j)
{
    Visits *v = user;
    v->seen[j]++;
    v->count++;
}

static void test_point_grid(void **state)
{
    (void)state;
    enum { N = 400 };
    hk_Vec3 p[N];
    for (int i = 0; i < N; i++)
        p[i] = hk_v3(2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1, 0.3 * hk_test_uniform() - 5);
    hk_PointGrid g;
    memset(&g, 0, sizeof g);
    hk_Error err;
    const double cell = 0.2;
    assert_int_equal(hk_point_grid_build(&g, p, N, cell, &err), HK_OK);
    for (int q = 0; q < 50; q++) {
        const hk_Vec3 x = p[q];
        Visits v;
        memset(&v, 0, sizeof v);
        hk_point_grid_query(&g, x, count_visit, &v);
        for (int j = 0; j < N; j++) {
            assert_true(v.seen[j] <= 1);                                    /* once at most */
            if (hk_v3_dist(x, p[j]) < cell) assert_int_equal(v.seen[j], 1); /* every neighbour */
        }
    }
    /* coordinates too far for 32-bit cells are refused */
    p[7].x = 1e300;
    assert_int_equal(hk_point_grid_build(&g, p, N, cell, &err), HK_ERR_INVALID);
    hk_point_grid_free(&g);
}

static void test_closest_point_triangle(void **state)
{
    (void)state;
    const hk_Vec3 a = hk_v3(0, 0, 0), b = hk_v3(1, 0, 0.2), c = hk_v3(0.3, 0.9, -0.1);
    for (int k = 0; k < 300; k++) {
        const hk_Vec3 x = hk_v3(3 * hk_test_uniform() - 1, 3 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1);
        const double got = hk_v3_dist(x, hk_closest_point_triangle(x, a, b, c));
        /* brute force over a fine barycentric lattice: never closer than the answer */
        double best = 1e300;
        const int m = 60;
        for (int i = 0; i <= m; i++)
            for (int j = 0; i + j <= m; j++) {
                const double u = (double)i / m, v = (double)j / m;
                const hk_Vec3 q =
                    hk_v3_add(a, hk_v3_add(hk_v3_scale(hk_v3_sub(b, a), u), hk_v3_scale(hk_v3_sub(c, a), v)));
                best = fmin(best, hk_v3_dist(x, q));
            }
        assert_true(got <= best + 1e-12);
        assert_true(got > best - 0.02); /* the lattice's resolution */
    }
}

/* ---- the project's head --------------------------------------------------------- */

/* Length of the edges that belong to one triangle. */
static double boundary_length(const hk_Mesh *m)
{
    double length = 0.0;
    for (int t = 0; t < m->triangle_count; t++)
        for (int c = 0; c < 3; c++) {
            const int a = m->triangles[3 * t + c], b = m->triangles[3 * t + (c + 1) % 3];
            int shared = 0;
            for (int u = 0; u < m->triangle_count && !shared; u++)
                for (int k = 0; k < 3; k++)
                    shared |= m->triangles[3 * u + k] == b && m->triangles[3 * u + (k + 1) % 3] == a;
            if (!shared) length += hk_v3_dist(m->positions[a], m->positions[b]);
        }
    return length;
}

static void test_wick_follicles(void **state)
{
    (void)state;
    hk_Mesh head, wick;
    hk_Error err;
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/head.obj", &head, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick.obj", &wick, &err), HK_OK);
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    def.spacing = 0.02;
    def.threads = 1;
    hk_FollicleSamples out, again;
    assert_int_equal(hk_wick_follicles(&head, &wick, &def, &out, &err), HK_OK);
    /* A hexagonal packing over the wick's 493 cm^2 (142 at 2 cm), where the contour's
     * row, every d along the 58 cm boundary, has half its strip outside: expected
     * area / (sqrt(3)/2 d^2) + perimeter / (2 d) = 157 in all, perimeter / d = 29 on
     * the contour. Measured 156 and 29. */
    const double area = hk_mesh_area(&wick), perimeter = boundary_length(&wick);
    const double expected = area / (HEX_AREA * def.spacing * def.spacing) + perimeter / (2.0 * def.spacing);
    assert_true(fabs(out.count / expected - 1.0) < 0.08);
    for (int i = 0; i < out.count; i++) {
        /* near the wick (within the mask), with the wick's outward normal */
        double best = 1e300;
        int nearest = 0;
        for (int t = 0; t < wick.triangle_count; t++) {
            const int *v = wick.triangles + 3 * t;
            const double dist =
                hk_v3_dist(out.points[i], hk_closest_point_triangle(out.points[i], wick.positions[v[0]],
                                                                    wick.positions[v[1]], wick.positions[v[2]]));
            if (dist < best) best = dist, nearest = v[0];
        }
        assert_true(best < 0.3 * def.spacing);
        hk_assert_near(hk_v3_norm(out.normals[i]), 1.0, 1e-12);
        assert_true(hk_v3_dot(out.normals[i], wick.normals[nearest]) > 0.9);
    }
    assert_true(nearest_neighbours(out.points, out.count, NULL, 0).min > 0.5 * def.spacing);
    /* 2 threads and no contour: the same free follicles, byte for byte, and the
     * contour's missing */
    def.threads = 2;
    def.include_contour = 0;
    assert_int_equal(hk_wick_follicles(&head, &wick, &def, &again, &err), HK_OK);
    hk_assert_near(out.count - again.count, perimeter / def.spacing, 2.0);
    assert_memory_equal(again.points, out.points, sizeof(hk_Vec3) * (size_t)again.count);
    assert_memory_equal(again.normals, out.normals, sizeof(hk_Vec3) * (size_t)again.count);
    hk_follicle_samples_free(&again);
    /* fitting every head vertex within 5 mm (2692) would exceed the dense solve's limit */
    def.fit_spacing = 1e-4;
    def.margin = 0.005;
    assert_int_equal(hk_wick_follicles(&head, &wick, &def, &again, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "fit_spacing");
    hk_follicle_samples_free(&out);
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
}

static void test_wick_bad_input(void **state)
{
    (void)state;
    hk_Mesh wick;
    hk_Error err;
    hk_FollicleSamples out;
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick-200.obj", &wick, &err), HK_OK);
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID); /* spacing unset */
    def.spacing = 0.02;
    def.fit_spacing = NAN;
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    def.fit_spacing = 0.0;
    def.max_particles = -1;
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    def.max_particles = 100; /* 0.02 m on the wick makes about 140 */
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "more than max_particles");
    def.max_particles = 1000;
    const int saved = wick.triangles[7];
    wick.triangles[7] = wick.vertex_count; /* out of range */
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "triangle 2");
    wick.triangles[7] = saved;
    const hk_Vec3 saved_p = wick.positions[3];
    wick.positions[3].x = NAN;
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    wick.positions[3] = saved_p;
    const int tris = wick.triangle_count;
    wick.triangle_count = 0;
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_ERR_INVALID);
    wick.triangle_count = tris;
    /* the wick alone (no head) still works */
    def.spacing = 0.04;
    assert_int_equal(hk_wick_follicles(NULL, &wick, &def, &out, &err), HK_OK);
    assert_true(out.count > 0);
    hk_follicle_samples_free(&out);
    hk_mesh_free(&wick);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_interpolates_constraints),
        cmocka_unit_test(test_fit_recovers_sphere),
        cmocka_unit_test(test_gradient_is_analytic),
        cmocka_unit_test(test_fit_same_bytes_any_threads),
        cmocka_unit_test(test_fit_bad_input),
        cmocka_unit_test(test_sphere_from_one_seed),
        cmocka_unit_test(test_fitted_sphere),
        cmocka_unit_test(test_fixed_contour_and_mask),
        cmocka_unit_test(test_mask_alone),
        cmocka_unit_test(test_max_particles),
        cmocka_unit_test(test_same_bytes),
        cmocka_unit_test(test_sampling_bad_input),
        cmocka_unit_test(test_projection),
        cmocka_unit_test(test_point_grid),
        cmocka_unit_test(test_closest_point_triangle),
        cmocka_unit_test(test_wick_follicles),
        cmocka_unit_test(test_wick_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
