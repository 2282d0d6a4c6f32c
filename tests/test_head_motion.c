/* Head motion (src/dynamics/): the scripted motions and the motion files give states
 * whose velocities, accelerations, angular velocity and angular acceleration are the
 * time derivatives of their positions and rotations (checked with central finite
 * differences), rotations stay orthonormal, the pivot stays put, the ease-in starts
 * from rest, keyframes are reproduced exactly, bad files give file:line messages, and
 * mutated files never crash. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics/motion_internal.h"
#include "hairkit/motion.h"


/* ---- Helpers ------------------------------------------------------------------------ */

static double vec_max_abs(hk_Vec3 a) { return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z))); }

/* |a - b| <= rtol * max(|a|, |b|) + atol, componentwise on the largest component. */
static void assert_vec_close_impl(hk_Vec3 a, hk_Vec3 b, double rtol, double atol, const char *what, double t, int line)
{
    const double diff = vec_max_abs(hk_v3_sub(a, b));
    const double tol = rtol * fmax(vec_max_abs(a), vec_max_abs(b)) + atol;
    if (!(diff <= tol)) {
        print_error("line %d: %s at t=%.9g: (%.12g, %.12g, %.12g) vs (%.12g, %.12g, %.12g), "
                    "diff %.3g > tol %.3g\n",
                    line, what, t, a.x, a.y, a.z, b.x, b.y, b.z, diff, tol);
        fail();
    }
}
#define assert_vec_close(a, b, rtol, atol, what, t)                                                                    \
    assert_vec_close_impl((a), (b), (rtol), (atol), (what), (t), __LINE__)

static hk_RigidState eval_at(const hk_HeadMotion *m, double t)
{
    hk_RigidState st;
    hk_head_motion_eval(m, t, &st);
    return st;
}

/* R^T R = I and det R = 1 to rounding. */
static void assert_rotation(const hk_Mat3 *r)
{
    hk_Mat3 rtr = hk_m3_transpose(r);
    rtr = hk_m3_mul(&rtr, r);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) hk_assert_near(rtr.m[i][j], i == j ? 1.0 : 0.0, 1e-14);
    const double det = hk_v3_dot(hk_m3_col(r, 0), hk_v3_cross(hk_m3_col(r, 1), hk_m3_col(r, 2)));
    hk_assert_near(det, 1.0, 1e-14);
}

/* omega from (R(t+h) - R(t-h)) / (2h) R(t)^T = [omega]x + O(h^2), its skew part. */
static hk_Vec3 fd_omega(const hk_RigidState *plus, const hk_RigidState *minus, const hk_RigidState *mid, double h)
{
    hk_Mat3 d;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) d.m[i][j] = (plus->rot.m[i][j] - minus->rot.m[i][j]) / (2 * h);
    hk_Mat3 rt = hk_m3_transpose(&mid->rot);
    hk_Mat3 w = hk_m3_mul(&d, &rt);
    return hk_v3(0.5 * (w.m[2][1] - w.m[1][2]), 0.5 * (w.m[0][2] - w.m[2][0]), 0.5 * (w.m[1][0] - w.m[0][1]));
}

/* Every derivative the state claims against central differences at t, with step h;
 * `scale` is the size of the motion's velocities, for an absolute floor near zeros. */
static void check_derivatives(const hk_HeadMotion *m, double t, double h, double scale)
{
    const hk_RigidState mid = eval_at(m, t), plus = eval_at(m, t + h), minus = eval_at(m, t - h);
    assert_rotation(&mid.rot);
    const double rtol = 1e-6, atol = 1e-7 * scale;
    const hk_Vec3 fd_vel = hk_v3_scale(hk_v3_sub(plus.trans, minus.trans), 0.5 / h);
    const hk_Vec3 fd_acc = hk_v3_scale(hk_v3_sub(plus.vel, minus.vel), 0.5 / h);
    const hk_Vec3 fd_alpha = hk_v3_scale(hk_v3_sub(plus.omega, minus.omega), 0.5 / h);
    assert_vec_close(mid.vel, fd_vel, rtol, atol, "vel vs FD of trans", t);
    assert_vec_close(mid.acc, fd_acc, rtol, atol, "acc vs FD of vel", t);
    assert_vec_close(mid.omega, fd_omega(&plus, &minus, &mid, h), rtol, atol, "omega vs FD of R", t);
    assert_vec_close(mid.alpha, fd_alpha, rtol, atol, "alpha vs FD of omega", t);
    /* The acceleration also against the second difference of the position, whose
     * rounding error eps |T| / h^2 allows it only with the larger steps. */
    if (h >= 1e-6) {
        const hk_Vec3 dd =
            hk_v3_scale(hk_v3_add(hk_v3_sub(plus.trans, hk_v3_scale(mid.trans, 2.0)), minus.trans), 1.0 / (h * h));
        assert_vec_close(mid.acc, dd, 1e-4, 1e-5 * scale, "acc vs second difference of trans", t);
    }
    /* A scalp point: hk_rigid_point's velocity and acceleration. */
    const hk_Vec3 x = hk_v3(0.06, 0.12, -0.03);
    hk_Vec3 p0, p1, v0, v1, v, a;
    hk_rigid_point(&plus, x, &p1, &v1, NULL);
    hk_rigid_point(&minus, x, &p0, &v0, NULL);
    hk_rigid_point(&mid, x, NULL, &v, &a);
    assert_vec_close(v, hk_v3_scale(hk_v3_sub(p1, p0), 0.5 / h), rtol, atol, "point velocity", t);
    assert_vec_close(a, hk_v3_scale(hk_v3_sub(v1, v0), 0.5 / h), rtol, atol, "point acceleration", t);
}

/* One-sided second-order differences f'(t) ~ d (-3 f(t) + 4 f(t + d h) - f(t + 2 d h)) / 2h
 * with d = +1 or -1: at a key, each side is smooth up to the key, so this checks that
 * the derivatives there are the limits from either side. */
static hk_Vec3 one_sided(hk_Vec3 f0, hk_Vec3 f1, hk_Vec3 f2, double d, double h)
{
    return hk_v3_scale(hk_v3_add(hk_v3_scale(f0, -3.0), hk_v3_sub(hk_v3_scale(f1, 4.0), f2)), d / (2 * h));
}

static void check_one_sided(const hk_HeadMotion *m, double t, double h, double d, double scale)
{
    const hk_RigidState s0 = eval_at(m, t), s1 = eval_at(m, t + d * h), s2 = eval_at(m, t + 2 * d * h);
    const double rtol = 1e-6, atol = 1e-7 * scale;
    assert_vec_close(s0.vel, one_sided(s0.trans, s1.trans, s2.trans, d, h), rtol, atol, "vel vs one-sided FD of trans",
                     t);
    assert_vec_close(s0.acc, one_sided(s0.vel, s1.vel, s2.vel, d, h), rtol, atol, "acc vs one-sided FD of vel", t);
    assert_vec_close(s0.alpha, one_sided(s0.omega, s1.omega, s2.omega, d, h), rtol, atol,
                     "alpha vs one-sided FD of omega", t);
    hk_Mat3 dr;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            dr.m[i][j] = d * (-3 * s0.rot.m[i][j] + 4 * s1.rot.m[i][j] - s2.rot.m[i][j]) / (2 * h);
    const hk_Mat3 rt = hk_m3_transpose(&s0.rot);
    const hk_Mat3 w = hk_m3_mul(&dr, &rt);
    const hk_Vec3 om =
        hk_v3(0.5 * (w.m[2][1] - w.m[1][2]), 0.5 * (w.m[0][2] - w.m[2][0]), 0.5 * (w.m[1][0] - w.m[0][1]));
    assert_vec_close(s0.omega, om, rtol, atol, "omega vs one-sided FD of R", t);
}

static hk_HeadMotion *scripted_ok(const char *name, double amplitude, double frequency)
{
    hk_HeadMotion *m = NULL;
    hk_Error err;
    hk_Status st = hk_head_motion_scripted(name, amplitude, frequency, hk_default_head_pivot(), &m, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_non_null(m);
    return m;
}

static hk_HeadMotion *load_ok(const char *text)
{
    hk_HeadMotion *m = NULL;
    hk_Error err;
    hk_Status st = hk_head_motion_load(hk_test_write_text("motion.txt", text), &m, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_non_null(m);
    return m;
}

/* The rotation by angle (radians) about the unit axis u, by Rodrigues' formula,
 * written out independently of the library. */
static hk_Mat3 rodrigues(hk_Vec3 u, double angle)
{
    const double c = cos(angle), s = sin(angle);
    hk_Mat3 r;
    const double k[3] = {u.x, u.y, u.z};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) r.m[i][j] = (i == j ? c : 0.0) + (1 - c) * k[i] * k[j];
    r.m[0][1] -= s * u.z, r.m[1][0] += s * u.z;
    r.m[0][2] += s * u.y, r.m[2][0] -= s * u.y;
    r.m[1][2] -= s * u.x, r.m[2][1] += s * u.x;
    return r;
}

static void assert_state_is_identity(const hk_RigidState *st)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) assert_true(st->rot.m[i][j] == (i == j ? 1.0 : 0.0));
    const hk_Vec3 z = hk_v3_zero();
    assert_vec_close(st->trans, z, 0, 0, "trans", 0);
    assert_vec_close(st->vel, z, 0, 0, "vel", 0);
    assert_vec_close(st->acc, z, 0, 0, "acc", 0);
    assert_vec_close(st->omega, z, 0, 0, "omega", 0);
    assert_vec_close(st->alpha, z, 0, 0, "alpha", 0);
}

/* ---- Scripted motions -------------------------------------------------------------- */

static const char *const script_names[] = {"nod", "shake", "tilt", "sway", "jump"};

static void test_still(void **state)
{
    (void)state;
    hk_HeadMotion *m = scripted_ok("still", 30, 2);
    for (double t = -1.0; t < 5.0; t += 0.37) {
        hk_RigidState st = eval_at(m, t);
        assert_state_is_identity(&st);
    }
    assert_true(isinf(hk_head_motion_duration(m)));
    assert_int_equal(hk_head_motion_key_count(m), 0);
    hk_head_motion_destroy(m);
    hk_RigidState id = hk_rigid_identity();
    assert_state_is_identity(&id);
    hk_head_motion_destroy(NULL);
}

static void test_scripted_derivatives(void **state)
{
    (void)state;
    const double amplitude[5] = {25, 40, 15, 0.05, 0.03}, freq[5] = {1.5, 0.8, 1.1, 0.6, 2.0};
    for (int k = 0; k < 5; k++) {
        hk_HeadMotion *m = scripted_ok(script_names[k], amplitude[k], freq[k]);
        const double te = 0.5 / freq[k];
        /* Speeds are of the order of amplitude x 2 pi f (metres: the lever arm of the
         * rotations is some 0.2 m). */
        const double scale = (k < 3 ? amplitude[k] * HK_PI / 180 * 0.2 : amplitude[k]) * 2 * HK_PI * freq[k];
        for (int i = 1; i < 60; i++) {
            const double t = 4.0 * te * i / 60.0 + 1e-3;
            if (fabs(t - te) < 2e-5) continue; /* the ease-in's end: C2, not smoother */
            check_derivatives(m, t, 1e-5, scale);
        }
        hk_head_motion_destroy(m);
    }
}

/* g(t) = A s(t / T_e) sin(2 pi f t), with the quintic smoothstep s over half a period. */
static double profile(double a, double f, double t)
{
    if (t <= 0) return 0;
    const double u = fmin(t * 2 * f, 1.0);
    return a * u * u * u * (10 - 15 * u + 6 * u * u) * sin(2 * HK_PI * f * t);
}

static void test_scripted_formulas(void **state)
{
    (void)state;
    const double a = 30, f = 1.25;
    const hk_Vec3 pivot = hk_default_head_pivot();
    for (int k = 0; k < 5; k++) {
        hk_HeadMotion *m = scripted_ok(script_names[k], k < 3 ? a : 0.04, f);
        for (double t = -0.5; t < 3.0; t += 0.0731) {
            const hk_RigidState st = eval_at(m, t);
            assert_rotation(&st.rot);
            if (k < 3) {
                /* The rotation about axis k by g(t) degrees; the pivot stays fixed. */
                const hk_Mat3 want = rodrigues(hk_v3_unit(k), profile(a, f, t) * HK_PI / 180);
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) hk_assert_near(st.rot.m[i][j], want.m[i][j], 1e-14);
                hk_Vec3 p, v, acc;
                hk_rigid_point(&st, pivot, &p, &v, &acc);
                assert_vec_close(p, pivot, 0, 1e-16, "pivot position", t);
                assert_vec_close(v, hk_v3_zero(), 0, 1e-16, "pivot velocity", t);
                assert_vec_close(acc, hk_v3_zero(), 0, 1e-15, "pivot acceleration", t);
                /* The axis is fixed: omega is along it. */
                hk_assert_near(hk_v3_norm(hk_v3_cross(st.omega, hk_v3_unit(k))), 0, 1e-15);
            } else {
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) assert_true(st.rot.m[i][j] == (i == j));
                const hk_Vec3 want = hk_v3_scale(hk_v3_unit(k - 3), profile(0.04, f, t));
                assert_vec_close(st.trans, want, 0, 1e-16, "translation", t);
            }
        }
        hk_head_motion_destroy(m);
    }
    /* Signs: a nod lowers the face (+z turns toward -y), a shake turns it toward +x, a
     * tilt leans the crown (+y) toward -x. */
    const double quarter = 0.25 / f + 1.0 / f; /* a crest after the ease-in */
    const char *names[3] = {"nod", "shake", "tilt"};
    const hk_Vec3 probe[3] = {hk_v3(0, 0, 1), hk_v3(0, 0, 1), hk_v3(0, 1, 0)};
    const hk_Vec3 sign[3] = {hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(-1, 0, 0)};
    for (int k = 0; k < 3; k++) {
        hk_HeadMotion *m = scripted_ok(names[k], a, f);
        const hk_RigidState st = eval_at(m, quarter);
        assert_true(hk_v3_dot(hk_m3_mul_v3(&st.rot, probe[k]), sign[k]) > 0.49);
        hk_head_motion_destroy(m);
    }
}

/* Rest before t = 0, zero velocity and acceleration at 0+, continuous acceleration
 * where the ease-in ends. */
static void test_ease_in(void **state)
{
    (void)state;
    const double f = 1.0, te = 0.5;
    for (int k = 0; k < 5; k++) {
        hk_HeadMotion *m = scripted_ok(script_names[k], k < 3 ? 20 : 0.05, f);
        hk_RigidState st = eval_at(m, -0.3);
        assert_state_is_identity(&st);
        st = eval_at(m, 0.0);
        assert_state_is_identity(&st);
        /* Near 0: g ~ t^4, g' ~ t^3, g'' ~ t^2 (s ~ 10 u^3 times sin ~ t): doubling a
         * small t multiplies the speeds by 8 and the accelerations by 4. */
        const hk_RigidState s1 = eval_at(m, 1e-4), s2 = eval_at(m, 2e-4);
        const double v1 = vec_max_abs(s1.vel) + vec_max_abs(s1.omega);
        const double v2 = vec_max_abs(s2.vel) + vec_max_abs(s2.omega);
        const double a1 = vec_max_abs(s1.acc) + vec_max_abs(s1.alpha);
        const double a2 = vec_max_abs(s2.acc) + vec_max_abs(s2.alpha);
        assert_true(v1 > 0 && a1 > 0);
        hk_assert_near(v2 / v1, 8.0, 0.01);
        hk_assert_near(a2 / a1, 4.0, 0.01);
        /* Across T_e the acceleration changes by O(dt) only. */
        const hk_RigidState lo = eval_at(m, te - 1e-9), hi = eval_at(m, te + 1e-9);
        assert_vec_close(lo.acc, hi.acc, 0, 1e-6, "acc across the ease-in end", te);
        assert_vec_close(lo.alpha, hi.alpha, 0, 1e-6, "alpha across the ease-in end", te);
        hk_head_motion_destroy(m);
    }
}

static void test_scripted_errors(void **state)
{
    (void)state;
    hk_HeadMotion *m = (hk_HeadMotion *)&m; /* must come back NULL */
    hk_Error err;
    const hk_Vec3 c = hk_default_head_pivot();
    assert_int_equal(hk_head_motion_scripted("wobble", 10, 1, c, &m, &err), HK_ERR_INVALID);
    assert_null(m);
    assert_string_equal(err.message, "unknown head motion 'wobble' (expected still, nod, shake, tilt, sway or jump)");
    assert_int_equal(hk_head_motion_scripted("nod", 200, 1, c, &m, &err), HK_ERR_INVALID);
    assert_string_equal(err.message, "amplitude of head motion 'nod' must be in [-180, 180] degrees, got 200");
    assert_int_equal(hk_head_motion_scripted("sway", 11, 1, c, &m, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "[-10, 10] m");
    assert_int_equal(hk_head_motion_scripted("nod", NAN, 1, c, &m, &err), HK_ERR_INVALID);
    assert_int_equal(hk_head_motion_scripted("nod", 10, 0, c, &m, &err), HK_ERR_INVALID);
    assert_string_equal(err.message, "frequency of head motion 'nod' must be in (0, 1000] Hz, got 0");
    assert_int_equal(hk_head_motion_scripted("shake", 10, INFINITY, c, &m, &err), HK_ERR_INVALID);
    assert_int_equal(hk_head_motion_scripted("jump", 0.1, -1, c, &m, &err), HK_ERR_INVALID);
    assert_int_equal(hk_head_motion_scripted("tilt", 10, 1, hk_v3(0, NAN, 0), &m, &err), HK_ERR_INVALID);
    assert_int_equal(hk_head_motion_scripted(NULL, 10, 1, c, &m, NULL), HK_ERR_INVALID);
    assert_null(m);
    /* Names in any case; still ignores its amplitude and frequency. */
    assert_int_equal(hk_head_motion_scripted("Nod", 10, 1, c, &m, &err), HK_OK);
    hk_head_motion_destroy(m);
    assert_int_equal(hk_head_motion_scripted("STILL", NAN, 0, c, &m, &err), HK_OK);
    hk_head_motion_destroy(m);
}

/* ---- The rotation map ---------------------------------------------------------------- */

/* hk_rotation_exp along polynomial curves r(t) through the series/closed-form switch
 * (|r| = 2), near zero and through |r| = 2 pi, where the exponential's Jacobian is
 * singular: omega and alpha still match the finite differences of R. */
static void test_rotation_exp(void **state)
{
    (void)state;
    const double centres[] = {0.0, 1e-9, 0.3, 1.99999, 2.0, 2.00001, 3.1, 2 * HK_PI, 9.0, 40.0};
    for (size_t c = 0; c < sizeof centres / sizeof *centres; c++) {
        const hk_Vec3 r0 = hk_v3_scale(hk_v3_normalize(hk_v3(0.3, -0.8, 0.5)), centres[c]);
        const hk_Vec3 r1 = hk_v3(0.7, 0.2, -0.4), r2 = hk_v3(-0.3, 0.5, 0.9);
        for (int s = -3; s <= 3; s++) {
            const double t = 0.01 * s, h = 1e-5;
            hk_Mat3 rot[3];
            hk_Vec3 om[3], al[3];
            for (int k = 0; k < 3; k++) {
                const double tk = t + (k - 1) * h;
                const hk_Vec3 r = hk_v3_add(r0, hk_v3_add(hk_v3_scale(r1, tk), hk_v3_scale(r2, tk * tk)));
                const hk_Vec3 dr = hk_v3_add(r1, hk_v3_scale(r2, 2 * tk)), ddr = hk_v3_scale(r2, 2);
                hk_rotation_exp(r, dr, ddr, &rot[k], &om[k], &al[k]);
                assert_rotation(&rot[k]);
                const double n = hk_v3_norm(r);
                const hk_Mat3 want = rodrigues(n > 0 ? hk_v3_scale(r, 1 / n) : hk_v3(1, 0, 0), n);
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) hk_assert_near(rot[k].m[i][j], want.m[i][j], 1e-13);
            }
            hk_RigidState plus = hk_rigid_identity(), minus = plus, mid = plus;
            plus.rot = rot[2], minus.rot = rot[0], mid.rot = rot[1];
            assert_vec_close(om[1], fd_omega(&plus, &minus, &mid, h), 1e-7, 1e-9, "omega", t);
            assert_vec_close(al[1], hk_v3_scale(hk_v3_sub(om[2], om[0]), 0.5 / h), 1e-7, 1e-9, "alpha", t);
        }
    }
}

/* ---- Motion files -------------------------------------------------------------------- */

/* Line n holds key n - 2 (line 1 is the pivot). */
static const char *const sample = "Pivot 0.01 -0.02 0.005\n"
                                  "0.0   0     0     0      1 0 0   0\n"
                                  "0.5   0.01 -0.004 0.002  1 0 0   25\n"
                                  "0.9  -0.01  0     0.001  1 0.2 0 -15\n"
                                  "1.6   0     0.003 0      0 1 0   40\n"
                                  "2.0   0.02  0     0      0 1 1  -30   # a comment\n"
                                  "3.1   0     0     0      0 0 1   190\n"
                                  "3.5   0     0     0      0 0 0   0\n";

static const double sample_keys[7][8] = {
    {0.0, 0, 0, 0, 1, 0, 0, 0},      {0.5, 0.01, -0.004, 0.002, 1, 0, 0, 25}, {0.9, -0.01, 0, 0.001, 1, 0.2, 0, -15},
    {1.6, 0, 0.003, 0, 0, 1, 0, 40}, {2.0, 0.02, 0, 0, 0, 1, 1, -30},         {3.1, 0, 0, 0, 0, 0, 1, 190},
    {3.5, 0, 0, 0, 0, 0, 0, 0},
};

static void test_file_keys_exact(void **state)
{
    (void)state;
    hk_HeadMotion *m = load_ok(sample);
    assert_int_equal(hk_head_motion_key_count(m), 7);
    hk_assert_near(hk_head_motion_duration(m), 3.5, 0);
    const hk_Vec3 c = hk_head_motion_pivot(m);
    hk_assert_near(c.x, 0.01, 0);
    hk_assert_near(c.y, -0.02, 0);
    hk_assert_near(c.z, 0.005, 0);
    for (int k = 0; k < 7; k++) {
        const double *key = sample_keys[k];
        const hk_RigidState st = eval_at(m, key[0]);
        const hk_Vec3 axis = hk_v3_normalize(hk_v3(key[4], key[5], key[6]));
        const hk_Mat3 want = rodrigues(axis, key[7] * HK_PI / 180);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) hk_assert_near(st.rot.m[i][j], want.m[i][j], 2e-16);
        /* x -> R (x - c) + c + p: T = p + c - R c; the pivot lands on c + p exactly up
         * to the rounding of R c. */
        hk_Vec3 pos;
        hk_rigid_point(&st, c, &pos, NULL, NULL);
        assert_vec_close(pos, hk_v3_add(c, hk_v3(key[1], key[2], key[3])), 0, 1e-17, "pivot at key", key[0]);
        /* Rest at the first and last keys. */
        if (k == 0 || k == 6) {
            const hk_Vec3 z = hk_v3_zero();
            assert_vec_close(st.vel, z, 0, 0, "vel at an end key", key[0]);
            assert_vec_close(st.acc, z, 0, 0, "acc at an end key", key[0]);
            assert_vec_close(st.omega, z, 0, 0, "omega at an end key", key[0]);
            assert_vec_close(st.alpha, z, 0, 0, "alpha at an end key", key[0]);
        }
    }
    /* Holding before the first key and after the last. */
    const hk_RigidState first = eval_at(m, 0.0), last = eval_at(m, 3.5);
    for (double t = -2.0; t < 0.0; t += 0.3) {
        hk_RigidState st = eval_at(m, t);
        assert_memory_equal(&st, &first, sizeof st);
    }
    for (double t = 3.5; t < 9.0; t += 0.7) {
        hk_RigidState st = eval_at(m, t);
        assert_memory_equal(&st, &last, sizeof st);
    }
    hk_head_motion_destroy(m);
}

static void test_file_derivatives(void **state)
{
    (void)state;
    hk_HeadMotion *m = load_ok(sample);
    for (double t = 0.013; t < 3.5; t += 0.0177) {
        /* Central differences across a key lose an order (the jerk jumps there): keys
         * are checked below with a smaller step. */
        int near_key = 0;
        for (int k = 0; k < 7; k++) near_key |= fabs(t - sample_keys[k][0]) < 5e-6;
        if (!near_key) check_derivatives(m, t, 2e-6, 1.0);
    }
    /* At the keys, the end ones included, from either side: the interpolation is C2
     * there, but the jerk jumps, so central differences across a key are only first
     * order. */
    for (int k = 0; k < 7; k++) {
        check_one_sided(m, sample_keys[k][0], 2e-6, +1.0, 1.0);
        check_one_sided(m, sample_keys[k][0], 2e-6, -1.0, 1.0);
    }
    hk_head_motion_destroy(m);
}

/* Position, velocity and acceleration continuous at every key, including where the
 * motion starts and stops. */
static void test_file_c2(void **state)
{
    (void)state;
    hk_HeadMotion *m = load_ok(sample);
    const double e = 1e-10;
    for (int k = 0; k < 7; k++) {
        const double t = sample_keys[k][0];
        const hk_RigidState lo = eval_at(m, t - e), hi = eval_at(m, t + e);
        assert_vec_close(lo.trans, hi.trans, 0, 1e-9, "trans across a key", t);
        assert_vec_close(lo.vel, hi.vel, 0, 1e-7, "vel across a key", t);
        assert_vec_close(lo.acc, hi.acc, 0, 1e-6, "acc across a key", t);
        assert_vec_close(lo.omega, hi.omega, 0, 1e-7, "omega across a key", t);
        assert_vec_close(lo.alpha, hi.alpha, 0, 1e-6, "alpha across a key", t);
    }
    hk_head_motion_destroy(m);
}

/* One key: that pose forever. Two keys: the quintic smoothstep between them; the
 * default pivot without a Pivot line. */
static void test_file_few_keys(void **state)
{
    (void)state;
    hk_HeadMotion *m = load_ok("# one pose\n1.0 0.1 0.2 0.3 0 1 0 90\n");
    const hk_Vec3 c = hk_default_head_pivot();
    hk_Vec3 pc = hk_head_motion_pivot(m);
    assert_memory_equal(&pc, &c, sizeof c);
    const hk_RigidState ref = eval_at(m, 1.0);
    for (double t = -3; t < 3; t += 0.25) {
        hk_RigidState st = eval_at(m, t);
        assert_memory_equal(&st, &ref, sizeof st);
    }
    hk_assert_near(hk_head_motion_duration(m), 1.0, 0);
    hk_head_motion_destroy(m);

    m = load_ok("-1 0 0 0  0 0 0 0\n1 0.2 0 0  0 0 0 0\n");
    hk_assert_near(hk_head_motion_duration(m), 1.0, 0);
    for (double t = -1; t <= 1; t += 0.125) {
        const double u = (t + 1) / 2, s = u * u * u * (10 - 15 * u + 6 * u * u);
        const hk_RigidState st = eval_at(m, t);
        hk_assert_near(st.trans.x, 0.2 * s, 1e-15);
        hk_assert_near(st.trans.y, 0, 0);
    }
    check_derivatives(m, 0.3, 1e-5, 0.1);
    hk_head_motion_destroy(m);

    m = load_ok("-5 0 0 0  0 0 0 0\n-2 0.2 0 0  0 0 0 0\n");
    hk_assert_near(hk_head_motion_duration(m), 0.0, 0); /* ends before 0 */
    hk_head_motion_destroy(m);
}

/* Whole turns are scripted as written: 0, 180, 360, 540 degrees about y. */
static void test_file_turns(void **state)
{
    (void)state;
    hk_HeadMotion *m = load_ok("0 0 0 0 0 1 0 0\n1 0 0 0 0 1 0 180\n2 0 0 0 0 1 0 360\n"
                               "3 0 0 0 0 1 0 540\n");
    for (double t = 0.011; t < 3; t += 0.031) check_derivatives(m, t, 1e-5, 1.0);
    const hk_RigidState mid = eval_at(m, 1.5);
    assert_true(mid.omega.y > 2.0); /* still turning the same way through 270 degrees */
    hk_head_motion_destroy(m);
}

static void test_example_file(void **state)
{
    (void)state;
    hk_HeadMotion *m = NULL;
    hk_Error err;
    hk_Status st = hk_head_motion_load(HK_SOURCE_DIR "/examples/motions/nod-and-shake.txt", &m, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_int_equal(hk_head_motion_key_count(m), 11);
    hk_assert_near(hk_head_motion_duration(m), 4.5, 0);
    for (double t = 0.005; t < 4.5; t += 0.0213) check_derivatives(m, t, 1e-5, 1.0);
    hk_head_motion_destroy(m);
}

/* What a motion was made from makes the same motion again (the simulation manifest
 * records it): a scripted motion's name and arguments as given, a file's path. */
static void test_source(void **state)
{
    (void)state;
    hk_HeadMotion *a = NULL, *b = NULL, *f = NULL;
    hk_Error err;
    const hk_Vec3 pivot = hk_v3(0.01, -0.02, 0.003);
    assert_int_equal(hk_head_motion_scripted("Shake", 33.3, 1.7, pivot, &a, &err), HK_OK);
    const hk_HeadMotionSource s = hk_head_motion_source(a);
    assert_string_equal(s.script, "shake");
    assert_null(s.file);
    assert_true(s.amplitude == 33.3 && s.frequency == 1.7);
    assert_memory_equal(&s.pivot, &pivot, sizeof pivot);
    assert_int_equal(hk_head_motion_scripted(s.script, s.amplitude, s.frequency, s.pivot, &b, &err), HK_OK);
    for (double t = 0.0; t < 2.0; t += 0.37) {
        hk_RigidState x, y;
        hk_head_motion_eval(a, t, &x);
        hk_head_motion_eval(b, t, &y);
        assert_memory_equal(&x, &y, sizeof x);
    }
    const char *path = HK_SOURCE_DIR "/examples/motions/nod-and-shake.txt";
    assert_int_equal(hk_head_motion_load(path, &f, &err), HK_OK);
    assert_null(hk_head_motion_source(f).script);
    assert_string_equal(hk_head_motion_source(f).file, path);
    hk_head_motion_destroy(a);
    hk_head_motion_destroy(b);
    hk_head_motion_destroy(f);
}

/* Loads `text` expecting failure with `code` and exactly `message` (the temporary
 * folder prefix removed). */
static void load_fails(const char *text, hk_Status code, const char *message)
{
    hk_HeadMotion *m = (hk_HeadMotion *)&m;
    hk_Error err;
    const char *path = hk_test_write_text("motion.txt", text);
    hk_Status st = hk_head_motion_load(path, &m, &err);
    if (st == HK_OK) print_error("accepted: %s\n", text);
    assert_int_equal(st, code);
    assert_null(m);
    const size_t dir = strlen(hk_test_tmpdir()) + 1;
    assert_true(strncmp(err.message, path, strlen(path)) == 0);
    assert_string_equal(err.message + dir, message);
}

static void test_file_errors(void **state)
{
    (void)state;
    load_fails("0 0 0 0 1 0 0 0\n1 0 0 0 1 0 0 5\n1 0 0 0 1 0 0 5\n", HK_ERR_INVALID,
               "motion.txt:3: time 1 is not after the previous keyframe's 1 (line 2): times must "
               "increase strictly");
    load_fails("# times\n0 0 0 0 1 0 0 0\n\n2 0 0 0 1 0 0 5\n1.5 0 0 0 1 0 0 5\n", HK_ERR_INVALID,
               "motion.txt:5: time 1.5 is not after the previous keyframe's 2 (line 4): times must "
               "increase strictly");
    load_fails("0.1 0 0 0 1 0 0 0\n0.1000001 0 0 0 1 0 0 5\n", HK_ERR_INVALID,
               "motion.txt:2: time 0.1000001 is less than 1e-06 s after the previous keyframe's 0.1 "
               "(line 1)");
    load_fails("0 0 0 0 1 0 0 0\n1 0 0 0 1 0 0\n", HK_ERR_PARSE,
               "motion.txt:2: expected 8 numbers on a keyframe line (t tx ty tz ax ay az angle), got 7");
    load_fails("0 0 0 0 1 0 0 0 9\n", HK_ERR_PARSE,
               "motion.txt:1: expected 8 numbers on a keyframe line (t tx ty tz ax ay az angle), got 9");
    load_fails("0 0 0 zero 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:1: 'zero' is not a finite number (value 4 of 'keyframe')");
    load_fails("0 0 0 0 1 0 0 nan\n", HK_ERR_PARSE,
               "motion.txt:1: 'nan' is not a finite number (value 8 of 'keyframe')");
    load_fails("inf 0 0 0 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:1: unknown key 'inf' in a head motion file (a keyframe line is t tx ty tz "
               "ax ay az angle)");
    load_fails("-inf 0 0 0 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:1: '-inf' is not a finite number (value 1 of 'keyframe')");
    load_fails("0 0 1e999 0 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:1: '1e999' is out of the range of double precision (value 3 of 'keyframe')");
    load_fails("", HK_ERR_PARSE, "motion.txt: file is empty");
    load_fails("# nothing but comments\n\n", HK_ERR_PARSE,
               "motion.txt: no keyframe (expected lines 't tx ty tz ax ay az angle')");
    load_fails("Pivot 0 0 0\n", HK_ERR_PARSE, "motion.txt: no keyframe (expected lines 't tx ty tz ax ay az angle')");
    load_fails("0 0 0 0 0 0 0 30\n", HK_ERR_INVALID,
               "motion.txt:1: the rotation axis is zero but the angle is 30 degrees (a zero axis goes "
               "only with angle 0)");
    load_fails("Pivot 0 0\n0 0 0 0 1 0 0 0\n", HK_ERR_PARSE, "motion.txt:1: expected 3 numbers after 'Pivot', got 2");
    load_fails("Pivot 0 0 0\npivot 0 0 0\n0 0 0 0 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:2: duplicate key 'Pivot' (first given at line 1)");
    load_fails("# c\n0 0 0 0 1 0 0 0\nPivot 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:3: Pivot must come before the first keyframe (line 2)");
    load_fails("Pivot 0 1e4 0\n0 0 0 0 1 0 0 0\n", HK_ERR_INVALID,
               "motion.txt:1: Pivot coordinates must be within +-1000 m, got 1e4");
    load_fails("Pivto 0 0 0\n0 0 0 0 1 0 0 0\n", HK_ERR_PARSE,
               "motion.txt:1: unknown key 'Pivto' in a head motion file (a keyframe line is t tx ty "
               "tz ax ay az angle)");
    load_fails("2e6 0 0 0 1 0 0 0\n", HK_ERR_INVALID, "motion.txt:1: time must be within +-1e+06 s, got 2e6");
    load_fails("0 0 -1001 0 1 0 0 0\n", HK_ERR_INVALID, "motion.txt:1: translation must be within +-1000 m, got -1001");
    load_fails("0 0 0 0 1 0 0 1e6\n", HK_ERR_INVALID, "motion.txt:1: angle must be within +-100000 degrees, got 1e6");
    load_fails("0 0 0 0 1 0 0 0\n1 0 0 0 1 0 0 \"5\"x\n", HK_ERR_PARSE,
               "motion.txt:2: misplaced double quote: quotes enclose a whole value, as in \"my "
               "file.txt\"");

    /* A missing file and a folder. */
    hk_HeadMotion *m = NULL;
    hk_Error err;
    assert_int_equal(hk_head_motion_load("/nonexistent/motion.txt", &m, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/motion.txt: cannot open");
    assert_int_equal(hk_head_motion_load(hk_test_tmpdir(), &m, &err), HK_ERR_IO);
    assert_null(m);

    /* A tiny axis is a direction, not zero; an axis of any length is normalised. */
    m = load_ok("0 0 0 0 1e-300 0 0 90\n");
    hk_RigidState st = eval_at(m, 0);
    hk_assert_near(st.rot.m[1][2], -1.0, 1e-15);
    hk_head_motion_destroy(m);
    m = load_ok("0 0 0 0 0 0 0 0\n");
    st = eval_at(m, 0);
    assert_state_is_identity(&st); /* pivot or not: the pose is the identity */
    hk_head_motion_destroy(m);
}

/* More keyframes than allowed: refused at the first one too many, before anything is
 * allocated for them. */
static void test_file_key_limit(void **state)
{
    (void)state;
    /* Identical lines keep the file under the 16 MiB input limit; the count is checked
     * before the times. */
    static const char line[] = "0 0 0 0 0 0 0 0\n";
    const size_t n = HK_MAX_MOTION_KEYS + 1, ll = sizeof line - 1, len = n * ll;
    char *text = malloc(len);
    assert_non_null(text);
    for (size_t i = 0; i < n; i++) memcpy(text + i * ll, line, ll);
    const char *path = hk_test_write_file("motion.txt", text, len);
    free(text);
    hk_HeadMotion *m = NULL;
    hk_Error err;
    assert_int_equal(hk_head_motion_load(path, &m, &err), HK_ERR_INVALID);
    assert_null(m);
    hk_assert_contains(err.message, "motion.txt:1000001: more than 1000000 keyframes");
}

/* Mutated copies of the sample: each load either succeeds with a usable motion or
 * fails with a message naming the file; the sanitizer build checks the rest. */
static void test_fuzz(void **state)
{
    (void)state;
    static const char *const junk[10] = {
        "1e308 ", "-", "nan", "\"", "#", "\r\n", "Pivot 0 0 0\n", "0 0 0 0 0 0 0 0\n", "\t", "99999999"};
    unsigned long long x = 0x9E3779B97F4A7C15ULL;
    int rejected = 0, accepted = 0;
    for (int iter = 0; iter < 2000; iter++) {
        char buf[2048];
        size_t len = strlen(sample);
        memcpy(buf, sample, len);
        const int edits = 1 + iter % 4;
        for (int e = 0; e < edits; e++) len = hk_test_mutate(buf, len, sizeof buf, " \t\n#-.e0123456789", junk, 10, &x);
        const char *path = hk_test_write_file("fuzz_motion.txt", buf, len);
        hk_HeadMotion *m = NULL;
        hk_Error err;
        err.message[0] = '\0';
        hk_Status st = hk_head_motion_load(path, &m, &err);
        if (st == HK_OK) {
            const int n = hk_head_motion_key_count(m);
            assert_true(n >= 1 && n <= HK_MAX_MOTION_KEYS);
            const double end = hk_head_motion_duration(m);
            assert_true(end >= 0 && isfinite(end));
            for (double t = -1.0; t < 5.0; t += 0.173) {
                const hk_RigidState s = eval_at(m, t);
                assert_rotation(&s.rot);
                assert_true(hk_v3_isfinite(s.trans) && hk_v3_isfinite(s.vel) && hk_v3_isfinite(s.acc));
                assert_true(hk_v3_isfinite(s.omega) && hk_v3_isfinite(s.alpha));
            }
            hk_head_motion_destroy(m);
            accepted++;
        } else {
            assert_null(m);
            assert_true(st == HK_ERR_PARSE || st == HK_ERR_INVALID);
            assert_true(strncmp(err.message, path, strlen(path)) == 0);
            assert_true(strlen(err.message) > strlen(path) + 3);
            rejected++;
        }
    }
    print_message("motion fuzz: %d rejected, %d accepted\n", rejected, accepted);
    assert_true(rejected > 500 && accepted > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_still),
        cmocka_unit_test(test_scripted_derivatives),
        cmocka_unit_test(test_scripted_formulas),
        cmocka_unit_test(test_ease_in),
        cmocka_unit_test(test_scripted_errors),
        cmocka_unit_test(test_rotation_exp),
        cmocka_unit_test(test_file_keys_exact),
        cmocka_unit_test(test_file_derivatives),
        cmocka_unit_test(test_file_c2),
        cmocka_unit_test(test_file_few_keys),
        cmocka_unit_test(test_file_turns),
        cmocka_unit_test(test_example_file),
        cmocka_unit_test(test_file_errors),
        cmocka_unit_test(test_file_key_limit),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_source),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
