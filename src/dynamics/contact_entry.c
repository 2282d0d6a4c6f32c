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
#include "dynamics_internal.h"

double hk_dynamics_largest_entry(hk_StrandDynamics *d, const double *before, const double *after)
{
    if (d->contact_samples == 0) return 0.0;
    hk_Vec3 *from = d->entry_pos, *to = d->entry_pos + d->entry_count;
    hk_dynamics_head_space_half_samples(d, before, from);
    hk_dynamics_head_space_half_samples(d, after, to);
    double entry = 0.0;
    /* the collision samples (odd points), with the strand's envelope, and the tip
     * (tip_contact.c), with none */
    for (int j = 1; j < d->entry_count; j += j + 2 < d->entry_count ? 2 : 1) {
        const int tip = j == d->entry_count - 1;
        for (int k = 0; k < d->tip.shape_count; k++) {
            const hk_Shape *sh = &d->tip.shapes[k];
            if (!(sh->penalty > 0.0)) continue;
            const double dent = hk_shape_dent(sh, to[j], NULL, NULL);
            if (!(dent > entry)) continue;
            /* felt at the start: the penalty was on */
            const double extra = tip ? 0.0 : d->contact.envelope_alpha * sh->volume;
            if (hk_shape_dent(sh, from[j], NULL, NULL) + extra > 0.0) continue;
            entry = dent;
        }
    }
    return entry;
}
