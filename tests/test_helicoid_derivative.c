/* The derivatives of a traced helicoid piece with respect to its parameters
 * (hk_helicoid_piece_derivative: forward-mode differentiation through the RK4 steps,
 * Piuze et al. 2011 §3 eq. 1-2) against an independent reference: central differences of
 * the model itself (hk_helicoid_piece_model), points and end tangent; and fits that use
 * them against fits with forward-difference Jacobians. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/helicoid_fit.h"
#include "helicoid/helicoid_internal.h"

#define COUNT 30

static double rnd(double lo, double hi) { return lo + (hi - lo) * hk_test_uniform(); }

/* Central differences of the model in parameter j with step d: points and end tangent. */
static void central(hk_HelicoidFitter *f, const double *k, int j, double d, const hk_CurveStart *s, double length,
                    hk_Vec3 *dp, hk_Vec3 *dt)
{
    double a[4], b[4];
    memcpy(a, k, sizeof a);
    memcpy(b, k, sizeof b);
    a[j] += d, b[j] -= d;
    hk_Vec3 pa[COUNT], pb[COUNT];
    hk_CurveStart ea, eb;
    assert_int_equal(hk_helicoid_piece_model(f, a, s, length, COUNT, pa, &ea), 0);
    assert_int_equal(hk_helicoid_piece_model(f, b, s, length, COUNT, pb, &eb), 0);
    for (int i = 0; i < COUNT; i++) dp[i] = hk_v3_scale(hk_v3_sub(pa[i], pb[i]), 0.5 / d);
    *dt = hk_v3_scale(hk_v3_sub(hk_m3_col(&ea.frame, 0), hk_m3_col(&eb.frame, 0)), 0.5 / d);
}

/* Random pieces with alpha != 0 (the model's own trace is then RK4, the same steps as
 * the differentiated one; with alpha = 0 it is a closed form, exact, and the two differ
 * by RK4's error) and curvatures up to 150 / m (up to 4 RK4 substeps per sample, which
 * the tangents follow). Steps of the differences: 1e-4 per metre for the curvatures (the
 * parameters are tens per metre), 1e-6 for alpha, where the differences are best: a ten
 * times smaller step makes their misses ten times larger (rounding of the traced points
 * divided by the step), a ten times larger one too (truncation). They agree with the
 * derivatives to 6e-9 of a column's largest entry at worst; checked to 1e-7. */
static void test_piece_derivative_matches_differences(void **state)
{
    (void)state;
    hk_Error err;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(COUNT, &err);
    assert_non_null(f);
    double worst = 0.0;
    for (int t = 0; t < 40; t++) {
        const double k[4] = {rnd(-150, 150), rnd(-8, 8), rnd(-20, 20), rnd(0.05, 1.5) * (t % 2 ? 1 : -1)};
        const double length = rnd(0.02, 0.1);
        hk_CurveStart s = {hk_v3(rnd(-0.1, 0.1), rnd(0, 0.2), rnd(-0.1, 0.1)),
                           hk_helicoid_frame(rnd(-3, 3), rnd(-1, 1))};
        hk_Vec3 p[COUNT], q[COUNT], dp[4 * COUNT], dt[4];
        hk_CurveStart e, eq;
        if (hk_helicoid_piece_model(f, k, &s, length, COUNT, q, &eq) != 0) continue; /* a refused piece */
        assert_int_equal(hk_helicoid_piece_derivative(f, k, &s, length, COUNT, p, &e, dp, dt), 0);
        for (int i = 0; i < COUNT; i++) assert_true(hk_v3_dist(p[i], q[i]) < 1e-14);
        assert_true(hk_v3_dist(hk_m3_col(&e.frame, 0), hk_m3_col(&eq.frame, 0)) < 1e-12);
        for (int j = 0; j < 4; j++) {
            hk_Vec3 ref[COUNT], ref_t;
            central(f, k, j, (j == 3 ? 1e-6 : 1e-4), &s, length, ref, &ref_t);
            double size = 0.0, miss = 0.0;
            for (int i = 0; i < COUNT; i++) {
                size = fmax(size, hk_v3_norm(ref[i]));
                miss = fmax(miss, hk_v3_dist(ref[i], dp[j * COUNT + i]));
            }
            assert_true(miss <= 1e-7 * size);
            assert_true(hk_v3_dist(ref_t, dt[j]) <= 1e-7 * fmax(hk_v3_norm(ref_t), 1e-3));
            worst = fmax(worst, miss / size);
        }
    }
    print_message("  d points / d k against central differences: largest miss %.2g of the column\n", worst);
    hk_helicoid_fitter_destroy(f);
}

/* The fitter's search trace (hk_helicoid_piece_rk4_local: phases carried as unknowns,
 * RK4 steps of up to 0.5 rad over up to 4 samples) and its differentiated form
 * (hk_helicoid_piece_rk4_tangent_local): the same points and end bytes, and derivatives
 * that agree with central differences of the plain trace as the standard tracer's do
 * (1e-7 of a column), except where a difference straddles a change in the plan of steps
 * (a span or substep count switching with the parameters, where the trace jumps by its
 * RK4 error): at most 2 columns in 160, and those within 1e-5. */
static void test_search_trace_derivative(void **state)
{
    (void)state;
    enum { STEPS = COUNT - 1 };
    int pieces = 0, over = 0;
    double worst = 0.0;
    for (int t = 0; pieces < 40 && t < 1000; t++) {
        const hk_Helicoid k = {rnd(-150, 150), rnd(-8, 8), rnd(-20, 20), rnd(0.05, 1.5) * (t % 2 ? 1 : -1)};
        const double length = rnd(0.02, 0.1);
        double per_w, constant;
        hk_helicoid_turn_bound(&k, &per_w, &constant);
        if (!((per_w + constant) * length / STEPS <= 1.0)) continue; /* the fitter's resolution rule */
        hk_Vec3 p[COUNT], q[COUNT], dp[4 * COUNT], dt[4];
        hk_HelicoidAngles a, b;
        hk_helicoid_piece_rk4_local(&k, length, STEPS, 0.5, 4, p, &a);
        hk_helicoid_piece_rk4_tangent_local(&k, length, STEPS, 0.5, 4, q, dp, &b, dt);
        assert_memory_equal(p, q, sizeof p);
        assert_memory_equal(&a, &b, sizeof a);
        pieces++;
        for (int j = 0; j < 4; j++) {
            const double d = j == 3 ? 1e-6 : 1e-4;
            hk_Helicoid kp = k, km = k;
            double *xp = &kp.kt, *xm = &km.kt;
            xp[j] += d, xm[j] -= d;
            hk_Vec3 pa[COUNT], pb[COUNT];
            hk_HelicoidAngles ea, eb;
            hk_helicoid_piece_rk4_local(&kp, length, STEPS, 0.5, 4, pa, &ea);
            hk_helicoid_piece_rk4_local(&km, length, STEPS, 0.5, 4, pb, &eb);
            double size = 0.0, miss = 0.0;
            for (int i = 0; i < COUNT; i++) {
                const hk_Vec3 ref = hk_v3_scale(hk_v3_sub(pa[i], pb[i]), 0.5 / d);
                size = fmax(size, hk_v3_norm(ref));
                miss = fmax(miss, hk_v3_dist(ref, dp[j * COUNT + i]));
            }
            const hk_Vec3 ta = hk_v3(ea.cp * ea.ct, ea.cp * ea.st, ea.sp),
                          tb = hk_v3(eb.cp * eb.ct, eb.cp * eb.st, eb.sp);
            const hk_Vec3 ref_t = hk_v3_scale(hk_v3_sub(ta, tb), 0.5 / d);
            assert_true(miss <= 1e-5 * size);
            assert_true(hk_v3_dist(ref_t, dt[j]) <= 1e-5 * fmax(hk_v3_norm(ref_t), 1e-3));
            over += miss > 1e-7 * size || hk_v3_dist(ref_t, dt[j]) > 1e-7 * fmax(hk_v3_norm(ref_t), 1e-3);
            worst = fmax(worst, miss / size);
        }
    }
    print_message("  search trace: %d pieces, d points / d k against central differences: largest miss %.2g of the "
                  "column, %d of %d columns over 1e-7\n",
                  pieces, worst, over, 4 * pieces);
    assert_int_equal(pieces, 40);
    assert_true(over <= 2);
}

/* Fits with the derivatives (the default) and with forward differences
 * (model_derivative = NULL) of strands traced from known two-piece helicoids, with the
 * root frame refined (noise on the first points): both recover the strands within the
 * tolerance; the derivatives use fewer traces. */
static void test_fits_agree(void **state)
{
    (void)state;
    hk_Error err;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(256, &err);
    assert_non_null(f);
    long with = 0, without = 0;
    for (int t = 0; t < 10; t++) {
        hk_PHelicoid h;
        memset(&h, 0, sizeof h);
        h.frame = hk_helicoid_frame(rnd(-3, 3), rnd(-1, 1));
        h.piece_count = 2;
        for (int p = 0; p < 2; p++) {
            h.k[p] = (hk_Helicoid){rnd(5, 30), rnd(-3, 3), rnd(-10, 10), rnd(-0.5, 0.5)};
            h.length[p] = rnd(0.04, 0.08);
        }
        const double step = 0.002;
        const int n = hk_phelicoid_point_count(&h, step);
        hk_Vec3 pts[256];
        assert_true(n > 0 && n <= 256);
        assert_int_equal(hk_phelicoid_trace(&h, step, NULL, NULL, pts, NULL, &err), HK_OK);
        for (int i = 1; i < n; i++) pts[i] = hk_v3_add(pts[i], hk_v3(rnd(-2e-5, 2e-5), rnd(-2e-5, 2e-5), 0.0));
        hk_CurveFitDef opt = hk_default_helicoid_fit_def();
        hk_PHelicoid out;
        hk_CurveFit a, b;
        assert_int_equal(hk_helicoid_fit(f, pts, n, &opt, &out, &a, &err), HK_OK);
        opt.model_derivative = NULL;
        assert_int_equal(hk_helicoid_fit(f, pts, n, &opt, &out, &b, &err), HK_OK);
        assert_true(a.error <= opt.tolerance);
        assert_true(b.error <= opt.tolerance);
        with += a.evaluations, without += b.evaluations;
    }
    print_message("  10 noisy two-piece strands: %ld model calls with derivatives, %ld with differences\n", with,
                  without);
    assert_true(with < without);
    hk_helicoid_fitter_destroy(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_piece_derivative_matches_differences),
        cmocka_unit_test(test_search_trace_derivative),
        cmocka_unit_test(test_fits_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
