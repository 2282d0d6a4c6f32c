/* The head moved by an input (hk_head_motion_follow, motion.h), against an independent
 * reference: the offset's velocity and acceleration against central finite differences
 * of its position, the spring's equation e'' = -2 w e' - w^2 e checked at every time,
 * the position and velocity continuous where the target jumps, the offset reaching the
 * target without overshoot (critical damping), the base motion added unchanged, and bad
 * input refused. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/motion.h"

static hk_RigidState at(const hk_HeadMotion *m, double t)
{
    hk_RigidState s;
    hk_head_motion_eval(m, t, &s);
    return s;
}

/* Velocity and acceleration against central differences of the position (h = 1e-4 s:
 * truncation ~ h^2 |d''''| and round-off ~ 1e-16 / h^2 both below 1e-6 here). */
static void check_derivatives(const hk_HeadMotion *m, double t)
{
    const double h = 1e-4;
    const hk_RigidState a = at(m, t - h), b = at(m, t), c = at(m, t + h);
    const hk_Vec3 vel = hk_v3_scale(hk_v3_sub(c.trans, a.trans), 0.5 / h);
    const hk_Vec3 acc = hk_v3_scale(hk_v3_add(hk_v3_sub(c.trans, hk_v3_scale(b.trans, 2.0)), a.trans), 1.0 / (h * h));
    assert_true(hk_v3_norm(hk_v3_sub(vel, b.vel)) < 1e-6 * (1.0 + hk_v3_norm(b.vel)));
    assert_true(hk_v3_norm(hk_v3_sub(acc, b.acc)) < 1e-4 * (1.0 + hk_v3_norm(b.acc)));
}

static void test_follow_derivatives_and_jumps(void **state)
{
    (void)state;
    hk_HeadMotion *m = NULL;
    hk_Error err;
    const double w = 12.0;
    assert_int_equal(hk_head_motion_follow(NULL, w, &m, &err), HK_OK);
    /* at rest at the origin until a target is given */
    hk_RigidState s = at(m, 0.3);
    assert_true(hk_v3_norm(s.trans) == 0.0 && hk_v3_norm(s.vel) == 0.0 && hk_v3_norm(s.acc) == 0.0);
    const hk_Vec3 targets[3] = {hk_v3(0.05, 0.0, 0.0), hk_v3(0.02, -0.03, 0.01), hk_v3(0.0, 0.0, 0.0)};
    const double times[3] = {0.1, 0.17, 0.31};
    for (int k = 0; k < 3; k++) {
        const hk_RigidState before = at(m, times[k]);
        hk_head_motion_follow_target(m, times[k], targets[k]);
        const hk_RigidState after = at(m, times[k]);
        /* the head does not jump, nor its speed: only the acceleration may */
        assert_true(hk_v3_norm(hk_v3_sub(before.trans, after.trans)) < 1e-15);
        assert_true(hk_v3_norm(hk_v3_sub(before.vel, after.vel)) < 1e-14);
        for (double t = times[k] + 0.001; t < times[k] + 0.06; t += 0.0123) {
            check_derivatives(m, t);
            /* the spring's equation, with e = d - target */
            const hk_RigidState q = at(m, t);
            const hk_Vec3 e = hk_v3_sub(q.trans, targets[k]);
            const hk_Vec3 rhs = hk_v3_sub(hk_v3_scale(q.vel, -2.0 * w), hk_v3_scale(e, w * w));
            assert_true(hk_v3_norm(hk_v3_sub(q.acc, rhs)) < 1e-9 * (1.0 + hk_v3_norm(q.acc)));
        }
    }
    /* critically damped from rest: reaches the target without passing it */
    hk_head_motion_follow_reset(m);
    hk_head_motion_follow_target(m, 0.0, hk_v3(0.1, 0.0, 0.0));
    double last = 0.0;
    for (double t = 0.01; t < 2.0; t += 0.01) {
        const double x = at(m, t).trans.x;
        assert_true(x >= last && x <= 0.1);
        last = x;
    }
    assert_true(fabs(last - 0.1) < 1e-6);
    /* reset: back at rest at the origin */
    hk_head_motion_follow_reset(m);
    s = at(m, 1.0);
    assert_true(hk_v3_norm(s.trans) == 0.0 && hk_v3_norm(s.vel) == 0.0);
    hk_head_motion_destroy(m);
}

static void test_follow_adds_to_base(void **state)
{
    (void)state;
    hk_HeadMotion *base = NULL, *m = NULL;
    hk_Error err;
    assert_int_equal(hk_head_motion_scripted("shake", 25.0, 1.0, hk_default_head_pivot(), &base, &err), HK_OK);
    assert_int_equal(hk_head_motion_follow(base, 8.0, &m, &err), HK_OK);
    hk_head_motion_follow_target(m, 0.2, hk_v3(0.0, 0.04, 0.0));
    for (double t = 0.0; t < 1.0; t += 0.07) {
        const hk_RigidState b = at(base, t), f = at(m, t);
        /* the rotation is the base's; the position moved by the offset alone */
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) assert_true(f.rot.m[i][j] == b.rot.m[i][j]);
        assert_true(hk_v3_norm(hk_v3_sub(f.omega, b.omega)) == 0.0);
        assert_true(fabs(f.trans.x - b.trans.x) < 1e-15 && fabs(f.trans.z - b.trans.z) < 1e-15);
        if (t > 0.2) check_derivatives(m, t);
    }
    assert_true(hk_head_motion_duration(m) == INFINITY);
    assert_string_equal(hk_head_motion_source(m).script, "follow");
    hk_head_motion_destroy(m);
    hk_head_motion_destroy(base);
}

static void test_follow_errors(void **state)
{
    (void)state;
    hk_HeadMotion *m = (hk_HeadMotion *)1;
    hk_Error err;
    assert_int_equal(hk_head_motion_follow(NULL, 0.0, &m, &err), HK_ERR_INVALID);
    assert_null(m);
    assert_int_equal(hk_head_motion_follow(NULL, NAN, &m, &err), HK_ERR_INVALID);
    assert_non_null(strstr(err.message, "rate"));
    /* a target on a motion of another kind is ignored */
    hk_HeadMotion *still = NULL;
    assert_int_equal(hk_head_motion_scripted("still", 0.0, 1.0, hk_default_head_pivot(), &still, &err), HK_OK);
    hk_head_motion_follow_target(still, 0.0, hk_v3(1, 1, 1));
    assert_true(hk_v3_norm(at(still, 1.0).trans) == 0.0);
    hk_head_motion_destroy(still);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_follow_derivatives_and_jumps),
        cmocka_unit_test(test_follow_adds_to_base),
        cmocka_unit_test(test_follow_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
