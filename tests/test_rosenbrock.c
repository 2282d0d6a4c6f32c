/* The thesis's Rosenbrock + Palmer minimiser (src/optimize/rosenbrock.c): Palmer's
 * directions against an independent Gram-Schmidt and in the degenerate cases Palmer
 * was made for, exact trial sequences, minima of test functions, the benefit of the
 * rotation, stopping rules and limits, NaN and other hostile objectives, errors. */
#include "hk_test.h"

#include <float.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hairkit/statics.h"
#include "optimize/optimize_internal.h"

#define NMAX 10

/* ---- helpers -------------------------------------------------------------------- */

static double dot(int n, const double *a, const double *b)
{
    double s = 0.0;
    for (int j = 0; j < n; j++) s += a[j] * b[j];
    return s;
}

/* Random orthonormal basis (modified Gram-Schmidt of random vectors, twice for full
 * accuracy), rows = directions. */
static void random_basis(int n, double *xi)
{
    for (int i = 0; i < n; i++) {
        double *v = xi + i * n;
        for (int j = 0; j < n; j++) v[j] = 2.0 * hk_test_uniform() - 1.0;
        for (int pass = 0; pass < 2; pass++)
            for (int k = 0; k < i; k++) {
                const double p = dot(n, v, xi + k * n);
                for (int j = 0; j < n; j++) v[j] -= p * xi[k * n + j];
            }
        const double s = sqrt(dot(n, v, v));
        for (int j = 0; j < n; j++) v[j] /= s;
    }
}

static void assert_orthonormal(int n, const double *xi)
{
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) hk_assert_near(dot(n, xi + a * n, xi + b * n), a == b ? 1.0 : 0.0, 1e-12);
}

/* A_k / max|d| (0-based k): the advance from direction k on, scaled so that tiny or
 * huge advances neither underflow nor overflow. Returns 0 when A_k = 0. */
static int scaled_advance(int n, const double *xi, const double *d, int k, double *a)
{
    double c = 0.0;
    for (int i = k; i < n; i++) c = fmax(c, fabs(d[i]));
    memset(a, 0, (size_t)n * sizeof(double));
    if (c == 0.0) return 0;
    for (int i = k; i < n; i++)
        for (int j = 0; j < n; j++) a[j] += (d[i] / c) * xi[i * n + j];
    return 1;
}

/* Rosenbrock's 1960 procedure as the thesis writes it: classical Gram-Schmidt of
 * A_k = sum_{i>=k} d_i xi_i. Defined only when every d is non-zero. */
static void gram_schmidt_reference(int n, const double *xi, const double *d, double *out)
{
    for (int k = 0; k < n; k++) {
        double a[NMAX], b[NMAX];
        scaled_advance(n, xi, d, k, a);
        memcpy(b, a, sizeof a);
        for (int m = 0; m < k; m++) {
            const double p = dot(n, a, out + m * n);
            for (int j = 0; j < n; j++) b[j] -= p * out[m * n + j];
        }
        const double s = sqrt(dot(n, b, b));
        for (int j = 0; j < n; j++) out[k * n + j] = b[j] / s;
    }
}

/* The properties that define Rosenbrock's new directions, checked without computing
 * them: orthonormal; xi'_1 = A_1 / |A_1| (when A_1 != 0); and A_k lies in the span of
 * xi'_1..xi'_k, i.e. A_k . xi'_m = 0 for m > k (the Gram-Schmidt triangle). */
static void assert_rosenbrock_directions(int n, const double *xi, const double *d, const double *out)
{
    assert_orthonormal(n, out);
    double a[NMAX];
    if (scaled_advance(n, xi, d, 0, a)) {
        const double s = sqrt(dot(n, a, a));
        for (int j = 0; j < n; j++) hk_assert_near(out[j], a[j] / s, 1e-12);
    }
    for (int k = 0; k < n; k++) {
        if (!scaled_advance(n, xi, d, k, a)) continue;
        const double s = sqrt(dot(n, a, a));
        for (int m = k + 1; m < n; m++) hk_assert_near(dot(n, a, out + m * n) / s, 0.0, 1e-12);
    }
}

/* Objective wrapper: counts the calls, records the first points (their first NMAX
 * coordinates), and fails the test instead of hanging if the minimiser keeps calling. */
#define RECORD_MAX 64
typedef struct Probe {
    int n;
    double (*fn)(const double *x, int n);
    long calls;
    long call_limit;
    double rec[RECORD_MAX][NMAX];
} Probe;

static void probe_init(Probe *p, int n, double (*fn)(const double *, int), long call_limit)
{
    memset(p, 0, sizeof *p);
    p->n = n;
    p->fn = fn;
    p->call_limit = call_limit;
}

static double probe_eval(void *user, const double *x)
{
    Probe *p = user;
    if (p->calls >= p->call_limit) fail_msg("objective called more than %ld times", p->call_limit);
    const double f = p->fn(x, p->n);
    if (p->calls < RECORD_MAX) memcpy(p->rec[p->calls], x, (size_t)(p->n < NMAX ? p->n : NMAX) * sizeof(double));
    p->calls++;
    return f;
}

/* A minimiser that loops without calling f cannot be stopped by the probe: a watchdog
 * turns such a hang into a prompt failure with a message. */
static void watchdog(int sig)
{
    (void)sig;
    static const char msg[] = "test_rosenbrock: the minimiser still runs after 60 s: it hangs\n";
    const ssize_t w = write(STDERR_FILENO, msg, sizeof msg - 1);
    (void)w;
    _exit(1);
}

static void arm_watchdog(void)
{
    signal(SIGALRM, watchdog);
    alarm(60);
}

/* Teardown of the tests that arm it, so that a failed assertion leaves it disarmed. */
static int disarm_watchdog(void **state)
{
    (void)state;
    alarm(0);
    return 0;
}

/* ---- objectives ------------------------------------------------------------------- */

static double banana(const double *x, int n)
{
    (void)n;
    return (1 - x[0]) * (1 - x[0]) + 100 * (x[1] - x[0] * x[0]) * (x[1] - x[0] * x[0]);
}

static double parabola_1d(const double *x, int n)
{
    (void)n;
    return (x[0] - 1.0) * (x[0] - 1.0);
}

/* Flat (f = 0) for |x| <= 1: every small trial ties. */
static double flat_bottom(const double *x, int n)
{
    (void)n;
    return fmax(fabs(x[0]) - 1.0, 0.0);
}

/* 1 + sum (i+1) (x_i - 0.3 i)^2 + 5 (x0 + x1 + x2 - 0.9)^2 + (x0 - x2 + 0.6)^4 / 2 in
 * three dimensions: coupled, not quadratic, minimum 1 at (0, 0.3, 0.6) (f* != 0 so that
 * epsilon, which is relative to |f|, means something). */
static double bowl(const double *x, int n)
{
    double f = 1.0;
    for (int i = 0; i < n; i++) f += (i + 1) * (x[i] - 0.3 * i) * (x[i] - 0.3 * i);
    const double s = x[0] + x[1] + x[2] - 0.9, t = x[0] - x[2] + 0.6;
    return f + 5.0 * s * s + 0.5 * t * t * t * t;
}

static double nan_objective(const double *x, int n)
{
    (void)x, (void)n;
    return NAN;
}

/* Quadratic (x0-3)^2 + x1^2, but NaN for x0 >= 2: the search must stay where f exists. */
static double nan_beyond_two(const double *x, int n)
{
    (void)n;
    return x[0] >= 2.0 ? NAN : (x[0] - 3.0) * (x[0] - 3.0) + x[1] * x[1];
}

/* |x0| + |x1|: at the origin no trial with a non-zero step ever succeeds. */
static double kink(const double *x, int n)
{
    (void)n;
    return fabs(x[0]) + fabs(x[1]);
}

/* Unbounded below along x0; x1 does not matter at all. */
static double downhill(const double *x, int n)
{
    (void)n;
    return -x[0];
}

static double infinite_objective(const double *x, int n)
{
    (void)x, (void)n;
    return INFINITY;
}

/* ---- Palmer's directions ---------------------------------------------------------- */

static void test_defaults(void **state)
{
    (void)state;
    const hk_RosenbrockDef o = hk_default_rosenbrock_def();
    assert_int_equal(o.max_stages, 20);
    hk_assert_near(o.epsilon, 1e-4, 0.0);
    hk_assert_near(o.initial_step, 0.1, 0.0);
    hk_assert_near(o.alpha, 3.0, 0.0);
    hk_assert_near(o.beta, 0.5, 0.0);
    assert_true(o.max_evaluations == 10000000L);
}

/* With every d non-zero, Palmer's formula is an algebraic rewrite of Rosenbrock's
 * Gram-Schmidt: same vectors. The header promises them up to sign; this implementation
 * keeps Palmer's sign (sqrt(d_{k-1}^2) = |d_{k-1}|), which is exactly Gram-Schmidt's. */
static void test_palmer_equals_gram_schmidt(void **state)
{
    (void)state;
    for (int t = 0; t < 200; t++) {
        const int n = 1 + t % NMAX;
        double xi[NMAX * NMAX], d[NMAX], palmer[NMAX * NMAX], gs[NMAX * NMAX];
        random_basis(n, xi);
        for (int i = 0; i < n; i++) {
            const double mag = 0.2 + 2.0 * hk_test_uniform();
            d[i] = hk_test_uniform() < 0.5 ? -mag : mag;
        }
        if (t % 7 == 3) d[n - 1] *= 1e-6; /* small trailing advance */
        hk_rosenbrock_palmer_directions(n, xi, d, palmer);
        gram_schmidt_reference(n, xi, d, gs);
        assert_orthonormal(n, palmer);
        for (int k = 0; k < n; k++) {
            const double c = dot(n, palmer + k * n, gs + k * n);
            hk_assert_near(fabs(c), 1.0, 1e-10); /* same line */
            hk_assert_near(c, 1.0, 1e-10);       /* and the same sign */
        }
    }
}

/* The degenerate advances where Gram-Schmidt divides 0 by 0: Palmer's directions must
 * still be orthonormal, start along the total advance and keep the triangle. */
static void test_palmer_degenerate_advances(void **state)
{
    (void)state;
    double xi[NMAX * NMAX], out[NMAX * NMAX];
    enum { CASES = 9 };
    const double cases[CASES][6] = {
        {1, 0, 2, -1, 0.5, 3},            /* d_{k-1} = 0 in the middle */
        {2, -1, 0, 0, 0, 0},              /* trailing zeros */
        {0, 0, 0, 4, 0, 0},               /* a single advance */
        {0, 0, 0, 0, 0, -2},              /* only the last direction advanced */
        {0, 0, 0, 0, 0, 0},               /* no advance at all */
        {0, 3, 0, 0, -1, 0},              /* leading and repeated zeros */
        {1e-200, 1, 0, 1e-300, 0, -2},    /* magnitudes that underflow when squared */
        {1, 1e-170, 1e-170, 0, 0, 0},     /* a tail whose squares are subnormal */
        {1e250, 0, -3e250, 1e-250, 0, 7}, /* squares that overflow */
    };
    for (int c = 0; c < CASES; c++) {
        random_basis(6, xi);
        hk_rosenbrock_palmer_directions(6, xi, cases[c], out);
        assert_rosenbrock_directions(6, xi, cases[c], out);
    }
    /* No advance: every direction kept as it was. */
    random_basis(6, xi);
    hk_rosenbrock_palmer_directions(6, xi, cases[4], out);
    assert_memory_equal(out, xi, 36 * sizeof(double));
    /* An overflowed advance (only an objective unbounded below makes one) gives no
     * direction either: the directions are kept too. */
    const double overflowed[6] = {1, INFINITY, 0, 2, 0, 0};
    hk_rosenbrock_palmer_directions(6, xi, overflowed, out);
    assert_memory_equal(out, xi, 36 * sizeof(double));
    /* Random advances with about a third of them zero, all sizes. */
    for (int t = 0; t < 300; t++) {
        const int n = 1 + t % NMAX;
        double d[NMAX];
        random_basis(n, xi);
        for (int i = 0; i < n; i++)
            d[i] = hk_test_uniform() < 0.35 ? 0.0 : (2.0 * hk_test_uniform() - 1.0) * (1 + 9 * hk_test_uniform());
        hk_rosenbrock_palmer_directions(n, xi, d, out);
        assert_rosenbrock_directions(n, xi, d, out);
    }
}

/* One dimension: the single direction turns to follow the sign of the advance. */
static void test_palmer_one_dimension(void **state)
{
    (void)state;
    const double xi = 1.0;
    double out = 0.0, d = -0.7;
    hk_rosenbrock_palmer_directions(1, &xi, &d, &out);
    hk_assert_near(out, -1.0, 1e-15);
    d = 0.0;
    hk_rosenbrock_palmer_directions(1, &xi, &d, &out);
    hk_assert_near(out, 1.0, 0.0);
}

/* ---- exact trial sequences ----------------------------------------------------------- */

static void assert_recorded(const Probe *p, long call, double x0) { hk_assert_near(p->rec[call][0], x0, 1e-14); }

/* f = (x - 1)^2 from 0 with steps 0.1, alpha 3, beta 0.5, worked out by hand:
 * stage 1: 0.1 ok, 0.4 ok, 1.3 ok, 4.0 fails (success then failure: stage over, d = 1.3);
 * stage 2, steps reset to 0.1 along +x (d > 0): 1.4 fails, 1.25 ok, 1.1 ok, 0.65 fails. */
static void test_trial_sequence_1d(void **state)
{
    (void)state;
    Probe p;
    probe_init(&p, 1, parabola_1d, 1000);
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 2;
    double x = 0.0;
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(1, &x, probe_eval, &p, &o, &r, &err), HK_OK);
    const double expect[] = {0.0, 0.1, 0.4, 1.3, 4.0, 1.4, 1.25, 1.1, 0.65};
    const long count = (long)(sizeof expect / sizeof expect[0]);
    assert_int_equal(p.calls, count);
    assert_int_equal(r.evaluations, count);
    for (long i = 0; i < count; i++) assert_recorded(&p, i, expect[i]);
    hk_assert_near(x, 1.1, 1e-14);
    hk_assert_near(r.f, 0.01, 1e-14);
    assert_int_equal(r.iterations, 2);
    assert_false(r.converged);
}

/* Ties are successes (f(x_try) <= f(x)), so on a flat bottom the steps grow: 0.1, 0.4
 * (flat), 1.3 (f = 0.3 > 0: fails) and the stage ends there. */
static void test_ties_succeed(void **state)
{
    (void)state;
    Probe p;
    probe_init(&p, 1, flat_bottom, 1000);
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 1;
    double x = 0.0;
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(1, &x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(p.calls, 4);
    assert_recorded(&p, 1, 0.1);
    assert_recorded(&p, 2, 0.4);
    assert_recorded(&p, 3, 1.3);
    hk_assert_near(x, 0.4, 1e-15);
}

/* Stage 1 tries the coordinate axes in turn; stage 2 restarts with the initial step
 * along the normalised total advance of stage 1 (the rotation and the step reset). */
static void test_stage_restart_along_advance(void **state)
{
    (void)state;
    const double x0[2] = {-1.2, 1.0};
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.initial_step = 0.05;
    o.epsilon = 0.0;
    /* Stage 1 alone: where it ends and how many calls it takes. */
    Probe p1;
    probe_init(&p1, 2, banana, 100000);
    double x1[2] = {x0[0], x0[1]};
    o.max_stages = 1;
    hk_MinimizeResult r1;
    assert_int_equal(hk_rosenbrock_minimize(2, x1, probe_eval, &p1, &o, &r1, NULL), HK_OK);
    assert_int_equal(r1.iterations, 1);
    hk_assert_near(p1.rec[1][0], x0[0] + 0.05, 1e-15); /* first trial: +e along axis 1 */
    hk_assert_near(p1.rec[1][1], x0[1], 0.0);
    /* It succeeded (f 24.2 -> 15.0), so the second trial, +e along axis 2, starts there. */
    hk_assert_near(p1.rec[2][0], x0[0] + 0.05, 1e-15);
    hk_assert_near(p1.rec[2][1], x0[1] + 0.05, 1e-15);
    assert_true(r1.evaluations < RECORD_MAX);
    /* Two stages: the first call after stage 1's calls is x1 + 0.05 (x1 - x0)/|x1 - x0|. */
    Probe p2;
    probe_init(&p2, 2, banana, 100000);
    double x2[2] = {x0[0], x0[1]};
    o.max_stages = 2;
    hk_MinimizeResult r2;
    assert_int_equal(hk_rosenbrock_minimize(2, x2, probe_eval, &p2, &o, &r2, NULL), HK_OK);
    assert_int_equal(r2.iterations, 2);
    const double ax = x1[0] - x0[0], ay = x1[1] - x0[1], na = hypot(ax, ay);
    assert_true(na > 0.0);
    const long first = r1.evaluations;
    hk_assert_near(p2.rec[first][0], x1[0] + 0.05 * ax / na, 1e-14);
    hk_assert_near(p2.rec[first][1], x1[1] + 0.05 * ay / na, 1e-14);
}

/* ---- minima ---------------------------------------------------------------------------- */

static void test_banana(void **state)
{
    (void)state;
    Probe p;
    probe_init(&p, 2, banana, 2000000);
    double x[2] = {-1.2, 1.0};
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 100000;
    o.epsilon = 1e-14;
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, &err), HK_OK);
    print_message("banana: %d stages, %ld evaluations, f = %.3g at (%.8f, %.8f)\n", r.iterations, r.evaluations, r.f,
                  x[0], x[1]);
    assert_true(r.converged);
    hk_assert_near(x[0], 1.0, 1e-4);
    hk_assert_near(x[1], 1.0, 1e-4);
    assert_true(r.f < 1e-8);
    hk_assert_near(r.f, banana(x, 2), 0.0);
    assert_int_equal(r.evaluations, p.calls);
}

/* An ill-conditioned quadratic 1 + (x - c)^T H (x - c) in 8 dimensions, H = Q^T L Q with
 * Q a random rotation and eigenvalues L from 1 to 1e4. */
#define QN 8
typedef struct Quadratic {
    double h[QN * QN];
    double c[QN];
} Quadratic;
static Quadratic quad;

static double quadratic(const double *x, int n)
{
    double y[QN], f = 1.0;
    for (int i = 0; i < n; i++) y[i] = x[i] - quad.c[i];
    for (int i = 0; i < n; i++) f += y[i] * dot(n, quad.h + i * n, y);
    return f;
}

static void make_quadratic(void)
{
    double q[QN * QN];
    random_basis(QN, q);
    for (int i = 0; i < QN; i++)
        for (int j = 0; j < QN; j++) {
            double s = 0.0;
            for (int k = 0; k < QN; k++) s += q[k * QN + i] * pow(1e4, (double)k / (QN - 1)) * q[k * QN + j];
            quad.h[i * QN + j] = s;
        }
    for (int i = 0; i < QN; i++) quad.c[i] = 2.0 * hk_test_uniform() - 1.0;
}

/* The rotation is what makes the method work on a valley that is not aligned with the
 * axes. The same search without it (runs of one stage, each restarting on the coordinate
 * axes) is a coordinate descent, which on a quadratic of condition number kappa gains
 * only a factor ~(1 - c/kappa) per sweep of >= 2n = 16 trials (Gauss-Seidel); with
 * kappa = 1e4 and a target 1e-10 above the minimum from ~10^3 above it, that is of the
 * order of 10^5-10^6 evaluations. The rotating search lines its directions up with the
 * valley in a few dozen stages (measured: ~18,000 evaluations, ~110 stages). Asserted:
 * it reaches the minimum to 1e-5 in under 150,000 evaluations, and the axis-bound search,
 * given 10 times as many evaluations as the rotating one used, is still short of the
 * target (measured: f - 1 ~ 4e-3 after ~180,000). */
static void test_rotated_quadratic(void **state)
{
    (void)state;
    make_quadratic();
    const double target = 1.0 + 1e-10;
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 100000;
    o.epsilon = 1e-15;
    Probe p;
    probe_init(&p, QN, quadratic, 10000000);
    double x[QN] = {0};
    hk_MinimizeResult rot;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(QN, x, probe_eval, &p, &o, &rot, &err), HK_OK);
    assert_true(rot.converged);
    for (int i = 0; i < QN; i++) hk_assert_near(x[i], quad.c[i], 1e-5);
    assert_true(rot.f <= target);
    /* Coordinate descent with the same trial rules. */
    double y[QN] = {0};
    hk_RosenbrockDef one = o;
    one.max_stages = 1;
    long evaluations = 0;
    double f = quadratic(y, QN);
    while (f > target && evaluations < 10 * rot.evaluations) {
        hk_MinimizeResult r;
        assert_int_equal(hk_rosenbrock_minimize(QN, y, probe_eval, &p, &one, &r, &err), HK_OK);
        evaluations += r.evaluations;
        f = r.f;
    }
    print_message("rotated quadratic: rotating %ld evaluations (%d stages) to f - 1 = %.2g; "
                  "axis-aligned %ld evaluations reach f - 1 = %.2g\n",
                  rot.evaluations, rot.iterations, rot.f - 1.0, evaluations, f - 1.0);
    assert_true(rot.evaluations < 150000);
    assert_true(f > target);
}

/* ---- stopping rules and limits --------------------------------------------------------- */

static void test_stage_limit(void **state)
{
    (void)state;
    Probe p;
    probe_init(&p, 2, banana, 1000000);
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 3;
    o.epsilon = 0.0;
    double x[2] = {-1.2, 1.0};
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(r.iterations, 3);
    assert_false(r.converged);
    assert_int_equal(r.evaluations, p.calls);
    hk_assert_near(r.f, banana(x, 2), 0.0);
    assert_true(r.f < banana((const double[]){-1.2, 1.0}, 2));
}

static void test_evaluation_limit(void **state)
{
    (void)state;
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 1000;
    o.epsilon = 0.0;
    for (long limit = 1; limit <= 200; limit += 13) {
        Probe p;
        probe_init(&p, 2, banana, 1000000);
        o.max_evaluations = limit;
        double x[2] = {-1.2, 1.0};
        hk_MinimizeResult r;
        assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
        assert_int_equal(r.evaluations, limit); /* used to the last evaluation */
        assert_int_equal(p.calls, limit);
        assert_false(r.converged);
        assert_true(r.iterations < 1000);
        hk_assert_near(r.f, banana(x, 2), 0.0); /* the best point found, with its value */
        if (limit == 1) {
            assert_int_equal(r.iterations, 0);
            hk_assert_near(x[0], -1.2, 0.0);
        }
    }
}

/* The search stops after the first stage that lowers f by no more than epsilon |f| at
 * the stage's start. Checked stage by stage: the algorithm is deterministic, so the run
 * limited to k stages reproduces the first k stages of the full run. */
static void test_epsilon_stopping(void **state)
{
    (void)state;
    enum { N = 3 };
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 1000;
    o.epsilon = 1e-6;
    double x[N] = {2.1, -1.3, 0.7};
    hk_MinimizeResult r;
    Probe p;
    probe_init(&p, N, bowl, 1000000);
    assert_int_equal(hk_rosenbrock_minimize(N, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_true(r.converged);
    assert_true(r.iterations >= 2 && r.iterations < 1000);
    for (int i = 0; i < N; i++) hk_assert_near(x[i], 0.3 * i, 1e-3);
    double f_prev = bowl((const double[]){2.1, -1.3, 0.7}, N);
    for (int k = 1; k <= r.iterations; k++) {
        hk_RosenbrockDef ok = o;
        ok.max_stages = k;
        double y[N] = {2.1, -1.3, 0.7};
        hk_MinimizeResult rk;
        probe_init(&p, N, bowl, 1000000);
        assert_int_equal(hk_rosenbrock_minimize(N, y, probe_eval, &p, &ok, &rk, NULL), HK_OK);
        const int last = k == r.iterations;
        /* Stage k's decrease is small exactly at the last stage. */
        assert_int_equal(f_prev - rk.f <= o.epsilon * fabs(f_prev), last);
        assert_int_equal(rk.converged, last);
        assert_int_equal(rk.iterations, k);
        f_prev = rk.f;
    }
    hk_assert_near(f_prev, r.f, 0.0);
    /* A larger epsilon stops sooner. */
    Probe q;
    probe_init(&q, N, bowl, 1000000);
    double z[N] = {2.1, -1.3, 0.7};
    hk_MinimizeResult rz;
    o.epsilon = 0.1;
    assert_int_equal(hk_rosenbrock_minimize(N, z, probe_eval, &q, &o, &rz, NULL), HK_OK);
    assert_true(rz.converged);
    assert_true(rz.iterations < r.iterations);
}

/* ---- hostile objectives: must end even with no evaluation limit ------------------------ */

/* The objective for the NaN test: finite at the first call, NaN at every later one. */
static long nan_after_first_calls;
static double nan_after_first(const double *x, int n) { return nan_after_first_calls++ == 0 ? banana(x, n) : NAN; }

static void test_nan_after_start(void **state)
{
    (void)state;
    arm_watchdog();
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_evaluations = 0;
    o.max_stages = 1000;
    Probe p;
    probe_init(&p, 2, nan_after_first, 100000);
    nan_after_first_calls = 0;
    double x[2] = {0.5, 0.5};
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, &err), HK_OK);
    /* Every trial failed: x is still the finite start, f its value. */
    hk_assert_near(x[0], 0.5, 0.0);
    hk_assert_near(x[1], 0.5, 0.0);
    hk_assert_near(r.f, banana((const double[]){0.5, 0.5}, 2), 0.0);
    assert_int_equal(r.evaluations, p.calls);
    print_message("NaN objective: ended after %ld evaluations, %d stages\n", r.evaluations, r.iterations);
}

/* NaN only beyond x0 = 2, the unconstrained minimum (3, 0) lies there: NaN trials are
 * failures, so the search presses against the edge from the finite side. */
static void test_nan_region(void **state)
{
    (void)state;
    arm_watchdog();
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_evaluations = 0;
    o.max_stages = 1000;
    o.epsilon = 1e-12;
    Probe p;
    probe_init(&p, 2, nan_beyond_two, 1000000);
    double x[2] = {-1.0, 1.0};
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    /* The edge acts like a constraint, on which a direct search stalls short of the
     * constrained minimum (2, 0) (here at x1 ~ -0.014, f - 1 ~ 2e-4): close, not exact. */
    assert_true(x[0] < 2.0);
    hk_assert_near(x[0], 2.0, 1e-6);
    hk_assert_near(x[1], 0.0, 0.05);
    assert_true(isfinite(r.f));
    hk_assert_near(r.f, 1.0, 1e-3);
    hk_assert_near(r.f, nan_beyond_two(x, 2), 0.0);
}

static void test_kink_and_unbounded_terminate(void **state)
{
    (void)state;
    arm_watchdog();
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_evaluations = 0;
    o.max_stages = 50;
    /* |x0| + |x1| at the origin: every non-zero step fails, down to the last normal
     * number (~1020 halvings per direction). */
    Probe p;
    probe_init(&p, 2, kink, 100000);
    double x[2] = {0.0, 0.0};
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    hk_assert_near(x[0], 0.0, 0.0);
    hk_assert_near(x[1], 0.0, 0.0);
    assert_true(r.converged); /* the stage did not lower f */
    assert_int_equal(r.iterations, 1);
    /* -x0: steps grow until the trial point overflows, which is a failure. */
    o.max_stages = 5;
    probe_init(&p, 2, downhill, 1000000);
    x[0] = 0.0, x[1] = 0.0;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_true(isfinite(x[0]) && isfinite(x[1]) && isfinite(r.f));
    assert_true(x[0] > 1e300);
    hk_assert_near(r.f, -x[0], 0.0);
}

/* ---- size -------------------------------------------------------------------------------- */

static double sphere(const double *x, int n)
{
    double f = 1.0;
    for (int i = 0; i < n; i++) f += (x[i] - 1.0) * (x[i] - 1.0) * (1.0 + 0.01 * i);
    return f;
}

/* A few hundred unknowns, as for a long strand: Palmer stays orthonormal and starts
 * along the advance, and a short search runs and improves f. */
static void test_large_dimension(void **state)
{
    (void)state;
    enum { N = 300 };
    double *xi = malloc(sizeof(double) * N * N), *out = malloc(sizeof(double) * N * N);
    double *d = malloc(sizeof(double) * N), *a = malloc(sizeof(double) * N);
    assert_non_null(xi), assert_non_null(out), assert_non_null(d), assert_non_null(a);
    random_basis(N, xi);
    for (int i = 0; i < N; i++) d[i] = i % 5 == 2 ? 0.0 : 2.0 * hk_test_uniform() - 1.0;
    hk_rosenbrock_palmer_directions(N, xi, d, out);
    assert_orthonormal(N, out);
    assert_true(scaled_advance(N, xi, d, 0, a));
    const double s = sqrt(dot(N, a, a));
    for (int j = 0; j < N; j++) hk_assert_near(out[j], a[j] / s, 1e-12);
    free(xi), free(out), free(d), free(a);

    enum { M = 200 };
    double x[M] = {0};
    Probe p;
    probe_init(&p, M, sphere, 10000000);
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = 3;
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(M, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(r.iterations, 3);
    assert_int_equal(r.evaluations, p.calls);
    assert_true(r.f < 0.1 * (sphere((const double[M]){0}, M) - 1.0) + 1.0);
}

/* ---- errors ------------------------------------------------------------------------------ */

static void test_nonfinite_start(void **state)
{
    (void)state;
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    double x[2] = {0.25, -0.5};
    hk_MinimizeResult r;
    hk_Error err;
    Probe p;
    probe_init(&p, 2, nan_objective, 1000);
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, &err), HK_ERR_NUMERIC);
    assert_int_equal(err.code, HK_ERR_NUMERIC);
    hk_assert_contains(err.message, "rosenbrock");
    hk_assert_contains(err.message, "not finite");
    assert_int_equal(p.calls, 1);
    assert_int_equal(r.evaluations, 1);
    hk_assert_near(x[0], 0.25, 0.0);
    probe_init(&p, 2, infinite_objective, 1000);
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_ERR_NUMERIC);
}

static void expect_invalid(int n, double *x, hk_ObjectiveFn f, const hk_RosenbrockDef *o, const char *needle)
{
    Probe p;
    probe_init(&p, 2, banana, 1000);
    hk_MinimizeResult r = {123.0, 7, 7, 7};
    hk_Error err;
    hk_error_clear(&err);
    assert_int_equal(hk_rosenbrock_minimize(n, x, f, &p, o, &r, &err), HK_ERR_INVALID);
    assert_int_equal(err.code, HK_ERR_INVALID);
    hk_assert_contains(err.message, "rosenbrock");
    hk_assert_contains(err.message, needle);
    assert_int_equal(p.calls, 0); /* refused before any evaluation */
    assert_int_equal(r.evaluations, 0);
    assert_int_equal(r.converged, 0);
    /* No error report wanted: same status, no crash. */
    assert_int_equal(hk_rosenbrock_minimize(n, x, f, &p, o, NULL, NULL), HK_ERR_INVALID);
}

static void test_invalid_arguments(void **state)
{
    (void)state;
    const hk_RosenbrockDef d = hk_default_rosenbrock_def();
    double x[2] = {0, 0};
    expect_invalid(0, x, probe_eval, &d, "dimension");
    expect_invalid(-3, x, probe_eval, &d, "dimension");
    expect_invalid(2, NULL, probe_eval, &d, "x");
    expect_invalid(2, x, NULL, &d, "objective");
    /* NULL options mean the defaults (test_null_defaults.c) */
    hk_RosenbrockDef o = d;
    o.max_stages = 0;
    expect_invalid(2, x, probe_eval, &o, "max_stages");
    const double bad_eps[] = {-1e-9, NAN, INFINITY};
    for (int i = 0; i < 3; i++) {
        o = d, o.epsilon = bad_eps[i];
        expect_invalid(2, x, probe_eval, &o, "epsilon");
    }
    const double bad_step[] = {0.0, -0.1, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        o = d, o.initial_step = bad_step[i];
        expect_invalid(2, x, probe_eval, &o, "initial_step");
    }
    const double bad_alpha[] = {1.0, 0.5, 1.0000001, NAN, INFINITY};
    for (int i = 0; i < 5; i++) {
        o = d, o.alpha = bad_alpha[i];
        expect_invalid(2, x, probe_eval, &o, "alpha");
    }
    const double bad_beta[] = {0.0, -0.5, 1.0, 0.9999999, 1.5, NAN};
    for (int i = 0; i < 6; i++) {
        o = d, o.beta = bad_beta[i];
        expect_invalid(2, x, probe_eval, &o, "beta");
    }
    /* The limits of the sane range are accepted. */
    o = d, o.alpha = 1.001, o.beta = 0.999, o.epsilon = 0.0, o.max_stages = 1;
    o.max_evaluations = -5;
    Probe p;
    probe_init(&p, 2, banana, 1000000);
    hk_MinimizeResult r;
    assert_int_equal(hk_rosenbrock_minimize(2, x, probe_eval, &p, &o, &r, NULL), HK_OK);
    assert_int_equal(r.iterations, 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_palmer_equals_gram_schmidt),
        cmocka_unit_test(test_palmer_degenerate_advances),
        cmocka_unit_test(test_palmer_one_dimension),
        cmocka_unit_test(test_trial_sequence_1d),
        cmocka_unit_test(test_ties_succeed),
        cmocka_unit_test(test_stage_restart_along_advance),
        cmocka_unit_test(test_banana),
        cmocka_unit_test(test_rotated_quadratic),
        cmocka_unit_test(test_stage_limit),
        cmocka_unit_test(test_evaluation_limit),
        cmocka_unit_test(test_epsilon_stopping),
        cmocka_unit_test_teardown(test_nan_after_start, disarm_watchdog),
        cmocka_unit_test_teardown(test_nan_region, disarm_watchdog),
        cmocka_unit_test_teardown(test_kink_and_unbounded_terminate, disarm_watchdog),
        cmocka_unit_test(test_large_dimension),
        cmocka_unit_test(test_nonfinite_start),
        cmocka_unit_test(test_invalid_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
