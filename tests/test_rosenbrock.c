/* The thesis's Rosenbrock + Palmer minimiser (src/statics/rosenbrock.c): Palmer's
 * directions against classical Gram-Schmidt, orthonormality in the degenerate cases
 * Palmer was made for, minima of test functions, limits and errors. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/statics.h"

#define NMAX 8

/* Random orthonormal basis (Gram-Schmidt of random vectors), rows = directions. */
static void random_basis(int n, double *xi)
{
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) xi[i * n + j] = 2 * hk_test_uniform() - 1;
        for (int k = 0; k < i; k++) {
            double d = 0;
            for (int j = 0; j < n; j++) d += xi[i * n + j] * xi[k * n + j];
            for (int j = 0; j < n; j++) xi[i * n + j] -= d * xi[k * n + j];
        }
        double s = 0;
        for (int j = 0; j < n; j++) s += xi[i * n + j] * xi[i * n + j];
        for (int j = 0; j < n; j++) xi[i * n + j] /= sqrt(s);
    }
}

static void assert_orthonormal(int n, const double *xi)
{
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            double d = 0;
            for (int j = 0; j < n; j++) d += xi[a * n + j] * xi[b * n + j];
            hk_assert_near(d, a == b ? 1.0 : 0.0, 1e-12);
        }
}

/* Rosenbrock's original procedure: Gram-Schmidt of A_k = sum_{i>=k} d_i xi_i. */
static void gram_schmidt_reference(int n, const double *xi, const double *d, double *out)
{
    for (int k = 0; k < n; k++) {
        double b[NMAX] = {0};
        for (int i = k; i < n; i++)
            for (int j = 0; j < n; j++) b[j] += d[i] * xi[i * n + j];
        for (int m = 0; m < k; m++) {
            double p = 0;
            for (int j = 0; j < n; j++) p += b[j] * out[m * n + j];
            for (int j = 0; j < n; j++) b[j] -= p * out[m * n + j];
        }
        double s = 0;
        for (int j = 0; j < n; j++) s += b[j] * b[j];
        for (int j = 0; j < n; j++) out[k * n + j] = b[j] / sqrt(s);
    }
}

static void test_palmer_equals_gram_schmidt(void **state)
{
    (void)state;
    for (int t = 0; t < 50; t++) {
        const int n = 2 + t % (NMAX - 1);
        double xi[NMAX * NMAX], d[NMAX], palmer[NMAX * NMAX], gs[NMAX * NMAX];
        random_basis(n, xi);
        for (int i = 0; i < n; i++) d[i] = (2 * hk_test_uniform() - 1) * (1 + 10 * hk_test_uniform());
        hk_rosenbrock_palmer_directions(n, xi, d, palmer);
        gram_schmidt_reference(n, xi, d, gs);
        assert_orthonormal(n, palmer);
        /* Same directions up to sign (Palmer's sign convention differs). */
        for (int k = 0; k < n; k++) {
            double dot = 0;
            for (int j = 0; j < n; j++) dot += palmer[k * n + j] * gs[k * n + j];
            hk_assert_near(fabs(dot), 1.0, 1e-10);
        }
    }
}

static void test_palmer_degenerate_advances(void **state)
{
    (void)state;
    const int n = 6;
    double xi[36], out[36];
    /* d_{k-1} = 0 in the middle, trailing zeros, a single advance, no advance at all:
     * Gram-Schmidt divides by zero in all of these, Palmer must stay orthonormal. */
    const double cases[5][6] = {{1, 0, 2, -1, 0.5, 3}, {2, -1, 0, 0, 0, 0}, {0, 0, 0, 4, 0, 0},
                                {0, 0, 0, 0, 0, 0}, {1e-200, 1, 0, 1e-300, 0, -2}};
    for (int c = 0; c < 5; c++) {
        random_basis(n, xi);
        hk_rosenbrock_palmer_directions(n, xi, cases[c], out);
        assert_orthonormal(n, out);
        /* xi'_1 lies along the total advance A_1 (when there is one). */
        double a1[6] = {0}, na = 0, dot = 0;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) a1[j] += cases[c][i] * xi[i * n + j];
        for (int j = 0; j < n; j++) na += a1[j] * a1[j], dot += a1[j] * out[j];
        if (na > 0) hk_assert_near(dot / sqrt(na), 1.0, 1e-12);
    }
}

static double banana(const double *x, void *user)
{
    (void)user;
    return (1 - x[0]) * (1 - x[0]) + 100 * (x[1] - x[0] * x[0]) * (x[1] - x[0] * x[0]);
}

static void test_banana(void **state)
{
    (void)state;
    double x[2] = {-1.2, 1.0};
    hk_RosenbrockOptions o = hk_default_rosenbrock_options();
    o.max_stages = 100000;
    o.epsilon = 1e-14;
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(2, x, banana, NULL, &o, &r, &err), HK_OK);
    assert_true(r.converged);
    hk_assert_near(x[0], 1.0, 1e-4);
    hk_assert_near(x[1], 1.0, 1e-4);
    assert_true(r.f < 1e-8);
}

/* An ill-conditioned quadratic (condition 1e4) whose axes are rotated 45 degrees in
 * pairs of coordinates: a search along fixed coordinate axes crawls along the narrow
 * valleys, the rotating directions find them. */
static double valley(const double *x, void *user)
{
    const int *count = user;
    (void)count;
    double f = 0;
    for (int i = 0; i < 6; i += 2) {
        double u = (x[i] + x[i + 1] - 1.0) / sqrt(2.0), v = (x[i] - x[i + 1]) / sqrt(2.0);
        f += u * u + 1e4 * v * v;
    }
    return f;
}

static void test_rotation_helps(void **state)
{
    (void)state;
    hk_RosenbrockOptions o = hk_default_rosenbrock_options();
    o.max_stages = 100000;
    o.epsilon = 1e-12;
    double x[6] = {3, -2, 1, 4, -3, 0};
    hk_MinimizeResult rotating;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(6, x, valley, NULL, &o, &rotating, &err), HK_OK);
    for (int i = 0; i < 6; i++) hk_assert_near(x[i], 0.5, 1e-4);
    /* The same search with the rotation disabled (one stage at a time, restarted on
     * the coordinate axes) needs many more evaluations to get as low. */
    double y[6] = {3, -2, 1, 4, -3, 0};
    hk_RosenbrockOptions one = o;
    one.max_stages = 1;
    long evaluations = 0;
    double f = valley(y, NULL);
    /* Capped: past 20x the rotating search's effort the point is made. */
    for (int stage = 0; f > rotating.f && evaluations < 20 * rotating.evaluations; stage++) {
        hk_MinimizeResult r;
        assert_int_equal(hk_rosenbrock_minimize(6, y, valley, NULL, &one, &r, &err), HK_OK);
        evaluations += r.evaluations;
        f = r.f;
    }
    print_message("valley: rotating %ld evaluations; axis-aligned %ld evaluations reach only f = %.3g\n",
                  rotating.evaluations, evaluations, f);
    assert_true(evaluations > 3 * rotating.evaluations);
}

static void test_limits(void **state)
{
    (void)state;
    hk_RosenbrockOptions o = hk_default_rosenbrock_options();
    o.max_stages = 3;
    o.epsilon = 0.0;
    double x[2] = {-1.2, 1.0};
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_rosenbrock_minimize(2, x, banana, NULL, &o, &r, &err), HK_OK);
    assert_int_equal(r.iterations, 3);
    assert_false(r.converged);
    o.max_stages = 1000;
    o.max_evaluations = 50;
    x[0] = -1.2, x[1] = 1.0;
    assert_int_equal(hk_rosenbrock_minimize(2, x, banana, NULL, &o, &r, &err), HK_OK);
    assert_true(r.evaluations <= 50);
    assert_false(r.converged);
    hk_assert_near(r.f, banana(x, NULL), 0.0); /* x and f agree */
}

static int nan_calls;
static double nan_after_start(const double *x, void *user)
{
    (void)user;
    return nan_calls++ == 0 ? x[0] * x[0] : NAN;
}

static void test_errors_and_nan(void **state)
{
    (void)state;
    hk_RosenbrockOptions o = hk_default_rosenbrock_options();
    o.max_evaluations = 100000;
    double x[2] = {1, 1};
    hk_MinimizeResult r;
    hk_Error err;
    /* NaN trials are failures: the search ends (by its evaluation limit or by steps too
     * small to move x) instead of hanging, and x is left at the finite start. */
    assert_int_equal(hk_rosenbrock_minimize(2, x, nan_after_start, NULL, &o, &r, &err), HK_OK);
    hk_assert_near(x[0], 1.0, 0.0);
    assert_int_equal(hk_rosenbrock_minimize(0, x, banana, NULL, &o, &r, &err), HK_ERR_INVALID);
    o.beta = 1.5;
    assert_int_equal(hk_rosenbrock_minimize(2, x, banana, NULL, &o, &r, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "rosenbrock");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_palmer_equals_gram_schmidt),
        cmocka_unit_test(test_palmer_degenerate_advances),
        cmocka_unit_test(test_banana),
        cmocka_unit_test(test_rotation_helps),
        cmocka_unit_test(test_limits),
        cmocka_unit_test(test_errors_and_nan),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
