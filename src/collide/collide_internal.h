/* Internal to hairkit (not installed, not exported): the quick rejection of the
 * collision shapes. Included as "collide/collide_internal.h". */
#ifndef HK_COLLIDE_INTERNAL_H
#define HK_COLLIDE_INTERNAL_H

#include <math.h>

#include "hairkit/collide.h"

/* The radius beyond which a point is outside the shape: |p - centre| > bound +
 * sqrt(3) * |extra| implies dent(p) + extra < 0 (no contact). For every kind, dent(p) <=
 * R - |p - c| with R the largest radius (sphere, ellipsoid: the radial surface distance
 * is at most the largest semi-axis) or the half-diagonal (cuboid; a field's grid, which
 * reaches its margin beyond the mesh, so that the envelopes of a few centimetres stay
 * inside it). Computed from the
 * shape's fields each time, so that a shape edited by hand needs no refresh. */
/* fmax(a, b) and fmin(a, b) without the call into libm (GCC -O2 keeps them calls: the
 * shapes' bounds took 1.1 million calls of each in the head driver's 8 frames): the
 * other operand when one is NaN, else the larger or smaller. Only a tie of +0 and -0
 * may take the other zero than libm's, which no caller can tell (a bound is squared or
 * has a positive term added; a radius only compared). */
static inline double hk_larger(double a, double b) { return a > b || isnan(b) ? a : b; }
static inline double hk_smaller(double a, double b) { return a < b || isnan(b) ? a : b; }

static inline double hk_shape_bound(const hk_Shape *s)
{
    const double a = s->half.x, b = s->half.y, c = s->half.z;
    if (s->kind == HK_SHAPE_CUBOID || s->kind == HK_SHAPE_FIELD) return sqrt(a * a + b * b + c * c);
    return hk_larger(a, hk_larger(b, c));
}

#endif /* HK_COLLIDE_INTERNAL_H */
