/* 4 x 4 matrices for OpenGL (gl_math.h). */
#include <math.h>

#include "viewer/gl_math.h"

static const double DEG = HK_PI / 180.0;

hk_Vec3 hk_view_direction(double azimuth_deg, double elevation_deg)
{
    const double az = azimuth_deg * DEG, el = elevation_deg * DEG;
    return hk_v3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
}

static hk_Mat4 identity(void)
{
    hk_Mat4 r = {{0}};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0f;
    return r;
}

hk_Mat4 hk_mat4_affine(hk_Vec3 c, hk_Vec3 x, hk_Vec3 y, hk_Vec3 z, hk_Vec3 scale, hk_Vec3 offset)
{
    hk_Mat4 r = identity();
    const hk_Vec3 rows[3] = {hk_v3_scale(x, scale.x), hk_v3_scale(y, scale.y), hk_v3_scale(z, scale.z)};
    const double off[3] = {offset.x, offset.y, offset.z};
    for (int i = 0; i < 3; i++) {
        r.m[0 + i] = (float)rows[i].x;
        r.m[4 + i] = (float)rows[i].y;
        r.m[8 + i] = (float)rows[i].z;
        r.m[12 + i] = (float)(off[i] - hk_v3_dot(rows[i], c));
    }
    return r;
}

hk_Mat4 hk_mat4_view(hk_Vec3 origin, hk_Vec3 right, hk_Vec3 up, hk_Vec3 forward)
{
    /* OpenGL's eye looks down -z. */
    return hk_mat4_affine(origin, right, up, hk_v3_neg(forward), hk_v3(1, 1, 1), hk_v3(0, 0, 0));
}

hk_Mat4 hk_mat4_perspective(double fov_deg, double aspect, double n, double f)
{
    hk_Mat4 r = {{0}};
    const double t = 1.0 / tan(0.5 * fov_deg * DEG);
    r.m[0] = (float)(t / aspect);
    r.m[5] = (float)t;
    r.m[10] = (float)((f + n) / (n - f));
    r.m[11] = -1.0f;
    r.m[14] = (float)(2.0 * f * n / (n - f));
    return r;
}
