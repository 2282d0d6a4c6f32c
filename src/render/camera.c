/* The camera: a perspective view from the options' azimuth and elevation, at the
 * distance where every hair point and head vertex fits the picture. */
#include "render_internal.h"

static const double DEG = HK_PI / 180.0;

/* Unit vector from azimuth (about +y, 0 = +z, positive towards +x) and elevation. */
static hk_Vec3 direction(double azimuth_deg, double elevation_deg)
{
    const double az = azimuth_deg * DEG, el = elevation_deg * DEG;
    return hk_v3(sin(az) * cos(el), sin(el), cos(az) * cos(el));
}

hk_View hk_camera_frame(const hk_Scene *scene)
{
    const hk_RenderDef *o = scene->opt;
    hk_View v;
    v.perspective = 1;
    v.width = o->width;
    v.height = o->height;
    v.depth_offset = 0.0;
    v.forward = hk_v3_neg(direction(o->azimuth_deg, o->elevation_deg));
    hk_Vec3 side = hk_v3_cross(v.forward, hk_v3(0, 1, 0));
    if (hk_v3_norm(side) < 1e-9) side = hk_v3(1, 0, 0); /* looking straight up or down */
    v.right = hk_v3_normalize(side);
    v.up = hk_v3_cross(v.right, v.forward);
    const double ty = tan(0.5 * o->fov_deg * DEG) * 0.92; /* 4% margin on each side */
    const double tx = ty * (double)o->width / (double)o->height;
    v.focal = 0.5 * o->height / tan(0.5 * o->fov_deg * DEG);
    if (o->camera_distance > 0.0) {
        v.target = o->camera_target;
        v.distance = o->camera_distance;
        v.origin = hk_v3_madd(v.target, v.forward, -v.distance);
        return v;
    }
    hk_Vec3 target = hk_v3_scale(hk_v3_add(scene->lo, scene->hi), 0.5);
    /* Distance so that every point fits, then centre the picture on the points'
     * projection and fit again. */
    const hk_HairFile *h = scene->hair;
    const long hair_n = (long)h->point_count, n = hair_n + (scene->head ? scene->head->vertex_count : 0);
#define SCENE_POINT(i) ((i) < hair_n ? hk_hair_point(h, (uint32_t)(i)) : scene->head->positions[(i)-hair_n])
    for (int pass = 0; pass < 2; pass++) {
        double dist = 1e-6;
        /* max and min are exact: the same result whatever the threads. */
#pragma omp parallel for schedule(static) reduction(max : dist) num_threads(scene->threads)
        for (long i = 0; i < n; i++) {
            const hk_Vec3 r = hk_v3_sub(SCENE_POINT(i), target);
            const double w = hk_v3_dot(r, v.forward);
            const double need_x = fabs(hk_v3_dot(r, v.right)) / tx - w, need_y = fabs(hk_v3_dot(r, v.up)) / ty - w;
            const double need = need_x > need_y ? need_x : need_y;
            const double front = 1e-3 - w; /* everything in front of the eye */
            const double d = need > front ? need : front;
            if (d > dist) dist = d;
        }
        v.origin = hk_v3_madd(target, v.forward, -dist);
        v.target = target;
        v.distance = dist;
        if (pass == 1) break;
        double xlo = 1e300, xhi = -1e300, ylo = 1e300, yhi = -1e300;
#pragma omp parallel for schedule(static) reduction(min                                                                \
                                                    : xlo, ylo) reduction(max                                          \
                                                                          : xhi, yhi) num_threads(scene->threads)
        for (long i = 0; i < n; i++) {
            const hk_Vec3 d = hk_v3_sub(SCENE_POINT(i), v.origin);
            const double z = hk_v3_dot(d, v.forward);
            const double x = hk_v3_dot(d, v.right) / z, y = hk_v3_dot(d, v.up) / z;
            if (x < xlo) xlo = x;
            if (x > xhi) xhi = x;
            if (y < ylo) ylo = y;
            if (y > yhi) yhi = y;
        }
        if (!(xlo <= xhi)) break; /* no points */
        /* Move the target sideways by the offset of the projection's centre, at the
         * target's depth. */
        target = hk_v3_madd(target, v.right, 0.5 * (xlo + xhi) * dist);
        target = hk_v3_madd(target, v.up, 0.5 * (ylo + yhi) * dist);
    }
#undef SCENE_POINT
    return v;
}
