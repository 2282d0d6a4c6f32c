/* Rigid motion of the head (placeholder until the head-motion module lands). */
#ifndef HAIRKIT_MOTION_H
#define HAIRKIT_MOTION_H

#include "hairkit/vecmath.h"

/* Rigid motion of the head at time t: a head-space point x is at world R x + T. */
typedef struct hk_RigidState {
    hk_Mat3 rot;    /* R(t) */
    hk_Vec3 trans;  /* T(t) */
    hk_Vec3 vel;    /* dT/dt */
    hk_Vec3 acc;    /* d2T/dt2 */
    hk_Vec3 omega;  /* world angular velocity: dR/dt = [omega]x R */
    hk_Vec3 alpha;  /* d omega/dt */
} hk_RigidState;

#endif
