/* Generalized helicoids (src/helicoid/, Piuze et al. 2011 §3-4.2): the field and its continued angle,
 * exact straight lines, circles and spirals, RK4 against closed forms and its order, p-helicoid
 * joins, waviness, the pi-rotation rule, wisps, IDW interpolation (guides reproduced, the
 * paper's Fig. 6 pair) and bad input. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/helicoid.h"
#include "helicoid/helicoid_internal.h"

static hk_Vec3 rand_unit(void)
{
    for (;;) {
        hk_Vec3 v = hk_v3(2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1);
        double n = hk_v3_norm(v);
        if (n > 0.1 && n <= 1.0) return hk_v3_scale(v, 1.0 / n);
    }
}

static hk_Mat3 rand_rotation(void)
{
    double q[4] = {2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1,
                   2 * hk_test_uniform() - 1};
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++) q[i] /= n;
    return hk_helicoid_rotation_from_quat(q);
}

static hk_PHelicoid one_piece(hk_Vec3 root, hk_Mat3 frame, hk_Helicoid k, double length)
{
    hk_PHelicoid h;
    memset(&h, 0, sizeof h);
    h.root = root;
    h.frame = frame;
    h.piece_count = 1;
    h.k[0] = k;
    h.length[0] = length;
    return h;
}

static hk_Helicoid kv(double kt, double kn, double kb, double alpha)
{
    hk_Helicoid k = {kt, kn, kb, alpha};
    return k;
}

/* Traces h into a fresh buffer (and frames when asked); asserts success. */
static hk_Vec3 *trace(const hk_PHelicoid *h, double step, hk_HelicoidMethod m, const hk_Waviness *w,
                      const hk_Vec3 *offset, hk_Mat3 **frames, int *count)
{
    *count = hk_phelicoid_point_count(h, step);
    assert_true(*count > 0);
    hk_Vec3 *p = malloc(sizeof *p * (size_t)*count);
    if (frames) *frames = malloc(sizeof **frames * (size_t)*count);
    hk_Error err;
    if (m == HK_HELICOID_AUTO) {
        assert_int_equal(hk_phelicoid_trace(h, step, w, offset, p, frames ? *frames : NULL, &err), HK_OK);
    } else {
        hk_HelicoidPlacement pl;
        pl.origin[0] = h->root;
        pl.frame[0] = h->frame;
        if (offset && h->piece_count > 1)
            assert_int_equal(hk_phelicoid_trace_with(h, step, m, NULL, NULL, NULL, NULL, NULL, &pl, &err), HK_OK);
        assert_int_equal(
            hk_phelicoid_trace_with(h, step, m, w, offset, offset ? &pl : NULL, p, frames ? *frames : NULL, NULL, &err),
            HK_OK);
    }
    return p;
}

static double max_dist(const hk_Vec3 *a, const hk_Vec3 *b, int n)
{
    double m = 0.0;
    for (int i = 0; i < n; i++) m = fmax(m, hk_v3_dist(a[i], b[i]));
    return m;
}

static double mat_diff(const hk_Mat3 *a, const hk_Mat3 *b)
{
    double m = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) m = fmax(m, fabs(a->m[i][j] - b->m[i][j]));
    return m;
}

/* Field by field (padding bytes are not part of a p-helicoid). */
static void assert_same_phelicoid(const hk_PHelicoid *a, const hk_PHelicoid *b)
{
    assert_int_equal(a->piece_count, b->piece_count);
    assert_memory_equal(&a->root, &b->root, sizeof a->root);
    assert_memory_equal(&a->frame, &b->frame, sizeof a->frame);
    assert_memory_equal(a->k, b->k, sizeof(hk_Helicoid) * (size_t)a->piece_count);
    assert_memory_equal(a->length, b->length, sizeof(double) * (size_t)a->piece_count);
}

static void assert_rotation(const hk_Mat3 *q, double tol)
{
    hk_Mat3 t = hk_m3_transpose(q), p = hk_m3_mul(&t, q), i = hk_m3_identity();
    assert_true(mat_diff(&p, &i) <= tol);
    double det = hk_v3_dot(hk_m3_col(q, 0), hk_v3_cross(hk_m3_col(q, 1), hk_m3_col(q, 2)));
    hk_assert_near(det, 1.0, tol);
}

/* ---- field and frame ---------------------------------------------------------------- */

static void test_frame_eq2(void **state)
{
    (void)state;
    hk_Mat3 f0 = hk_helicoid_frame(0.0, 0.0), id = hk_m3_identity();
    assert_true(mat_diff(&f0, &id) == 0.0);
    for (int i = 0; i < 50; i++) {
        double th = 20 * hk_test_uniform() - 10, ph = 20 * hk_test_uniform() - 10;
        hk_Mat3 f = hk_helicoid_frame(th, ph);
        assert_rotation(&f, 1e-14);
        hk_Vec3 b = hk_v3_cross(hk_m3_col(&f, 0), hk_m3_col(&f, 1));
        assert_true(hk_v3_dist(b, hk_m3_col(&f, 2)) < 1e-15);
    }
    /* eq. 1 at the origin: theta = phi = 0 whatever k. */
    double th, ph;
    hk_Helicoid k = kv(1.3, -0.7, 2.0, 0.4);
    hk_helicoid_angles(&k, hk_v3_zero(), 0.0, &th, &ph);
    assert_true(th == 0.0 && ph == 0.0);
    /* eq. 1 literally where its denominator is positive (arctan = atan2 there). */
    hk_Vec3 x = hk_v3(0.2, 0.1, 0.3);
    hk_helicoid_angles(&k, x, 0.0, &th, &ph);
    double lit = atan((1.3 * 0.2 - 0.7 * 0.1) / (1 - 0.7 * 0.2 - 1.3 * 0.1)) + 2.0 * 0.3;
    hk_assert_near(th, lit, 1e-15);
    hk_assert_near(ph, 0.4 * lit, 1e-15);
    hk_helicoid_angles(NULL, x, 0.0, &th, NULL);
    assert_true(isnan(th));
}

/* Walking around the singular axis w = 0 (at (0, 1/k_T) for k = (k_T, 0, 0, .)) counts one 2 pi
 * cycle, and each small step changes theta a little even across atan2's cut. */
static void test_theta_continuation(void **state)
{
    (void)state;
    hk_Helicoid k = kv(2.0, 0.0, 0.0, 0.5);
    const int n = 400;
    double prev = 0.0;
    hk_helicoid_angles(&k, hk_v3(0.0, 0.5 - 0.3, 0.0), 0.0, &prev, NULL);
    const double start = prev;
    for (int i = 1; i <= n; i++) {
        double a = -HK_PI / 2 + (2.0 * HK_PI) * i / n;
        hk_Vec3 x = hk_v3(0.3 * cos(a), 0.5 + 0.3 * sin(a), 0.0);
        double th, ph;
        hk_helicoid_angles(&k, x, prev, &th, &ph);
        assert_true(fabs(th - prev) < 0.1);
        hk_assert_near(ph, 0.5 * th, 1e-15);
        prev = th;
    }
    hk_assert_near(prev - start, (2.0 * HK_PI), 1e-12);
}

/* ---- closed forms ------------------------------------------------------------------- */

/* k = 0: a straight line along E_T, exact with both integrators. k_B alone: straight too, its
 * direction turned by k_B z0 about E_B when the start is at height z0 (the plain helicoid). */
static void test_straight_lines(void **state)
{
    (void)state;
    for (int m = 0; m < 2; m++)
        for (int trial = 0; trial < 5; trial++) {
            hk_Vec3 root = hk_v3(hk_test_uniform(), hk_test_uniform(), hk_test_uniform());
            hk_Mat3 q = rand_rotation();
            hk_PHelicoid h = one_piece(root, q, kv(0, 0, 0, 0), 0.7);
            int n;
            hk_Mat3 *f;
            hk_Vec3 *p = trace(&h, 0.1, (hk_HelicoidMethod)m, NULL, NULL, &f, &n);
            assert_int_equal(n, 8);
            for (int i = 0; i < n; i++) {
                hk_Vec3 ref = hk_v3_madd(root, hk_m3_col(&q, 0), 0.1 * i);
                assert_true(hk_v3_dist(p[i], ref) < 1e-15);
                assert_true(mat_diff(&f[i], &q) == 0.0);
            }
            free(p);
            free(f);
            h.k[0] = kv(0, 0, 3.0, 0);
            const hk_Vec3 off = hk_v3(0.0, 0.05, 0.2);
            p = trace(&h, 0.1, (hk_HelicoidMethod)m, NULL, &off, NULL, &n);
            const hk_Vec3 dir = hk_m3_mul_v3(&q, hk_v3(cos(0.6), sin(0.6), 0.0));
            const hk_Vec3 start = hk_v3_add(root, hk_m3_mul_v3(&q, off));
            for (int i = 0; i < n; i++) assert_true(hk_v3_dist(p[i], hk_v3_madd(start, dir, 0.1 * i)) < 1e-14);
            free(p);
        }
}

/* k = (k_T, 0, 0, 0): the circle of radius 1/|k_T| in the E_T-E_N plane, centre at E_N / k_T. */
static void test_circle_exact(void **state)
{
    (void)state;
    const double kts[] = {2.0, -0.5, 1e-9};
    for (int c = 0; c < 3; c++) {
        const double kt = kts[c];
        hk_Mat3 q = rand_rotation();
        hk_Vec3 root = hk_v3(0.3, -0.2, 0.1);
        hk_PHelicoid h = one_piece(root, q, kv(kt, 0, 0, 0), 5.0);
        int n;
        hk_Mat3 *f;
        hk_Vec3 *p = trace(&h, 0.05, HK_HELICOID_AUTO, NULL, NULL, &f, &n);
        for (int i = 0; i < n; i++) {
            const double s = 5.0 * i / (n - 1);
            const double sh = sin(0.5 * kt * s); /* 1 - cos(k s) = 2 sin^2(k s / 2), no cancellation */
            const hk_Vec3 loc = hk_v3(sin(kt * s) / kt, 2 * sh * sh / kt, 0.0);
            const hk_Vec3 ref = hk_v3_add(root, hk_m3_mul_v3(&q, loc));
            assert_true(hk_v3_dist(p[i], ref) < 2e-14);
            const hk_Vec3 t = hk_m3_mul_v3(&q, hk_v3(cos(kt * s), sin(kt * s), 0.0));
            assert_true(hk_v3_dist(hk_m3_col(&f[i], 0), t) < 1e-14);
        }
        free(f);
        /* RK4 on the same field: O(h^4) close. */
        hk_Vec3 *r = trace(&h, 0.05, HK_HELICOID_RK4, NULL, NULL, NULL, &n);
        /* 5.9e-7 for k_T = 2 (k h = 0.1), 5.8e-9 for k_T = -0.5 */
        assert_true(max_dist(p, r, n) < 3e-2 * pow(kt * 0.05, 4) + 1e-14);
        free(p);
        free(r);
    }
}

/* The closed form for alpha = 0 (logarithmic spirals, any k_T, k_N, k_B, any start) against RK4
 * with a fine step. */
static void test_spiral_closed_form_vs_rk4(void **state)
{
    (void)state;
    const hk_Helicoid ks[] = {kv(1.5, 0.4, 0, 0), kv(-0.8, 0.3, 2.0, 0), kv(0.0, 0.6, 0, 0), kv(1.0, -0.2, 0.5, 0),
                              kv(1e-10, 1e-10, 0, 0)};
    const hk_Vec3 offs[] = {hk_v3(0, 0, 0), hk_v3(0, 0.05, -0.1), hk_v3(0, -0.1, 0.1), hk_v3(0.1, -0.2, 0.3),
                            hk_v3(0, 0.01, 0)};
    for (int c = 0; c < 5; c++) {
        hk_PHelicoid h = one_piece(hk_v3(1, 2, 3), rand_rotation(), ks[c], 2.5);
        int n, m;
        hk_Vec3 *a = trace(&h, 0.1, HK_HELICOID_AUTO, NULL, &offs[c], NULL, &n);
        hk_Vec3 *b = trace(&h, 0.1 / 64, HK_HELICOID_RK4, NULL, &offs[c], NULL, &m);
        assert_int_equal(m - 1, 64 * (n - 1));
        for (int i = 0; i < n; i++) assert_true(hk_v3_dist(a[i], b[64 * i]) < 1e-10);
        free(a);
        free(b);
    }
    /* The planar spiral from the root in closed form: |w| = 1 + k_N s, theta = (k_T/k_N) log(1 + k_N s). */
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(1.5, 0.4, 0, 0), 2.0);
    int n;
    hk_Mat3 *f;
    hk_Vec3 *p = trace(&h, 0.25, HK_HELICOID_AUTO, NULL, NULL, &f, &n);
    const double s = 2.0, th = 1.5 / 0.4 * log1p(0.4 * s);
    /* x + i y = (w - 1) / c with w = (1 + k_N s) e^{i theta}, c = k_N + i k_T */
    const double wr = (1 + 0.4 * s) * cos(th) - 1, wi = (1 + 0.4 * s) * sin(th), cc = 0.4 * 0.4 + 1.5 * 1.5;
    hk_assert_near(p[n - 1].x, (wr * 0.4 + wi * 1.5) / cc, 1e-14);
    hk_assert_near(p[n - 1].y, (wi * 0.4 - wr * 1.5) / cc, 1e-14);
    hk_assert_near(atan2(f[n - 1].m[1][0], f[n - 1].m[0][0]), remainder(th, (2.0 * HK_PI)), 1e-14);
    free(p);
    free(f);
}

/* k = (k_T, 0, 0, alpha): the strand stays on the cylinder |w| = 1 (radius 1/k_T about the axis
 * (0, 1/k_T, z)) and climbs it: with u = alpha k_T s, phi = gd(u) = atan(sinh u),
 * theta = phi / alpha, z = log(cosh u) / (alpha k_T), x + i y = (e^{i theta} - 1) / (i k_T). */
static void test_cylinder_closed_form(void **state)
{
    (void)state;
    const double kt = 1.5, al = 0.7;
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(kt, 0, 0, al), 4.0);
    int n;
    hk_Vec3 *p = trace(&h, 0.004, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    for (int i = 0; i < n; i += 50) {
        const double s = 4.0 * i / (n - 1), u = al * kt * s, phi = atan(sinh(u)), th = phi / al;
        const hk_Vec3 ref = hk_v3(sin(th) / kt, (1 - cos(th)) / kt, log(cosh(u)) / (al * kt));
        assert_true(hk_v3_dist(p[i], ref) < 1e-10);
    }
    free(p);
}

/* RK4's order on a general field: halving the step divides the error by ~16. The steps
 * turn the field by at most 0.24 rad, under the tracer's substep threshold (0.25), so
 * that each is one RK4 step: (|k_N + i k_T| / |w| + |k_B|)(1 + |alpha|) h <= 0.24 with
 * |w| >= 0.93 along this strand. */
static void test_rk4_order(void **state)
{
    (void)state;
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(1.2, 0.4, 0.8, 0.6), 2.0);
    const hk_Vec3 off = hk_v3(0.0, 0.05, 0.1);
    int n;
    hk_Vec3 *ref = trace(&h, 1.0 / 4096, HK_HELICOID_RK4, NULL, &off, NULL, &n);
    const hk_Vec3 tip = ref[n - 1];
    free(ref);
    double e[4];
    for (int j = 0; j < 4; j++) {
        hk_Vec3 *p = trace(&h, 0.05 / (1 << j), HK_HELICOID_RK4, NULL, &off, NULL, &n);
        e[j] = hk_v3_dist(p[n - 1], tip);
        free(p);
    }
    print_message("RK4 tip errors: %.3e %.3e %.3e %.3e\n", e[0], e[1], e[2], e[3]);
    for (int j = 0; j < 3; j++) {
        const double ratio = e[j] / e[j + 1];
        assert_true(ratio > 13.0 && ratio < 19.0);
    }
    assert_true(e[3] < 1e-8);
}

/* Output spacings coarser than the field allows are split into substeps: a tight curl
 * (k_T = 300/m, a radian per 3.3 mm sample) and a strand passing a tenth of its
 * origin's distance from the singular axis, traced at their sample spacing, match the
 * same parameters traced 64 times finer (the reference: RK4 converged) to a micron.
 * Without the substeps the curl is off by 20 microns. */
static void test_rk4_substeps(void **state)
{
    (void)state;
    const hk_Helicoid cases[2] = {kv(300, 10, 40, 0.3), kv(30, -90, 5, 0.2)};
    for (int c = 0; c < 2; c++) {
        hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), cases[c], 0.01);
        int n, nf;
        hk_Vec3 *coarse = trace(&h, 0.01 / 3, HK_HELICOID_RK4, NULL, NULL, NULL, &n);
        hk_Vec3 *fine = trace(&h, 0.01 / 192, HK_HELICOID_RK4, NULL, NULL, NULL, &nf);
        assert_int_equal(nf, 64 * (n - 1) + 1);
        double worst = 0.0;
        for (int i = 0; i < n; i++) worst = fmax(worst, hk_v3_dist(coarse[i], fine[64 * i]));
        print_message("  substeps, case %d: coarse trace within %.2e m of a 64x finer one\n", c, worst);
        assert_true(worst < 1e-6);
        free(coarse);
        free(fine);
    }
}

/* ---- p-helicoids -------------------------------------------------------------------- */

static hk_PHelicoid three_pieces(void)
{
    hk_PHelicoid h = one_piece(hk_v3(0.1, 0.2, 0.3), rand_rotation(), kv(1.0, 0.3, 0.5, 0.4), 1.0);
    h.piece_count = 3;
    h.k[1] = kv(-2.0, 0.1, -0.4, 0.0); /* closed form */
    h.length[1] = 0.75;
    h.k[2] = kv(0.5, -0.2, 1.0, -0.8);
    h.length[2] = 1.3;
    return h;
}

static void test_point_count(void **state)
{
    (void)state;
    hk_PHelicoid h = three_pieces();
    assert_int_equal(hk_phelicoid_point_count(&h, 0.25), 1 + 4 + 3 + 6);
    h.length[0] = 3 * 0.1;
    h.length[1] = 0.3;
    h.length[2] = 0.7;
    assert_int_equal(hk_phelicoid_point_count(&h, 0.1), 1 + 3 + 3 + 7);
    assert_int_equal(hk_phelicoid_point_count(&h, 10.0), 4);
    hk_assert_near(hk_phelicoid_length(&h), 1.3, 1e-15);
    /* Straight pieces: the points are evenly spaced within a piece and the joins are exact. */
    for (int i = 0; i < 3; i++) h.k[i] = kv(0, 0, 0, 0);
    h.length[0] = 0.35;
    h.length[1] = 0.2;
    h.length[2] = 0.05;
    int n;
    hk_Vec3 *p = trace(&h, 0.1, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    assert_int_equal(n, 1 + 4 + 2 + 1);
    const double s[] = {0, 0.0875, 0.175, 0.2625, 0.35, 0.45, 0.55, 0.6};
    for (int i = 0; i < n; i++) assert_true(hk_v3_dist(p[i], hk_v3_madd(h.root, hk_m3_col(&h.frame, 0), s[i])) < 1e-14);
    free(p);
}

/* §3.4: piece i+1 starts at the end of piece i with the frame of eq. 2 there. Tracing the rest
 * as a new strand from that point and frame gives the same points; the frame is continuous. */
static void test_joint_continuity(void **state)
{
    (void)state;
    hk_PHelicoid h = three_pieces();
    const double step = 0.05;
    int n;
    hk_Mat3 *f;
    hk_Vec3 *p = trace(&h, step, HK_HELICOID_AUTO, NULL, NULL, &f, &n);
    int joint = 0;
    for (int i = 0; i + 1 < h.piece_count; i++) {
        joint += hk_helicoid_piece_steps(h.length[i], step);
        assert_rotation(&f[joint], 1e-13);
        hk_PHelicoid rest = h;
        rest.root = p[joint];
        rest.frame = f[joint];
        rest.piece_count = h.piece_count - 1 - i;
        memmove(rest.k, h.k + i + 1, sizeof(hk_Helicoid) * (size_t)rest.piece_count);
        memmove(rest.length, h.length + i + 1, sizeof(double) * (size_t)rest.piece_count);
        int m;
        hk_Mat3 *g;
        hk_Vec3 *q = trace(&rest, step, HK_HELICOID_AUTO, NULL, NULL, &g, &m);
        assert_int_equal(m, n - joint);
        assert_true(max_dist(q, p + joint, m) < 1e-13);
        for (int j = 0; j < m; j++) assert_true(mat_diff(&g[j], &f[joint + j]) < 1e-13);
        free(q);
        free(g);
        /* The frame turns across the join no faster than inside the pieces. */
        double inside = 0.0;
        for (int j = 1; j < n; j++)
            if (j != joint + 1) inside = fmax(inside, mat_diff(&f[j], &f[j - 1]));
        assert_true(mat_diff(&f[joint + 1], &f[joint]) <= 2.0 * inside);
    }
    free(p);
    free(f);
}

/* A phase c: on a straight strand along x (frame identity, E_N = y, E_B = z) the waved
 * points are exactly (s, a sin(b s + c), a cos(b s + c)), the root included. */
static void test_waviness_phase(void **state)
{
    (void)state;
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(0, 0, 0, 0), 0.3);
    const hk_Waviness w = {0.01, 25.0, 1.1};
    int n;
    hk_Vec3 *q = trace(&h, 0.01, HK_HELICOID_AUTO, &w, NULL, NULL, &n);
    assert_int_equal(n, 31);
    for (int i = 0; i < n; i++) {
        const double s = 0.01 * i;
        const hk_Vec3 ref = hk_v3(s, 0.01 * sin(25.0 * s + 1.1), 0.01 * cos(25.0 * s + 1.1));
        assert_true(hk_v3_dist(q[i], ref) < 1e-15);
    }
    free(q);
}

/* Eq. 4: the waved point is a cos(b s) E_B + a sin(b s) E_N away from the unwaved one. */
static void test_waviness(void **state)
{
    (void)state;
    hk_PHelicoid h = three_pieces();
    const hk_Waviness w = {0.02, 40.0, 0.0};
    int n, m;
    hk_Mat3 *f;
    hk_Vec3 *p = trace(&h, 0.05, HK_HELICOID_AUTO, NULL, NULL, &f, &n);
    hk_Vec3 *q = trace(&h, 0.05, HK_HELICOID_AUTO, &w, NULL, NULL, &m);
    assert_int_equal(n, m);
    double s = 0.0;
    int i = 0;
    for (int piece = 0; piece < h.piece_count; piece++) {
        const int steps = hk_helicoid_piece_steps(h.length[piece], 0.05);
        for (int j = piece == 0 ? 0 : 1; j <= steps; j++, i++) {
            const double sj = s + h.length[piece] * j / steps;
            hk_assert_near(hk_v3_dist(p[i], q[i]), 0.02, 1e-13);
            hk_Vec3 ref = hk_v3_madd(p[i], hk_m3_col(&f[i], 2), 0.02 * cos(40 * sj));
            ref = hk_v3_madd(ref, hk_m3_col(&f[i], 1), 0.02 * sin(40 * sj));
            assert_true(hk_v3_dist(ref, q[i]) < 1e-13);
        }
        s += h.length[piece];
    }
    assert_int_equal(i, n);
    free(p);
    free(q);
    free(f);
}

/* ---- the pi-rotation rule ----------------------------------------------------------- */

static void test_canonical_rule(void **state)
{
    (void)state;
    for (int trial = 0; trial < 10; trial++) {
        hk_PHelicoid h = three_pieces();
        h.k[0].kt = -fabs(h.k[0].kt) - hk_test_uniform();
        h.k[2].kt = 2 * hk_test_uniform() - 1;
        const hk_Vec3 off = hk_v3(0.0, 0.03, -0.02);
        for (int m = 0; m < 2; m++) {
            hk_PHelicoid c = h;
            hk_phelicoid_canonical(&c);
            assert_true(c.k[0].kt > 0.0);
            for (int i = 0; i < 3; i++) {
                assert_true(c.k[i].kt == -h.k[i].kt);
                assert_true(c.k[i].kn == h.k[i].kn && c.k[i].kb == h.k[i].kb && c.k[i].alpha == h.k[i].alpha);
            }
            int n;
            hk_Mat3 *fa, *fb;
            hk_Vec3 *a = trace(&h, 0.05, (hk_HelicoidMethod)m, NULL, NULL, &fa, &n);
            hk_Vec3 *b = trace(&c, 0.05, (hk_HelicoidMethod)m, NULL, NULL, &fb, &n);
            assert_true(max_dist(a, b, n) < 1e-12);
            for (int i = 0; i < n; i++) {
                /* E_T the same, E_N and E_B reversed */
                assert_true(hk_v3_dist(hk_m3_col(&fa[i], 0), hk_m3_col(&fb[i], 0)) < 1e-12);
                assert_true(hk_v3_dist(hk_m3_col(&fa[i], 1), hk_v3_neg(hk_m3_col(&fb[i], 1))) < 1e-12);
            }
            free(a);
            free(b);
            free(fa);
            free(fb);
            /* The field itself maps: the streamline through root + Q off is that through
             * root + Q D (D off). */
            const hk_Vec3 offc = hk_v3(off.x, -off.y, -off.z);
            a = trace(&h, 0.05, (hk_HelicoidMethod)m, NULL, &off, NULL, &n);
            b = trace(&c, 0.05, (hk_HelicoidMethod)m, NULL, &offc, NULL, &n);
            assert_true(max_dist(a, b, n) < 1e-12);
            free(a);
            free(b);
        }
        /* Already canonical: unchanged. */
        hk_PHelicoid c = h;
        c.k[0].kt = 0.5;
        hk_PHelicoid d = c;
        hk_phelicoid_canonical(&d);
        assert_same_phelicoid(&c, &d);
    }
    /* The literal reading of §3-4.1 ("rotate Q by pi about E_N, negate k_T") turns the strand
     * back on itself: its first step goes along -E_T. */
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(-1.0, -0.1, 0.3, 1.0), 1.0);
    hk_PHelicoid e = h;
    e.frame = hk_m3_from_cols(hk_v3(-1, 0, 0), hk_v3(0, 1, 0), hk_v3(0, 0, -1));
    e.k[0].kt = 1.0;
    int n;
    hk_Vec3 *a = trace(&h, 0.1, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    hk_Vec3 *b = trace(&e, 0.1, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    assert_true(a[1].x > 0.09 && b[1].x < -0.09);
    free(a);
    free(b);
    hk_phelicoid_canonical(NULL);
}

/* ---- wisps -------------------------------------------------------------------------- */

static void test_wisp(void **state)
{
    (void)state;
    hk_PHelicoid g = three_pieces();
    const double step = 0.05, radius = 0.01;
    const int n = hk_phelicoid_point_count(&g, step), count = 32;
    hk_Vec3 *guide = malloc(sizeof *guide * (size_t)n);
    hk_Vec3 *w = malloc(sizeof *w * (size_t)n * count);
    hk_Vec3 *w2 = malloc(sizeof *w2 * (size_t)n * count);
    hk_Error err;
    assert_int_equal(hk_phelicoid_trace(&g, step, NULL, NULL, guide, NULL, &err), HK_OK);
    assert_int_equal(hk_phelicoid_wisp(&g, count, radius, 0.0, 42, step, NULL, w, &err), HK_OK);
    double lo = INFINITY, hi = 0.0, jump = 0.0;
    for (int j = 0; j < count; j++) {
        const hk_Vec3 *p = w + (size_t)j * n;
        const hk_Vec3 d0 = hk_v3_sub(p[0], g.root);
        const double r0 = hk_v3_norm(d0);
        assert_true(r0 <= radius);
        hk_assert_near(hk_v3_dot(d0, hk_m3_col(&g.frame, 0)), 0.0, 1e-15); /* in the E_N-E_B plane */
        double prev = 1.0;
        for (int i = 1; i < n; i++) {
            const double ratio = hk_v3_dist(p[i], guide[i]) / r0;
            lo = fmin(lo, ratio);
            hi = fmax(hi, ratio);
            jump = fmax(jump, fabs(ratio - prev));
            prev = ratio;
            hk_assert_near(hk_v3_dist(p[i], p[i - 1]), hk_v3_dist(guide[i], guide[i - 1]), 0.05 * step);
        }
    }
    /* The field's neighbouring streamlines converge and diverge smoothly (k_N, shear), not
     * suddenly: not even at the joins, where a wisp strand changes field off the guide. */
    print_message("wisp: distance to the guide / distance at the root in [%.3f, %.3f], largest change "
                  "per step %.3f\n",
                  lo, hi, jump);
    assert_true(lo > 0.25 && hi < 4.0);
    assert_true(jump < 0.15);
    /* Deterministic, strand j independent of the count. */
    assert_int_equal(hk_phelicoid_wisp(&g, 5, radius, 0.0, 42, step, NULL, w2, &err), HK_OK);
    assert_memory_equal(w, w2, sizeof *w * (size_t)n * 5);
    assert_int_equal(hk_phelicoid_wisp(&g, count, radius, 0.0, 43, step, NULL, w2, &err), HK_OK);
    assert_true(memcmp(w, w2, sizeof *w * (size_t)n) != 0);
    /* Radius 0, spread 0: the guide itself. */
    assert_int_equal(hk_phelicoid_wisp(&g, 3, 0.0, 0.0, 1, step, NULL, w2, &err), HK_OK);
    assert_memory_equal(w2 + 2 * (size_t)n, guide, sizeof *guide * (size_t)n);
    /* Spread: same roots, strands tilted by at most the spread. */
    assert_int_equal(hk_phelicoid_wisp(&g, count, radius, 0.2, 42, step, NULL, w2, &err), HK_OK);
    for (int j = 0; j < count; j++) {
        const hk_Vec3 *a = w + (size_t)j * n, *b = w2 + (size_t)j * n;
        assert_true(hk_v3_dist(a[0], b[0]) < 1e-15);
        const double c = hk_v3_dot(hk_v3_normalize(hk_v3_sub(a[1], a[0])), hk_v3_normalize(hk_v3_sub(b[1], b[0])));
        assert_true(acos(fmin(1.0, c)) <= 0.2 + 1e-9);
        hk_assert_near(hk_v3_dist(a[n - 1], a[0]), hk_v3_dist(b[n - 1], b[0]), 1e-12); /* rigid */
    }
    free(guide);
    free(w);
    free(w2);
}

/* ---- interpolation ------------------------------------------------------------------ */

static hk_PHelicoid random_guide(hk_Vec3 root)
{
    hk_PHelicoid h = one_piece(root, rand_rotation(), kv(0, 0, 0, 0), 1.0);
    h.piece_count = 1 + (int)(4 * hk_test_uniform());
    for (int i = 0; i < h.piece_count; i++) {
        h.k[i] = kv(4 * hk_test_uniform() - 2, hk_test_uniform() - 0.5, 2 * hk_test_uniform() - 1,
                    2 * hk_test_uniform() - 1);
        h.length[i] = 0.2 + hk_test_uniform();
    }
    return h;
}

static void test_idw_reproduces_guides(void **state)
{
    (void)state;
    hk_PHelicoid g[6];
    for (int i = 0; i < 6; i++) g[i] = random_guide(hk_v3(hk_test_uniform(), 0.0, hk_test_uniform()));
    hk_Error err;
    for (int i = 0; i < 6; i++) {
        hk_PHelicoid out;
        hk_PHelicoid c = g[i];
        hk_phelicoid_canonical(&c);
        assert_int_equal(hk_phelicoid_interpolate(g, 6, g[i].root, NULL, 3.0, &out, &err), HK_OK);
        assert_same_phelicoid(&out, &c);
        /* Next to the root: the guide (canonical form), continuously. */
        const hk_Vec3 x = hk_v3_madd(g[i].root, hk_v3(1, 0, 0), 1e-7);
        assert_int_equal(hk_phelicoid_interpolate(g, 6, x, NULL, 3.0, &out, &err), HK_OK);
        assert_int_equal(out.piece_count, c.piece_count);
        assert_true(mat_diff(&out.frame, &c.frame) < 1e-9);
        hk_assert_near(out.k[0].kt, c.k[0].kt, 1e-9);
        hk_assert_near(hk_phelicoid_length(&out), hk_phelicoid_length(&c), 1e-9);
        int n, m;
        hk_Vec3 *a = trace(&out, 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
        hk_Vec3 *b = trace(&c, 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &m);
        if (n == m) {
            for (int j = 0; j < n; j++) b[j] = hk_v3_add(b[j], hk_v3_sub(x, c.root));
            assert_true(max_dist(a, b, n) < 1e-6);
        }
        free(a);
        free(b);
    }
    /* The output may be one of the guides (no aliasing trouble). */
    hk_PHelicoid copy[6];
    memcpy(copy, g, sizeof g);
    assert_int_equal(hk_phelicoid_interpolate(copy, 6, hk_v3(0.5, 0.1, 0.5), NULL, 3.0, &copy[0], &err), HK_OK);
    hk_PHelicoid ref;
    assert_int_equal(hk_phelicoid_interpolate(g, 6, hk_v3(0.5, 0.1, 0.5), NULL, 3.0, &ref, &err), HK_OK);
    assert_same_phelicoid(&copy[0], &ref);
}

/* Shepard weights w_i ~ d_i^-3 on two single-piece guides; piece counts and lengths by §4.2. */
static void test_idw_weights(void **state)
{
    (void)state;
    hk_PHelicoid g[2];
    g[0] = one_piece(hk_v3(0, 0, 0), hk_m3_identity(), kv(1.0, 0.2, 0.0, 0.5), 1.0);
    g[1] = one_piece(hk_v3(1, 0, 0), hk_m3_identity(), kv(3.0, -0.2, 1.0, 0.1), 2.0);
    g[1].piece_count = 3;
    g[1].k[1] = kv(0.5, 0.5, 0.5, 0.5);
    g[1].length[1] = 0.5;
    g[1].k[2] = kv(0.7, 0.0, 0.0, 0.0);
    g[1].length[2] = 0.5;
    hk_Error err;
    for (int i = 1; i < 10; i++) {
        const double t = i / 10.0, w0 = pow(t, -3), w1 = pow(1 - t, -3), a = w0 / (w0 + w1), b = 1 - a;
        hk_PHelicoid out;
        assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(t, 0, 0), NULL, 3.0, &out, &err), HK_OK);
        hk_assert_near(out.k[0].kt, a * 1.0 + b * 3.0, 1e-13);
        hk_assert_near(out.k[0].kb, b * 1.0, 1e-13);
        const int pieces = (int)floor(a * 1 + b * 3 + 0.5);
        assert_int_equal(out.piece_count, pieces);
        hk_assert_near(hk_phelicoid_length(&out), a * 1.0 + b * 3.0, 1e-13);
        if (pieces > 1) {
            hk_assert_near(out.length[0], a * 1.0 + b * 2.0, 1e-13);
            hk_assert_near(out.k[1].kt, a * 1.0 + b * 0.5, 1e-13); /* guide 0 lends its only piece */
        }
        assert_true(hk_v3_dist(out.root, hk_v3(t, 0, 0)) == 0.0);
        assert_rotation(&out.frame, 1e-14);
    }
    /* Power 1 through pow(). */
    hk_PHelicoid out;
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(0.25, 0, 0), NULL, 1.0, &out, &err), HK_OK);
    hk_assert_near(out.k[0].kt, 0.75 * 1.0 + 0.25 * 3.0, 1e-13);
    /* A huge power: the far guide's weight underflows to 0, the nearest guide alone. */
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(0.25, 0, 0), NULL, 1e4, &out, &err), HK_OK);
    assert_true(out.k[0].kt == 1.0 && out.piece_count == 1 && out.length[0] == 1.0);
}

/* The paper's Fig. 6 pair: k = (1, -0.1, 0.3, 1) and its pi-rotated copy, the same strand turned
 * by pi about its root tangent, written (a) with k_T = -1 and the same frame (the rule's other
 * side) and (b) with k_T = 1 and the frame turned. Both interpolate to strands of the guides'
 * shape turning smoothly about the tangent from one guide to the other, never through a
 * straight helicoid (k_T -> 0), as averaging k_T = 1 and -1 would. */
static void test_fig6_pi_rotated_pair(void **state)
{
    (void)state;
    const hk_Helicoid k = kv(1.0, -0.1, 0.3, 1.0);
    hk_PHelicoid g[2];
    g[0] = one_piece(hk_v3(0, 0, 0), hk_m3_identity(), k, 3.0);
    g[1] = one_piece(hk_v3(0, 0, 2), hk_m3_identity(), kv(-1.0, -0.1, 0.3, 1.0), 3.0);
    hk_PHelicoid gb[2] = {g[0], g[1]};
    gb[1].k[0] = k;
    gb[1].frame = hk_m3_from_cols(hk_v3(1, 0, 0), hk_v3(0, -1, 0), hk_v3(0, 0, -1));
    int n;
    hk_Vec3 *ga = trace(&g[0], 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    hk_Vec3 *gc = trace(&g[1], 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    hk_Vec3 *gd = trace(&gb[1], 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    assert_true(max_dist(gc, gd, n) < 1e-12); /* (a) and (b) are the same strand */
    const double chord = hk_v3_dist(ga[0], ga[n - 1]);
    /* The collapsed interpolant, k_T = (1 + -1) / 2 = 0, is a straight line (a ray to the sink
     * of k_N = -0.1 at distance 10). */
    hk_PHelicoid flat = g[0];
    flat.k[0].kt = 0.0;
    hk_Vec3 *gf = trace(&flat, 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    hk_assert_near(hk_v3_dist(gf[0], gf[n - 1]), 3.0, 1e-12);
    free(gf);
    print_message("Fig. 6 guide: chord / length = %.3f (a straight helicoid: 1)\n", chord / 3.0);
    assert_true(chord < 0.9 * 3.0);
    hk_Error err;
    double prev_angle = -1.0;
    hk_Vec3 *prev = NULL;
    double max_step = 0.0;
    for (int i = 0; i <= 20; i++) {
        const hk_Vec3 x = hk_v3(0, 0, 2.0 * i / 20);
        hk_PHelicoid out, outb;
        assert_int_equal(hk_phelicoid_interpolate(g, 2, x, NULL, 3.0, &out, &err), HK_OK);
        assert_int_equal(hk_phelicoid_interpolate(gb, 2, x, NULL, 3.0, &outb, &err), HK_OK);
        hk_assert_near(out.k[0].kt, 1.0, 1e-15);
        hk_assert_near(out.k[0].kn, -0.1, 1e-15);
        assert_true(mat_diff(&out.frame, &outb.frame) < 1e-15);
        /* A turn about E_T = x by the angle of the normalised quaternion sum w_A q_A + w_B q_B,
         * 2 atan(w_B / w_A), from 0 to pi. */
        assert_true(hk_v3_dist(hk_m3_col(&out.frame, 0), hk_v3(1, 0, 0)) < 1e-15);
        assert_true(out.frame.m[2][1] >= -1e-15);
        const double angle = acos(fmax(-1.0, fmin(1.0, out.frame.m[1][1])));
        const double t = i / 20.0, wa = pow(t, -3), wb = pow(1 - t, -3);
        hk_assert_near(angle, i == 0 ? 0.0 : (i == 20 ? HK_PI : 2 * atan2(wb, wa)), 1e-7);
        assert_true(angle >= prev_angle - 1e-15);
        prev_angle = angle;
        hk_Vec3 *p = trace(&out, 0.05, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
        hk_assert_near(hk_v3_dist(p[0], p[n - 1]), chord, 1e-12); /* congruent to the guides */
        if (prev) {
            for (int j = 0; j < n; j++) max_step = fmax(max_step, hk_v3_dist(hk_v3_sub(p[j], x), prev[j]));
            free(prev);
        }
        for (int j = 0; j < n; j++) p[j] = hk_v3_sub(p[j], x);
        prev = p;
    }
    hk_assert_near(prev_angle, HK_PI, 1e-12);
    free(prev);
    /* Neighbours 1/20 of the way apart: the largest turn (mid-way, d angle / dt = 12) moves
     * points up to ~2.5 from the axis by 0.6 rad. */
    print_message("Fig. 6: largest change between neighbouring interpolants %.3f (strand length 3)\n", max_step);
    assert_true(max_step < 1.5);
    free(ga);
    free(gc);
    free(gd);
}

static void test_idw_normal(void **state)
{
    (void)state;
    hk_PHelicoid g[2];
    g[0] = one_piece(hk_v3(-1, 0, 0), hk_m3_identity(), kv(0.5, 0, 0, 0), 1.0);
    g[1] = one_piece(hk_v3(1, 0, 0), hk_m3_from_cols(hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(0, 0, 1)), kv(0.5, 0, 0, 0),
                     1.0);
    hk_Error err;
    hk_PHelicoid a, b;
    const hk_Vec3 up = hk_v3(0, 2, 0);
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(0.5, 0, 0), NULL, 3.0, &a, &err), HK_OK);
    assert_true(a.frame.m[1][0] < 0.0); /* the average leans into the surface y < 0 */
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(0.5, 0, 0), &up, 3.0, &b, &err), HK_OK);
    hk_assert_near(b.frame.m[1][0], 0.0, 1e-15);
    assert_rotation(&b.frame, 1e-14);
    /* The smallest rotation: E_T keeps its side along z... here it lands on +x. */
    assert_true(b.frame.m[0][0] > 0.99);
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(1.5, 0, 0), &up, 3.0, &b, &err), HK_OK);
    assert_true(b.frame.m[1][0] >= -1e-15);
    assert_rotation(&b.frame, 1e-14);
    /* Pointing straight in (one guide, E_T = -n): a quarter turn lays it on the surface. */
    assert_int_equal(hk_phelicoid_interpolate(g + 1, 1, hk_v3(3, 0, 0), &up, 3.0, &b, &err), HK_OK);
    hk_assert_near(b.frame.m[1][0], 0.0, 1e-15);
    hk_assert_near(hk_v3_norm(hk_m3_col(&b.frame, 0)), 1.0, 1e-15);
    assert_rotation(&b.frame, 1e-14);
    /* Already outside: untouched. */
    const hk_Vec3 down = hk_v3(0, -1, 0);
    assert_int_equal(hk_phelicoid_interpolate(g, 2, hk_v3(0.5, 0, 0), &down, 3.0, &b, &err), HK_OK);
    assert_memory_equal(&a.frame, &b.frame, sizeof a.frame);
}

/* ---- singular axis and bad input ---------------------------------------------------- */

static void test_sink(void **state)
{
    (void)state;
    /* k_N = -1: every streamline of the plane runs into the axis at (1, 0) after length 1. */
    hk_PHelicoid h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(0.0, -1.0, 0, 0), 3.0);
    const hk_Waviness w = {0.01, 10.0, 0.0};
    int n;
    hk_Mat3 *f;
    hk_Vec3 *p = trace(&h, 0.1, HK_HELICOID_AUTO, &w, NULL, &f, &n);
    for (int i = 0; i < n; i++) assert_true(hk_v3_isfinite(p[i]) && isfinite(f[i].m[0][0]));
    free(p);
    free(f);
    p = trace(&h, 0.1, HK_HELICOID_AUTO, NULL, NULL, NULL, &n);
    assert_true(hk_v3_dist(p[n - 1], hk_v3(1, 0, 0)) == 0.0);
    free(p);
    /* Spiralling in (k_T != 0), and RK4 with alpha != 0: finite, never a crash. */
    const hk_Helicoid ks[] = {kv(0.5, -1.0, 0, 0), kv(0.5, -1.0, 0.2, 0.3), kv(0, -1.0, 0, 0.5)};
    for (int c = 0; c < 3; c++) {
        h.k[0] = ks[c];
        p = trace(&h, 0.1, HK_HELICOID_AUTO, &w, NULL, &f, &n);
        for (int i = 0; i < n; i++) assert_true(hk_v3_isfinite(p[i]) && isfinite(f[i].m[2][2]));
        free(p);
        free(f);
    }
    /* Starting on the axis. */
    const hk_Vec3 off = hk_v3(1.0, 0.0, 0.0);
    h.k[0] = kv(0, -1.0, 0, 0);
    p = trace(&h, 0.5, HK_HELICOID_AUTO, NULL, &off, NULL, &n);
    for (int i = 0; i < n; i++) assert_true(hk_v3_isfinite(p[i]));
    free(p);
}

static void test_bad_input(void **state)
{
    (void)state;
    hk_PHelicoid good = three_pieces(), h;
    hk_Vec3 pts[64];
    hk_Error err;
    const double nan = NAN;
#define EXPECT_BAD(call)                                                                                               \
    do {                                                                                                               \
        hk_error_clear(&err);                                                                                          \
        assert_int_not_equal((call), HK_OK);                                                                           \
        assert_true(strlen(err.message) > 0);                                                                          \
    } while (0)
    h = good;
    h.piece_count = 0;
    EXPECT_BAD(hk_phelicoid_trace(&h, 0.5, NULL, NULL, pts, NULL, &err));
    assert_int_equal(hk_phelicoid_point_count(&h, 0.5), -1);
    hk_assert_near(hk_phelicoid_length(&h), 0.0, 0.0);
    h.piece_count = HK_HELICOID_MAX_PIECES + 1;
    EXPECT_BAD(hk_phelicoid_trace(&h, 0.5, NULL, NULL, pts, NULL, &err));
    h = good;
    h.length[1] = 0.0;
    EXPECT_BAD(hk_phelicoid_trace(&h, 0.5, NULL, NULL, pts, NULL, &err));
    hk_assert_contains(err.message, "piece 2");
    h.length[1] = -1.0;
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    h.length[1] = nan;
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    h = good;
    h.k[2].alpha = nan;
    EXPECT_BAD(hk_phelicoid_trace(&h, 0.5, NULL, NULL, pts, NULL, &err));
    h = good;
    h.k[0].kt = INFINITY;
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    h = good;
    h.root.y = nan;
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    h = good;
    h.frame.m[0][0] *= 1.01;
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    h.frame = hk_m3_from_cols(hk_v3(1, 0, 0), hk_v3(0, 1, 0), hk_v3(0, 0, -1)); /* a reflection */
    EXPECT_BAD(hk_phelicoid_check(&h, &err));
    EXPECT_BAD(hk_phelicoid_check(NULL, &err));
    EXPECT_BAD(hk_phelicoid_trace(NULL, 0.5, NULL, NULL, pts, NULL, &err));
    /* steps */
    EXPECT_BAD(hk_phelicoid_trace(&good, 0.0, NULL, NULL, pts, NULL, &err));
    EXPECT_BAD(hk_phelicoid_trace(&good, -1.0, NULL, NULL, pts, NULL, &err));
    EXPECT_BAD(hk_phelicoid_trace(&good, nan, NULL, NULL, pts, NULL, &err));
    EXPECT_BAD(hk_phelicoid_trace(&good, INFINITY, NULL, NULL, pts, NULL, &err));
    EXPECT_BAD(hk_phelicoid_trace(&good, 1e-12, NULL, NULL, pts, NULL, &err)); /* too many points */
    assert_int_equal(hk_phelicoid_point_count(&good, 1e-12), -1);
    h = good;
    h.length[0] = 1e300;
    assert_int_equal(hk_phelicoid_point_count(&h, 1e-300), -1);
    EXPECT_BAD(hk_phelicoid_trace(&good, 0.5, NULL, NULL, NULL, NULL, &err));
    const hk_Vec3 bad_off = hk_v3(0, nan, 0);
    EXPECT_BAD(hk_phelicoid_trace(&good, 0.5, NULL, &bad_off, pts, NULL, &err));
    const hk_Waviness bw[] = {{-0.1, 1.0, 0.0}, {nan, 1.0, 0.0}, {0.1, INFINITY, 0.0}, {0.1, 1.0, nan}};
    for (int i = 0; i < 4; i++) EXPECT_BAD(hk_phelicoid_trace(&good, 0.5, &bw[i], NULL, pts, NULL, &err));
    /* huge parameters: finite input, non-finite trace reported */
    h = one_piece(hk_v3_zero(), hk_m3_identity(), kv(1e308, 1e308, 1e308, 1e308), 1.0);
    hk_error_clear(&err);
    hk_Status st = hk_phelicoid_trace(&h, 0.5, NULL, NULL, pts, NULL, &err);
    assert_true(st == HK_OK || st == HK_ERR_NUMERIC);
    /* interpolation */
    hk_PHelicoid g[2] = {good, good}, out;
    g[1].root = hk_v3(1, 0, 0);
    EXPECT_BAD(hk_phelicoid_interpolate(g, 0, hk_v3_zero(), NULL, 3.0, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate(NULL, 2, hk_v3_zero(), NULL, 3.0, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3(nan, 0, 0), NULL, 3.0, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3_zero(), NULL, 0.0, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3_zero(), NULL, nan, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3_zero(), NULL, 3.0, NULL, &err));
    const hk_Vec3 zero = hk_v3_zero();
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3(0.5, 0, 0), &zero, 3.0, &out, &err));
    g[1].length[0] = -1.0;
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3(0.5, 0, 0), NULL, 3.0, &out, &err));
    hk_assert_contains(err.message, "guide 1");
    g[1] = good;
    g[1].root = hk_v3(1e300, 1e300, 0);
    g[0].root = hk_v3(-1e300, -1e300, 0);
    EXPECT_BAD(hk_phelicoid_interpolate(g, 2, hk_v3_zero(), NULL, 3.0, &out, &err));
    /* wisps */
    EXPECT_BAD(hk_phelicoid_wisp(&good, -1, 0.1, 0.0, 1, 0.5, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, -0.1, 0.0, 1, 0.5, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, nan, 0.0, 1, 0.5, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, 0.1, 4.0, 1, 0.5, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, 0.1, nan, 1, 0.5, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, 0.1, 0.0, 1, 0.0, NULL, pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, 0.1, 0.0, 1, 0.5, NULL, NULL, &err));
    EXPECT_BAD(hk_phelicoid_wisp(&good, 1, 0.1, 0.0, 1, 0.5, &bw[0], pts, &err));
    EXPECT_BAD(hk_phelicoid_wisp(NULL, 1, 0.1, 0.0, 1, 0.5, NULL, pts, &err));
    assert_int_equal(hk_phelicoid_wisp(&good, 0, 0.1, 0.0, 1, 0.5, NULL, NULL, &err), HK_OK);
#undef EXPECT_BAD
}

/* Random p-helicoids of all kinds trace to finite points or report an error; never a crash. */
static void test_fuzz(void **state)
{
    (void)state;
    hk_Vec3 *pts = malloc(sizeof *pts * 4096);
    hk_Mat3 *frames = malloc(sizeof *frames * 4096);
    hk_Error err;
    for (int trial = 0; trial < 300; trial++) {
        hk_PHelicoid h = random_guide(hk_v3_zero());
        const double scale = pow(10.0, 6 * hk_test_uniform() - 3);
        for (int i = 0; i < h.piece_count; i++) {
            h.k[i].kt *= scale;
            h.k[i].kn *= scale;
            h.k[i].kb *= scale;
            if (hk_test_uniform() < 0.3) h.k[i].alpha = 0.0;
        }
        const hk_Vec3 off = hk_v3_scale(rand_unit(), hk_test_uniform());
        const hk_Waviness w = {0.01, 30.0, 0.0};
        const double step = 0.02 + 0.2 * hk_test_uniform();
        if (hk_phelicoid_point_count(&h, step) > 4096) continue;
        if (hk_phelicoid_trace(&h, step, &w, &off, pts, frames, &err) == HK_OK) {
            const int n = hk_phelicoid_point_count(&h, step);
            for (int i = 0; i < n; i++) assert_true(hk_v3_isfinite(pts[i]));
        }
    }
    free(pts);
    free(frames);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_eq2),
        cmocka_unit_test(test_theta_continuation),
        cmocka_unit_test(test_straight_lines),
        cmocka_unit_test(test_circle_exact),
        cmocka_unit_test(test_spiral_closed_form_vs_rk4),
        cmocka_unit_test(test_cylinder_closed_form),
        cmocka_unit_test(test_rk4_order),
        cmocka_unit_test(test_rk4_substeps),
        cmocka_unit_test(test_point_count),
        cmocka_unit_test(test_joint_continuity),
        cmocka_unit_test(test_waviness),
        cmocka_unit_test(test_waviness_phase),
        cmocka_unit_test(test_canonical_rule),
        cmocka_unit_test(test_wisp),
        cmocka_unit_test(test_idw_reproduces_guides),
        cmocka_unit_test(test_idw_weights),
        cmocka_unit_test(test_fig6_pi_rotated_pair),
        cmocka_unit_test(test_idw_normal),
        cmocka_unit_test(test_sink),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
