/* Internal to hairkit (not installed, not exported): what the dynamics reads from the
 * statics energy's workspace. Included as "rod/rod_internal.h". */
#ifndef HK_ROD_INTERNAL_H
#define HK_ROD_INTERNAL_H

#include "hairkit/rod.h"

/* Collision sample i (0 <= i < hk_strand_collision_sample_count) as the last
 * hk_strand_energy call with this workspace and a gradient (grad or hess not NULL) found
 * it: returns 1 if it touched a shape, and then *grad is the gradient of its penalty
 * energy (w * dE/dp, with w the arc length the sample stands for) at its position, in
 * the coordinates of that call; 0 otherwise (and for every sample after a call without
 * a gradient, or hk_strand_max_penetration). The dynamics' body friction reads its
 * normal force here instead of evaluating the shapes again. */
int hk_strand_workspace_contact(const hk_StrandWorkspace *ws, int i, hk_Vec3 *grad);

/* The collision samples of element p that the last hk_strand_energy call with this
 * workspace and a gradient found touching (those hk_strand_workspace_contact reports),
 * ascending, in *samples; returns their count (0 after a call without a gradient or
 * hk_strand_max_penetration). The dynamics' sweep visits these alone. */
int hk_strand_workspace_touching(const hk_StrandWorkspace *ws, int p, const int **samples);

/* The walk of hk_strand_energy (order as its: 2 with a Hessian, 1 with a gradient, 0
 * without) for coordinates q, the strand's root pose now and env, kept for the next
 * hk_strand_energy call with these very inputs, which then starts from it (the same
 * bits as its own walk). Its node positions (N + 1) and collision samples are read
 * with the two functions below until the next call with ws. */
void hk_strand_workspace_prepare(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, int order,
                                 hk_StrandWorkspace *ws);

/* The nodes' positions (N + 1) of the last walk with ws. */
const hk_Vec3 *hk_strand_workspace_nodes(const hk_StrandWorkspace *ws);

/* The collision samples' positions in the last walk with ws (hk_strand_collision_sample_count
 * of them), known[i] = 1 where computed: 0 where the sample's element was beyond the
 * reach of every shape (its start farther from each than the shape's bound, sqrt 3
 * times the envelope's extra and the element's length), its position left as it was. */
void hk_strand_workspace_samples(const hk_StrandWorkspace *ws, hk_Vec3 *pos, unsigned char *known);

/* hk_superhelix_points that also gives the node positions (N + 1) of the same walk,
 * the same bits as hk_superhelix_nodes': one walk for both (the dynamics' step
 * acceptance, contact_entry.c). */
void hk_superhelix_points_nodes(const hk_SuperHelix *sh, const double *q, const double *s, int count, hk_Vec3 *pos,
                                hk_Vec3 *nodes);

#endif /* HK_ROD_INTERNAL_H */
