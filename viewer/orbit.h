/* The viewer's camera: the CPU renderer's (src/render/camera.c), fitted by
 * hk_render_fit_camera, then turned, moved and zoomed about its target. */
#ifndef HK_VIEWER_ORBIT_H
#define HK_VIEWER_ORBIT_H

#include "viewer/gl_math.h"

typedef struct hk_Orbit {
    double azimuth, elevation; /* degrees, as --view */
    double distance, fov;      /* fov: vertical, degrees */
    hk_Vec3 target;
    double radius; /* of the scene, for the near and far planes */
} hk_Orbit;

typedef struct hk_OrbitFrame {
    hk_Vec3 origin, right, up, forward;
    hk_Mat4 view, projection;
    double focal; /* pixels per unit at depth 1 */
} hk_OrbitFrame;

hk_OrbitFrame hk_orbit_frame(const hk_Orbit *o, int width, int height);
void hk_orbit_turn(hk_Orbit *o, double d_azimuth, double d_elevation);
/* Moves the target by (dx, dy) pixels of a picture `height` pixels high. */
void hk_orbit_pan(hk_Orbit *o, double dx, double dy, int height);
void hk_orbit_zoom(hk_Orbit *o, double factor);

#endif
