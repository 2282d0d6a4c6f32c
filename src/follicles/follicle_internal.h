/* Private pieces of the follicle sampling (Piuze et al. 2011 §4.3): the dense solve of the
 * thin-plate interpolation system and the neighbour grid of the particle system. */
#ifndef HK_FOLLICLE_INTERNAL_H
#define HK_FOLLICLE_INTERNAL_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/vecmath.h"

/* Solves the interpolation system of the kernel |x|^3 with a linear polynomial,
 *   [A  P] [w]   [h]      A_ij = |c_i - c_j|^3,  P = [1 x y z] (n x 4),
 *   [P' 0] [p] = [0],
 * for centres c (n >= 4, in coordinates of order one). w has n entries, p 4. */
hk_Status hk_rbf_solve(int n, const hk_Vec3 *c, const double *h, int threads, double *w, double p[4], hk_Error *err);

/* Uniform grid over points for neighbour queries within the cell size. Cells are
 * hashed; a bucket lists its points in increasing index order, so neighbour loops
 * visit them in an order independent of threads. */
typedef struct hk_PointGrid {
    double cell;       /* cell size */
    int count;         /* points */
    int bucket_count;  /* power of two */
    int *bucket_start; /* bucket_count + 1 */
    int *items;        /* count point indices, grouped by bucket */
    int32_t *key;      /* 3 * count integer cell coordinates */
} hk_PointGrid;

/* Builds the grid of `count` points with cells of size `cell` (> 0). Reuses the
 * grid's arrays when large enough. */
hk_Status hk_point_grid_build(hk_PointGrid *g, const hk_Vec3 *p, int count, double cell, hk_Error *err);
void hk_point_grid_free(hk_PointGrid *g);

/* Calls visit(user, j) for every point j in the 27 cells around x (each point once). */
void hk_point_grid_query(const hk_PointGrid *g, hk_Vec3 x, void (*visit)(void *user, int j), void *user);

/* Distance queries to a triangle mesh within a fixed radius: triangles bucketed in a
 * uniform grid by their bounding boxes grown by the radius, so one cell answers. */
typedef struct hk_TriangleGrid {
    const hk_Vec3 *positions;
    const int *triangles;
    hk_Vec3 origin;
    double cell, radius;
    int dims[3];
    int *cell_start; /* dims[0] dims[1] dims[2] + 1 */
    int *items;      /* triangle indices, grouped by cell */
} hk_TriangleGrid;

/* positions and triangles must outlive the grid. radius > 0. */
hk_Status hk_triangle_grid_build(hk_TriangleGrid *g, const hk_Vec3 *positions, const int *triangles, int triangle_count,
                                 double radius, hk_Error *err);
void hk_triangle_grid_free(hk_TriangleGrid *g);

/* Smallest distance from x to the mesh when it is below the grid's radius, else a
 * value >= radius. When tangential is not NULL, it receives the part of x - closest
 * point in the closest triangle's plane (how far x lies beyond the mesh's edge). */
double hk_triangle_grid_distance(const hk_TriangleGrid *g, hk_Vec3 x, double *tangential);

/* Closest point to p on the triangle (a, b, c) (Ericson, Real-Time Collision
 * Detection, §5.1.5). */
hk_Vec3 hk_closest_point_triangle(hk_Vec3 p, hk_Vec3 a, hk_Vec3 b, hk_Vec3 c);

#endif
