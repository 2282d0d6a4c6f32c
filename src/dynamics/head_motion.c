/* Head motion (issue 6): scripted motions in closed form, the rigid-body kinematics of
 * a head point, and the dispatch to keyframed motions (motion_file.c). The roots of the
 * Super-Helices are clamped to the head (paper 000 §3.4), so these are the boundary
 * conditions the dynamics sees. Formulas: docs/dynamics.md, "Head motion". */
#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include "io/keyfile.h"
#include "motion_internal.h"


hk_RigidState hk_rigid_identity(void)
{
    hk_RigidState st;
    st.rot = hk_m3_identity();
    st.trans = st.vel = st.acc = st.omega = st.alpha = hk_v3_zero();
    return st;
}

void hk_rigid_point(const hk_RigidState *st, hk_Vec3 x, hk_Vec3 *pos, hk_Vec3 *vel, hk_Vec3 *acc)
{
    const hk_Vec3 r = hk_m3_mul_v3(&st->rot, x); /* lever arm from the head-space origin */
    const hk_Vec3 w_r = hk_v3_cross(st->omega, r);
    if (pos) *pos = hk_v3_add(r, st->trans);
    if (vel) *vel = hk_v3_add(st->vel, w_r);
    if (acc) *acc = hk_v3_add(st->acc, hk_v3_add(hk_v3_cross(st->alpha, r), hk_v3_cross(st->omega, w_r)));
}

/* The top of the neck capsule of tools/make_assets.c (axis x = 0, z = -0.015, from
 * y = -0.16 up to y = -0.01): the head nods and turns about the joints between the
 * skull and the first vertebrae, which sit there, some 4.5 cm below the ears. */
hk_Vec3 hk_default_head_pivot(void) { return hk_v3(0.0, -0.010, -0.015); }

void hk_motion_about_pivot(hk_RigidState *st, hk_Vec3 pivot, hk_Vec3 p, hk_Vec3 dp, hk_Vec3 ddp)
{
    /* The pivot is a head point that only p moves: T = p + c - R c, and the derivatives
     * of -R c are those of a point with lever arm R c. */
    const hk_Vec3 rc = hk_m3_mul_v3(&st->rot, pivot);
    const hk_Vec3 w_rc = hk_v3_cross(st->omega, rc);
    st->trans = hk_v3_add(p, hk_v3_sub(pivot, rc));
    st->vel = hk_v3_sub(dp, w_rc);
    st->acc = hk_v3_sub(ddp, hk_v3_add(hk_v3_cross(st->alpha, rc), hk_v3_cross(st->omega, w_rc)));
}

/* ---- Scripted motions ------------------------------------------------------------- */

typedef struct Script {
    const char *name;
    hk_MotionKind kind;
    int axis; /* 0, 1, 2 for x, y, z */
} Script;

static const Script scripts[] = {
    {"still", HK_MOTION_STILL, 0}, {"nod", HK_MOTION_ROTATE, 0},     {"shake", HK_MOTION_ROTATE, 1},
    {"tilt", HK_MOTION_ROTATE, 2}, {"sway", HK_MOTION_TRANSLATE, 0}, {"jump", HK_MOTION_TRANSLATE, 1},
};

#define HK_MAX_SCRIPT_DEGREES 180.0 /* a head turns less; more would wrap around */
#define HK_MAX_SCRIPT_METRES  10.0
#define HK_MAX_SCRIPT_HZ      1000.0

hk_Status hk_head_motion_scripted(const char *name, double amplitude, double frequency, hk_Vec3 pivot,
                                  hk_HeadMotion **out, hk_Error *err)
{
    *out = NULL;
    const Script *s = NULL;
    for (size_t i = 0; name && i < sizeof scripts / sizeof *scripts; i++)
        if (hk_key_equal(name, scripts[i].name)) s = &scripts[i];
    if (!s)
        return hk_error_set(err, HK_ERR_INVALID,
                            "unknown head motion '%s' (expected still, nod, shake, tilt, sway or jump)",
                            name ? name : "(null)");
    if (!hk_v3_isfinite(pivot))
        return hk_error_set(err, HK_ERR_INVALID, "the pivot of head motion '%s' is not finite", s->name);
    if (s->kind != HK_MOTION_STILL) {
        const int rotate = s->kind == HK_MOTION_ROTATE;
        const double max = rotate ? HK_MAX_SCRIPT_DEGREES : HK_MAX_SCRIPT_METRES;
        if (!(fabs(amplitude) <= max))
            return hk_error_set(err, HK_ERR_INVALID, "amplitude of head motion '%s' must be in [-%g, %g] %s, got %g",
                                s->name, max, max, rotate ? "degrees" : "m", amplitude);
        if (!(frequency > 0.0 && frequency <= HK_MAX_SCRIPT_HZ))
            return hk_error_set(err, HK_ERR_INVALID, "frequency of head motion '%s' must be in (0, %g] Hz, got %g",
                                s->name, HK_MAX_SCRIPT_HZ, frequency);
    }
    hk_HeadMotion *m = hk_calloc_array(1, sizeof *m, err);
    if (!m) return HK_ERR_NOMEM;
    m->kind = s->kind;
    m->pivot = pivot;
    m->script = s->name;
    m->amplitude_given = amplitude;
    m->axis = hk_v3_unit(s->axis);
    m->amplitude = s->kind == HK_MOTION_ROTATE ? amplitude * (HK_PI / 180.0) : amplitude;
    m->frequency = frequency;
    *out = m;
    return HK_OK;
}

/* g(t) = A s(t / T_e) sin(w t) with w = 2 pi f, T_e = 1 / (2 f) and the quintic
 * smoothstep s(u) = 10u^3 - 15u^4 + 6u^5: s, s', s'' vanish at u = 0 and s', s'' at
 * u = 1, so g is C2 at t = 0 (rest before) and at t = T_e (pure sine after) without
 * relying on sin(w T_e) = 0, i.e. whatever the length of the ease-in. */
static void scripted_profile(const hk_HeadMotion *m, double t, double g[3])
{
    g[0] = g[1] = g[2] = 0.0;
    if (!(t > 0.0)) return;
    const double w = 2.0 * HK_PI * m->frequency, te = 0.5 / m->frequency;
    double s = 1.0, ds = 0.0, dds = 0.0;
    if (t < te) {
        const double u = t / te;
        s = u * u * u * (10.0 + u * (-15.0 + 6.0 * u));
        ds = 30.0 * u * u * (u - 1.0) * (u - 1.0) / te;
        dds = 60.0 * u * (u - 1.0) * (2.0 * u - 1.0) / (te * te);
    }
    const double sn = sin(w * t), cs = cos(w * t), a = m->amplitude;
    g[0] = a * s * sn;
    g[1] = a * (ds * sn + s * w * cs);
    g[2] = a * (dds * sn + 2.0 * ds * w * cs - s * w * w * sn);
}

void hk_head_motion_eval(const hk_HeadMotion *m, double t, hk_RigidState *out)
{
    assert(isfinite(t));
    *out = hk_rigid_identity();
    if (m->kind == HK_MOTION_KEYS) {
        hk_motion_keys_eval(m, t, out);
        return;
    }
    if (m->kind == HK_MOTION_FOLLOW) {
        hk_motion_follow_eval(m, t, out);
        return;
    }
    if (m->kind == HK_MOTION_STILL) return;
    double g[3];
    scripted_profile(m, t, g);
    const hk_Vec3 zero = hk_v3_zero();
    if (m->kind == HK_MOTION_TRANSLATE) {
        out->trans = hk_v3_scale(m->axis, g[0]);
        out->vel = hk_v3_scale(m->axis, g[1]);
        out->acc = hk_v3_scale(m->axis, g[2]);
        return;
    }
    /* A fixed axis: omega = g' axis and alpha = g'' axis, which hk_rotation_exp also
     * finds (r x r' = 0); one code path for R keeps scripted and keyed motions alike. */
    hk_rotation_exp(hk_v3_scale(m->axis, g[0]), hk_v3_scale(m->axis, g[1]), hk_v3_scale(m->axis, g[2]), &out->rot,
                    &out->omega, &out->alpha);
    hk_motion_about_pivot(out, m->pivot, zero, zero, zero);
}

double hk_head_motion_duration(const hk_HeadMotion *m)
{
    if (m->kind == HK_MOTION_FOLLOW) return m->base ? hk_head_motion_duration(m->base) : INFINITY;
    if (m->kind != HK_MOTION_KEYS) return INFINITY;
    const double last = m->times[m->key_count - 1];
    return last > 0.0 ? last : 0.0;
}

hk_Vec3 hk_head_motion_pivot(const hk_HeadMotion *m) { return m->pivot; }

hk_HeadMotionSource hk_head_motion_source(const hk_HeadMotion *m)
{
    hk_HeadMotionSource s = {m->script, m->amplitude_given, m->frequency, m->pivot, m->path};
    return s;
}

int hk_head_motion_key_count(const hk_HeadMotion *m) { return m->kind == HK_MOTION_KEYS ? m->key_count : 0; }

void hk_head_motion_destroy(hk_HeadMotion *m)
{
    if (!m) return;
    hk_free(m->times);
    hk_free(m->knots);
    hk_free(m->path);
    hk_free(m);
}
