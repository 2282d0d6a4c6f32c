/* Keeps interpolated strands out of the body. Blending guides that fell to different
 * sides of the head (Lansink 2010 §4.1.4.3 blends whatever three guides a wick triangle
 * has) can put a strand's middle inside the head, where no guide ever was; the statics
 * keep the guides out with the shapes' penalty (§4.1.2), but nothing checks the strands
 * made from them. A follow-the-leader pass (the rule of hair simulators since Müller
 * et al. 2012, "Fast simulation of inextensible hair and fur") walks each strand from
 * the root: a point inside a body shape goes out to the surface, and the segment from
 * the previous point gets its length back, so the strand stays as long as its guides. */
#include <math.h>
#include <string.h>

#include "collide/collide_internal.h"
#include "groom_internal.h"

/* How far outside a pushed point lands (m): two hair diameters, so that float
 * rounding and the segment-length correction that follows leave it outside, and far
 * below anything visible. */
#define BODY_MARGIN 1e-4

/* Rounds of (push out, restore length) per point. Against one convex shape the second
 * round already finds the point outside; where two shapes meet (the head and the face
 * ellipsoids) the pushes alternate between them and converge within a few rounds. */
#define ROUNDS 64

hk_Status hk_groom_body_shapes(const hk_Shape *shapes, int count, hk_Shape **body, int *body_count, hk_Error *err)
{
    *body = NULL;
    *body_count = 0;
    int n = 0;
    for (int i = 0; i < count; i++) n += !shapes[i].styling;
    if (n == 0) return HK_OK;
    *body = hk_alloc_array((size_t)n, sizeof **body, err);
    if (!*body) return HK_ERR_NOMEM;
    for (int i = 0; i < count; i++)
        if (!shapes[i].styling) (*body)[(*body_count)++] = shapes[i];
    return HK_OK;
}

/* The body shapes' quick tests, set up once per strand: whether a point is so clearly
 * outside every shape that hk_collision_deepest would pass it over (penetration.c's
 * out_of_reach or clearly_outside for each shape). A strand's points nearly all lie
 * outside the body (4,880,120 of the 4,885,669 points of a simulated frame's strands
 * on examples/guides200), and hk_collision_deepest spent about 185 instructions on
 * each, two fifths of the regrowth: with these tests first, only the few points near a
 * shape are asked of it. The squared distance to a shape's centre is computed as
 * hk_collision_deepest computes it; the ellipsoid's own test, where a point is within
 * its reach, takes products with its radii's reciprocals where clearly_outside divides
 * by the radii. The slack (1e-6 of the squares, against the 1e-9 of clearly_outside)
 * is far above the few roundings by which the products and the divisions differ, so a
 * point passed over here is one hk_collision_deepest passes over: the same bytes. */
#define QUICK_SLACK (1.0 + 1e-6)
#define MAX_QUICK   8 /* shapes tested this way at most */

typedef struct QuickTest {
    hk_Vec3 centre;
    double reach2; /* the square of the shape's bound (hk_shape_bound), with the slack */
    int ellipsoid; /* its own test too (a sphere's radius is its bound; a cuboid or a
                      field has the bound's test only) */
    hk_Vec3 axis[3];
    double inv_half[3]; /* an ellipsoid's 1 / radius along each axis */
} QuickTest;

static QuickTest quick_test(const hk_Shape *s)
{
    QuickTest t;
    const double bound = hk_shape_bound(s);
    t.centre = s->centre;
    t.reach2 = bound * bound * QUICK_SLACK;
    t.ellipsoid = s->kind == HK_SHAPE_ELLIPSOID;
    for (int k = 0; k < 3; k++) {
        t.axis[k] = s->axis[k];
        t.inv_half[k] = 1.0 / hk_v3_get(s->half, k);
    }
    return t;
}

/* Whether p is clearly outside the shape (0: it may be inside, ask the shape). */
static inline int clearly_outside(const QuickTest *t, hk_Vec3 p)
{
    const hk_Vec3 d = hk_v3_sub(p, t->centre);
    if (hk_v3_norm2(d) > t->reach2) return 1;
    if (!t->ellipsoid) return 0;
    const double u = hk_v3_dot(d, t->axis[0]) * t->inv_half[0], v = hk_v3_dot(d, t->axis[1]) * t->inv_half[1],
                 w = hk_v3_dot(d, t->axis[2]) * t->inv_half[2];
    return u * u + v * v + w * w > QUICK_SLACK;
}

static inline int outside_all(const QuickTest *tests, int count, hk_Vec3 p)
{
    for (int i = 0; i < count; i++)
        if (!clearly_outside(&tests[i], p)) return 0;
    return 1;
}

/* One Newton step on the deepest shape's dent (thesis §4.1.2.1; for the ellipsoid the
 * dent is measured along the ray from the centre, its gradient is not a unit vector):
 * dent(q + dq) ~ dent + g.dq = -BODY_MARGIN with dq along g. Returns 0 when q is
 * outside every body shape (nothing to do) or the dent has no direction (the very
 * centre of a shape, where no strand point gets). tests: the shapes' quick tests, or
 * NULL. */
static int push_out(const hk_Shape *body, int count, const QuickTest *tests, hk_Vec3 *q)
{
    if (tests && outside_all(tests, count, *q)) return 0;
    double depth;
    const int i = hk_collision_deepest(body, count, 0.0, *q, &depth);
    if (i < 0) return 0;
    hk_Vec3 g;
    hk_shape_dent(&body[i], *q, &g, NULL);
    const double g2 = hk_v3_norm2(g);
    if (!(g2 > 1e-12)) return 0;
    *q = hk_v3_madd(*q, g, -(depth + BODY_MARGIN) / g2);
    return 1;
}

void hk_groom_keep_outside(const hk_Shape *body, int count, float *points, int point_count)
{
    if (count <= 0 || point_count < 2) return;
    QuickTest quick[MAX_QUICK];
    const QuickTest *tests = count <= MAX_QUICK ? quick : NULL;
    for (int i = 0; tests && i < count; i++) quick[i] = quick_test(&body[i]);
    /* The root stays on the scalp (it may sit a little inside the true shape, between
     * the wick's vertices). Later points keep the segment vectors of the blend until one
     * has to move; from then on they follow it. Until then a point is the blend's, and
     * one clearly outside the body is left as it is: push_out would find it outside. */
    int j = 1;
    while (tests && j < point_count &&
           outside_all(tests, count, hk_v3(points[3 * j], points[3 * j + 1], points[3 * j + 2])))
        j++;
    if (j == point_count) return;
    hk_Vec3 prev = hk_v3(points[3 * j - 3], points[3 * j - 2], points[3 * j - 1]), prev_blend = prev;
    int moved = 0;
    for (; j < point_count; j++) {
        float *out = points + 3 * j;
        const hk_Vec3 blend = hk_v3(out[0], out[1], out[2]);
        const hk_Vec3 seg = hk_v3_sub(blend, prev_blend);
        prev_blend = blend;
        hk_Vec3 q = moved ? hk_v3_add(prev, seg) : blend;
        int pushed = 0;
        for (int r = 0; r < ROUNDS && push_out(body, count, tests, &q); r++) {
            pushed = 1;
            const hk_Vec3 d = hk_v3_sub(q, prev);
            const double n = hk_v3_norm(d);
            if (n > 1e-300) q = hk_v3_madd(prev, d, hk_v3_norm(seg) / n);
        }
        moved |= pushed;
        if (moved) {
            out[0] = (float)q.x;
            out[1] = (float)q.y;
            out[2] = (float)q.z;
        }
        prev = q;
    }
}
