/* Private to src/dynamics/: the head motion object shared by the scripted motions
 * (head_motion.c), the motion file reader (motion_file.c) and the rotation map
 * (rotation_exp.c). */
#ifndef HK_DYNAMICS_MOTION_INTERNAL_H
#define HK_DYNAMICS_MOTION_INTERNAL_H

#include "hairkit/motion.h"

typedef enum hk_MotionKind {
    HK_MOTION_STILL,
    HK_MOTION_ROTATE,    /* scripted rotation about `axis` through the pivot */
    HK_MOTION_TRANSLATE, /* scripted translation along `axis` */
    HK_MOTION_KEYS,      /* keyframes of a motion file */
    HK_MOTION_FOLLOW     /* a base motion moved by a translation that follows a target
                            (head_follow.c) */
} hk_MotionKind;

/* Channels of a keyframe: translation (m), then rotation vector (rad). */
#define HK_MOTION_CHANNELS 6

struct hk_HeadMotion {
    hk_MotionKind kind;
    hk_Vec3 pivot;
    /* What it was made from (hk_head_motion_source): the script's name and amplitude as
     * given, or the motion file's path as given (own copy). */
    const char *script;
    double amplitude_given;
    char *path;
    /* Scripted: g(t) = amplitude * ease * sin(2 pi frequency t). */
    hk_Vec3 axis;     /* unit */
    double amplitude; /* radians or metres */
    double frequency; /* Hz */
    /* Keyframes: times[key_count], strictly increasing; knots holds, per key and per
     * channel, the value and its first and second time derivatives there:
     * knots[(key * HK_MOTION_CHANNELS + channel) * 3 + order]. */
    int key_count;
    double *times;
    double *knots;
    /* Follow: the base motion (NULL: still) plus the offset d(t) = target + e(t), e the
     * critically damped spring's error since follow_t0 (head_follow.c). */
    const hk_HeadMotion *base;
    double follow_rate; /* omega (1/s) */
    double follow_t0;
    hk_Vec3 follow_target, follow_e0, follow_v0;
};

/* The rigid state of a follow motion at t (head_follow.c). */
void hk_motion_follow_eval(const hk_HeadMotion *m, double t, hk_RigidState *out);

/* R = exp([r]x) and, for r(t) with derivatives dr and ddr, the world angular velocity
 * omega (dR/dt = [omega]x R) and its derivative alpha. Smooth for every r, no
 * singularity at r = 0 or |r| = 2 pi. */
void hk_rotation_exp(hk_Vec3 r, hk_Vec3 dr, hk_Vec3 ddr, hk_Mat3 *rot, hk_Vec3 *omega, hk_Vec3 *alpha);

/* Completes st, whose rot, omega and alpha are set, for a rotation about `pivot`
 * followed by the translation p (derivatives dp, ddp): a head point x goes to
 * R (x - pivot) + pivot + p, so T = p + pivot - R pivot. */
void hk_motion_about_pivot(hk_RigidState *st, hk_Vec3 pivot, hk_Vec3 p, hk_Vec3 dp, hk_Vec3 ddp);

/* State of a keyframed motion at time t (motion_file.c). */
void hk_motion_keys_eval(const hk_HeadMotion *m, double t, hk_RigidState *out);

#endif
