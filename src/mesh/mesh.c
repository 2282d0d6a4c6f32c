/* Triangle meshes as data (hairkit/mesh.h): allocation, areas and smooth vertex normals.
 * The readers and writers of mesh files are in src/io (obj.c). */
#include <math.h>
#include <string.h>

#include "hairkit/mesh.h"

hk_Status hk_mesh_alloc(hk_Mesh *mesh, int vertex_count, int triangle_count, hk_Error *err)
{
    memset(mesh, 0, sizeof *mesh);
    if (vertex_count < 0 || vertex_count > HK_MAX_MESH_VERTICES || triangle_count < 0 ||
        triangle_count > HK_MAX_MESH_TRIANGLES)
        return hk_error_set(err, HK_ERR_INVALID, "mesh of %d vertices and %d triangles is out of range",
                            vertex_count, triangle_count);
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
