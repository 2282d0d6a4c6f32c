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

/* One Newton step on the deepest shape's dent (thesis §4.1.2.1; for the ellipsoid the
 * dent is measured along the ray from the centre, its gradient is not a unit vector):
 * dent(q + dq) ~ dent + g.dq = -BODY_MARGIN with dq along g. Returns 0 when q is
 * outside every body shape (nothing to do) or the dent has no direction (the very
 * centre of a shape, where no strand point gets). */
static int push_out(const hk_Shape *body, int count, hk_Vec3 *q)
{
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
    /* The root stays on the scalp (it may sit a little inside the true shape, between
     * the wick's vertices). Later points keep the segment vectors of the blend until one
     * has to move; from then on they follow it. */
    hk_Vec3 prev = hk_v3(points[0], points[1], points[2]), prev_blend = prev;
    int moved = 0;
    for (int j = 1; j < point_count; j++) {
        float *out = points + 3 * j;
        const hk_Vec3 blend = hk_v3(out[0], out[1], out[2]);
        const hk_Vec3 seg = hk_v3_sub(blend, prev_blend);
        const double len = hk_v3_norm(seg);
        prev_blend = blend;
        hk_Vec3 q = moved ? hk_v3_add(prev, seg) : blend;
        int pushed = 0;
        for (int r = 0; r < ROUNDS && push_out(body, count, &q); r++) {
            pushed = 1;
            const hk_Vec3 d = hk_v3_sub(q, prev);
            const double n = hk_v3_norm(d);
            if (n > 1e-300) q = hk_v3_madd(prev, d, len / n);
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
