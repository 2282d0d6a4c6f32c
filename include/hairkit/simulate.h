/* A full head of hair in motion (Bertails et al. 2006 §4.1): one Super-Helix per guide follicle
 * of the wick, starting from its statics rest shape, moved by the head, pushed by the
 * body's collision shapes with friction and by its neighbouring guides, and the
 * interpolated hair regrown from the moving guides every frame. */
#ifndef HAIRKIT_SIMULATE_H
#define HAIRKIT_SIMULATE_H

#include "hairkit/capture.h"
#include "hairkit/core.h"
#include "hairkit/dynamics.h"
#include "hairkit/export.h"
#include "hairkit/groom.h"
#include "hairkit/hair_contacts.h"
#include "hairkit/io.h"
#include "hairkit/motion.h"
#include "hairkit/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_HairSimDef {
    int threads;             /* OpenMP threads (<= 0: the default); results do not
                                depend on it */
    hk_DynamicsDef dynamics; /* of every guide */
    int hair_contacts;       /* guide-guide interactions on (default 1) */
    hk_HairContactDef contacts;
    hk_ProgressFn progress; /* may be NULL: progress of the initial statics */
    void *progress_user;
} hk_HairSimDef;

/* The defaults for a hairstyle: dynamics from its InternalFriction, AirDrag and
 * BodyFriction, every guide stepped by the linearly implicit Euler step with the
 * guide-guide contacts solved together (docs/dynamics.md, "Long guides on a head"),
 * contacts scaled to the mass of its strands. */
HK_API hk_HairSimDef hk_hair_sim_def_for(const hk_Hairstyle *style);

/* The same for the defaults of a hairstyle file (hk_default_hairstyle) with hair of
 * 40 um radius and 20 cm. */
HK_API hk_HairSimDef hk_default_hair_sim_def(void);

typedef struct hk_HairSim hk_HairSim;

/* Solves every guide's rest shape (the groom's statics, with the layered envelopes)
 * on the still head and sets up its dynamics. The hairstyle, shapes and wick are
 * copied or only read here. options NULL: hk_hair_sim_def_for(style). */
HK_API hk_Status hk_hair_sim_create(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                                    const hk_Mesh *wick, const hk_HairSimDef *options, hk_HairSim **out, hk_Error *err);
HK_API void hk_hair_sim_destroy(hk_HairSim *sim);

/* The guides of an import (hairkit/capture.h, hk_groom_import) in motion: each a copy of
 * the fitted Super-Helix, at rest in its captured shape (q) with the natural shape found
 * by the inverse statics (q_rest); the hairstyle gives the dynamics' friction and drag,
 * CollisionStep and VisualityStep. Guide-guide contacts are off (options->hair_contacts is
 * ignored): the captured guides are closer than the contacts' distance in places, and
 * pushed apart they would leave the capture. hk_hair_sim_guides and hk_hair_sim_groom
 * are for grown guides: rebuild the strands with hk_imported_groom_strands and
 * hk_hair_sim_strands. */
HK_API hk_Status hk_hair_sim_create_imported(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                                             const hk_ImportedGroom *groom, const hk_HairSimDef *options,
                                             hk_HairSim **out, hk_Error *err);

/* The guides' Super-Helices as they are now (world space), guide_count of them. */
HK_API const hk_SuperHelix *const *hk_hair_sim_strands(const hk_HairSim *sim);

typedef struct hk_HairSimStats {
    int substeps;      /* steps of all guides (more than guides where motion was fast,
                          or where long guides take several steps a frame) */
    long iterations;   /* evaluations of the forces (Newton iterations), all guides */
    int recovered;     /* guides that could not be advanced even in the smallest
                          substeps: held at rest relative to the head at t, then
                          advanced again (never dropped, never aborting the head);
                          counted in each step of a frame where a frame takes several */
    int contact_pairs; /* guide-guide pairs tracked, and pushing (a normal impulse) */
    int contacts;
    int sticking;       /* pushing pairs held by static friction */
    int contact_sweeps; /* Gauss-Seidel sweeps of the contacts' solve over all guides */
    int body_contacts;  /* collision samples touching the body, all guides */
    double seconds;     /* wall time of the advance */
} hk_HairSimStats;

/* Advances every guide from time t to t + dt with the head motion (NULL: still). */
HK_API hk_Status hk_hair_sim_advance(hk_HairSim *sim, const hk_HeadMotion *motion, double t, double dt,
                                     hk_HairSimStats *stats, hk_Error *err);

/* Lets the hair settle for `seconds` (steps of dt) with the head held in the pose
 * `head` (NULL: at rest): the groomed rest shape ignores guide-guide contacts, which
 * then push neighbouring guides apart at first (a pre-roll, as animators do). */
HK_API hk_Status hk_hair_sim_settle(hk_HairSim *sim, const hk_RigidState *head, double seconds, double dt,
                                    hk_Error *err);

/* Settling until the hair is at rest: at least `seconds`, then on until no guide's tip
 * has moved faster than rest_speed over rest_steps steps in a row, or max_seconds in
 * all. A pile of hair held by friction can take a few seconds to come to rest: on
 * examples/guides200 one guide still slid 0.4 mm/s after the first second and stopped
 * at about 2.3 s (docs/dynamics.md, "Contacts solved together"). */
typedef struct hk_SettleDef {
    double seconds;     /* at least (default 1) */
    double max_seconds; /* at most, in all (default 5; = seconds for a fixed settling) */
    double rest_speed;  /* m/s: the fastest tip at rest (default 1e-4, 0.1 mm/s) */
    int rest_steps;     /* steps in a row (default 5) */
} hk_SettleDef;

HK_API hk_SettleDef hk_default_settle_def(void);

typedef struct hk_SettleReport {
    double seconds;   /* settled in all */
    int at_rest;      /* 1: the tips came to rest; 0: max_seconds was reached first */
    double tip_speed; /* m/s: the fastest tip over the last step */
} hk_SettleReport;

/* o NULL: the defaults; report may be NULL. */
HK_API hk_Status hk_hair_sim_settle_until_still(hk_HairSim *sim, const hk_RigidState *head, double dt,
                                                const hk_SettleDef *o, hk_SettleReport *report, hk_Error *err);

/* The threads of the next calls (options.threads; <= 0: the OpenMP default), and of the
 * guide-guide contacts unless their own were set. The results do not depend on it. */
HK_API void hk_hair_sim_set_threads(hk_HairSim *sim, int threads);

HK_API int hk_hair_sim_guide_count(const hk_HairSim *sim);
HK_API int hk_hair_sim_points_per_strand(const hk_HairSim *sim);

/* The guides now, sampled every VisualityStep (guide_count x points x 3, world). */
HK_API void hk_hair_sim_guides(const hk_HairSim *sim, double *out);

/* The groom of the current frame: the guides as above and the interpolated strands
 * regrown from them (same seed: same roots and clumps every frame), kept out of the
 * body shapes where the head is at the end of the last step (docs/grooming.md). g is
 * filled (free with hk_groom_free). go NULL: the defaults; go->threads <= 0: the
 * simulation's threads. */
HK_API hk_Status hk_hair_sim_groom(const hk_HairSim *sim, const hk_Mesh *wick, const hk_GroomDef *go, hk_Groom *g,
                                   hk_Error *err);


/* ---- a simulation written to a folder (sim_run.c, sim_files.c, sim_rebuild.c) -------
 * What `hairkit simulate` does (docs/dynamics.md, "The full head"): frame k is written
 * as DIR/guides_kkkk.hair (the guides) and, unless guides_only, DIR/frame_kkkk.png; the
 * interpolated hair is regrown from the guides as written (float), out of the body
 * posed by the motion at t = k / fps, so that DIR/simulation.txt (which records the
 * motion) and the guides rebuild it byte for byte (hk_simulation_rebuild);
 * full_hair also writes it, DIR/frame_kkkk.hair. */

typedef struct hk_SimProgress {
    long frame, frames;   /* frames written so far (0: the hair is at rest, none yet), in all */
    int guides, elements; /* elements: per guide, the most of any guide */
    int elements_min;     /* the fewest of any guide (an import's guides differ) */
    double seconds_setup; /* loading, the guides' statics and the preroll */
    double preroll;       /* seconds of hair time settled before frame 0 */
    int preroll_at_rest;  /* 1: the guides came to rest within preroll_max */
    double seconds;       /* since the first frame began */
    /* totals so far, by stage: advancing the guides, regrowing the interpolated hair,
     * rendering the picture, writing files (encoding the PNG included) */
    double seconds_dynamics, seconds_regrow, seconds_render, seconds_write;
    int frames_at_once; /* frames regrown and drawn at the same time, each on its own
                           thread: the stages' totals are summed over them and may
                           exceed `seconds` */
    long long bytes;    /* written so far */
    long substeps;      /* guide steps so far */
    long recovered;     /* guides that could not be advanced through a frame even in
                           the smallest substeps, so far (each held at rest relative
                           to the head for that frame, then advanced on;
                           hk_HairSimStats.recovered) */
    int removed;        /* files of an earlier run removed from the folder */
    int video;          /* at the end: 1 DIR/hair.mp4 made, 0 no ffmpeg, -1 ffmpeg failed */
} hk_SimProgress;

/* Called with frame 0 once the hair is at rest, then after every frame. */
typedef void (*hk_SimProgressFn)(void *user, const hk_SimProgress *p);

typedef struct hk_SimRunDef {
    long frames;                      /* 1 to 100000 */
    double fps;                       /* the time step is 1/fps */
    double preroll;                   /* seconds of settling on the still head before frame 0, at
                                         least; then on until the guides' tips rest (slower than
                                         0.1 mm/s for 5 frames; hk_hair_sim_settle_until_still) */
    double preroll_max;               /* seconds of settling at most (default 5; <= preroll: exactly
                                         preroll) */
    int guides_only;                  /* no interpolated hair, no pictures */
    int full_hair;                    /* also DIR/frame_kkkk.hair, every strand */
    int hair_contacts;                /* guide-guide interactions (default 1) */
    int damping;                      /* internal friction and air drag (default 1) */
    hk_DynamicsIntegrator integrator; /* HK_INTEGRATOR_AUTO (default): the hair
                                         simulation's default (the linear Euler step); else TR-BDF2
                                         with the O(N) solver or the linear Euler step with the
                                         dense one */
    int video;                        /* DIR/hair.mp4 with ffmpeg when installed (default 1) */
    int threads;                      /* <= 0: all cores; the files do not depend on it */
    uint64_t seed;                    /* of the interpolation */
    const hk_HeadMotion *motion;      /* NULL: still */
    hk_RenderDef render;              /* camera_distance <= 0: fixed at the first frame's fit */
    hk_ProgressFn statics_progress;   /* may be NULL: the guides' rest shapes */
    void *statics_user;
    hk_SimProgressFn progress; /* may be NULL */
    void *progress_user;
} hk_SimRunDef;

HK_API hk_SimRunDef hk_default_sim_run_def(void);

/* Loads the setup, solves the guides at rest, settles them, and writes every frame to
 * dir (made if missing; files of an earlier run removed first, see
 * hk_simulation_clean_folder) with DIR/simulation.txt. p (may be NULL) gets the final
 * figures. */
HK_API hk_Status hk_simulation_run(const char *setup_path, const char *dir, const hk_SimRunDef *options,
                                   hk_SimProgress *p, hk_Error *err);

/* Removes from dir the files a simulation writes, and only them: frame_kkkk.png,
 * frame_kkkk.hair, guides_kkkk.hair (k: 4 digits or more), hair.mp4, simulation.txt,
 * and temporary files they left (NAME.tmp-XXXXXX). *removed counts them. A missing
 * folder is nothing to clean. */
HK_API hk_Status hk_simulation_clean_folder(const char *dir, int *removed, hk_Error *err);

/* DIR/STEM_kkkk.EXT */
HK_API hk_Status hk_simulation_frame_path(char *buf, size_t size, const char *dir, const char *stem, long frame,
                                          const char *ext, hk_Error *err);

/* The full hair of frame k of the simulation in dir (guides first, then the interpolated
 * strands, kept out of the body posed at the frame's time, as DIR/frame_kkkk.hair of a
 * --full-hair run, byte for byte once saved), from DIR/simulation.txt (with the head's
 * motion), DIR/guides_kkkk.hair and the setup's hairstyle, wick and collision file and
 * the motion file if any (refused if any changed since). threads <= 0: all cores. out is
 * filled (hk_hair_free). */
HK_API hk_Status hk_simulation_rebuild(const char *dir, long frame, int threads, hk_HairFile *out, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
