/* Super-Helix reconstruction (Bertails et al. 2006 §3.2, Appendix A): exact helices, straight
 * rods, C1 continuity between elements, inextensibility, natural curliness formulas
 * and the root frame of thesis §4.1.4.1. */
#include "hk_test.h"

#include <math.h>

#include "hairkit/rod.h"

static const double pi = HK_PI;

static hk_SuperHelix *make_strand(int n, double length)
{
    double len[64], sum = 0.0;
    for (int i = 0; i < n; i++) sum += len[i] = 1.0 + 0.3 * sin(1.7 * i); /* uneven elements */
    for (int i = 0; i < n; i++) len[i] *= length / sum;
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, len, &sh, &err), HK_OK);
    return sh;
}

static void test_natural_curvature_formulas(void **state)
{
    (void)state;
    double tau, k1;
    /* DESIGN.md: c = Delta / 2 pi, kappa = r / (r^2 + c^2), tau = c / (r^2 + c^2). */
    hk_helix_natural_curvature(0.01, 0.005, &tau, &k1);
    const double c = 0.005 / (2 * pi);
    hk_assert_rel(k1, 0.01 / (1e-4 + c * c), 1e-15, 0);
    hk_assert_rel(tau, c / (1e-4 + c * c), 1e-15, 0);
    /* Small pitch: the paper's 1/r_h and Delta/(2 pi r_h^2) are the limit. */
    hk_helix_natural_curvature(0.01, 1e-6, &tau, &k1);
    hk_assert_rel(k1, 100.0, 1e-6, 0);
    hk_assert_rel(tau, 1e-6 / (2 * pi * 1e-4), 1e-6, 0);
    /* HelixRadius 0 is straight hair whatever the step. */
    hk_helix_natural_curvature(0.0, 0.05, &tau, &k1);
    assert_true(tau == 0.0 && k1 == 0.0);
}

/* With uniform (tau, kappa1, 0) the strand is one exact helix of radius r and pitch
 * 2 pi c whatever N (Bertails et al. 2006 §3.2): check every sample against the analytic curve. */
static void check_exact_helix(int n, double r_h, double step)
{
    hk_SuperHelix *sh = make_strand(n, 0.5);
    double tau, k1;
    hk_helix_natural_curvature(r_h, step, &tau, &k1);
    hk_superhelix_set_uniform_rest(sh, tau, k1, 0.0);
    sh->root = hk_v3(0.1, -0.2, 0.3);
    sh->root_frame = hk_root_frame(hk_v3(0.3, -1.0, 0.2));
    /* Helix axis: the Darboux vector tau n0 + kappa1 n1 at the root. */
    const hk_Vec3 n0 = hk_m3_col(&sh->root_frame, 0), n1 = hk_m3_col(&sh->root_frame, 1);
    const double omega = sqrt(tau * tau + k1 * k1);
    const hk_Vec3 axis = hk_v3_scale(hk_v3_add(hk_v3_scale(n0, tau), hk_v3_scale(n1, k1)), 1.0 / omega);
    /* The centreline's centre of curvature at s = 0 lies on the axis: r - n2 ... use
     * the closed-form helix: r(s) = a + r_h (cos(w s) e1 + sin(w s) e2) + c w s axis. */
    const double c = step / (2 * pi);
    const hk_Vec3 t_perp = hk_v3_sub(n0, hk_v3_scale(axis, hk_v3_dot(n0, axis)));
    const hk_Vec3 e2 = hk_v3_normalize(t_perp); /* direction of motion around the axis */
    const hk_Vec3 e1 = hk_v3_cross(e2, axis);   /* from axis to the curve at s = 0 */
    const hk_Vec3 centre = hk_v3_sub(sh->root, hk_v3_scale(e1, r_h));
    const int count = 200;
    for (int j = 0; j <= count; j++) {
        double s = sh->total_length * j / count;
        hk_Vec3 p;
        hk_superhelix_eval(sh, NULL, s, &p, NULL);
        double ang = omega * s;
        hk_Vec3 ref = hk_v3_add(centre, hk_v3_add(hk_v3_scale(e1, r_h * cos(ang)), hk_v3_scale(e2, r_h * sin(ang))));
        ref = hk_v3_madd(ref, axis, c * omega * s);
        /* Agreement to 1e-13 m over 0.5 m of strand (tens of turns). */
        hk_assert_near(hk_v3_dist(p, ref), 0.0, 1e-13);
    }
    hk_superhelix_destroy(sh);
}

static void test_exact_helix(void **state)
{
    (void)state;
    check_exact_helix(1, 0.01, 0.005);  /* Bertails et al. 2006 Appendix B, wavy */
    check_exact_helix(7, 0.006, 0.005); /* curly */
    check_exact_helix(5, 0.001, 0.01);  /* fuzzy: many turns per element */
    check_exact_helix(3, 0.02, -0.01);  /* left-handed */
}

static void test_straight_and_twisted_rods(void **state)
{
    (void)state;
    hk_SuperHelix *sh = make_strand(4, 0.2);
    sh->root = hk_v3(1, 2, 3);
    sh->root_frame = hk_root_frame(hk_v3(0, 0, -1));
    const hk_Vec3 n0 = hk_m3_col(&sh->root_frame, 0);
    /* Pure twist (kappa = 0): the centreline stays straight, the frame spins at tau. */
    hk_superhelix_set_uniform_rest(sh, 250.0, 0.0, 0.0);
    for (int j = 0; j <= 50; j++) {
        double s = 0.2 * j / 50;
        hk_Vec3 p;
        hk_Mat3 f;
        hk_superhelix_eval(sh, NULL, s, &p, &f);
        hk_Vec3 ref = hk_v3_madd(sh->root, n0, s);
        hk_assert_near(hk_v3_dist(p, ref), 0.0, 1e-15);
        hk_Vec3 n1 = hk_m3_col(&f, 1), n1_0 = hk_m3_col(&sh->root_frame, 1);
        hk_assert_near(hk_v3_dot(n1, n1_0), cos(250.0 * s), 1e-13);
    }
    /* Zero and vanishing curvatures (deep inside the series branch): no division by a
     * small |Omega|, the strand stays on the straight line up to the true deviation of
     * a curve of curvature kappa, kappa L^2 / 2 (1e-14 m for 1e-12 / m over 0.2 m). */
    const double tiny[] = {0.0, 1e-300, 1e-12};
    for (int t = 0; t < 3; t++) {
        hk_superhelix_set_uniform_rest(sh, tiny[t], -tiny[t], tiny[t]);
        hk_Vec3 tip;
        hk_superhelix_eval(sh, NULL, 0.2, &tip, NULL);
        assert_true(hk_v3_isfinite(tip));
        hk_assert_near(hk_v3_dist(tip, hk_v3_madd(sh->root, n0, 0.2)), 0.0,
                       0.5 * sqrt(2.0) * tiny[t] * 0.04 + 4e-16 * 4);
    }
    hk_superhelix_destroy(sh);
}

static void test_c1_continuity_and_inextensibility(void **state)
{
    (void)state;
    hk_SuperHelix *sh = make_strand(6, 0.3);
    for (int i = 0; i < 18; i++) sh->q[i] = 60.0 * sin(0.9 * i + 0.4) + 5.0 * cos(2.1 * i);
    sh->root_frame = hk_root_frame(hk_v3(1, 0.2, -0.4));
    hk_Vec3 nodes[7];
    hk_Mat3 frames[7];
    hk_superhelix_nodes(sh, NULL, nodes, frames);
    for (int e = 1; e < 6; e++) {
        double s = sh->s_start[e];
        /* The node pose equals the end of the previous element and the start of the next. */
        hk_Vec3 p;
        hk_Mat3 f;
        hk_superhelix_eval(sh, NULL, s, &p, &f);
        hk_assert_near(hk_v3_dist(p, nodes[e]), 0.0, 1e-15);
        /* One-sided derivatives of r and of the frame agree (C1): dr/ds = n0 both sides. */
        const double h = 1e-7;
        hk_Vec3 pm, pp;
        hk_superhelix_eval(sh, NULL, s - h, &pm, NULL);
        hk_superhelix_eval(sh, NULL, s + h, &pp, NULL);
        hk_Vec3 left = hk_v3_scale(hk_v3_sub(nodes[e], pm), 1.0 / h);
        hk_Vec3 right = hk_v3_scale(hk_v3_sub(pp, nodes[e]), 1.0 / h);
        hk_Vec3 t = hk_m3_col(&frames[e], 0);
        /* One-sided differences are accurate to h kappa / 2 ~ 1e-5. */
        hk_assert_near(hk_v3_dist(left, t), 0.0, 2e-5);
        hk_assert_near(hk_v3_dist(right, t), 0.0, 2e-5);
    }
    /* Orthonormal frames and unit speed everywhere (inextensible, unshearable). */
    for (int j = 0; j < 300; j++) {
        double s = 0.3 * (j + 0.5) / 300;
        hk_Mat3 f;
        hk_Vec3 p0, p1, p2;
        hk_superhelix_eval(sh, NULL, s, &p0, &f);
        hk_Mat3 ftf = hk_m3_transpose(&f);
        ftf = hk_m3_mul(&ftf, &f);
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) hk_assert_near(ftf.m[a][b], a == b, 1e-14);
        const double h = 1e-6;
        hk_superhelix_eval(sh, NULL, s - h, &p1, NULL);
        hk_superhelix_eval(sh, NULL, s + h, &p2, NULL);
        hk_Vec3 t = hk_v3_scale(hk_v3_sub(p2, p1), 0.5 / h);
        hk_assert_near(hk_v3_dist(t, hk_m3_col(&f, 0)), 0.0, 1e-7);
    }
    hk_superhelix_destroy(sh);
}

static void test_sampling(void **state)
{
    (void)state;
    hk_SuperHelix *sh = make_strand(3, 0.1);
    for (int i = 0; i < 9; i++) sh->q[i] = 20.0 * cos(i);
    /* 0.1 / 0.03: samples 0, 0.03, 0.06, 0.09 and the tip. */
    assert_int_equal(hk_superhelix_sample_count(sh, 0.03), 5);
    /* Exact multiple: the last regular sample is the tip, not repeated. */
    assert_int_equal(hk_superhelix_sample_count(sh, 0.025), 5);
    double s[5];
    hk_Vec3 p[5], t[5];
    hk_superhelix_sample(sh, NULL, 0.03, s, p, t);
    hk_assert_near(s[4], sh->total_length, 0.0);
    for (int j = 0; j < 5; j++) {
        hk_Vec3 ref;
        hk_Mat3 f;
        hk_superhelix_eval(sh, NULL, s[j], &ref, &f);
        hk_assert_near(hk_v3_dist(p[j], ref), 0.0, 1e-16);
        hk_assert_near(hk_v3_dist(t[j], hk_m3_col(&f, 0)), 0.0, 1e-15);
    }
    hk_superhelix_destroy(sh);
}

static void test_root_frame(void **state)
{
    (void)state;
    /* Thesis §4.1.4.1: n1 = n0 x y / |...|, fallback (0,0,1) for vertical n0, n2 = n0 x n1. */
    hk_Mat3 f = hk_root_frame(hk_v3(2, 0, 0));
    hk_assert_near(hk_v3_dist(hk_m3_col(&f, 0), hk_v3(1, 0, 0)), 0, 0);
    hk_assert_near(hk_v3_dist(hk_m3_col(&f, 1), hk_v3(0, 0, 1)), 0, 0);
    hk_assert_near(hk_v3_dist(hk_m3_col(&f, 2), hk_v3(0, -1, 0)), 0, 0);
    f = hk_root_frame(hk_v3(0, -3, 0));
    hk_assert_near(hk_v3_dist(hk_m3_col(&f, 1), hk_v3(0, 0, 1)), 0, 0);
    hk_assert_near(hk_v3_dist(hk_m3_col(&f, 2), hk_v3_cross(hk_v3(0, -1, 0), hk_v3(0, 0, 1))), 0, 0);
    f = hk_root_frame(hk_v3(0.3, 0.5, -0.8));
    hk_Mat3 ftf = hk_m3_transpose(&f);
    ftf = hk_m3_mul(&ftf, &f);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) hk_assert_near(ftf.m[a][b], a == b, 1e-15);
    hk_assert_near(hk_m3_col(&f, 1).y, 0.0, 1e-16); /* n1 horizontal */
}

static void test_invalid_strands(void **state)
{
    (void)state;
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    double bad[2] = {0.1, -0.1};
    assert_int_equal(hk_superhelix_create(2, bad, &sh, &err), HK_ERR_INVALID);
    assert_null(sh);
    hk_assert_contains(err.message, "element 2");
    assert_int_equal(hk_superhelix_create(0, bad, &sh, &err), HK_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_natural_curvature_formulas),
        cmocka_unit_test(test_exact_helix),
        cmocka_unit_test(test_straight_and_twisted_rods),
        cmocka_unit_test(test_c1_continuity_and_inextensibility),
        cmocka_unit_test(test_sampling),
        cmocka_unit_test(test_root_frame),
        cmocka_unit_test(test_invalid_strands),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
