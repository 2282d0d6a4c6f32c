/* A head moved by an interactive input (hk_head_motion_follow, motion.h): a base motion
 * plus a translation that follows a target as a critically damped spring. The roots are
 * clamped to the head (Bertails et al. 2006 §3.4), so the dynamics needs the head's
 * velocity and acceleration: both are exact here, and the velocity stays continuous
 * when the target jumps (a mouse drag moves it every frame). */
#include <math.h>

#include "motion_internal.h"

hk_Status hk_head_motion_follow(const hk_HeadMotion *base, double rate, hk_HeadMotion **out, hk_Error *err)
{
    *out = NULL;
    if (!(rate > 0.0 && rate < 1e6))
        return hk_error_set(err, HK_ERR_INVALID, "the rate of a following head must be in (0, 1e6) 1/s, got %g", rate);
    hk_HeadMotion *m = hk_calloc_array(1, sizeof *m, err);
    if (!m) return HK_ERR_NOMEM;
    m->kind = HK_MOTION_FOLLOW;
    m->base = base;
    m->pivot = base ? hk_head_motion_pivot(base) : hk_default_head_pivot();
    m->script = "follow";
    m->frequency = 1.0;
    m->follow_rate = rate;
    hk_head_motion_follow_reset(m);
    *out = m;
    return HK_OK;
}

void hk_head_motion_follow_reset(hk_HeadMotion *m)
{
    if (m->kind != HK_MOTION_FOLLOW) return;
    m->follow_t0 = 0.0;
    m->follow_target = m->follow_e0 = m->follow_v0 = hk_v3_zero();
}

/* e(s) = (A + B s) exp(-w s), A = e0, B = v0 + w e0:
 *   e'  = (B - w (A + B s)) exp(-w s),  e'' = (w^2 (A + B s) - 2 w B) exp(-w s). */
static void spring(const hk_HeadMotion *m, double t, hk_Vec3 *e, hk_Vec3 *de, hk_Vec3 *dde)
{
    const double w = m->follow_rate, s = t - m->follow_t0, decay = exp(-w * s);
    const hk_Vec3 a = m->follow_e0, b = hk_v3_add(m->follow_v0, hk_v3_scale(a, w));
    const hk_Vec3 now = hk_v3_add(a, hk_v3_scale(b, s));
    *e = hk_v3_scale(now, decay);
    *de = hk_v3_scale(hk_v3_sub(b, hk_v3_scale(now, w)), decay);
    *dde = hk_v3_scale(hk_v3_sub(hk_v3_scale(now, w * w), hk_v3_scale(b, 2.0 * w)), decay);
}

void hk_head_motion_follow_target(hk_HeadMotion *m, double t, hk_Vec3 target)
{
    if (m->kind != HK_MOTION_FOLLOW || !isfinite(t) || !hk_v3_isfinite(target)) return;
    hk_Vec3 e, de, dde;
    spring(m, t, &e, &de, &dde);
    /* d(t) kept: the new error is the old offset measured from the new target */
    const hk_Vec3 d = hk_v3_add(m->follow_target, e);
    m->follow_t0 = t;
    m->follow_target = target;
    m->follow_e0 = hk_v3_sub(d, target);
    m->follow_v0 = de;
}

void hk_motion_follow_eval(const hk_HeadMotion *m, double t, hk_RigidState *out)
{
    if (m->base)
        hk_head_motion_eval(m->base, t, out);
    else
        *out = hk_rigid_identity();
    hk_Vec3 e, de, dde;
    spring(m, t, &e, &de, &dde);
    /* x -> R x + T + d: the offset adds to the position and its derivatives. */
    out->trans = hk_v3_add(out->trans, hk_v3_add(m->follow_target, e));
    out->vel = hk_v3_add(out->vel, de);
    out->acc = hk_v3_add(out->acc, dde);
}
