/* The viewer's camera (orbit.h). */
#include <math.h>

#include "viewer/orbit.h"

static const double DEG = HK_PI / 180.0;

hk_OrbitFrame hk_orbit_frame(const hk_Orbit *o, int width, int height)
{
    hk_OrbitFrame f;
    /* As src/render/camera.c: forward from the view direction, right level. */
    f.forward = hk_v3_neg(hk_view_direction(o->azimuth, o->elevation));
    hk_Vec3 side = hk_v3_cross(f.forward, hk_v3(0, 1, 0));
    if (hk_v3_norm(side) < 1e-9) side = hk_v3(1, 0, 0);
    f.right = hk_v3_normalize(side);
    f.up = hk_v3_cross(f.right, f.forward);
    f.origin = hk_v3_madd(o->target, f.forward, -o->distance);
    f.view = hk_mat4_view(f.origin, f.right, f.up, f.forward);
    const double near_z = fmax(o->distance - 2.0 * o->radius, 1e-3 * o->distance);
    const double far_z = o->distance + 2.0 * o->radius;
    f.projection = hk_mat4_perspective(o->fov, (double)width / height, near_z, far_z);
    f.focal = 0.5 * height / tan(0.5 * o->fov * DEG);
    return f;
}

void hk_orbit_turn(hk_Orbit *o, double d_azimuth, double d_elevation)
{
    o->azimuth = fmod(o->azimuth + d_azimuth, 360.0);
    o->elevation = fmin(89.0, fmax(-89.0, o->elevation + d_elevation));
}

void hk_orbit_pan(hk_Orbit *o, double dx, double dy, int height)
{
    const hk_OrbitFrame f = hk_orbit_frame(o, height, height);
    const double per_pixel = o->distance / f.focal;
    o->target = hk_v3_madd(o->target, f.right, -dx * per_pixel);
    o->target = hk_v3_madd(o->target, f.up, dy * per_pixel);
}

void hk_orbit_zoom(hk_Orbit *o, double factor)
{
    o->distance = fmin(50.0 * o->radius + 1.0, fmax(1e-3, o->distance * factor));
}
