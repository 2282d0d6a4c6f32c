/* Head motion: where the scalp is, and how fast it moves, at any time (issue 6).
 *
 * The hair roots are fixed in head space; the dynamics needs their world positions,
 * velocities and accelerations, and the head's angular velocity and acceleration (the
 * clamped root frame turns with the head). A head motion is either scripted (nod,
 * shake, tilt, sway, jump: closed forms, derivatives exact) or read from a motion file
 * of keyframes (docs/file-formats.md, "Head motion file"; interpolation C2 in time).
 * Conventions (DESIGN.md): metres, seconds, y up, the face looks along +z. Formulas and
 * their reasons: docs/dynamics.md, "Head motion". */
#ifndef HAIRKIT_MOTION_H
#define HAIRKIT_MOTION_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Rigid motion of the head at time t: the head-space point x is at world R x + T. */
typedef struct hk_RigidState {
    hk_Mat3 rot;   /* R(t), a rotation */
    hk_Vec3 trans; /* T(t) (m) */
    hk_Vec3 vel;   /* dT/dt (m/s) */
    hk_Vec3 acc;   /* d2T/dt2 (m/s^2) */
    hk_Vec3 omega; /* world angular velocity (rad/s): dR/dt = [omega]x R */
    hk_Vec3 alpha; /* d omega/dt (rad/s^2) */
} hk_RigidState;

/* The state of a head at rest at the origin: R = I, everything else zero. */
HK_API hk_RigidState hk_rigid_identity(void);

/* World position, velocity and acceleration of the head-space point x:
 *   pos = R x + T,  vel = dT/dt + omega x (R x),
 *   acc = d2T/dt2 + alpha x (R x) + omega x (omega x (R x)).
 * Any of pos, vel, acc may be NULL. */
HK_API void hk_rigid_point(const hk_RigidState *st, hk_Vec3 x, hk_Vec3 *pos, hk_Vec3 *vel, hk_Vec3 *acc);

/* Default pivot of the head's rotations (m, head space): (0, -0.010, -0.015), the top
 * of the neck of assets/head.obj, where the skull sits on the spine (see
 * docs/dynamics.md). */
HK_API hk_Vec3 hk_default_head_pivot(void);

typedef struct hk_HeadMotion hk_HeadMotion;

/* Scripted motions, by name (any case):
 *   still                 the head does not move (amplitude, frequency ignored)
 *   nod, shake, tilt      rotation about the axis x, y or z through `pivot` by the
 *                         angle g(t) degrees (nod > 0 lowers the face, shake > 0
 *                         turns it toward +x, tilt > 0 leans the crown toward -x)
 *   sway, jump            translation by g(t) metres along x or y
 * with g(t) = amplitude * s(t / T_e) * sin(2 pi frequency t), T_e = 1 / (2 frequency)
 * (half a period) and the ease-in s(u) = 10u^3 - 15u^4 + 6u^5 for 0 <= u <= 1, 1
 * after; g = 0 for t <= 0. s(0) = s'(0) = s''(0) = 0 and s(1) = 1, s'(1) = s''(1) = 0,
 * so the motion starts from rest with zero acceleration and is C2 throughout.
 * Amplitude: degrees for rotations, |amplitude| <= 180; metres for translations,
 * |amplitude| <= 10. Frequency in (0, 1000] Hz. HK_ERR_INVALID, with a message, for an
 * unknown name or values out of range. */
HK_API hk_Status hk_head_motion_scripted(const char *name, double amplitude, double frequency, hk_Vec3 pivot,
                                         hk_HeadMotion **out, hk_Error *err);

/* Reads a head motion file (docs/file-formats.md, "Head motion file"): an optional
 * `Pivot x y z` line, then keyframes `t tx ty tz ax ay az angle_deg`. Errors name the
 * file and the line. On error *out is NULL. */
HK_API hk_Status hk_head_motion_load(const char *path, hk_HeadMotion **out, hk_Error *err);

/* The rigid state at time t (finite). Before the start (t <= 0 for a scripted motion,
 * the first keyframe for a file) and after the last keyframe the head holds its pose
 * with zero velocity and acceleration. */
HK_API void hk_head_motion_eval(const hk_HeadMotion *m, double t, hk_RigidState *out);

/* How long the motion lasts: INFINITY for a scripted motion (it never stops), the time
 * of the last keyframe (at least 0) for a motion file. */
HK_API double hk_head_motion_duration(const hk_HeadMotion *m);

/* The pivot the rotations turn about (head space). */
HK_API hk_Vec3 hk_head_motion_pivot(const hk_HeadMotion *m);

/* What a motion was made from, enough to make it again (the manifest of `hairkit
 * simulate` records it): a scripted motion's name and its arguments as given to
 * hk_head_motion_scripted, or the path of the motion file as given to
 * hk_head_motion_load. The strings belong to the motion. */
typedef struct hk_HeadMotionSource {
    const char *script; /* "still", "nod", "shake", "tilt", "sway", "jump"; NULL for a file */
    double amplitude;   /* degrees or metres, as given (scripted) */
    double frequency;   /* Hz (scripted) */
    hk_Vec3 pivot;
    const char *file; /* the motion file; NULL for a scripted motion */
} hk_HeadMotionSource;

HK_API hk_HeadMotionSource hk_head_motion_source(const hk_HeadMotion *m);

/* Number of keyframes of a motion file; 0 for a scripted motion. */
HK_API int hk_head_motion_key_count(const hk_HeadMotion *m);

/* A head moved by an interactive input (`hairkit view`, dragging the head): the motion
 * `base` (NULL: still; it must outlive this one) followed by a translation d(t) added to
 * its position, x -> R x + T + d. d follows a target point as a critically damped spring
 * of rate `rate` (1/s, > 0): with e = d - target, e'' = -2 rate e' - rate^2 e, solved in
 * closed form, e(t) = (e0 + (v0 + rate e0) s) exp(-rate s) with s = t - t0, so that the
 * head's velocity is continuous when the target jumps and its acceleration, which the
 * dynamics needs (Bertails et al. 2006 §3.4: the roots are clamped to the head), is
 * exact. d starts at rest at the origin, target 0. hk_head_motion_source gives the
 * script "follow" and the base's pivot. */
HK_API hk_Status hk_head_motion_follow(const hk_HeadMotion *base, double rate, hk_HeadMotion **out, hk_Error *err);

/* From time t on, d heads for `target` (m, world), starting from where it is at t and
 * as fast (times before t are no longer those of the earlier target). Does nothing to a
 * motion not made by hk_head_motion_follow. */
HK_API void hk_head_motion_follow_target(hk_HeadMotion *m, double t, hk_Vec3 target);

/* d back at rest at the origin, target 0 (a simulation started again from t = 0). */
HK_API void hk_head_motion_follow_reset(hk_HeadMotion *m);

/* Releases a motion; safe on NULL. */
HK_API void hk_head_motion_destroy(hk_HeadMotion *m);

/* Most keyframes a motion file may hold (a 16 MiB file has room for about a million). */
#define HK_MAX_MOTION_KEYS 1000000

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_MOTION_H */
