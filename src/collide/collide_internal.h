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

/* Whether p lies so far from shape s that hk_shape_dent(s, p) + extra <= -margin
 * (margin >= 0), so that the dent need not be taken: with c = |extra| + margin,
 * |p - centre| >= bound + sqrt(3) c implies dent(p) <= -c for the sphere and the
 * ellipsoid (dent <= bound - |p - centre|) and for the cuboid (were every face depth
 * above -c, each |p_i| would be below half_i + c and |p - centre| below |half| +
 * sqrt(3) c). A relative 1e-9 of the reach to spare covers the rounding of both sides,
 * so the answers are those of the dent itself. Never for a field, whose dent beyond its
 * grid is the field's own. */
static inline int hk_shape_beyond(const hk_Shape *s, double extra, double margin, hk_Vec3 p)
{
    if (s->kind == HK_SHAPE_FIELD) return 0;
    const double reach = (hk_shape_bound(s) + 1.7320508075688772 * (fabs(extra) + margin)) * (1.0 + 1e-9);
    return hk_v3_norm2(hk_v3_sub(p, s->centre)) > reach * reach;
}

/* Whether p is clearly outside shape s itself (dent < 0, within rounding of the surface
 * left to the dent), without the dent's square roots and divisions: a sphere's or an
 * ellipsoid's point (penetration.c); 0 for the others. */
int hk_shape_outside(const hk_Shape *s, hk_Vec3 p);

#endif /* HK_COLLIDE_INTERNAL_H */
