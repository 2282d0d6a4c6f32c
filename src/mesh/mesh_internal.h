/* Internal to hairkit (not installed, not exported): geometry the mesh functions share.
 * Included as "mesh/mesh_internal.h". */
#ifndef HK_MESH_INTERNAL_H
#define HK_MESH_INTERNAL_H

#include "hairkit/vecmath.h"

/* Closest point to p on the triangle (a, b, c) as barycentric weights w (Ericson,
 * Real-Time Collision Detection, §5.1.5: the Voronoi regions of the vertices, the
 * edges, the face). A degenerate triangle gives one of its vertex regions. */
void hk_triangle_closest_barycentric(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c, double w[3]);

/* Distance from p to the triangle (a, b, c). */
double hk_triangle_distance(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c);

#endif /* HK_MESH_INTERNAL_H */
