/* The tip's contact with the body.
 *
 * The body's penalty acts at the statics' collision samples, the midpoints of pieces
 * of CollisionStep (thesis §4.1.2; paper 000 §4.2), so the last half piece, from the
 * last sample to the tip, is guarded by nothing: a tip that meets the head at an angle
 * goes in past the last sample, and under shake and tilt the tips of guides of
 * examples/guides200 reached 2.2-2.7 mm into the face and the neck while the samples
 * stayed within 1 mm (docs/dynamics.md, "Limitations"). The tip gets a penalty of its
 * own, on the body shapes themselves (not their envelopes, not the styling shapes:
 * where the statics' samples already hold the strand, at rest on the scalp's
 * envelope, it adds nothing), standing for the half piece: weight CollisionStep / 2.
 * It is part of the potential (hk_dynamics_total_energy) as it is of the forces. */
#include "dynamics_internal.h"

int hk_dynamics_tip_contact(const hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointKinematics *tip,
                            hk_PointForce *pf)
{
    if (d->tip.shape_count == 0) return 0;
    const hk_Vec3 x = hk_m3_tmul_v3(&head->rot, hk_v3_sub(tip->k.pos, head->trans));
    if (!(hk_collision_depth(d->tip.shapes, d->tip.shape_count, 0.0, x) > 0.0)) return 0;
    return hk_body_contact_force(&d->tip, head, tip->k.pos, tip->k.vel, hk_m3_col(&tip->k.frame, 0), pf);
}

double hk_dynamics_tip_energy(hk_StrandDynamics *d, const double *q)
{
    if (d->tip.shape_count == 0) return 0.0;
    const hk_Vec3 x = hk_dynamics_head_space_tip(d, q);
    return d->tip.weight * hk_collision_penalty(d->tip.shapes, d->tip.shape_count, 0.0, x, NULL, NULL);
}
