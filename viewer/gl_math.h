/* 4 x 4 matrices for OpenGL (column-major floats) from hairkit's vectors. */
#ifndef HK_VIEWER_GL_MATH_H
#define HK_VIEWER_GL_MATH_H

#include "hairkit/vecmath.h"

typedef struct hk_Mat4 {
    float m[16]; /* column-major: m[4 * column + row] */
} hk_Mat4;

/* World -> eye for an eye at `origin` looking along `forward` (unit, orthonormal with
 * right and up). */
hk_Mat4 hk_mat4_view(hk_Vec3 origin, hk_Vec3 right, hk_Vec3 up, hk_Vec3 forward);
/* OpenGL's perspective: vertical field of view (degrees), aspect, near and far. */
hk_Mat4 hk_mat4_perspective(double fov_deg, double aspect, double near_z, double far_z);
/* The affine map p -> (dot(p - c, x) a + ox, dot(p - c, y) b + oy, dot(p - c, z) c + oz). */
hk_Mat4 hk_mat4_affine(hk_Vec3 centre, hk_Vec3 x, hk_Vec3 y, hk_Vec3 z, hk_Vec3 scale, hk_Vec3 offset);

/* Unit vector from azimuth (about +y, 0 = +z, towards +x) and elevation, degrees: the
 * CPU renderer's convention (src/render/camera.c). */
hk_Vec3 hk_view_direction(double azimuth_deg, double elevation_deg);

#endif
