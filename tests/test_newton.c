/* The generic Newton minimiser (src/optimize/newton.c) on functions with known minima:
 * a convex quadratic (one step), Rosenbrock's banana (non-convex start, damping
 * needed), an indefinite start, and the error paths. */
#include "hk_test.h"

#include <math.h>

#include "hairkit/statics.h"

/* f = 1/2 (x - c)^T A (x - c) with A = [[4, 1, 0], [1, 3, 1], [0, 1, 2]]. */
static double quadratic(void *user, const double *x, double *g, double *h)
{
    (void)user;
    static const double a[3][3] = {{4, 1, 0}, {1, 3, 1}, {0, 1, 2}}, c[3] = {1, -2, 3};
    double d[3] = {x[0] - c[0], x[1] - c[1], x[2] - c[2]}, f = 0.0;
    for (int i = 0; i < 3; i++) {
        double ad = 0.0;
        for (int j = 0; j < 3; j++) ad += a[i][j] * d[j];
        f += 0.5 * d[i] * ad;
        if (g) g[i] = ad;
        if (h)
            for (int j = 0; j < 3; j++) h[i * 3 + j] = a[i][j];
    }
    return f;
}

static void test_quadratic_in_one_step(void **state)
{
    (void)state;
    double x[3] = {10, 10, 10};
    hk_NewtonDef o = hk_default_newton_def();
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_newton_minimize(3, x, quadratic, NULL, NULL, &o, &r, &err), HK_OK);
    assert_true(r.converged);
    assert_int_equal(r.iterations, 1); /* Newton is exact on a quadratic */
    hk_assert_near(x[0], 1, 1e-12);
    hk_assert_near(x[1], -2, 1e-12);
    hk_assert_near(x[2], 3, 1e-12);
}

static double banana(void *user, const double *x, double *g, double *h)
{
    (void)user;
    double a = 1 - x[0], b = x[1] - x[0] * x[0];
    if (g) {
        g[0] = -2 * a - 400 * x[0] * b;
        g[1] = 200 * b;
    }
    if (h) {
        h[0] = 2 - 400 * b + 800 * x[0] * x[0];
        h[1] = h[2] = -400 * x[0];
        h[3] = 200;
    }
    return a * a + 100 * b * b;
}

static void test_banana(void **state)
{
    (void)state;
    /* From (-1.2, 1) and from (0, 0.5) where the Hessian is indefinite. */
    const double starts[2][2] = {{-1.2, 1.0}, {0.0, 0.5}};
    for (int s = 0; s < 2; s++) {
        double x[2] = {starts[s][0], starts[s][1]};
        hk_NewtonDef o = hk_default_newton_def();
        o.energy_scale = 1.0;
        hk_MinimizeResult r;
        hk_Error err;
        assert_int_equal(hk_newton_minimize(2, x, banana, NULL, NULL, &o, &r, &err), HK_OK);
        assert_true(r.converged);
        hk_assert_near(x[0], 1.0, 1e-7);
        hk_assert_near(x[1], 1.0, 1e-7);
        assert_true(r.iterations < 60);
    }
}

static double not_finite(void *user, const double *x, double *g, double *h)
{
    (void)x, (void)g, (void)h, (void)user;
    return NAN;
}

static void test_errors(void **state)
{
    (void)state;
    double x[2] = {0, 0};
    hk_NewtonDef o = hk_default_newton_def();
    hk_MinimizeResult r;
    hk_Error err;
    assert_int_equal(hk_newton_minimize(2, x, not_finite, NULL, NULL, &o, &r, &err), HK_ERR_NUMERIC);
    hk_assert_contains(err.message, "not finite");
    assert_int_equal(hk_newton_minimize(0, x, banana, NULL, NULL, &o, &r, &err), HK_ERR_INVALID);
    /* An iteration limit is reported as not converged, not as an error. */
    o.max_iterations = 2;
    double y[2] = {-1.2, 1.0};
    assert_int_equal(hk_newton_minimize(2, y, banana, NULL, NULL, &o, &r, &err), HK_OK);
    assert_false(r.converged);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_quadratic_in_one_step),
        cmocka_unit_test(test_banana),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
