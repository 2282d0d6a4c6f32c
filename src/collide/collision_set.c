/* A set of collision shapes that owns the distance fields of its meshes (hairkit/collide.h):
 * the one place where a mesh becomes a body shape, for the collision files' Mesh lines
 * and a setup's HeadCollider alike (docs/file-formats.md). */
#include <string.h>

#include "hairkit/collide.h"

hk_Status hk_collision_add_mesh(hk_CollisionSet *set, const hk_Mesh *mesh, const hk_DistanceFieldDef *def,
                                double volume, double penalty, hk_Error *err)
{
    hk_DistanceField *field = hk_calloc_array(1, sizeof *field, err);
    hk_Shape *shapes = hk_alloc_array((size_t)set->count + 1, sizeof *shapes, err);
    hk_DistanceField **fields = hk_alloc_array((size_t)set->field_count + 1, sizeof *fields, err);
    hk_Status st = field && shapes && fields ? HK_OK : HK_ERR_NOMEM;
    if (st == HK_OK) st = hk_distance_field_build(mesh, def, field, err);
    if (st != HK_OK) {
        hk_free(field);
        hk_free(shapes);
        hk_free(fields);
        return st;
    }
    /* The fields are allocated one by one: the shapes' pointers to them stay valid. */
    if (set->count > 0) memcpy(shapes, set->shapes, (size_t)set->count * sizeof *shapes);
    if (set->field_count > 0) memcpy(fields, set->fields, (size_t)set->field_count * sizeof *fields);
    shapes[set->count] = hk_shape_field(field, volume, penalty);
    fields[set->field_count] = field;
    hk_free(set->shapes);
    hk_free(set->fields);
    set->shapes = shapes;
    set->fields = fields;
    set->count++;
    set->field_count++;
    return HK_OK;
}

void hk_collision_free(hk_CollisionSet *set)
{
    if (!set) return;
    for (int i = 0; i < set->field_count; i++) {
        hk_distance_field_free(set->fields[i]);
        hk_free(set->fields[i]);
    }
    hk_free(set->fields);
    hk_free(set->shapes);
    memset(set, 0, sizeof *set);
}
