/* A full head of hair in motion (paper 000 §4.1): one Super-Helix per guide follicle
 * of the wick, starting from its statics rest shape, moved by the head, pushed by the
 * body's collision shapes with friction and by its neighbouring guides, and the
 * interpolated hair regrown from the moving guides every frame. */
#ifndef HAIRKIT_SIMULATE_H
#define HAIRKIT_SIMULATE_H

#include "hairkit/core.h"
#include "hairkit/dynamics.h"
#include "hairkit/groom.h"
#include "hairkit/hair_contacts.h"
#include "hairkit/motion.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_HairSimOptions {
    int threads;                  /* OpenMP threads (<= 0: the default); results do not
                                     depend on it */
    hk_DynamicsParams dynamics;   /* of every guide */
    int hair_contacts;            /* guide-guide interactions on (default 1) */
    hk_HairContactParams contacts;
    hk_ProgressFn progress;       /* may be NULL: progress of the initial statics */
    void *progress_user;
} hk_HairSimOptions;

/* Dynamics from the hairstyle's InternalFriction, AirDrag and BodyFriction, contacts
 * with their defaults. */
hk_HairSimOptions hk_default_hair_sim_options(const hk_HairstyleDef *style);

typedef struct hk_HairSim hk_HairSim;

/* Solves every guide's rest shape (the groom's statics, with the layered envelopes)
 * on the still head and sets up its dynamics. The hairstyle, shapes and wick are
 * copied or only read here. */
hk_Status hk_hair_sim_create(const hk_HairstyleDef *style, const hk_Shape *shapes, int shape_count,
                             const hk_Mesh *wick, const hk_HairSimOptions *options, hk_HairSim **out,
                             hk_Error *err);
void hk_hair_sim_destroy(hk_HairSim *sim);

typedef struct hk_HairSimStats {
    int substeps;         /* steps of all guides (more than guides where motion was fast) */
    int contact_pairs;    /* guide-guide pairs tracked, and in contact */
    int contacts;
    int body_contacts;    /* collision samples touching the body, all guides */
    double seconds;       /* wall time of the advance */
} hk_HairSimStats;

/* Advances every guide from time t to t + dt with the head motion (NULL: still). */
hk_Status hk_hair_sim_advance(hk_HairSim *sim, const hk_HeadMotion *motion, double t, double dt,
                              hk_HairSimStats *stats, hk_Error *err);

/* Lets the hair settle for `seconds` (steps of dt) with the head held in the pose
 * `head` (NULL: at rest): the groomed rest shape ignores guide-guide contacts, which
 * then push neighbouring guides apart at first (a pre-roll, as animators do). */
hk_Status hk_hair_sim_settle(hk_HairSim *sim, const hk_RigidState *head, double seconds, double dt,
                             hk_Error *err);

int hk_hair_sim_guide_count(const hk_HairSim *sim);
int hk_hair_sim_points_per_strand(const hk_HairSim *sim);

/* The guides now, sampled every VisualityStep (guide_count x points x 3, world). */
void hk_hair_sim_guides(const hk_HairSim *sim, double *out);

/* The groom of the current frame: the guides as above and the interpolated strands
 * regrown from them (same seed: same roots and clumps every frame), kept out of the
 * body shapes where the head is at the end of the last step (docs/grooming.md). g is
 * filled (free with hk_groom_free). */
hk_Status hk_hair_sim_groom(const hk_HairSim *sim, const hk_Mesh *wick, const hk_GroomOptions *go,
                            hk_Groom *g, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
