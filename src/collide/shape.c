/* Construction of collision shapes (Lansink 2010 §4.1.2.1): sphere, ellipsoid, cuboid;
 * shapes posed by the head's rigid motion. */
#include "hairkit/collide.h"

static hk_Shape shape_base(hk_ShapeKind kind, hk_Vec3 centre, hk_Vec3 half, const hk_Vec3 axes[3], double volume,
                           double penalty)
{
    hk_Shape s;
    s.kind = kind;
    s.volume = volume;
    s.penalty = penalty;
    s.centre = centre;
    s.half = half;
    s.styling = 0;
    s.field = NULL;
    for (int i = 0; i < 3; i++) s.axis[i] = axes ? hk_v3_normalize(axes[i]) : hk_v3_unit(i);
    return s;
}

hk_Shape hk_shape_sphere(hk_Vec3 centre, double radius, double volume, double penalty)
{
    return shape_base(HK_SHAPE_SPHERE, centre, hk_v3(radius, radius, radius), NULL, volume, penalty);
}

hk_Shape hk_shape_ellipsoid(hk_Vec3 centre, hk_Vec3 radii, const hk_Vec3 axes[3], double volume, double penalty)
{
    return shape_base(HK_SHAPE_ELLIPSOID, centre, radii, axes, volume, penalty);
}

hk_Shape hk_shape_cuboid(hk_Vec3 centre, hk_Vec3 half_dims, const hk_Vec3 axes[3], double volume, double penalty)
{
    return shape_base(HK_SHAPE_CUBOID, centre, half_dims, axes, volume, penalty);
}

hk_Shape hk_shape_field(const hk_DistanceField *field, double volume, double penalty)
{
    hk_Vec3 half = hk_v3_zero();
    for (int i = 0; i < 3; i++) hk_v3_set(&half, i, 0.5 * (field->size[i] - 1) * field->spacing);
    hk_Shape s = shape_base(HK_SHAPE_FIELD, hk_v3_add(field->origin, half), half, NULL, volume, penalty);
    s.field = field;
    return s;
}

void hk_shapes_posed(const hk_Shape *shapes, int count, const hk_RigidState *head, hk_Shape *out)
{
    for (int i = 0; i < count; i++) {
        out[i] = shapes[i];
        hk_rigid_point(head, shapes[i].centre, &out[i].centre, NULL, NULL);
        for (int k = 0; k < 3; k++) out[i].axis[k] = hk_m3_mul_v3(&head->rot, shapes[i].axis[k]);
    }
}
