/* A full head simulated live (`hairkit view --simulate`, docs/viewer.md): the guides of
 * hk_hair_sim (simulate.h) advanced one fixed time step at a time, and the whole head
 * regrown from them after every step as `hairkit simulate` regrows its frames
 * (Bertails et al. 2006 §4.1: the interpolated hair follows the guides). The step is
 * simulated time, not wall time: the same steps give the same hair whatever the display
 * does. */
#ifndef HAIRKIT_LIVE_SIM_H
#define HAIRKIT_LIVE_SIM_H

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/hairfile.h"
#include "hairkit/motion.h"
#include "hairkit/scene.h"
#include "hairkit/simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_LiveSimDef {
    double fps;         /* the time step is 1/fps (default 30, the paper's) */
    double preroll;     /* seconds of settling on the still head before time 0, at least
                           (default 1), then on until the tips rest (hk_SimRunDef) */
    double preroll_max; /* at most (default 5; <= preroll: exactly preroll) */
    int hair_contacts;  /* guide-guide interactions (default 1) */
    int guides_only;    /* the guides only, no interpolated hair (default 0) */
    int threads;        /* <= 0: all cores; the hair does not depend on it */
    uint64_t seed;      /* of the interpolation (default 1, as hairkit simulate) */
} hk_LiveSimDef;

HK_API hk_LiveSimDef hk_default_live_sim_def(void);

typedef struct hk_LiveSim hk_LiveSim;

/* The scene's guides solved at rest on the still head, settled, and the hair of time 0.
 * The scene (loaded with HK_SCENE_GROOMING: hairstyle, collision shapes, wick) is only
 * read, here and by every step: it must outlive the simulation. options NULL: the
 * defaults. */
HK_API hk_Status hk_live_sim_create(const hk_Scene *scene, const hk_LiveSimDef *options, hk_LiveSim **out,
                                    hk_Error *err);
HK_API void hk_live_sim_destroy(hk_LiveSim *s);

/* One step: the guides advanced from t to t + 1/fps with the head's motion (NULL:
 * still), then the hair regrown, kept out of the body where the head is at t + 1/fps.
 * stats may be NULL. */
HK_API hk_Status hk_live_sim_step(hk_LiveSim *s, const hk_HeadMotion *motion, hk_HairSimStats *stats, hk_Error *err);

/* The hair now: the guides first, then the interpolated strands (hk_groom_to_hair); the
 * same strands of the same points after every step. */
HK_API const hk_HairFile *hk_live_sim_hair(const hk_LiveSim *s);

HK_API int hk_live_sim_guide_count(const hk_LiveSim *s);
HK_API double hk_live_sim_time(const hk_LiveSim *s); /* simulated seconds since time 0 */
HK_API long hk_live_sim_steps(const hk_LiveSim *s);
HK_API double hk_live_sim_time_step(const hk_LiveSim *s);
/* The head where the last step left it (at rest at time 0). */
HK_API hk_RigidState hk_live_sim_head(const hk_LiveSim *s);
/* Seconds of hair time settled before time 0, and whether the tips came to rest. */
HK_API double hk_live_sim_preroll(const hk_LiveSim *s, int *at_rest);

#ifdef __cplusplus
}
#endif

#endif
