/* Collision shapes and their penalty energy (Lansink 2010 §4.1.2).
 *
 * A shape measures the penetration depth `dent` of a point (positive inside, negative
 * outside). The penalty energy density of a point is
 *     e(p) = 1/2 * k * max(dent(p) + extra, 0)^2,        extra = alpha * volume,
 * where k is the shape's Penalty, volume its Volume (the envelope thickness v of
 * §4.1.2.2) and alpha in [0, 1] the strand's envelope level (0 for the lowest
 * follicle, 1 for the highest). A strand's collision energy is the sum of e over its
 * collision samples times the sample spacing. Gradients and Hessians with respect to
 * p are analytic; the rod energy chains them to its generalized coordinates. */
#ifndef HAIRKIT_COLLIDE_H
#define HAIRKIT_COLLIDE_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/mesh.h"
#include "hairkit/motion.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hk_ShapeKind {
    HK_SHAPE_SPHERE = 0,
    HK_SHAPE_ELLIPSOID = 1,
    HK_SHAPE_CUBOID = 2,
    HK_SHAPE_FIELD = 3 /* a mesh's signed distance field (a head as a collider) */
} hk_ShapeKind;

typedef struct hk_Shape {
    hk_ShapeKind kind;
    double volume;  /* envelope thickness v in metres (may be negative, §4.1.2.2) */
    double penalty; /* stiffness k >= 0 (J/m^3: energy density per dent^2 per length) */
    hk_Vec3 centre;
    hk_Vec3 half;                  /* ellipsoid radii / cuboid half-dimensions (a, b, c) along the
                                      axes; for a sphere all three equal the radius; for a field the
                                      half-dimensions of its grid */
    hk_Vec3 axis[3];               /* orthonormal local axes U, V, W (identity for a sphere) */
    int styling;                   /* 0 (the constructors' value): part of the body, which no strand may
                                      enter (docs/grooming.md); 1: a styling field such as the soft
                                      sphere before the face (thesis Appendix C, coupes 3-4) that only
                                      shapes the guides through its penalty */
    const hk_DistanceField *field; /* HK_SHAPE_FIELD: the field, borrowed (it must outlive
                                      the shape and its copies); NULL for the others */
} hk_Shape;

/* Shape constructors; axes are normalised. The fields may be edited afterwards (a shape
 * has no derived state). */
HK_API hk_Shape hk_shape_sphere(hk_Vec3 centre, double radius, double volume, double penalty);
HK_API hk_Shape hk_shape_ellipsoid(hk_Vec3 centre, hk_Vec3 radii, const hk_Vec3 axes[3], double volume, double penalty);
HK_API hk_Shape hk_shape_cuboid(hk_Vec3 centre, hk_Vec3 half_dims, const hk_Vec3 axes[3], double volume,
                                double penalty);

/* A mesh as a body shape: dent = -field(p) (the signed distance, negative inside), with
 * the field's grid placed where the mesh was (centre: the grid's centre; axes: the
 * world's) and moved like the other shapes (hk_shapes_posed). The dent's gradient is the
 * trilinear field's; its Hessian is taken as zero, as the cuboid's. The field is
 * borrowed. */
HK_API hk_Shape hk_shape_field(const hk_DistanceField *field, double volume, double penalty);

/* A set of collision shapes with the distance fields its mesh shapes borrow: data
 * (docs/library.md), made by hk_collision_load (a collision file) or filled by
 * hk_collision_add_mesh, released with hk_collision_free. The set owns what it made:
 * the shapes array and every field in `fields`; copies of its shapes (hk_shapes_posed,
 * a simulation's) borrow the fields and must not outlive it. A zeroed set is empty. */
typedef struct hk_CollisionSet {
    hk_Shape *shapes; /* count shapes, in head space */
    int count;
    hk_DistanceField **fields; /* field_count fields, each allocated alone so that adding a
                                  mesh never moves the ones the shapes point to */
    int field_count;
} hk_CollisionSet;

/* Appends a mesh as a body shape: its signed distance field (hk_distance_field_build
 * with def; NULL: the defaults, a 2 mm grid in metres) becomes set's and the shape
 * hk_shape_field(field, volume, penalty) is added after the others. The mesh is not
 * kept. On error the set is unchanged. The collision files' `Mesh` lines and a setup's
 * `HeadCollider` both come here (docs/file-formats.md). */
HK_API hk_Status hk_collision_add_mesh(hk_CollisionSet *set, const hk_Mesh *mesh, const hk_DistanceFieldDef *def,
                                       double volume, double penalty, hk_Error *err);

/* Releases the shapes and the fields; the set is left empty. Safe on a zeroed or freed set. */
HK_API void hk_collision_free(hk_CollisionSet *set);

/* The shapes (head space) where the head's rigid state puts them: out[i] is shapes[i]
 * with its centre at R c + T and its axes turned by R (the rest unchanged). Body shapes
 * move with the head, world-space strands do not (docs/grooming.md). out[count] may not
 * overlap shapes. */
HK_API void hk_shapes_posed(const hk_Shape *shapes, int count, const hk_RigidState *head, hk_Shape *out);

/* Penetration depth of p as defined by the thesis:
 *   field:     dent = -distance(p) in the field's grid (hk_shape_field)
 *   sphere:    dent = r - |p - c|
 *   ellipsoid: dent = |p - c| / ratio - |p - c|, ratio = |(pU/a, pV/b, pW/c)| (radial
 *              distance to the surface along the ray from the centre, §4.1.2.1.1)
 *   cuboid:    dent = min(a - |pU|, b - |pV|, c - |pW|)
 * grad (if not NULL) receives d dent / dp and hess (if not NULL) the 3x3 second
 * derivative (zero for the cuboid, which is piecewise linear). At the centre of an
 * ellipsoid, where the radial measure is undefined, dent is the smallest radius and
 * the derivatives are zero. */
HK_API double hk_shape_dent(const hk_Shape *shape, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess);

/* Penalty energy density e(p) of one shape (see top of file) with envelope level
 * alpha; adds its gradient to *grad and its Hessian to *hess when they are not NULL
 * (callers zero them first). Returns the energy density. Cheap when p is far outside
 * (farther from the centre than the largest radius, or the cuboid's half-diagonal, plus
 * sqrt(3) |extra|). */
HK_API double hk_shape_penalty(const hk_Shape *shape, double alpha, hk_Vec3 p, hk_Vec3 *grad, hk_Mat3 *hess);

/* Sum of hk_shape_penalty over shapes[0..count). grad and hess are overwritten (set
 * to the sum) when not NULL. Returns the summed energy density. */
HK_API double hk_collision_penalty(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p, hk_Vec3 *grad,
                                   hk_Mat3 *hess);

/* Largest dent + extra > 0 over shapes at p (0 when p touches none): how deep a
 * point sits inside the envelopes. Used by tests and reports. */
HK_API double hk_collision_depth(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p);

/* The same, naming the shape: the index of the shape p is deepest inside (dent + extra
 * > 0, the first of equals), or -1 when p touches none; *depth (if not NULL) receives
 * hk_collision_depth's value. */
HK_API int hk_collision_deepest(const hk_Shape *shapes, int count, double alpha, hk_Vec3 p, double *depth);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_COLLIDE_H */
