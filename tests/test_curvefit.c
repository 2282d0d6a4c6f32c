/* Curve fitting machinery (Piuze et al. 2011 §5, include/hairkit/curvefit.h): the
 * discrete Fréchet measures against brute force, Nelder-Mead on standard and hostile
 * functions, start poses and resampling, single and piecewise fits of targets traced by
 * the test's own models (recovery of known parameters, splits at the join, noise), bad
 * input; the fits with both minimisers (least squares and the paper's Nelder-Mead). */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/curvefit.h"

/* ---- helpers ---------------------------------------------------------------------- */

static double uniform(double lo, double hi) { return lo + (hi - lo) * hk_test_uniform(); }

static double gaussian(void)
{
    const double u = 1.0 - hk_test_uniform(), v = hk_test_uniform();
    return sqrt(-2.0 * log(u)) * cos(2.0 * HK_PI * v);
}

static hk_Vec3 random_unit(void)
{
    for (;;) {
        const hk_Vec3 v = hk_v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        const double n = hk_v3_norm(v);
        if (n > 0.1 && n <= 1.0) return hk_v3_scale(v, 1.0 / n);
    }
}

static hk_CurveStart random_start(void)
{
    const hk_Vec3 t = random_unit();
    const hk_Vec3 r = random_unit();
    const hk_Vec3 n = hk_v3_normalize(hk_v3_madd(r, t, -hk_v3_dot(r, t)));
    hk_CurveStart s;
    s.pos = hk_v3(uniform(-0.1, 0.1), uniform(-0.1, 0.1), uniform(-0.1, 0.1));
    s.frame = hk_m3_from_cols(t, n, hk_v3_cross(t, n));
    return s;
}

/* ---- the test's curve models ---------------------------------------------------------- */

/* The discrete Frenet helix of the library (hk_curve_model_frenet_helix), by its
 * curvature and torsion. */
static int helix_trace(double kappa, double tau, const hk_CurveStart *start, double length, int count, hk_Vec3 *out,
                       hk_CurveStart *end)
{
    const double k[2] = {kappa, tau};
    return hk_curve_model_frenet_helix(NULL, k, start, length, count, out, end);
}

static int helix_model(void *user, const double *k, const hk_CurveStart *start, double length, int count, hk_Vec3 *out,
                       hk_CurveStart *end)
{
    (void)user;
    return helix_trace(k[0], k[1], start, length, count, out, end);
}

/* A planar arc: the helix without torsion. params: (kappa). */
static int arc_model(void *user, const double *k, const hk_CurveStart *start, double length, int count, hk_Vec3 *out,
                     hk_CurveStart *end)
{
    (void)user;
    return helix_trace(k[0], 0.0, start, length, count, out, end);
}

/* A straight line, no parameters. */
static int line_model(void *user, const double *k, const hk_CurveStart *start, double length, int count, hk_Vec3 *out,
                      hk_CurveStart *end)
{
    (void)user;
    (void)k;
    return helix_trace(0.0, 0.0, start, length, count, out, end);
}

/* Fails for every parameter vector. */
static int failing_model(void *user, const double *k, const hk_CurveStart *start, double length, int count,
                         hk_Vec3 *out, hk_CurveStart *end)
{
    (void)user, (void)k, (void)start, (void)length, (void)count, (void)out, (void)end;
    return 1;
}

/* The helix, but failing for tau < 0 and returning NaN points for kappa > 200: the fit
 * must route around both. */
static int patchy_model(void *user, const double *k, const hk_CurveStart *start, double length, int count, hk_Vec3 *out,
                        hk_CurveStart *end)
{
    if (k[1] < 0.0) return 1;
    const int rc = helix_model(user, k, start, length, count, out, end);
    if (k[0] > 200.0) out[count / 2].y = NAN;
    return rc;
}

/* The helix, counting its calls. */
typedef struct Counter {
    long calls;
} Counter;

static int counting_model(void *user, const double *k, const hk_CurveStart *start, double length, int count,
                          hk_Vec3 *out, hk_CurveStart *end)
{
    ((Counter *)user)->calls++;
    return helix_model(NULL, k, start, length, count, out, end);
}

/* Target: pieces of the helix model chained through their end poses. joins[] gets the
 * sample index where each piece after the first starts. */
static void make_helix_target(const hk_CurveStart *start, int pieces, const double (*k)[2], const int *segments,
                              double h, hk_Vec3 *out)
{
    hk_CurveStart pose = *start, end;
    int at = 0;
    for (int p = 0; p < pieces; p++) {
        helix_trace(k[p][0], k[p][1], &pose, h * segments[p], segments[p] + 1, out + at, &end);
        at += segments[p];
        pose = end;
    }
}

/* ---- Fréchet measures -------------------------------------------------------------- */

static void brute(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, int i, int j, double sum, double mx,
                  double *best_sum, double *best_max)
{
    const double d = hk_v3_dist(a[i], b[j]);
    sum += d;
    mx = d > mx ? d : mx;
    if (i == p - 1 && j == q - 1) {
        if (sum < *best_sum) *best_sum = sum;
        if (mx < *best_max) *best_max = mx;
        return;
    }
    if (i + 1 < p) brute(a, p, b, q, i + 1, j, sum, mx, best_sum, best_max);
    if (j + 1 < q) brute(a, p, b, q, i, j + 1, sum, mx, best_sum, best_max);
    if (i + 1 < p && j + 1 < q) brute(a, p, b, q, i + 1, j + 1, sum, mx, best_sum, best_max);
}

static void test_frechet_brute_force(void **state)
{
    (void)state;
    hk_Vec3 a[7], b[7];
    double work[7];
    for (int trial = 0; trial < 300; trial++) {
        const int p = 1 + (int)(7 * hk_test_uniform()), q = 1 + (int)(7 * hk_test_uniform());
        for (int i = 0; i < p; i++) a[i] = hk_v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        for (int j = 0; j < q; j++) b[j] = hk_v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        double bs = INFINITY, bm = INFINITY;
        brute(a, p, b, q, 0, 0, 0.0, 0.0, &bs, &bm);
        hk_assert_rel(hk_frechet_coupling(a, p, b, q, work), bs, 1e-14, 1e-300);
        hk_assert_rel(hk_frechet_coupling_normalized(a, p, b, q, work), bs / (p > q ? p : q), 1e-14, 1e-300);
        hk_assert_rel(hk_frechet_distance(a, p, b, q, work), bm, 1e-15, 1e-300);
        hk_FrechetMeasures m;
        assert_int_equal(hk_frechet_measures(a, p, b, q, &m, NULL), HK_OK);
        hk_assert_rel(m.coupling, bs, 1e-14, 1e-300);
        hk_assert_rel(m.normalized, bs / (p > q ? p : q), 1e-14, 1e-300);
        hk_assert_rel(m.distance, bm, 1e-15, 1e-300);
    }
}

static void test_frechet_symmetry(void **state)
{
    (void)state;
    hk_Vec3 a[40], b[40];
    double work[40];
    for (int trial = 0; trial < 100; trial++) {
        const int p = 1 + (int)(40 * hk_test_uniform()), q = trial % 3 ? 1 + (int)(40 * hk_test_uniform()) : p;
        for (int i = 0; i < p; i++) a[i] = hk_v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        for (int j = 0; j < q; j++) b[j] = hk_v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        /* Exactly, not approximately: the fits compare these values. */
        assert_true(hk_frechet_coupling(a, p, b, q, work) == hk_frechet_coupling(b, q, a, p, work));
        assert_true(hk_frechet_distance(a, p, b, q, work) == hk_frechet_distance(b, q, a, p, work));
        assert_true(hk_frechet_coupling_normalized(a, p, b, q, work) ==
                    hk_frechet_coupling_normalized(b, q, a, p, work));
    }
}

static void test_frechet_identical_and_shifted(void **state)
{
    (void)state;
    enum { N = 25 };
    hk_Vec3 a[N], b[N];
    double work[N];
    /* A planar wiggle in z = 0; shifted along z by d every pair (a_i, b_j) is at least d
     * apart and the diagonal coupling has N pairs of exactly d. */
    for (int i = 0; i < N; i++) a[i] = hk_v3(0.01 * i, 0.003 * sin(0.7 * i), 0.0);
    assert_true(hk_frechet_coupling(a, N, a, N, work) == 0.0);
    assert_true(hk_frechet_distance(a, N, a, N, work) == 0.0);
    const double d = 0.0017;
    for (int i = 0; i < N; i++) b[i] = hk_v3(a[i].x, a[i].y, d);
    hk_assert_rel(hk_frechet_distance(a, N, b, N, work), d, 1e-15, 0);
    hk_assert_rel(hk_frechet_coupling_normalized(a, N, b, N, work), d, 1e-14, 0);
    hk_assert_rel(hk_frechet_coupling(a, N, b, N, work), N * d, 1e-14, 0);
    /* One point against a curve: every coupling pairs it with all of them. */
    const hk_Vec3 o = hk_v3(0, 0, 0);
    double sum = 0.0, mx = 0.0;
    for (int i = 0; i < N; i++) sum += hk_v3_norm(a[i]), mx = fmax(mx, hk_v3_norm(a[i]));
    hk_assert_rel(hk_frechet_coupling(&o, 1, a, N, work), sum, 1e-14, 0);
    hk_assert_rel(hk_frechet_distance(a, N, &o, 1, work), mx, 1e-15, 0);
}

static void test_frechet_bad_input(void **state)
{
    (void)state;
    hk_Vec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
    double work[3];
    assert_true(isnan(hk_frechet_coupling(a, 0, a, 3, work)));
    assert_true(isnan(hk_frechet_distance(NULL, 3, a, 3, work)));
    assert_true(isnan(hk_frechet_coupling_normalized(a, 3, a, 3, NULL)));
    hk_FrechetMeasures m;
    hk_Error err;
    assert_int_equal(hk_frechet_measures(a, 0, a, 3, &m, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "at least one point");
    assert_int_equal(hk_frechet_measures(a, 3, a, 3, NULL, &err), HK_ERR_INVALID);
    a[1].y = NAN;
    assert_int_equal(hk_frechet_measures(a, 3, a + 2, 1, &m, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 1 of the first curve");
    assert_int_equal(hk_frechet_measures(a + 2, 1, a, 3, &m, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 1 of the second curve");
    assert_int_equal(hk_frechet_measures(a, 100000, a, 100000, &m, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "too many");
}

/* ---- Nelder-Mead ---------------------------------------------------------------------- */

typedef struct Probe {
    long calls;
} Probe;

static double rosenbrock2(void *user, const double *x)
{
    ((Probe *)user)->calls++;
    const double a = 1.0 - x[0], b = x[1] - x[0] * x[0];
    return a * a + 100.0 * b * b;
}

static void test_nm_rosenbrock(void **state)
{
    (void)state;
    double x[2] = {-1.2, 1.0};
    const double scale[2] = {0.5, 0.5};
    hk_NelderMeadDef o = hk_default_nelder_mead_def();
    o.x_tolerance = 1e-10;
    o.f_tolerance = 1e-20;
    o.max_evaluations = 5000;
    Probe p = {0};
    hk_MinimizeResult r;
    assert_int_equal(hk_nelder_mead_minimize(2, x, scale, rosenbrock2, &p, &o, &r, NULL), HK_OK);
    assert_true(r.converged);
    assert_int_equal(r.evaluations, p.calls);
    hk_assert_near(x[0], 1.0, 1e-8);
    hk_assert_near(x[1], 1.0, 1e-8);
    assert_true(r.f < 1e-16);
    print_message("  nelder-mead rosenbrock: f = %.3g after %ld evaluations, %d iterations\n", r.f, r.evaluations,
                  r.iterations);
}

static double quadratic4(void *user, const double *x)
{
    (void)user;
    /* A rotated, badly scaled bowl: minimum 3 at (1, -2, 0.5, 4). */
    const double c[4] = {1.0, -2.0, 0.5, 4.0};
    double d[4], f = 3.0;
    for (int i = 0; i < 4; i++) d[i] = x[i] - c[i];
    const double u = d[0] + d[1], v = d[1] - d[2], w = d[2] + 0.5 * d[3], z = d[3] - d[0];
    f += u * u + 10.0 * v * v + 0.1 * w * w + 3.0 * z * z;
    return f;
}

static void test_nm_quadratic_4d(void **state)
{
    (void)state;
    double x[4] = {0, 0, 0, 0};
    const double scale[4] = {1, 1, 1, 1};
    hk_NelderMeadDef o = hk_default_nelder_mead_def();
    o.x_tolerance = 1e-10;
    o.f_tolerance = 1e-20;
    o.max_evaluations = 20000;
    hk_MinimizeResult r;
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, quadratic4, NULL, &o, &r, NULL), HK_OK);
    assert_true(r.converged);
    const double c[4] = {1.0, -2.0, 0.5, 4.0};
    for (int i = 0; i < 4; i++) hk_assert_near(x[i], c[i], 1e-7);
    hk_assert_near(r.f, 3.0, 1e-13);
}

/* Undefined (NaN) left of x0 = 0.5 and infinite below x1 = -1: a bowl centred at the
 * corner of the defined region's edge. */
static double walled(void *user, const double *x)
{
    ((Probe *)user)->calls++;
    if (x[0] < 0.5) return NAN;
    if (x[1] < -1.0) return INFINITY;
    return (x[0] - 0.2) * (x[0] - 0.2) + (x[1] + 1.5) * (x[1] + 1.5);
}

static void test_nm_nan_regions(void **state)
{
    (void)state;
    double x[2] = {2.0, 2.0};
    const double scale[2] = {1.0, 1.0};
    hk_NelderMeadDef o = hk_default_nelder_mead_def();
    o.max_evaluations = 3000;
    Probe p = {0};
    hk_MinimizeResult r;
    assert_int_equal(hk_nelder_mead_minimize(2, x, scale, walled, &p, &o, &r, NULL), HK_OK);
    assert_true(p.calls <= 3000);
    /* The constrained minimum is the corner (0.5, -1). */
    assert_true(isfinite(r.f));
    hk_assert_near(x[0], 0.5, 1e-6);
    hk_assert_near(x[1], -1.0, 1e-6);
    /* Start in the undefined region: NaN everywhere it looks -> an error, x untouched. */
    double y[2] = {-5.0, 0.0};
    const double small[2] = {0.1, 0.1};
    hk_Error err;
    p.calls = 0;
    assert_int_equal(hk_nelder_mead_minimize(2, y, small, walled, &p, &o, &r, &err), HK_ERR_NUMERIC);
    hk_assert_contains(err.message, "NaN or +inf");
    assert_int_equal(p.calls, 3000);
    assert_true(y[0] == -5.0 && y[1] == 0.0);
    /* Start undefined but a simplex vertex defined: it walks out. */
    double z[2] = {0.0, 0.0};
    const double big[2] = {1.0, 1.0};
    assert_int_equal(hk_nelder_mead_minimize(2, z, big, walled, &p, &o, &r, NULL), HK_OK);
    hk_assert_near(z[0], 0.5, 1e-6);
}

static double overflowing(void *user, const double *x)
{
    (void)user;
    return -x[0] * 1e300; /* decreases for ever: expansions overflow x */
}

static double constant(void *user, const double *x)
{
    (void)x;
    ((Probe *)user)->calls++;
    return 7.0;
}

static void test_nm_limits_and_determinism(void **state)
{
    (void)state;
    const double scale[2] = {0.5, 0.5};
    hk_NelderMeadDef o = hk_default_nelder_mead_def();
    o.max_evaluations = 57;
    double x[2] = {-1.2, 1.0};
    Probe p = {0};
    hk_MinimizeResult r;
    assert_int_equal(hk_nelder_mead_minimize(2, x, scale, rosenbrock2, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(p.calls, 57);
    assert_int_equal(r.evaluations, 57);
    assert_false(r.converged);
    double y[2] = {-1.2, 1.0};
    hk_MinimizeResult r2;
    assert_int_equal(hk_nelder_mead_minimize(2, y, scale, rosenbrock2, &p, &o, &r2, NULL), HK_OK);
    assert_memory_equal(x, y, sizeof x);
    assert_true(r.f == r2.f);
    /* Unbounded below: runs into the limit, never crashes on the overflowing points. */
    double u[1] = {0.0};
    const double s1[1] = {1.0};
    o.max_evaluations = 5000;
    assert_int_equal(hk_nelder_mead_minimize(1, u, s1, overflowing, NULL, &o, &r, NULL), HK_OK);
    assert_false(r.converged);
    assert_int_equal(r.evaluations, 5000);
    assert_true(isfinite(u[0]));
    /* No parameters: one evaluation. */
    p.calls = 0;
    assert_int_equal(hk_nelder_mead_minimize(0, u, NULL, constant, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(p.calls, 1);
    assert_true(r.converged);
    hk_assert_near(r.f, 7.0, 0.0);
}

static void test_nm_bad_arguments(void **state)
{
    (void)state;
    double x[17] = {0};
    double scale[17];
    for (int i = 0; i < 17; i++) scale[i] = 1.0;
    hk_NelderMeadDef o = hk_default_nelder_mead_def();
    hk_Error err;
    assert_int_equal(hk_nelder_mead_minimize(17, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    assert_int_equal(hk_nelder_mead_minimize(-1, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, NULL, NULL, &o, NULL, &err), HK_ERR_INVALID);
    assert_int_equal(hk_nelder_mead_minimize(4, x, NULL, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    scale[2] = 0.0;
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "scale[2]");
    scale[2] = 1.0;
    x[1] = NAN;
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    x[1] = 0.0;
    o.max_evaluations = 4;
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
    o = hk_default_nelder_mead_def();
    o.f_tolerance = NAN;
    assert_int_equal(hk_nelder_mead_minimize(4, x, scale, quadratic4, NULL, &o, NULL, &err), HK_ERR_INVALID);
}

/* ---- polylines ------------------------------------------------------------------------- */

static void assert_frame_near(const hk_Mat3 *a, const hk_Mat3 *b, double tol)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) hk_assert_near(a->m[i][j], b->m[i][j], tol);
}

static void test_start_pose(void **state)
{
    (void)state;
    enum { N = 20 };
    hk_Vec3 pts[N];
    hk_CurveStart s, e;
    for (int trial = 0; trial < 20; trial++) {
        const hk_CurveStart truth = random_start();
        helix_trace(uniform(5, 100), uniform(-50, 50), &truth, 0.1, N, pts, &e);
        assert_int_equal(hk_curve_estimate_start(pts, N, &s, NULL), HK_OK);
        assert_frame_near(&s.frame, &truth.frame, 1e-12);
        assert_true(s.pos.x == truth.pos.x && s.pos.y == truth.pos.y && s.pos.z == truth.pos.z);
    }
    /* Straight, with a repeated first point: tangent from the first non-zero segment,
     * a deterministic right-handed frame. */
    const hk_Vec3 dir = hk_v3_normalize(hk_v3(0.3, -0.2, 0.9));
    pts[0] = hk_v3(1, 2, 3);
    for (int i = 1; i < N; i++) pts[i] = hk_v3_madd(hk_v3(1, 2, 3), dir, 0.01 * (i - 1));
    assert_int_equal(hk_curve_estimate_start(pts, N, &s, NULL), HK_OK);
    const hk_Vec3 t = hk_m3_col(&s.frame, 0), n = hk_m3_col(&s.frame, 1), b = hk_m3_col(&s.frame, 2);
    hk_assert_near(hk_v3_dist(t, dir), 0.0, 1e-14);
    hk_assert_near(hk_v3_dot(t, n), 0.0, 1e-15);
    hk_assert_near(hk_v3_norm(n), 1.0, 1e-15);
    hk_assert_near(hk_v3_dist(b, hk_v3_cross(t, n)), 0.0, 1e-15);
    /* Straight first, bending later: the normal comes from the first point off the line. */
    for (int i = 0; i < N; i++) pts[i] = hk_v3(0.01 * i, i < 12 ? 0.0 : 0.001 * (i - 11) * (i - 11), 0.0);
    assert_int_equal(hk_curve_estimate_start(pts, N, &s, NULL), HK_OK);
    hk_assert_near(hk_v3_dist(hk_m3_col(&s.frame, 1), hk_v3(0, 1, 0)), 0.0, 1e-15);
    /* Bad input. */
    hk_Error err;
    assert_int_equal(hk_curve_estimate_start(pts, 1, &s, &err), HK_ERR_INVALID);
    pts[3].z = INFINITY;
    assert_int_equal(hk_curve_estimate_start(pts, N, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 3");
    for (int i = 0; i < N; i++) pts[i] = hk_v3(1, 1, 1);
    assert_int_equal(hk_curve_estimate_start(pts, N, &s, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "the same");
}

static void test_resample(void **state)
{
    (void)state;
    enum { N = 30 };
    hk_Vec3 pts[N], out[2 * N];
    hk_CurveStart e;
    const hk_CurveStart s0 = random_start();
    helix_trace(80.0, 30.0, &s0, 0.12, N, pts, &e);
    double len;
    /* Evenly spaced: comes back to rounding, with its length. */
    assert_int_equal(hk_curve_resample(pts, N, N, out, &len, NULL), HK_OK);
    hk_assert_rel(len, 0.12, 1e-14, 0);
    for (int i = 0; i < N; i++) hk_assert_near(hk_v3_dist(out[i], pts[i]), 0.0, 1e-15);
    /* Uneven: a line with bunched vertices becomes evenly spaced, ends kept exactly. */
    for (int i = 0; i < N; i++) {
        const double u = (double)i / (N - 1);
        pts[i] = hk_v3(u * u * u, 0.0, 0.0);
    }
    pts[5] = pts[4]; /* a zero-length segment on the way */
    /* Straight, by estimated arc length: the same (no vertex turns). */
    hk_Vec3 straight[2 * N];
    assert_int_equal(hk_curve_resample_arc(pts, N, 2 * N, straight, &len, NULL), HK_OK);
    hk_assert_rel(len, 1.0, 1e-15, 0);
    for (int i = 0; i < 2 * N; i++) hk_assert_near(straight[i].x, (double)i / (2 * N - 1), 1e-15);
    assert_int_equal(hk_curve_resample(pts, N, 2 * N, out, &len, NULL), HK_OK);
    hk_assert_rel(len, 1.0, 1e-15, 0);
    for (int i = 0; i < 2 * N; i++) hk_assert_near(out[i].x, (double)i / (2 * N - 1), 1e-15);
    assert_true(out[2 * N - 1].x == 1.0 && out[0].x == 0.0);
    hk_Error err;
    assert_int_equal(hk_curve_resample_arc(pts, 1, 5, out, &len, &err), HK_ERR_INVALID);
    assert_int_equal(hk_curve_resample(pts, 1, 5, out, &len, &err), HK_ERR_INVALID);
    assert_int_equal(hk_curve_resample(pts, N, 1, out, &len, &err), HK_ERR_INVALID);
    for (int i = 0; i < N; i++) pts[i] = hk_v3(2, 2, 2);
    assert_int_equal(hk_curve_resample(pts, N, N, out, &len, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "zero length");
}

/* Points at arc spacing s on a circle of radius R (an RK4 or closed-form trace): the
 * estimated arc length is the circle's exactly (the reference: R times the angle), where
 * the polyline is shorter by the chords' deficit 2 R sin(s / 2R) < s; resampled to their
 * own count they come back, and halfway samples sit on the chords' midpoints. */
static void test_resample_arc(void **state)
{
    (void)state;
    enum { N = 25 };
    const double radius = 0.03, angle = 2.5, s = radius * angle / (N - 1);
    hk_Vec3 pts[N], out[2 * N - 1], by_chord[N];
    for (int i = 0; i < N; i++) {
        const double a = angle * i / (N - 1);
        pts[i] = hk_v3(radius * cos(a), radius * sin(a), 0.01);
    }
    double arc, chord;
    assert_int_equal(hk_curve_resample_arc(pts, N, N, out, &arc, NULL), HK_OK);
    assert_int_equal(hk_curve_resample(pts, N, N, by_chord, &chord, NULL), HK_OK);
    hk_assert_rel(arc, radius * angle, 1e-13, 0);
    hk_assert_rel(chord, (N - 1) * 2.0 * radius * sin(s / (2.0 * radius)), 1e-13, 0);
    assert_true(arc - chord > 1e-6); /* the deficit the arc estimate removes: 1.6e-5 m here */
    assert_int_equal(hk_curve_resample_arc(pts, N, N, out, &arc, NULL), HK_OK);
    for (int i = 0; i < N; i++) hk_assert_near(hk_v3_dist(out[i], pts[i]), 0.0, 1e-15);
    assert_int_equal(hk_curve_resample_arc(pts, N, 2 * N - 1, out, &arc, NULL), HK_OK);
    for (int i = 0; i + 1 < N; i++)
        hk_assert_near(hk_v3_dist(out[2 * i + 1], hk_v3_scale(hk_v3_add(pts[i], pts[i + 1]), 0.5)), 0.0, 1e-15);
}

/* ---- fits -------------------------------------------------------------------------------- */

/* The minimiser the fit tests below run with: least squares (the default) and again with
 * the paper's Nelder-Mead (the *_nelder_mead entries of main). */
static int fit_method = HK_CURVEFIT_LEAST_SQUARES;

static hk_CurveFitDef fit_options(void)
{
    hk_CurveFitDef o = hk_default_curve_fit_def();
    o.method = fit_method;
    return o;
}

static hk_CurveFitDef exact_options(void)
{
    hk_CurveFitDef o = fit_options();
    o.lambda = 0.0;
    o.tolerance = 1e-7;
    o.param_tolerance = 1e-9;
    o.cost_tolerance = 1e-13;
    o.max_evaluations = 2000;
    o.restarts = 2;
    return o;
}

static void test_fit_single_arc(void **state)
{
    (void)state;
    enum { N = 30 };
    hk_Vec3 target[N];
    hk_CurveStart e;
    for (int trial = 0; trial < 10; trial++) {
        const hk_CurveStart s0 = random_start();
        const double kappa = uniform(5.0, 150.0), length = uniform(0.03, 0.15);
        helix_trace(kappa, 0.0, &s0, length, N, target, &e);
        hk_CurveFitDef o = exact_options();
        o.max_pieces = 1;
        const double seed[1] = {10.0}, scale[1] = {20.0};
        hk_CurveFit fit;
        hk_Error err;
        assert_int_equal(hk_curve_fit_piecewise(target, N, arc_model, NULL, 1, seed, scale, &o, &fit, &err), HK_OK);
        assert_int_equal(fit.piece_count, 1);
        hk_assert_rel(fit.params[0][0], kappa, 1e-6, 0);
        assert_true(fit.error < 1e-9);
        assert_true(fit.frechet < 1e-8);
        hk_assert_rel(fit.length[0], length, 1e-13, 0);
    }
}

static void test_fit_single_helix(void **state)
{
    (void)state;
    enum { N = 30 };
    hk_Vec3 target[N], traced[N];
    hk_CurveStart e;
    for (int trial = 0; trial < 10; trial++) {
        const hk_CurveStart s0 = random_start();
        const double k[2] = {uniform(20.0, 150.0), uniform(-60.0, 60.0)};
        const double length = 0.1;
        helix_trace(k[0], k[1], &s0, length, N, target, &e);
        hk_CurveFitDef o = exact_options();
        const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
        hk_CurveFit fit;
        hk_Error err;
        assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
        assert_int_equal(fit.piece_count, 1);
        hk_assert_rel(fit.params[0][0], k[0], 1e-4, 0);
        hk_assert_near(fit.params[0][1], k[1], 1e-4 * k[0]);
        assert_true(fit.error < 1e-7);
        /* The fit re-traces to the same curve and error. */
        assert_int_equal(hk_curve_fit_trace(&fit, helix_model, NULL, traced, &err), HK_OK);
        hk_FrechetMeasures m;
        assert_int_equal(hk_frechet_measures(target, N, traced, N, &m, NULL), HK_OK);
        hk_assert_rel(m.normalized, fit.error, 1e-6, 1e-9);
    }
}

static void test_fit_straight(void **state)
{
    (void)state;
    enum { N = 12 };
    hk_Vec3 target[N];
    const hk_Vec3 dir = hk_v3_normalize(hk_v3(1, 2, -1));
    for (int i = 0; i < N; i++) target[i] = hk_v3_scale(dir, 0.01 * i);
    hk_CurveFit fit;
    hk_Error err;
    /* No parameters: a single trace. */
    assert_int_equal(hk_curve_fit_piecewise(target, N, line_model, NULL, 0, NULL, NULL, NULL, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    assert_true(fit.error < 1e-15);
    /* The helix with lambda > 0: the regularisation takes both parameters to 0, even the
     * torsion that does not change a straight line's points. */
    hk_CurveFitDef o = fit_options();
    o.lambda = 1e-6;
    const double seed[2] = {40.0, 25.0}, scale[2] = {10.0, 10.0};
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    hk_assert_near(fit.params[0][0], 0.0, 1e-3);
    hk_assert_near(fit.params[0][1], 0.0, 1e-3);
    assert_true(fit.error < 1e-8);
}

static void test_fit_two_pieces(void **state)
{
    (void)state;
    enum { N = 31 };
    hk_Vec3 target[N];
    double worst_join = 0.0;
    for (int trial = 0; trial < 6; trial++) {
        const hk_CurveStart s0 = random_start();
        const double k[2][2] = {{uniform(30, 80), uniform(-30, 30)}, {uniform(100, 160), uniform(-60, 60)}};
        const int segments[2] = {trial % 2 ? 12 : 17, trial % 2 ? 18 : 13};
        const double h = 0.004;
        make_helix_target(&s0, 2, k, segments, h, target);
        hk_CurveFitDef o = exact_options();
        o.tolerance = 1e-6;
        o.min_fragment_length = 0.01;
        const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
        hk_CurveFit fit;
        hk_Error err;
        assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
        if (fit.piece_count != 2)
            for (int p = 0; p < fit.piece_count; p++)
                print_message("trial %d piece %d: first sample %d, k = (%g, %g), error %g\n", trial, p,
                              fit.first_sample[p], fit.params[p][0], fit.params[p][1], fit.piece_error[p]);
        assert_int_equal(fit.piece_count, 2);
        const int join = fit.first_sample[1];
        worst_join = fmax(worst_join, fabs((double)(join - segments[0])));
        assert_true(abs(join - segments[0]) <= 1);
        assert_true(fit.error < 1e-5);
        if (join == segments[0]) {
            for (int p = 0; p < 2; p++) {
                hk_assert_rel(fit.params[p][0], k[p][0], 1e-4, 0);
                hk_assert_near(fit.params[p][1], k[p][1], 1e-4 * k[p][0]);
            }
            assert_true(fit.error < 1e-8);
        }
        hk_assert_rel(fit.length[0] + fit.length[1], h * (N - 1), 1e-12, 0);
    }
    print_message("  two-piece targets: join found within %g samples\n", worst_join);
}

/* A fixed layout: P equal pieces whatever the target, fitted in turn and chained. On a
 * two-piece target joined at its middle, two fixed pieces are the generating ones (the
 * reference: their parameters); three pieces follow it better than one; a target too
 * short for P pieces gets as many as it holds; a negative count is refused. */
static void test_fit_fixed_pieces(void **state)
{
    (void)state;
    enum { N = 31 };
    hk_Vec3 target[N];
    const hk_CurveStart s0 = random_start();
    const double k[2][2] = {{45.0, 12.0}, {120.0, -30.0}};
    const int segments[2] = {15, 15};
    make_helix_target(&s0, 2, k, segments, 0.004, target);
    hk_CurveFitDef o = exact_options();
    o.fixed_pieces = 2;
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    hk_CurveFit fit;
    hk_Error err;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 2);
    assert_int_equal(fit.first_sample[1], 15);
    for (int p = 0; p < 2; p++) {
        hk_assert_rel(fit.params[p][0], k[p][0], 1e-6, 0);
        hk_assert_near(fit.params[p][1], k[p][1], 1e-6 * k[p][0]);
    }
    assert_true(fit.error < 1e-9);
    o.fixed_pieces = 3;
    o.tolerance = 1e-4;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 3);
    assert_int_equal(fit.first_sample[1], 10);
    assert_int_equal(fit.first_sample[2], 20);
    /* the middle piece straddles the join, which no helix follows: closer than one piece */
    hk_CurveFit one;
    o.fixed_pieces = 1;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &one, &err), HK_OK);
    assert_true(fit.error < 0.6 * one.error);
    o.fixed_pieces = 10; /* 10 pieces of 3 segments (4 samples, at least 5 mm): just fit in 30 segments */
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 10);
    o.fixed_pieces = 11; /* more than the samples hold: as many as they do */
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 10);
    o.fixed_pieces = 3; /* a target of 5 samples holds one piece of 4 */
    assert_int_equal(hk_curve_fit_piecewise(target, 5, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    o.fixed_pieces = -1;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "fixed_pieces");
    /* By length from the root (4 mm samples, pieces of at least 3 segments): a root piece
     * of 8 mm widened to 3 segments, then 20 mm (5 segments) from 8 mm on: starts at 0, 3
     * (the root piece), 7, 12, 17, 22, 27; the rest (3 segments) is the last piece's. */
    o.fixed_pieces = 0;
    o.piece_length = 0.02;
    o.root_piece_length = 0.008;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    const int starts[7] = {0, 3, 7, 12, 17, 22, 27};
    assert_int_equal(fit.piece_count, 7);
    for (int p = 0; p < 7; p++) assert_int_equal(fit.first_sample[p], starts[p]);
    o.piece_length = 1.0, o.root_piece_length = 0.0; /* longer than the target: one piece */
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    o.fixed_pieces = 2; /* two layouts at once */
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "two layouts");
    o.fixed_pieces = 0, o.piece_length = -0.01;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "piece_length");
}

/* Adds Gaussian noise of deviation sigma to every point but the root (which a capture
 * pins down). */
static void add_noise(hk_Vec3 *pts, int n, double sigma)
{
    for (int i = 1; i < n; i++)
        pts[i] = hk_v3_add(pts[i], hk_v3(sigma * gaussian(), sigma * gaussian(), sigma * gaussian()));
}

static void test_fit_noise(void **state)
{
    (void)state;
    enum { N = 30, TRIALS = 8 };
    hk_Vec3 target[N];
    hk_CurveStart e;
    const double sigma = 1e-4;
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    double mean_given = 0.0, mean_estimated = 0.0, mean_fixed = 0.0;
    for (int trial = 0; trial < TRIALS; trial++) {
        const hk_CurveStart s0 = random_start();
        const double k[2] = {uniform(20.0, 60.0), uniform(-20.0, 20.0)};
        helix_trace(k[0], k[1], &s0, 0.1, N, target, &e);
        add_noise(target, N, sigma);
        hk_CurveFitDef o = fit_options();
        o.lambda = 0.0;
        o.tolerance = 3e-4;
        hk_CurveFit fit;
        hk_Error err;
        /* Near the noise level: the mean distance of a 3D Gaussian is 1.6 sigma, and the
         * coupling can only do better than pairing point i with point i. */
        for (int mode = 0; mode < 3; mode++) {
            o.use_start = mode == 0; /* 0: the true root pose */
            o.start = s0;
            o.refine_start = mode != 2; /* 1: estimated and refined; 2: estimated only */
            assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                             HK_OK);
            if (mode == 2) {
                mean_fixed += fit.error / TRIALS;
                continue;
            }
            assert_int_equal(fit.piece_count, 1);
            assert_true(fit.error <= o.tolerance);
            assert_true(fit.frechet < 10.0 * sigma);
            hk_assert_rel(fit.params[0][0], k[0], 0.05, 0);
            hk_assert_near(fit.params[0][1], k[1], 0.1 * k[0]);
            if (mode == 0)
                mean_given += fit.error / TRIALS;
            else
                mean_estimated += fit.error / TRIALS;
        }
    }
    /* The frame from the first noisy points alone is poor (the first bend, h^2 kappa
     * ~ 0.5 mm, is comparable to the noise): refining it is what makes the fits good. */
    assert_true(mean_given < 1.6 * sigma);
    assert_true(mean_estimated < 2.0 * sigma);
    assert_true(mean_fixed > 2.0 * mean_estimated);
    print_message("  noisy targets (sigma 0.1 mm), mean normalised coupling: %.3f mm from the true root frame, "
                  "%.3f mm estimated and refined, %.3f mm estimated only\n",
                  1e3 * mean_given, 1e3 * mean_estimated, 1e3 * mean_fixed);
}

static void test_fit_bad_input(void **state)
{
    (void)state;
    enum { N = 20 };
    hk_Vec3 target[N];
    hk_CurveStart e;
    const hk_CurveStart s0 = random_start();
    helix_trace(50.0, 10.0, &s0, 0.08, N, target, &e);
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    hk_CurveFit fit;
    hk_Error err;
#define EXPECT(code, text, ...)                                                                                        \
    do {                                                                                                               \
        hk_error_clear(&err);                                                                                          \
        assert_int_equal(hk_curve_fit_piecewise(__VA_ARGS__, &fit, &err), code);                                       \
        hk_assert_contains(err.message, text);                                                                         \
        assert_int_equal(fit.piece_count, 0);                                                                          \
    } while (0)
    EXPECT(HK_ERR_INVALID, "at least 2", target, 1, helix_model, NULL, 2, seed, scale, NULL);
    EXPECT(HK_ERR_INVALID, "at least 2", target, 0, helix_model, NULL, 2, seed, scale, NULL);
    EXPECT(HK_ERR_INVALID, "NULL", target, N, NULL, NULL, 2, seed, scale, NULL);
    EXPECT(HK_ERR_INVALID, "NULL", target, N, helix_model, NULL, 2, NULL, scale, NULL);
    EXPECT(HK_ERR_INVALID, "parameters", target, N, helix_model, NULL, 9, seed, scale, NULL);
    const double bad_seed[2] = {NAN, 0.0}, bad_scale[2] = {1.0, 0.0};
    EXPECT(HK_ERR_INVALID, "seed[0]", target, N, helix_model, NULL, 2, bad_seed, scale, NULL);
    EXPECT(HK_ERR_INVALID, "scale[1]", target, N, helix_model, NULL, 2, seed, bad_scale, NULL);
    hk_CurveFitDef o = hk_default_curve_fit_def();
    o.max_pieces = 0;
    EXPECT(HK_ERR_INVALID, "max_pieces", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.max_pieces = HK_CURVEFIT_MAX_PIECES + 1;
    EXPECT(HK_ERR_INVALID, "max_pieces", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.split_threshold = 0.0;
    EXPECT(HK_ERR_INVALID, "split_threshold", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.split_threshold = 1.5;
    EXPECT(HK_ERR_INVALID, "split_threshold", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.lambda = NAN;
    EXPECT(HK_ERR_INVALID, "lambda", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.tolerance = -1.0;
    EXPECT(HK_ERR_INVALID, "tolerance", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.max_evaluations = 2;
    EXPECT(HK_ERR_INVALID, "max_evaluations", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.samples = HK_CURVEFIT_MAX_SAMPLES + 1;
    EXPECT(HK_ERR_INVALID, "samples", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.use_start = 1, o.start.frame.m[0][0] = 2.0;
    EXPECT(HK_ERR_INVALID, "start pose", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.method = 7;
    EXPECT(HK_ERR_INVALID, "method", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.penalty_weight[1] = -1.0;
    EXPECT(HK_ERR_INVALID, "penalty_weight[1]", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.arc_length = 2;
    EXPECT(HK_ERR_INVALID, "arc_length", target, N, helix_model, NULL, 2, seed, scale, &o);
    o = hk_default_curve_fit_def(), o.known_to_split = 2;
    EXPECT(HK_ERR_INVALID, "known_to_split", target, N, helix_model, NULL, 2, seed, scale, &o);
    /* Bad points. */
    hk_Vec3 bad[N];
    memcpy(bad, target, sizeof bad);
    bad[7].x = NAN;
    EXPECT(HK_ERR_INVALID, "point 7", bad, N, helix_model, NULL, 2, seed, scale, NULL);
    for (int i = 0; i < N; i++) bad[i] = hk_v3(1, 2, 3);
    EXPECT(HK_ERR_INVALID, "zero length", bad, N, helix_model, NULL, 2, seed, scale, NULL);
    /* A model that always fails. */
    EXPECT(HK_ERR_NUMERIC, "model failed", target, N, failing_model, NULL, 2, seed, scale, NULL);
    EXPECT(HK_ERR_NUMERIC, "model failed", target, N, failing_model, NULL, 0, NULL, NULL, NULL);
#undef EXPECT
    /* A model undefined in parts of its space still fits where it is defined. */
    const double seed_ok[2] = {30.0, 5.0};
    o = exact_options();
    assert_int_equal(hk_curve_fit_piecewise(target, N, patchy_model, NULL, 2, seed_ok, scale, &o, &fit, &err), HK_OK);
    hk_assert_rel(fit.params[0][0], 50.0, 1e-4, 0);
    hk_assert_near(fit.params[0][1], 10.0, 5e-3);
    /* The smallest targets fit (too short to split). */
    assert_int_equal(hk_curve_fit_piecewise(target, 2, helix_model, NULL, 2, seed, scale, NULL, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    assert_true(fit.error < 1e-12);
    assert_int_equal(hk_curve_fit_piecewise(target, 3, helix_model, NULL, 2, seed, scale, NULL, &fit, &err), HK_OK);
    assert_int_equal(fit.piece_count, 1);
    assert_true(fit.error < 1e-6);
    /* The workspace refuses targets larger than itself. */
    hk_CurveFitWorkspace *ws = hk_curve_fit_workspace_create(10, &err);
    assert_non_null(ws);
    assert_int_equal(hk_curve_fit_piecewise_ws(ws, target, N, helix_model, NULL, 2, seed, scale, NULL, &fit, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "workspace");
    hk_curve_fit_workspace_destroy(ws);
    assert_null(hk_curve_fit_workspace_create(1, &err));
    assert_null(hk_curve_fit_workspace_create(HK_CURVEFIT_MAX_SAMPLES + 1, &err));
    /* A malformed fit does not trace. */
    hk_Vec3 out[N];
    memset(&fit, 0, sizeof fit);
    assert_int_equal(hk_curve_fit_trace(&fit, helix_model, NULL, out, &err), HK_ERR_INVALID);
}

/* Hostile but finite targets (random zig-zags, huge and tiny coordinates, repeated
 * points) with small budgets: an error or a fit, never a crash or a hang. */
static void test_fit_hostile_targets(void **state)
{
    (void)state;
    enum { N = 24 };
    hk_Vec3 target[N];
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    const double magnitudes[5] = {1e-300, 1e-6, 1.0, 1e150, 1e300};
    hk_CurveFitDef o = hk_default_curve_fit_def();
    o.max_evaluations = 60;
    o.max_pieces = 8;
    o.min_fragment_length = 0.0;
    for (int trial = 0; trial < 40; trial++) {
        const double mag = magnitudes[trial % 5];
        const int n = 2 + (int)((N - 1) * hk_test_uniform());
        for (int i = 0; i < n; i++) {
            target[i] = hk_v3(mag * uniform(-1, 1), mag * uniform(-1, 1), mag * uniform(-1, 1));
            if (i > 0 && hk_test_uniform() < 0.2) target[i] = target[i - 1];
        }
        hk_CurveFit fit;
        hk_Error err;
        const hk_Status st = hk_curve_fit_piecewise(target, n, helix_model, NULL, 2, seed, scale, &o, &fit, &err);
        assert_true(st == HK_OK || st == HK_ERR_INVALID || st == HK_ERR_NUMERIC);
        if (st == HK_OK) {
            assert_true(fit.piece_count >= 1 && fit.piece_count <= o.max_pieces);
            assert_false(isnan(fit.error));
        } else {
            assert_int_equal(fit.piece_count, 0);
            assert_true(err.message[0] != '\0');
        }
    }
}

static void test_fit_evaluations_and_determinism(void **state)
{
    (void)state;
    enum { N = 31 };
    hk_Vec3 target[N];
    const hk_CurveStart s0 = random_start();
    const double k[2][2] = {{50, 10}, {130, -40}};
    const int segments[2] = {15, 15};
    make_helix_target(&s0, 2, k, segments, 0.004, target);
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    hk_CurveFitDef o = hk_default_curve_fit_def();
    o.tolerance = 1e-6;
    Counter c = {0};
    hk_CurveFit a, b;
    assert_int_equal(hk_curve_fit_piecewise(target, N, counting_model, &c, 2, seed, scale, &o, &a, NULL), HK_OK);
    assert_int_equal(a.evaluations, c.calls);
    assert_int_equal(hk_curve_fit_piecewise(target, N, counting_model, &c, 2, seed, scale, &o, &b, NULL), HK_OK);
    assert_memory_equal(&a, &b, sizeof a);
    /* One piece at most: the single fit of eq. (5). */
    o.max_pieces = 1;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &b, NULL), HK_OK);
    assert_int_equal(b.piece_count, 1);
    assert_true(b.error > a.error);
}

/* A finely traced strand fitted at a quarter of its points. The resampled points are
 * every 4th vertex, but the model steps the fine polyline's length per sample, while
 * the chord over 4 bent fine segments is shorter by about (kappa h)^2 / 24 = 0.17%: a
 * small, known mismatch (the price of resampling a polyline, not of the fit). */
static void test_fit_resampled(void **state)
{
    (void)state;
    enum { N = 121 };
    hk_Vec3 target[N];
    hk_CurveStart e;
    const hk_CurveStart s0 = random_start();
    helix_trace(60.0, 25.0, &s0, 0.1, N, target, &e);
    hk_CurveFitDef o = exact_options();
    o.samples = 31;
    o.max_pieces = 1;
    const double seed[2] = {30.0, 0.0}, scale[2] = {20.0, 20.0};
    hk_CurveFit fit;
    hk_Error err;
    assert_int_equal(hk_curve_fit_piecewise(target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err), HK_OK);
    assert_int_equal(fit.sample_count, 31);
    hk_assert_rel(fit.sample_spacing * 30, 0.1, 1e-12, 0);
    assert_true(fit.error < 5e-5);
    hk_assert_rel(fit.params[0][0], 60.0, 2e-2, 0);
    hk_assert_rel(fit.params[0][1], 25.0, 2e-2, 0);
    /* hk_curve_fit_piecewise_ws refuses more samples than its workspace holds. */
    hk_CurveFitWorkspace *ws = hk_curve_fit_workspace_create(31, &err);
    assert_non_null(ws);
    assert_int_equal(hk_curve_fit_piecewise_ws(ws, target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                     HK_OK);
    o.samples = 0;
    assert_int_equal(hk_curve_fit_piecewise_ws(ws, target, N, helix_model, NULL, 2, seed, scale, &o, &fit, &err),
                     HK_ERR_INVALID);
    hk_curve_fit_workspace_destroy(ws);
}

/* The fit tests again with the paper's minimiser. */
#define WITH_NELDER_MEAD(name)                                                                                         \
    static void name##_nelder_mead(void **state)                                                                       \
    {                                                                                                                  \
        fit_method = HK_CURVEFIT_NELDER_MEAD;                                                                          \
        name(state);                                                                                                   \
        fit_method = HK_CURVEFIT_LEAST_SQUARES;                                                                        \
    }
WITH_NELDER_MEAD(test_fit_single_arc)
WITH_NELDER_MEAD(test_fit_single_helix)
WITH_NELDER_MEAD(test_fit_straight)
WITH_NELDER_MEAD(test_fit_two_pieces)
WITH_NELDER_MEAD(test_fit_noise)
WITH_NELDER_MEAD(test_fit_fixed_pieces)

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frechet_brute_force),
        cmocka_unit_test(test_frechet_symmetry),
        cmocka_unit_test(test_frechet_identical_and_shifted),
        cmocka_unit_test(test_frechet_bad_input),
        cmocka_unit_test(test_nm_rosenbrock),
        cmocka_unit_test(test_nm_quadratic_4d),
        cmocka_unit_test(test_nm_nan_regions),
        cmocka_unit_test(test_nm_limits_and_determinism),
        cmocka_unit_test(test_nm_bad_arguments),
        cmocka_unit_test(test_start_pose),
        cmocka_unit_test(test_resample),
        cmocka_unit_test(test_resample_arc),
        cmocka_unit_test(test_fit_single_arc),
        cmocka_unit_test(test_fit_single_helix),
        cmocka_unit_test(test_fit_straight),
        cmocka_unit_test(test_fit_two_pieces),
        cmocka_unit_test(test_fit_noise),
        cmocka_unit_test(test_fit_bad_input),
        cmocka_unit_test(test_fit_hostile_targets),
        cmocka_unit_test(test_fit_evaluations_and_determinism),
        cmocka_unit_test(test_fit_resampled),
        cmocka_unit_test(test_fit_single_arc_nelder_mead),
        cmocka_unit_test(test_fit_single_helix_nelder_mead),
        cmocka_unit_test(test_fit_straight_nelder_mead),
        cmocka_unit_test(test_fit_two_pieces_nelder_mead),
        cmocka_unit_test(test_fit_noise_nelder_mead),
        cmocka_unit_test(test_fit_fixed_pieces),
        cmocka_unit_test(test_fit_fixed_pieces_nelder_mead),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
