/* Levenberg-Marquardt (hk_least_squares_minimize, curvefit.h): the references are closed
 * forms: Rosenbrock's function as residuals (minimum (1, 1), Moré, Garbow & Hillstrom
 * 1981, problem 1), a straight-line fit (the normal equations of linear least squares),
 * an exponential fit to exact data (its generating parameters) and a problem whose
 * residuals are undefined in half the plane; then limits, determinism, bad arguments. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/curvefit.h"

typedef struct Probe {
    long calls;
} Probe;

/* r = (10 (x1 - x0^2), 1 - x0): sum r^2 is Rosenbrock's banana, minimum 0 at (1, 1). */
static int rosenbrock(void *user, const double *x, double *r)
{
    if (user) ((Probe *)user)->calls++;
    r[0] = 10.0 * (x[1] - x[0] * x[0]);
    r[1] = 1.0 - x[0];
    return 0;
}

/* Its Jacobian, column-major: d r / d x0 = (-20 x0, -1), d r / d x1 = (10, 0). */
static int rosenbrock_jacobian(void *user, const double *x, double *jac)
{
    (void)user;
    jac[0] = -20.0 * x[0], jac[1] = -1.0, jac[2] = 10.0, jac[3] = 0.0;
    return 0;
}

static int no_jacobian(void *user, const double *x, double *jac)
{
    (void)user, (void)x, (void)jac;
    return 1;
}

/* A given Jacobian reaches the same minimum with one call per accepted point instead of
 * the n residual calls of forward differences; a Jacobian that is not available falls
 * back to the differences, and the result is the plain minimiser's to the bit. */
static void test_given_jacobian(void **state)
{
    (void)state;
    const double scale[2] = {1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(2, 2)];
    double x[2] = {-1.2, 1.0}, y[2] = {-1.2, 1.0}, z[2] = {-1.2, 1.0};
    Probe p = {0}, q = {0};
    hk_MinimizeResult r, rd, rf;
    assert_int_equal(
        hk_least_squares_minimize_jac(2, 2, x, scale, rosenbrock, rosenbrock_jacobian, &p, NULL, work, &r, NULL),
        HK_OK);
    assert_true(r.converged);
    hk_assert_near(x[0], 1.0, 1e-10);
    hk_assert_near(x[1], 1.0, 1e-10);
    assert_int_equal(hk_least_squares_minimize(2, 2, y, scale, rosenbrock, &q, NULL, work, &rd, NULL), HK_OK);
    assert_true(p.calls < q.calls);
    assert_int_equal(
        hk_least_squares_minimize_jac(2, 2, z, scale, rosenbrock, no_jacobian, NULL, NULL, work, &rf, NULL), HK_OK);
    assert_true(z[0] == y[0] && z[1] == y[1]);
    print_message("  rosenbrock with its Jacobian: %ld residual calls (%ld with differences)\n", p.calls, q.calls);
}

static void test_rosenbrock(void **state)
{
    (void)state;
    double x[2] = {-1.2, 1.0}; /* the standard start */
    const double scale[2] = {1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(2, 2)];
    Probe p = {0};
    hk_MinimizeResult r;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, &p, NULL, work, &r, NULL), HK_OK);
    assert_true(r.converged);
    assert_int_equal(r.evaluations, p.calls);
    hk_assert_near(x[0], 1.0, 1e-10);
    hk_assert_near(x[1], 1.0, 1e-10);
    assert_true(r.f < 1e-20);
    print_message("  levenberg-marquardt rosenbrock: cost %.3g after %ld evaluations, %d steps\n", r.f, r.evaluations,
                  r.iterations);
}

/* Points of a line with known scatter: y_i = a + b t_i + e_i. */
enum { LINE_N = 7 };
static const double line_t[LINE_N] = {0.0, 1.0, 2.0, 3.5, 4.0, 6.0, 7.5};
static const double line_y[LINE_N] = {1.1, 2.9, 5.2, 8.1, 8.8, 13.3, 15.9};

static int line_residuals(void *user, const double *x, double *r)
{
    (void)user;
    for (int i = 0; i < LINE_N; i++) r[i] = x[0] + x[1] * line_t[i] - line_y[i];
    return 0;
}

static void test_linear_fit(void **state)
{
    (void)state;
    /* The reference: the normal equations of the straight-line fit, solved by hand:
     * b = (n Sty - St Sy) / (n Stt - St^2), a = (Sy - b St) / n. */
    double st = 0.0, sy = 0.0, stt = 0.0, sty = 0.0;
    for (int i = 0; i < LINE_N; i++) {
        st += line_t[i], sy += line_y[i];
        stt += line_t[i] * line_t[i], sty += line_t[i] * line_y[i];
    }
    const double b = (LINE_N * sty - st * sy) / (LINE_N * stt - st * st), a = (sy - b * st) / LINE_N;
    double x[2] = {0.0, 0.0};
    const double scale[2] = {1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(2, LINE_N)];
    hk_MinimizeResult r;
    assert_int_equal(hk_least_squares_minimize(2, LINE_N, x, scale, line_residuals, NULL, NULL, work, &r, NULL), HK_OK);
    assert_true(r.converged);
    hk_assert_near(x[0], a, 1e-7);
    hk_assert_near(x[1], b, 1e-7);
    double res[LINE_N];
    line_residuals(NULL, x, res);
    double cost = 0.0;
    for (int i = 0; i < LINE_N; i++) cost += 0.5 * res[i] * res[i];
    hk_assert_rel(r.f, cost, 1e-12, 0);
    assert_true(r.f > 0.01); /* the data do scatter: the minimum is not zero */
}

/* gain_tolerance: from a start a micro-unit off the straight line's minimum (its cost
 * stays the scatter's), the next step's predicted gain is a minute fraction of the cost
 * (the offset squared against the scatter), so a run with gain_tolerance 1e-6 stops
 * after the Jacobian with x untouched, while the default (0) takes the step. */
static void test_gain_tolerance(void **state)
{
    (void)state;
    double x0[2] = {0.0, 0.0};
    const double scale[2] = {1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(2, LINE_N)];
    hk_MinimizeResult r0, r1;
    assert_int_equal(hk_least_squares_minimize(2, LINE_N, x0, scale, line_residuals, NULL, NULL, work, &r0, NULL),
                     HK_OK);
    const double start[2] = {x0[0], x0[1] + 1e-6};
    double x[2] = {start[0], start[1]}, y[2] = {start[0], start[1]};
    hk_LeastSquaresDef o = hk_default_least_squares_def();
    assert_int_equal(hk_least_squares_minimize(2, LINE_N, x, scale, line_residuals, NULL, &o, work, &r0, NULL), HK_OK);
    o.gain_tolerance = 1e-6;
    assert_int_equal(hk_least_squares_minimize(2, LINE_N, y, scale, line_residuals, NULL, &o, work, &r1, NULL), HK_OK);
    assert_true(r1.converged);
    assert_int_equal(r1.iterations, 0);
    assert_memory_equal(y, start, sizeof y);
    assert_true(r0.iterations > 0);
    assert_true(r1.evaluations < r0.evaluations);
    hk_assert_rel(r1.f, r0.f, 1e-9, 0); /* what it skipped was worth nothing */
}

/* y = c exp(-k t) + d sampled exactly at (c, k, d) = (2.5, 1.3, 0.4), from a far start
 * with badly scaled parameters. */
static int exponential(void *user, const double *x, double *r)
{
    (void)user;
    for (int i = 0; i < 20; i++) {
        const double t = 0.25 * i;
        r[i] = x[0] * exp(-x[1] * t) + x[2] - (2.5 * exp(-1.3 * t) + 0.4);
    }
    return 0;
}

static void test_exponential(void **state)
{
    (void)state;
    double x[3] = {1.0, 0.2, 0.0};
    const double scale[3] = {1.0, 1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(3, 20)];
    hk_MinimizeResult r;
    assert_int_equal(hk_least_squares_minimize(3, 20, x, scale, exponential, NULL, NULL, work, &r, NULL), HK_OK);
    assert_true(r.converged);
    hk_assert_near(x[0], 2.5, 1e-8);
    hk_assert_near(x[1], 1.3, 1e-8);
    hk_assert_near(x[2], 0.4, 1e-8);
}

/* Residuals undefined for x0 < 0.5 (the minimiser must step back from there); the
 * unconstrained minimum (1, 2) is inside the defined region. */
static int walled(void *user, const double *x, double *r)
{
    ((Probe *)user)->calls++;
    if (x[0] < 0.5) return 1;
    r[0] = 3.0 * (x[0] - 1.0);
    r[1] = x[1] - 2.0 * x[0];
    r[2] = x[0] * x[1] - 2.0;
    return 0;
}

static void test_undefined_regions(void **state)
{
    (void)state;
    double work[HK_LEAST_SQUARES_WORK(2, 3)];
    const double scale[2] = {1.0, 1.0};
    Probe p = {0};
    hk_MinimizeResult r;
    double x[2] = {0.6, -5.0}; /* the first steps head left, over the wall */
    assert_int_equal(hk_least_squares_minimize(2, 3, x, scale, walled, &p, NULL, work, &r, NULL), HK_OK);
    hk_assert_near(x[0], 1.0, 1e-9);
    hk_assert_near(x[1], 2.0, 1e-9);
    /* Undefined at the start: an error, x untouched. */
    double y[2] = {0.0, 0.0};
    hk_Error err;
    assert_int_equal(hk_least_squares_minimize(2, 3, y, scale, walled, &p, NULL, work, &r, &err), HK_ERR_NUMERIC);
    hk_assert_contains(err.message, "not defined at the start");
    assert_true(y[0] == 0.0 && y[1] == 0.0);
}

static void test_limits_and_determinism(void **state)
{
    (void)state;
    const double scale[2] = {1.0, 1.0};
    double work[HK_LEAST_SQUARES_WORK(2, 2)];
    hk_LeastSquaresDef o = hk_default_least_squares_def();
    o.max_evaluations = 9;
    double x[2] = {-1.2, 1.0}, y[2] = {-1.2, 1.0};
    Probe p = {0};
    hk_MinimizeResult r, r2;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, &p, &o, work, &r, NULL), HK_OK);
    assert_true(p.calls <= 9);
    assert_int_equal(r.evaluations, p.calls);
    assert_false(r.converged);
    /* never worse than the start: cost(-1.2, 1) = (10 * -0.44)^2 / 2 + 2.2^2 / 2 = 12.1 */
    assert_true(r.f <= 12.1 + 1e-12);
    assert_int_equal(hk_least_squares_minimize(2, 2, y, scale, rosenbrock, NULL, &o, work, &r2, NULL), HK_OK);
    assert_memory_equal(x, y, sizeof x);
    assert_true(r.f == r2.f);
}

static void test_bad_arguments(void **state)
{
    (void)state;
    double x[33] = {0}, scale[33], work[HK_LEAST_SQUARES_WORK(33, 40)];
    for (int i = 0; i < 33; i++) scale[i] = 1.0;
    hk_Error err;
    assert_int_equal(hk_least_squares_minimize(33, 40, x, scale, rosenbrock, NULL, NULL, work, NULL, &err),
                     HK_ERR_INVALID);
    assert_int_equal(hk_least_squares_minimize(0, 2, x, scale, rosenbrock, NULL, NULL, work, NULL, &err),
                     HK_ERR_INVALID);
    assert_int_equal(hk_least_squares_minimize(2, 1, x, scale, rosenbrock, NULL, NULL, work, NULL, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "1 residuals for 2 parameters");
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, NULL, NULL, NULL, work, NULL, &err), HK_ERR_INVALID);
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, NULL, NULL, NULL, &err),
                     HK_ERR_INVALID);
    scale[1] = 0.0;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, NULL, work, NULL, &err),
                     HK_ERR_INVALID);
    hk_assert_contains(err.message, "scale[1]");
    scale[1] = 1.0;
    x[0] = INFINITY;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, NULL, work, NULL, &err),
                     HK_ERR_INVALID);
    x[0] = 0.0;
    hk_LeastSquaresDef o = hk_default_least_squares_def();
    o.max_evaluations = 3;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, &o, work, NULL, &err), HK_ERR_INVALID);
    o = hk_default_least_squares_def();
    o.x_tolerance = NAN;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, &o, work, NULL, &err), HK_ERR_INVALID);
    o = hk_default_least_squares_def();
    o.gain_tolerance = -1.0;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, rosenbrock, NULL, &o, work, NULL, &err), HK_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_given_jacobian),    cmocka_unit_test(test_rosenbrock),
        cmocka_unit_test(test_linear_fit),        cmocka_unit_test(test_exponential),
        cmocka_unit_test(test_undefined_regions), cmocka_unit_test(test_limits_and_determinism),
        cmocka_unit_test(test_bad_arguments),     cmocka_unit_test(test_gain_tolerance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
