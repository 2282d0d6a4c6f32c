/* How deep a collision sample enters the body unfelt over one step.
 *
 * The body contacts are penalty forces at the collision samples (paper 000 §4.2, the
 * statics penalty of thesis §4.1.2). The linearly implicit Euler step (paper 000 §3.4)
 * evaluates them, with their stiffness, at the start of the step only: a sample that
 * is out of a shape's reach then moves through the step as if the shape were not
 * there, and ends inside it by up to the step's travel. That, not the penalty's
 * stiffness, is what let guides of examples/guides200 4.5 mm into the neck under a
 * nod at 0.16 m/s (docs/dynamics.md, "Limitations"). hk_strand_dynamics_advance splits
 * such a step: halving it halves the travel, and once the sample is inside, the next
 * step feels the penalty implicitly. The tip, which has a contact of its own on the
 * body shapes themselves (tip_contact.c), is watched the same way. Only points that
 * felt nothing at the start count: a point already inside is pushed by its penalty,
 * and splitting would not bring it out sooner. */
#include <string.h>

#include "collide/collide_internal.h"
#include "dynamics_internal.h"

/* The cache slot of the head-space positions of the samples, the tip and the nodes for
 * coordinates q: a step's end is the next step's start, and a split step starts where
 * it did, so the two last states are kept (half the cost of the check; the nodes, for
 * the step's largest travel, come from the same walk). With the full stiffness and the
 * linearly implicit Euler step, which evaluates at the accepted q next (the next step's,
 * on a head), the walk is the potential's own (hk_dynamics_potential_walk), which that
 * evaluation then takes over instead of walking again: a walk per step saved, and the
 * check's positions round as the potential's samples do. Its samples of an element
 * beyond every shape's reach are not computed (entry_known). TR-BDF2's next evaluation
 * is at a stage's iterate: it keeps the superhelix walk, the cheaper. */
static int slot_of(hk_StrandDynamics *d, const double *q)
{
    const size_t bytes = (size_t)(3 * d->sh->n) * sizeof(double);
    for (int k = 0; k < 2; k++)
        if (d->entry_valid[k] && memcmp(d->entry_q[k], q, bytes) == 0) {
            d->entry_next = 1 - k; /* keep this one */
            return k;
        }
    const int k = d->entry_next;
    memcpy(d->entry_q[k], q, bytes);
    if (d->params.stiffness == HK_STIFFNESS_FULL && d->params.integrator == HK_INTEGRATOR_LINEAR_EULER) {
        hk_dynamics_potential_walk(d, q, d->entry_pos[k], d->entry_known[k], d->entry_nodes[k]);
    } else {
        hk_dynamics_head_space_walk(d, q, d->entry_s, d->entry_count, d->entry_pos[k], d->entry_nodes[k]);
        memset(d->entry_known[k], 1, (size_t)d->entry_count);
    }
    d->entry_valid[k] = 1;
    d->entry_next = 1 - k;
    return k;
}


const hk_Vec3 *hk_dynamics_entry_nodes(hk_StrandDynamics *d, const double *q) { return d->entry_nodes[slot_of(d, q)]; }

double hk_dynamics_largest_entry(hk_StrandDynamics *d, const double *before, const double *after)
{
    if (d->contact_samples == 0) return 0.0;
    const int b = slot_of(d, before), a = slot_of(d, after);
    const hk_Vec3 *from = d->entry_pos[b], *to = d->entry_pos[a];
    const unsigned char *from_known = d->entry_known[b], *to_known = d->entry_known[a];
    double entry = 0.0;
    /* the collision samples, with the strand's envelope, and the tip (tip_contact.c),
     * with none; a sample not computed was beyond every shape's bound and envelope
     * (its element out of their reach): no dent at the end, not felt at the start */
    for (int j = 0; j < d->entry_count; j++) {
        if (!to_known[j]) continue;
        const int tip = j == d->entry_count - 1;
        for (int k = 0; k < d->tip.shape_count; k++) {
            const hk_Shape *sh = &d->tip.shapes[k];
            /* beyond the shape's bound (with extra = 0), or clearly outside it, the
             * point has no dent > entry >= 0: most points near the head lie outside
             * it, and the test spares the dent's roots and divisions */
            if (!(sh->penalty > 0.0) || hk_v3_dist(to[j], sh->centre) > hk_shape_bound(sh) ||
                hk_shape_outside(sh, to[j]))
                continue;
            const double dent = hk_shape_dent(sh, to[j], NULL, NULL);
            if (!(dent > entry)) continue;
            /* felt at the start: the penalty was on */
            const double extra = tip ? 0.0 : d->contact.envelope_alpha * sh->volume;
            if (from_known[j] && hk_shape_dent(sh, from[j], NULL, NULL) + extra > 0.0) continue;
            entry = dent;
        }
    }
    return entry;
}
