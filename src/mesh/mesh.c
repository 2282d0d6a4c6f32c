/* Triangle meshes as data (hairkit/mesh.h): allocation, areas, smooth vertex normals, and
 * the scale and up-axis transforms of a head made elsewhere.
 * The readers and writers of mesh files are in src/io (obj.c, mesh_ply.c). */
#include <math.h>
#include <string.h>

#include "hairkit/mesh.h"

hk_Status hk_mesh_alloc(hk_Mesh *mesh, int vertex_count, int triangle_count, hk_Error *err)
{
    memset(mesh, 0, sizeof *mesh);
    if (vertex_count < 0 || vertex_count > HK_MAX_MESH_VERTICES || triangle_count < 0 ||
        triangle_count > HK_MAX_MESH_TRIANGLES)
        return hk_error_set(err, HK_ERR_INVALID, "mesh of %d vertices and %d triangles is out of range", vertex_count,
                            triangle_count);
    mesh->positions = hk_calloc_array((size_t)vertex_count, sizeof(hk_Vec3), err);
    mesh->normals = hk_calloc_array((size_t)vertex_count, sizeof(hk_Vec3), err);
    mesh->triangles = hk_calloc_array((size_t)triangle_count * 3, sizeof(int), err);
    if (!mesh->positions || !mesh->normals || !mesh->triangles) {
        hk_mesh_free(mesh);
        return HK_ERR_NOMEM;
    }
    mesh->vertex_count = vertex_count;
    mesh->triangle_count = triangle_count;
    return HK_OK;
}

void hk_mesh_free(hk_Mesh *mesh)
{
    hk_free(mesh->positions);
    hk_free(mesh->normals);
    hk_free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}

double hk_mesh_triangle_area(const hk_Mesh *mesh, int t)
{
    const int *tri = mesh->triangles + 3 * t;
    const hk_Vec3 a = mesh->positions[tri[0]], b = mesh->positions[tri[1]], c = mesh->positions[tri[2]];
    return 0.5 * hk_v3_norm(hk_v3_cross(hk_v3_sub(b, a), hk_v3_sub(c, a)));
}

double hk_mesh_area(const hk_Mesh *mesh)
{
    double area = 0.0;
    for (int t = 0; t < mesh->triangle_count; t++) area += hk_mesh_triangle_area(mesh, t);
    return area;
}

void hk_mesh_compute_normals(hk_Mesh *mesh)
{
    for (int i = 0; i < mesh->vertex_count; i++) mesh->normals[i] = hk_v3_zero();
    for (int t = 0; t < mesh->triangle_count; t++) {
        const int *tri = mesh->triangles + 3 * t;
        const hk_Vec3 a = mesh->positions[tri[0]], b = mesh->positions[tri[1]], c = mesh->positions[tri[2]];
        const hk_Vec3 n = hk_v3_cross(hk_v3_sub(b, a), hk_v3_sub(c, a)); /* |n| = 2 area */
        for (int k = 0; k < 3; k++) mesh->normals[tri[k]] = hk_v3_add(mesh->normals[tri[k]], n);
    }
    for (int i = 0; i < mesh->vertex_count; i++) mesh->normals[i] = hk_v3_normalize(mesh->normals[i]);
}

/* ---- transforms: units and up axis of a head made elsewhere ---- */

hk_Status hk_mesh_scale(hk_Mesh *mesh, double s, hk_Error *err)
{
    if (!(s > 0.0) || !isfinite(s)) return hk_error_set(err, HK_ERR_INVALID, "scale %g: must be > 0 and finite", s);
    for (int i = 0; i < mesh->vertex_count; i++)
        if (!(fabs(mesh->positions[i].x * s) <= HK_MAX_MESH_COORDINATE &&
              fabs(mesh->positions[i].y * s) <= HK_MAX_MESH_COORDINATE &&
              fabs(mesh->positions[i].z * s) <= HK_MAX_MESH_COORDINATE))
            return hk_error_set(err, HK_ERR_INVALID, "scale %g: vertex %d leaves +-%g", s, i, HK_MAX_MESH_COORDINATE);
    if (s == 1.0) return HK_OK;
    for (int i = 0; i < mesh->vertex_count; i++) mesh->positions[i] = hk_v3_scale(mesh->positions[i], s);
    return HK_OK;
}

void hk_mesh_up_to_y(hk_Mesh *mesh, hk_Axis up)
{
    for (int i = 0; i < mesh->vertex_count; i++) {
        mesh->positions[i] = hk_v3_up_to_y(mesh->positions[i], up);
        mesh->normals[i] = hk_v3_up_to_y(mesh->normals[i], up);
    }
}
