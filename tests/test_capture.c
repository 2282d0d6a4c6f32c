/* Captured shapes made into Super-Helices at rest (hairkit/capture.h):
 * - the fit recovers known Super-Helices (sampled finely, so that the root tangent the
 *   fit estimates is exact to ~1e-5) and follows curves outside the model to its
 *   tolerance by choosing N;
 * - the inverse statics against the forward statics (Newton's minimiser, a second
 *   method): a strand at rest under gravity, sampled, fitted and inverted, gets back the
 *   natural shape it was solved with, and the forward statics of the inverted strand
 *   from that natural shape returns the captured shape;
 * - stability against Greenhill's critical height of a column standing under its own
 *   weight, clamped at its foot (A. G. Greenhill, "Determination of the greatest height
 *   consistent with stability that a vertical pole or mast can be made", Proc. Cambridge
 *   Phil. Soc. 4, 1881): l_c = (7.8373 EI / w)^(1/3), w the weight per length.
 * Real grooms are fitted in test_capture_data.c. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/capture.h"
#include "hairkit/statics.h"

/* A curly strand of n equal elements with varied curvatures, root frame as the fit
 * makes it (hk_root_frame of its root tangent). */
static hk_SuperHelix *known_strand(int n, double length, hk_Vec3 root, hk_Vec3 dir)
{
    double lengths[64] = {0};
    for (int e = 0; e < n; e++) lengths[e] = length / n;
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, lengths, &sh, &err), HK_OK);
    sh->root = root;
    sh->root_frame = hk_root_frame(dir);
    for (int e = 0; e < n; e++) {
        sh->q[3 * e] = 15.0 * sin(1.3 * e + 0.2);
        sh->q[3 * e + 1] = 40.0 + 12.0 * cos(0.7 * e);
        sh->q[3 * e + 2] = 10.0 * sin(2.1 * e + 1.0);
    }
    memcpy(sh->q_rest, sh->q, (size_t)(3 * n) * sizeof(double));
    return sh;
}

/* count points of sh at equal arc-length steps from the root to the tip. */
static hk_Vec3 *sample(const hk_SuperHelix *sh, const double *q, int count)
{
    double *s = malloc((size_t)count * sizeof *s);
    hk_Vec3 *p = malloc((size_t)count * sizeof *p);
    for (int j = 0; j < count; j++) s[j] = sh->total_length * j / (count - 1);
    hk_superhelix_points(sh, q, s, count, p);
    free(s);
    return p;
}

static void test_fit_recovers_known_strand(void **state)
{
    (void)state;
    const int n = 8;
    hk_SuperHelix *truth = known_strand(n, 0.2, hk_v3(0.1, 1.6, 0.05), hk_v3(0.2, -1.0, 0.4));
    hk_Vec3 *pts = sample(truth, NULL, 1001);
    hk_SuperHelixFitDef def = hk_default_superhelix_fit_def();
    def.elements = n;
    hk_SuperHelix *fit = NULL;
    hk_SuperHelixFitReport rep;
    hk_Error err;
    assert_int_equal(hk_superhelix_fit(pts, 1001, NULL, &def, &fit, &rep, &err), HK_OK);
    print_message("known strand: N %d, mean %.3g m, max %.3g m, %d iterations\n", rep.elements, rep.mean_error,
                  rep.max_error, rep.iterations);
    assert_int_equal(rep.elements, n);
    /* the polyline is shorter than the curve by kappa^2 h^3 / 24 per chord of length h:
     * with h = 0.2 mm and kappa <= 55/m, by at most 5e-6 of the length */
    hk_assert_rel(rep.length, 0.2, 5e-6, 0.0);
    assert_true(rep.length < 0.2);
    assert_true(rep.max_error < 2e-6);
    double top = 0.0;
    for (int i = 0; i < 3 * n; i++) {
        top = fmax(top, fabs(fit->q[i] - truth->q[i]));
        assert_true(fit->q_rest[i] == fit->q[i]);
    }
    print_message("largest curvature difference %.3g 1/m (curvatures up to %.0f 1/m)\n", top, 52.0);
    assert_true(top < 0.05);
    free(pts);
    hk_superhelix_destroy(fit);
    hk_superhelix_destroy(truth);
}

/* A curve that no Super-Helix of few elements follows: N doubles until the mean error
 * is below the tolerance, and the error reported is the one measured here again. */
static void test_fit_chooses_elements(void **state)
{
    (void)state;
    enum { COUNT = 200 };
    hk_Vec3 pts[COUNT];
    for (int j = 0; j < COUNT; j++) {
        const double t = 0.25 * j / (COUNT - 1);
        pts[j] = hk_v3(0.01 * sin(40.0 * t) + 0.004 * t, -t, 0.012 * (1.0 - cos(25.0 * t * (1.0 + t))));
    }
    hk_SuperHelixFitDef def = hk_default_superhelix_fit_def();
    def.element_length = 0.05;
    hk_SuperHelix *fit = NULL;
    hk_SuperHelixFitReport rep;
    hk_Error err;
    assert_int_equal(hk_superhelix_fit(pts, COUNT, NULL, &def, &fit, &rep, &err), HK_OK);
    print_message("curve: N %d, mean %.3g m, max %.3g m\n", rep.elements, rep.mean_error, rep.max_error);
    assert_true(rep.elements > 6); /* more than the first ceil(L / 5 cm) */
    assert_true(rep.mean_error <= def.tolerance);
    /* the report against the Super-Helix evaluated at the points' arc lengths */
    double s = 0.0, sum = 0.0, top = 0.0;
    for (int j = 1; j < COUNT; j++) {
        s += hk_v3_norm(hk_v3_sub(pts[j], pts[j - 1]));
        hk_Vec3 at;
        hk_superhelix_eval(fit, NULL, s, &at, NULL);
        const double d = hk_v3_norm(hk_v3_sub(at, pts[j]));
        sum += d;
        top = fmax(top, d);
    }
    hk_assert_rel(rep.mean_error, sum / (COUNT - 1), 1e-9, 1e-15);
    hk_assert_rel(rep.max_error, top, 1e-9, 1e-15);
    hk_superhelix_destroy(fit);
}

static void test_fit_refuses_bad_input(void **state)
{
    (void)state;
    hk_SuperHelix *fit = NULL;
    hk_Error err;
    hk_Vec3 same[3] = {hk_v3(1, 2, 3), hk_v3(1, 2, 3), hk_v3(1, 2, 3)};
    assert_int_equal(hk_superhelix_fit(same, 3, NULL, NULL, &fit, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "no length");
    assert_null(fit);
    assert_int_equal(hk_superhelix_fit(same, 1, NULL, NULL, &fit, NULL, &err), HK_ERR_INVALID);
    hk_Vec3 nan[2] = {hk_v3(0, 0, 0), hk_v3(NAN, 0, 0)};
    assert_int_equal(hk_superhelix_fit(nan, 2, NULL, NULL, &fit, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 2 is not finite");
    hk_SuperHelixFitDef def = hk_default_superhelix_fit_def();
    def.elements = 100000;
    hk_Vec3 line[2] = {hk_v3(0, 0, 0), hk_v3(0, -0.1, 0)};
    assert_int_equal(hk_superhelix_fit(line, 2, NULL, &def, &fit, NULL, &err), HK_ERR_INVALID);
    /* two points: a straight strand, exactly */
    hk_SuperHelixFitReport rep;
    assert_int_equal(hk_superhelix_fit(line, 2, NULL, NULL, &fit, &rep, &err), HK_OK);
    assert_int_equal(rep.elements, 1);
    assert_true(rep.max_error < 1e-12);
    hk_superhelix_destroy(fit);
}

/* Hair of 50 um radius, Young 3 GPa, 1300 kg/m^3, gravity -y. */
static hk_RodMaterial hair_material(void)
{
    return hk_rod_material(5e-5, 5e-5, 3e9, 0.48, 1300.0, hk_v3(0.0, -9.81, 0.0));
}

static void test_inverse_matches_forward_statics(void **state)
{
    (void)state;
    const int n = 10;
    hk_SuperHelix *truth = known_strand(n, 0.15, hk_v3(0.0, 0.0, 0.0), hk_v3(1.0, 0.3, 0.0));
    truth->material = hair_material();
    for (int e = 0; e < n; e++) truth->q_rest[3 * e + 1] *= 0.5, truth->q[3 * e + 1] *= 0.5;
    double q_rest[30];
    memcpy(q_rest, truth->q_rest, sizeof q_rest);
    hk_StaticsDef statics = hk_default_statics_def();
    statics.newton.tolerance = 1e-20;
    statics.newton.max_iterations = 200;
    hk_MinimizeResult res;
    hk_Error err;
    assert_int_equal(hk_statics_solve(truth, NULL, &statics, &res, &err), HK_OK);
    assert_true(res.converged);

    /* 1. The rest shape itself inverted: the natural shape comes back. */
    hk_SuperHelix *copy = NULL;
    double lengths[10] = {0};
    for (int e = 0; e < n; e++) lengths[e] = truth->length[e];
    assert_int_equal(hk_superhelix_create(n, lengths, &copy, &err), HK_OK);
    copy->material = truth->material;
    copy->root = truth->root;
    copy->root_frame = truth->root_frame;
    memcpy(copy->q, truth->q, sizeof q_rest);
    hk_InverseStaticsReport rep;
    assert_int_equal(hk_statics_invert(copy, NULL, NULL, &rep, &err), HK_OK);
    assert_true(rep.stable);
    assert_false(rep.settled);
    double top = 0.0, sag = 0.0;
    for (int i = 0; i < 3 * n; i++) {
        top = fmax(top, fabs(copy->q_rest[i] - q_rest[i]));
        sag = fmax(sag, fabs(truth->q[i] - q_rest[i]));
    }
    print_message("inverse of the rest shape: natural shape within %.3g 1/m (gravity bends by up to %.3g 1/m)\n", top,
                  sag);
    assert_true(sag > 1.0); /* gravity matters here */
    assert_true(top < 1e-6 * sag);

    /* 2. The rest shape as a capture: sampled, fitted, inverted, then solved forward from
     * the natural shape found: the capture again. */
    hk_Vec3 *pts = sample(truth, NULL, 601);
    hk_SuperHelixFitDef def = hk_default_superhelix_fit_def();
    def.elements = n;
    hk_SuperHelix *fit = NULL;
    hk_RodMaterial mat = hair_material();
    hk_SuperHelixFitReport fitted;
    assert_int_equal(hk_superhelix_fit(pts, 601, &mat, &def, &fit, &fitted, &err), HK_OK);
    print_message("the capture fitted: mean %.3g m, max %.3g m, %d iterations\n", fitted.mean_error, fitted.max_error,
                  fitted.iterations);
    double fitted_q[30];
    memcpy(fitted_q, fit->q, sizeof fitted_q);
    assert_int_equal(hk_statics_invert(fit, NULL, NULL, &rep, &err), HK_OK);
    assert_true(rep.stable);
    memcpy(fit->q, fit->q_rest, sizeof q_rest);
    assert_int_equal(hk_statics_solve(fit, NULL, &statics, &res, &err), HK_OK);
    double back = 0.0, worst = 0.0;
    for (int j = 0; j < 601; j += 20) {
        const double s = truth->total_length * j / 600;
        hk_Vec3 at, was;
        hk_superhelix_eval(fit, NULL, s, &at, NULL);
        hk_superhelix_eval(fit, fitted_q, s, &was, NULL);
        back = fmax(back, hk_v3_norm(hk_v3_sub(at, was)));
        worst = fmax(worst, hk_v3_norm(hk_v3_sub(at, pts[j])));
    }
    print_message("fitted, inverted and solved forward from its natural shape: within %.3g m of the fitted\n"
                  "shape, %.3g m of the capture\n",
                  back, worst);
    assert_true(back < 1e-7);
    assert_true(worst < fitted.max_error + 1e-7);
    free(pts);
    hk_superhelix_destroy(fit);
    hk_superhelix_destroy(copy);
    hk_superhelix_destroy(truth);
}

/* A straight strand standing up from a clamped root: its shape is an equilibrium for
 * any natural shape equal to it; stable below Greenhill's height, not above. */
static void check_column(double height_ratio, int expect_stable)
{
    const hk_RodMaterial mat = hair_material();
    const double w = mat.mass_per_length * 9.81, critical = cbrt(7.8373 * mat.stiffness[1] / w);
    const int n = 20;
    double lengths[20] = {0};
    for (int e = 0; e < n; e++) lengths[e] = height_ratio * critical / n;
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, lengths, &sh, &err), HK_OK);
    sh->material = mat;
    sh->root_frame = hk_root_frame(hk_v3(0.0, 1.0, 0.0));
    hk_InverseStaticsReport rep;
    assert_int_equal(hk_statics_invert(sh, NULL, NULL, &rep, &err), HK_OK);
    hk_Vec3 tip;
    hk_superhelix_eval(sh, NULL, sh->total_length, &tip, NULL);
    print_message("column of %.2f x Greenhill's %.1f mm: %s, drift %.1f mm, tip height %.1f mm\n", height_ratio,
                  1e3 * critical, rep.stable ? "stable" : "unstable", 1e3 * rep.drift, 1e3 * tip.y);
    assert_int_equal(rep.stable, expect_stable);
    assert_true(rep.rest_change < 1e-9); /* gravity along a straight column bends nothing */
    if (expect_stable) {
        assert_false(rep.settled);
        hk_assert_near(tip.y, sh->total_length, 1e-12);
    } else {
        assert_true(rep.settled);
        assert_true(tip.y < 0.9 * sh->total_length); /* it fell over */
        assert_true(rep.drift > 0.1 * sh->total_length);
    }
    hk_superhelix_destroy(sh);
}

static void test_stability_greenhill(void **state)
{
    (void)state;
    check_column(0.95, 1);
    check_column(1.05, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_recovers_known_strand), cmocka_unit_test(test_fit_chooses_elements),
        cmocka_unit_test(test_fit_refuses_bad_input),     cmocka_unit_test(test_inverse_matches_forward_statics),
        cmocka_unit_test(test_stability_greenhill),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
