/* Closest point of a triangle mesh and the smooth normal there: the surface normal at a guide's
 * root for interpolation on a surface (Piuze et al. 2011 §4.3). Brute force over the triangles. */
#include <math.h>

#include "hairkit/mesh.h"
#include "mesh/mesh_internal.h"

void hk_triangle_closest_barycentric(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c, double w[3])
{
    const hk_Vec3 ab = hk_v3_sub(b, a), ac = hk_v3_sub(c, a), ap = hk_v3_sub(p, a);
    w[0] = 1.0, w[1] = 0.0, w[2] = 0.0;
    const double d1 = hk_v3_dot(ab, ap), d2 = hk_v3_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return;
    const hk_Vec3 bp = hk_v3_sub(p, b);
    const double d3 = hk_v3_dot(ab, bp), d4 = hk_v3_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        w[0] = 0.0, w[1] = 1.0;
        return;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        w[0] = 1.0 - v, w[1] = v;
        return;
    }
    const hk_Vec3 cp = hk_v3_sub(p, c);
    const double d5 = hk_v3_dot(ab, cp), d6 = hk_v3_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        w[0] = 0.0, w[2] = 1.0;
        return;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double v = d2 / (d2 - d6);
        w[0] = 1.0 - v, w[2] = v;
        return;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double v = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        w[0] = 0.0, w[1] = 1.0 - v, w[2] = v;
        return;
    }
    const double sum = va + vb + vc;
    if (!(sum > 0.0)) return; /* degenerate triangle: its vertex regions cover it */
    w[1] = vb / sum, w[2] = vc / sum, w[0] = 1.0 - w[1] - w[2];
}

double hk_triangle_distance(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c)
{
    double w[3];
    hk_triangle_closest_barycentric(p, a, b, c, w);
    const hk_Vec3 q = hk_v3_add(hk_v3_scale(a, w[0]), hk_v3_add(hk_v3_scale(b, w[1]), hk_v3_scale(c, w[2])));
    return hk_v3_dist(p, q);
}

double hk_mesh_closest_point(const hk_Mesh *mesh, hk_Vec3 x, hk_Vec3 *point, hk_Vec3 *normal)
{
    double best = INFINITY;
    int best_t = -1;
    double best_w[3] = {1.0, 0.0, 0.0};
    if (!mesh || !hk_v3_isfinite(x)) return -1.0;
    for (int t = 0; t < mesh->triangle_count; t++) {
        const int *v = mesh->triangles + 3 * t;
        const hk_Vec3 a = mesh->positions[v[0]], b = mesh->positions[v[1]], c = mesh->positions[v[2]];
        double w[3];
        hk_triangle_closest_barycentric(x, a, b, c, w);
        const hk_Vec3 q = hk_v3_add(hk_v3_scale(a, w[0]), hk_v3_add(hk_v3_scale(b, w[1]), hk_v3_scale(c, w[2])));
        const double d = hk_v3_dist(x, q);
        if (d < best) {
            best = d, best_t = t;
            best_w[0] = w[0], best_w[1] = w[1], best_w[2] = w[2];
        }
    }
    if (best_t < 0) return -1.0;
    const int *v = mesh->triangles + 3 * best_t;
    hk_Vec3 q = hk_v3_zero(), n = hk_v3_zero();
    for (int k = 0; k < 3; k++) {
        q = hk_v3_madd(q, mesh->positions[v[k]], best_w[k]);
        n = hk_v3_madd(n, mesh->normals[v[k]], best_w[k]);
    }
    if (!(hk_v3_norm(n) > 1e-12)) {
        /* opposite vertex normals cancelling: the face's own normal */
        const hk_Vec3 a = mesh->positions[v[0]];
        n = hk_v3_cross(hk_v3_sub(mesh->positions[v[1]], a), hk_v3_sub(mesh->positions[v[2]], a));
    }
    if (point) *point = q;
    if (normal) *normal = hk_v3_normalize(n);
    return best;
}
