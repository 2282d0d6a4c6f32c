/* The collision shapes drawn as outlines (the C key): an ellipsoid or sphere as its
 * three principal ellipses, a cuboid (or a distance field's grid) as its twelve edges,
 * posed where the head is (hk_shapes_posed), as the dynamics sees them (Lansink 2010
 * §4.1.2: the body's envelopes). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "viewer/viewer_internal.h"

#define ELLIPSE_SEGMENTS 48

static float *put(float *out, hk_Vec3 p)
{
    out[0] = (float)p.x, out[1] = (float)p.y, out[2] = (float)p.z;
    return out + 3;
}

/* The point of the shape's box or ellipsoid at local coordinates (a, b, c) in [-1, 1]. */
static hk_Vec3 local(const hk_Shape *s, double a, double b, double c)
{
    hk_Vec3 p = hk_v3_madd(s->centre, s->axis[0], a * s->half.x);
    p = hk_v3_madd(p, s->axis[1], b * s->half.y);
    return hk_v3_madd(p, s->axis[2], c * s->half.z);
}

static float *outline(const hk_Shape *s, float *out)
{
    if (s->kind == HK_SHAPE_SPHERE || s->kind == HK_SHAPE_ELLIPSOID) {
        for (int plane = 0; plane < 3; plane++)
            for (int k = 0; k < ELLIPSE_SEGMENTS; k++)
                for (int e = 0; e < 2; e++) {
                    const double t = 2.0 * HK_PI * (k + e) / ELLIPSE_SEGMENTS, c = cos(t), n = sin(t);
                    const double u[3] = {plane == 0 ? 0.0 : c, plane == 0 ? c : (plane == 1 ? 0.0 : n),
                                         plane == 2 ? 0.0 : n};
                    out = put(out, local(s, u[0], u[1], u[2]));
                }
        return out;
    }
    /* the 12 edges: along each axis, at the four corners of the other two */
    for (int axis = 0; axis < 3; axis++)
        for (int corner = 0; corner < 4; corner++)
            for (int e = 0; e < 2; e++) {
                double u[3];
                u[axis] = e ? 1.0 : -1.0;
                u[(axis + 1) % 3] = corner & 1 ? 1.0 : -1.0;
                u[(axis + 2) % 3] = corner & 2 ? 1.0 : -1.0;
                out = put(out, local(s, u[0], u[1], u[2]));
            }
    return out;
}

int hk_viewer_shapes_update(hk_Viewer *v, const hk_RigidState *pose)
{
    const hk_Scene *sc = v->in->scene;
    if (!sc || sc->collision.count <= 0) return 1;
    const int n = sc->collision.count, per_shape = 3 * ELLIPSE_SEGMENTS * 2; /* vertices, the most of a shape */
    hk_Shape *posed = malloc((size_t)n * sizeof *posed);
    float *xyz = malloc((size_t)n * (size_t)per_shape * 3 * sizeof *xyz);
    if (!posed || !xyz) {
        free(posed);
        free(xyz);
        fprintf(stderr, "hairkit view: out of memory for the collision shapes\n");
        return 0;
    }
    const hk_RigidState rest = hk_rigid_identity();
    hk_shapes_posed(sc->collision.shapes, n, pose ? pose : &rest, posed);
    float *end = xyz;
    for (int i = 0; i < n; i++) end = outline(&posed[i], end);
    hk_gl_lines_set(&v->shapes, xyz, (int)((end - xyz) / 3));
    free(posed);
    free(xyz);
    return 1;
}
