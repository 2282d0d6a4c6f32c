/* Contacts of a strand with the body (paper 000 §4.2): a penalty force normal to the
 * collision shapes (the statics penalty of thesis §4.1.2, so a strand at rest lies where
 * the statics put it) and a tangential friction whose coefficient is blended, with the
 * cosine of the angle between the hair and its sliding direction, from the value with
 * the scales to the value against them. The friction is viscous (proportional to the
 * sliding speed, as in the paper) below friction_velocity and Coulomb (mu |F_n|) above:
 * a penalty method cannot hold a strand still, but this bounds the force by the
 * physical one. */
#include "dynamics_internal.h"

/* Friction of a sample pressed against the body with the normal force fn along
 * `normal` (out of the body): out->force is the friction force, out->damping its
 * linearisation; returns the force. */
static hk_Vec3 friction(const hk_BodyContact *bc, const hk_RigidState *head, hk_Vec3 pos, hk_Vec3 vel, hk_Vec3 tangent,
                        hk_Vec3 normal, double fn, hk_PointForce *out)
{
    /* Sliding velocity relative to the body surface. */
    const hk_Vec3 body_vel = hk_v3_add(head->vel, hk_v3_cross(head->omega, hk_v3_sub(pos, head->trans)));
    const hk_Vec3 vr = hk_v3_sub(vel, body_vel);
    const hk_Vec3 vt = hk_v3_madd(vr, normal, -hk_v3_dot(vr, normal));
    const double speed = hk_v3_norm(vt);
    /* cos = +1: the hair slides tip first, against its scales. */
    const double cosine = speed > 0.0 ? hk_v3_dot(hk_v3_normalize(tangent), vt) / speed : 0.0;
    const double mu = bc->friction_with + (bc->friction_against - bc->friction_with) * 0.5 * (1.0 + cosine);
    const double c = mu * fn / (speed > bc->friction_velocity ? speed : bc->friction_velocity);
    /* Linearisation: c times the projector on the tangent plane. */
    const hk_Mat3 nn = hk_m3_outer(normal, normal);
    hk_Mat3 proj = hk_m3_identity();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) proj.m[i][j] -= nn.m[i][j];
    out->damping = hk_m3_scale(&proj, c);
    out->s = 0.0;
    return hk_v3_scale(vt, -c);
}

int hk_body_contact_force(const hk_BodyContact *bc, const hk_RigidState *head, hk_Vec3 pos, hk_Vec3 vel,
                          hk_Vec3 tangent, hk_PointForce *out)
{
    /* The shapes live in head space: x = R^T (p - T). Per shape i in contact,
     * e_i = k_i dent_i^2 / 2 and g_i = k_i dent_i grad(dent_i), so the Gauss-Newton
     * stiffness is sum_i w g_i g_i^T / (2 e_i) = sum_i w k_i grad(dent_i) grad(dent_i)^T,
     * positive semi-definite (the curvature terms of the exact Hessian left out). Taken
     * shape by shape: g g^T / (2 e) of the sums understated it where a stiff shape meets
     * a soft one with a wide envelope (the head and the styling sphere before the face,
     * 3.5 times too soft), and Newton's iteration of a TR-BDF2 stage diverged there. */
    const hk_Vec3 x = hk_m3_tmul_v3(&head->rot, hk_v3_sub(pos, head->trans));
    hk_Vec3 g_head = hk_v3_zero();
    hk_Mat3 k_head = hk_m3_zero();
    double e = 0.0;
    for (int i = 0; i < bc->shape_count; i++) {
        hk_Vec3 gi = hk_v3_zero(); /* hk_shape_penalty adds to it */
        const double ei = hk_shape_penalty(&bc->shapes[i], bc->envelope_alpha, x, &gi, NULL);
        if (!(ei > 0.0)) continue;
        e += ei;
        g_head = hk_v3_add(g_head, gi);
        const hk_Mat3 gg = hk_m3_outer(gi, gi);
        const hk_Mat3 ki = hk_m3_scale(&gg, bc->weight / (2.0 * ei));
        k_head = hk_m3_add(&k_head, &ki);
    }
    if (!(e > 0.0)) return 0;
    const hk_Vec3 g = hk_m3_mul_v3(&head->rot, g_head); /* d e / d p, world */
    const double gn = hk_v3_norm(g);
    if (!(gn > 0.0)) return 0;
    const hk_Vec3 normal = hk_v3_scale(g, -1.0 / gn); /* out of the body */
    const double fn = bc->weight * gn;
    /* to world axes: R K R^T */
    const hk_Mat3 rk = hk_m3_mul(&head->rot, &k_head);
    const hk_Mat3 rt = hk_m3_transpose(&head->rot);
    out->stiffness = hk_m3_mul(&rk, &rt);
    const hk_Vec3 f = friction(bc, head, pos, vel, tangent, normal, fn, out);
    out->force = hk_v3_add(hk_v3_scale(normal, fn), f);
    return 1;
}

int hk_body_contact_friction(const hk_BodyContact *bc, const hk_RigidState *head, hk_Vec3 pos, hk_Vec3 vel,
                             hk_Vec3 tangent, hk_Vec3 grad, hk_PointForce *out)
{
    const double fn = hk_v3_norm(grad);
    if (!(fn > 0.0)) return 0;
    const hk_Vec3 normal = hk_v3_scale(grad, -1.0 / fn); /* out of the body */
    out->force = friction(bc, head, pos, vel, tangent, normal, fn, out);
    out->stiffness = hk_m3_zero();
    return 1;
}
