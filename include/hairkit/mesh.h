/* Triangle meshes (heads, wicks): Wavefront OBJ input and output, PLY input, and the
 * transforms a head made elsewhere needs (units, up axis). */
#ifndef HAIRKIT_MESH_H
#define HAIRKIT_MESH_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_MAX_MESH_VERTICES  10000000
#define HK_MAX_MESH_TRIANGLES 20000000
/* Largest |coordinate| of an OBJ or PLY vertex or normal: a head in metres, millimetres or
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
HK_API hk_Status hk_obj_load(const char *path, hk_Mesh *mesh, hk_Error *err);

/* Reads a PLY mesh, binary little-endian or ASCII (docs/file-formats.md, "PLY heads"):
 * a `vertex` element with x, y, z (float or double) and optional normals nx, ny, nz; a
 * `face` element whose list `vertex_indices` (or `vertex_index`, or its only list)
 * holds 0-based vertex indices, polygons of 3 or more corners triangulated as fans.
 * Other properties and elements are skipped. The normals are the file's (made unit) or,
 * when it has none, the area-weighted average of the faces'. Coordinates within
 * +-HK_MAX_MESH_COORDINATE; every element's count is checked against the file's size
 * before allocating. Errors give file:line (header, ASCII) or file:offset (binary). */
HK_API hk_Status hk_ply_mesh_load(const char *path, hk_Mesh *mesh, hk_Error *err);

/* Reads a head or wick in any mesh format hairkit reads: PLY when the name ends in .ply
 * (any case) or the file starts with a "ply" line, OBJ otherwise. */
HK_API hk_Status hk_mesh_load(const char *path, hk_Mesh *mesh, hk_Error *err);

/* Multiplies every vertex by s (> 0 and finite; 0.001 turns millimetres into metres);
 * refused, the mesh unchanged, when a coordinate would leave +-HK_MAX_MESH_COORDINATE. */
HK_API hk_Status hk_mesh_scale(hk_Mesh *mesh, double s, hk_Error *err);

/* Rotates the vertices and normals so that `up` becomes +y, by the smallest rotation
 * (hk_v3_up_to_y, the rotation of hk_hair_up_to_y and `hairkit convert --up`). */
HK_API void hk_mesh_up_to_y(hk_Mesh *mesh, hk_Axis up);

/* Writes v, vn and f v//vn lines atomically; `comment` (may be NULL) goes in a
 * leading # line. */
HK_API hk_Status hk_obj_save(const char *path, const hk_Mesh *mesh, const char *comment, hk_Error *err);

/* Area-weighted vertex normals from the faces (overwrites mesh->normals). */
HK_API void hk_mesh_compute_normals(hk_Mesh *mesh);

HK_API double hk_mesh_triangle_area(const hk_Mesh *mesh, int triangle);
HK_API double hk_mesh_area(const hk_Mesh *mesh);

/* The point of the mesh closest to x and the normal there, the vertex normals blended by the
 * point's barycentric weights (made unit; the face normal where they cancel). Brute force over
 * the triangles. Returns the distance, or -1 when the mesh has no triangles or x is not
 * finite (point and normal then untouched). point or normal may be NULL. */
HK_API double hk_mesh_closest_point(const hk_Mesh *mesh, hk_Vec3 x, hk_Vec3 *point, hk_Vec3 *normal);

/* count points uniform by area on the mesh (a triangle drawn by its area, then a point
 * uniform in it) and the vertex normals blended there (unit length), each from the
 * counter-based RNG (rng.h) keyed by (seed, its index): the same points whatever the
 * threads (<= 0: OpenMP's default). normal may be NULL. HK_ERR_INVALID when the mesh
 * has no area. */
HK_API hk_Status hk_mesh_sample_uniform(const hk_Mesh *mesh, long count, uint64_t seed, int threads, hk_Vec3 *point,
                                        hk_Vec3 *normal, hk_Error *err);

/* ---- signed distance fields ------------------------------------------------------ */

/* The signed distance to a closed triangle mesh sampled on a regular grid: negative
 * inside, positive outside (src/mesh/distance_field.c says how it is built). A head as
 * a collider (docs/capture.md). */
typedef struct hk_DistanceField {
    hk_Vec3 origin;  /* node (0, 0, 0) */
    double spacing;  /* between nodes */
    int size[3];     /* nodes along x, y and z (>= 2 each) */
    float *distance; /* size[0] * size[1] * size[2] values, x fastest, then y */
} hk_DistanceField;

typedef struct hk_DistanceFieldDef {
    double spacing;     /* grid spacing in the mesh's units (default 0.002: 2 mm in metres) */
    double margin;      /* the grid reaches this far beyond the mesh's bounding box (0.03) */
    int exact_band;     /* cells around each triangle whose distance is computed exactly
                           before the sweeps carry the closest triangles on (2) */
    double exact_reach; /* nodes this far from the mesh get their exact distance; beyond,
                           the chamfer distance of the sweeps, a few per cent long
                           (default 0.01) */
} hk_DistanceFieldDef;

HK_API hk_DistanceFieldDef hk_default_distance_field_def(void);

/* Builds the field of the mesh (def NULL: the defaults). The grid's size is checked
 * against the memory budget (hk_memory_check) before anything is allocated. The sign
 * is right everywhere for a closed mesh; an open one gets wrong signs along the lines
 * parallel to x through its holes. */
HK_API hk_Status hk_distance_field_build(const hk_Mesh *mesh, const hk_DistanceFieldDef *def, hk_DistanceField *out,
                                         hk_Error *err);

/* The field at p, trilinear between the nodes, and its gradient when grad is not NULL
 * (the trilinear interpolant's, constant along no axis; continuous in value, not in
 * gradient, across cell faces). Beyond the grid: the value at the nearest point of the
 * grid plus the distance to it, and the direction away as the gradient. */
HK_API double hk_distance_field_eval(const hk_DistanceField *field, hk_Vec3 p, hk_Vec3 *grad);

HK_API void hk_distance_field_free(hk_DistanceField *field);

/* Allocates an empty mesh of the given sizes (all zero). */
HK_API hk_Status hk_mesh_alloc(hk_Mesh *mesh, int vertex_count, int triangle_count, hk_Error *err);
HK_API void hk_mesh_free(hk_Mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif
