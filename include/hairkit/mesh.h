/* Triangle meshes (heads, wicks) and their Wavefront OBJ input and output. */
#ifndef HAIRKIT_MESH_H
#define HAIRKIT_MESH_H

#include "hairkit/core.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_MAX_MESH_VERTICES 10000000
#define HK_MAX_MESH_TRIANGLES 20000000
/* Largest |coordinate| of an OBJ vertex or normal: a head in metres, millimetres or
 * micrometres fits; 1e39 (or nan, inf) is refused at its line. */
#define HK_MAX_MESH_COORDINATE 1e6

typedef struct hk_Mesh {
    int vertex_count;
    int triangle_count;
    hk_Vec3 *positions; /* vertex_count */
    hk_Vec3 *normals;   /* vertex_count, unit length */
    int *triangles;     /* 3 * triangle_count vertex indices, counter-clockwise seen from outside */
} hk_Mesh;

/* Reads an OBJ file: `v`, `vn` and `f` lines (faces in any of the v, v/vt, v//vn,
 * v/vt/vn forms, negative indices counted from the end, polygons triangulated as
 * fans); other statements (vt, o, g, s, usemtl, mtllib) are ignored. A vertex's
 * normal is the average of the `vn` its face corners name, or, when the file has
 * none, the area-weighted average of its faces' normals. Numbers are decimal, as in
 * the key files (no hex floats, nan or inf), within +-HK_MAX_MESH_COORDINATE; an index
 * of 0 or out of range (vertex, normal, or a texture index of 0) is an error. Errors
 * give file:line. */
hk_Status hk_obj_load(const char *path, hk_Mesh *mesh, hk_Error *err);

/* Writes v, vn and f v//vn lines atomically; `comment` (may be NULL) goes in a
 * leading # line. */
hk_Status hk_obj_save(const char *path, const hk_Mesh *mesh, const char *comment, hk_Error *err);

/* Area-weighted vertex normals from the faces (overwrites mesh->normals). */
void hk_mesh_compute_normals(hk_Mesh *mesh);

double hk_mesh_triangle_area(const hk_Mesh *mesh, int triangle);
double hk_mesh_area(const hk_Mesh *mesh);

/* The point of the mesh closest to x and the normal there, the vertex normals blended by the
 * point's barycentric weights (made unit; the face normal where they cancel). Brute force over
 * the triangles. Returns the distance, or -1 when the mesh has no triangles or x is not
 * finite (point and normal then untouched). point or normal may be NULL. */
double hk_mesh_closest_point(const hk_Mesh *mesh, hk_Vec3 x, hk_Vec3 *point, hk_Vec3 *normal);

/* Allocates an empty mesh of the given sizes (all zero). */
hk_Status hk_mesh_alloc(hk_Mesh *mesh, int vertex_count, int triangle_count, hk_Error *err);
void hk_mesh_free(hk_Mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif
