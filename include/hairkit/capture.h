/* Captured and foreign hair made into Super-Helices at rest (docs/capture.md).
 *
 * A groom made in another tool or captured from real hair is a set of polylines. To move
 * it with Super-Helices (Bertails et al. 2006) each strand becomes a Super-Helix that
 * follows its polyline (hk_superhelix_fit), and then gets the natural curvatures and
 * twist that make that shape an equilibrium under gravity and the body
 * (hk_statics_invert), so that the hair does not sag when the simulation starts: the
 * inverse problem of Derouet-Jourdan, Bertails-Descoubes, Daviet and Thollot, "Inverse
 * Dynamic Hair Modeling with Frictional Contact", ACM TOG 32(6) (SIGGRAPH Asia 2013).
 * Lengths are metres: scale a groom in other units first (hk_hair_read's options). */
#ifndef HAIRKIT_CAPTURE_H
#define HAIRKIT_CAPTURE_H

#include "hairkit/core.h"
#include "hairkit/collide.h"
#include "hairkit/export.h"
#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"
#include "hairkit/rod.h"
#include "hairkit/statics.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- fitting a Super-Helix to a polyline ------------------------------------------ */

typedef struct hk_SuperHelixFitDef {
    int elements;          /* N, elements of equal length; 0: chosen, starting from
                              ceil(L / element_length) and doubled (each element split in
                              two, which keeps the shape) while the mean error is above
                              `tolerance`, up to max_elements and one element per segment
                              of the polyline */
    double element_length; /* the first N when chosen (m; default 0.01) */
    int max_elements;      /* largest N chosen (default 64) */
    double tolerance;      /* mean error at which the choice of N stops (m; default 5e-5) */
    int max_iterations;    /* Levenberg-Marquardt iterations per N (default 200) */
} hk_SuperHelixFitDef;

HK_API hk_SuperHelixFitDef hk_default_superhelix_fit_def(void);

/* How well a Super-Helix follows its polyline: the distance between each point of the
 * polyline (after the root) and the Super-Helix at the same arc length. */
typedef struct hk_SuperHelixFitReport {
    double mean_error; /* m */
    double max_error;  /* m */
    double length;     /* L: the polyline's length, the Super-Helix's too (m) */
    int elements;      /* N */
    int iterations;    /* Levenberg-Marquardt iterations, over every N tried */
} hk_SuperHelixFitReport;

/* The Super-Helix of N elements of equal length that follows the polyline points[0..count)
 * (count >= 2; consecutive equal points are skipped) in the least-squares sense: its
 * root is points[0], its root tangent the polyline's there (from the parabola through
 * the first three points), its root frame hk_root_frame of that tangent, its length the
 * polyline's, and its curvatures and twist q minimise the sum of squared distances
 * between each point and the Super-Helix at the point's arc length (Levenberg-Marquardt
 * with the exact Jacobian dr/dq of the kinematics; G1 by construction). q_rest is set to
 * q (the fitted shape is the rest shape without gravity: see hk_statics_invert). The
 * material is *material, or hk_superhelix_create's when NULL. def NULL: the defaults.
 * report may be NULL. */
HK_API hk_Status hk_superhelix_fit(const hk_Vec3 *points, int count, const hk_RodMaterial *material,
                                   const hk_SuperHelixFitDef *def, hk_SuperHelix **out, hk_SuperHelixFitReport *report,
                                   hk_Error *err);

/* ---- inverse statics ---------------------------------------------------------------- */

typedef struct hk_InverseStaticsDef {
    int settle_unstable;   /* 1 (default): a strand whose shape is an unstable equilibrium
                              is settled by the statics from that shape (it moves to the
                              stable rest nearby, and the report says how far); 0: left
                              as it is */
    hk_StaticsDef statics; /* the statics of that settling (hk_default_statics_def) */
} hk_InverseStaticsDef;

HK_API hk_InverseStaticsDef hk_default_inverse_statics_def(void);

typedef struct hk_InverseStaticsReport {
    int stable;         /* 1 when the Hessian of the total energy at the shape is
                           positive definite (a stable equilibrium) */
    int settled;        /* 1 when it was not and the statics settled the strand */
    double drift;       /* settled: the largest distance between a node of the shape
                           and the same node after settling (m); else 0 */
    double rest_change; /* max |q_rest - q| over the coordinates (1/m): how far the
                           natural shape is from the given one */
    double residual;    /* |grad E| at sh->q after the inversion, relative to the
                           largest external generalized force (0 when there is none) */
} hk_InverseStaticsReport;

/* Natural curvatures and twist that make the strand's current shape sh->q an equilibrium
 * under gravity and the shapes of env (NULL: gravity alone): the elastic force per
 * element is diagonal, l_Q K_i (q_iQ - q_rest_iQ), so with f = dE_ext/dq the gradient of
 * gravity and the shapes' penalties at sh->q,
 *     q_rest = q + f_iQ / (l_Q K_i),
 * in closed form (Derouet-Jourdan et al. 2013, §4, with the contact forces the
 * penalties give at the shape; choosing other forces inside the friction cone is not
 * done). Then the stability of that equilibrium: the Hessian of the total energy at q
 * (exact, hk_strand_energy) is factored; when it is not positive definite the strand is
 * unstable (a column of hair standing up higher than Greenhill's critical height, e.g.)
 * and, with def->settle_unstable, sh->q becomes the rest the statics find from it.
 * def NULL: the defaults. report may be NULL. */
HK_API hk_Status hk_statics_invert(hk_SuperHelix *sh, const hk_StrandEnvDef *env, const hk_InverseStaticsDef *def,
                                   hk_InverseStaticsReport *report, hk_Error *err);


/* ---- a whole groom imported (hairkit import; docs/capture.md, "Importing a groom") -- */

#define HK_IMPORT_ATTACH      3 /* guides each strand follows */
#define HK_MAX_IMPORT_STRANDS 10000000
/* Largest imported-guides text file read or written: above the 16 MiB of hand-written
 * input files (HK_MAX_INPUT_FILE_BYTES), as it grows with the groom (every one of
 * Sintel's 11,400 strands a guide takes 24 MB). */
#define HK_MAX_IMPORT_FILE_BYTES ((long)256 << 20)
#define HK_IMPORT_MAX_DRIFT      1e-3 /* a guide settled farther from its capture is followed by no strand (m) */

typedef struct hk_GroomImportDef {
    int guides;                   /* K; 0 (default): one guide per 75 strands, at least one;
                                     >= the strands: every strand is a guide */
    uint64_t seed;                /* picks the first guide of the farthest-point sampling (default 1) */
    int threads;                  /* OpenMP threads (<= 0: the default); the result does not
                                     depend on it */
    double station_step;          /* spacing of the guides' stations the other strands are
                                     attached to (m; default 0.001) */
    hk_RodMaterial material;      /* of every strand (default: 40 um radius, 3 GPa,
                                     Poisson 0.48, 1300 kg/m^3, gravity 9.81 down y) */
    double collision_step;        /* CollisionStep of the body's penalty in the inverse (m;
                                     default 0.005, the hairstyle's default): it must be
                                     the simulation's, whose contact samples are the
                                     statics' (hk_strand_collision_sample_count) */
    hk_SuperHelixFitDef fit;      /* hk_default_superhelix_fit_def */
    hk_InverseStaticsDef inverse; /* hk_default_inverse_statics_def */
    hk_ProgressFn progress;       /* may be NULL: stages "push out", "fit" */
    void *progress_user;
} hk_GroomImportDef;

HK_API hk_GroomImportDef hk_default_groom_import_def(void);

/* A groom made Super-Helix guides at rest and strands that follow them. A value: its
 * arrays belong to it (hk_imported_groom_free). */
typedef struct hk_ImportedGroom {
    int strand_count, guide_count;
    uint32_t *first_point; /* strand_count + 1 offsets into points */
    float *points;         /* the captured strands in input order (moved out of the body),
                              3 floats per point */
    int *guide_strand;     /* guide_count: the strand each guide was fitted to */
    hk_SuperHelix **guide; /* guide_count: q the fitted captured shape, q_rest the natural
                              shape that makes it an equilibrium */
    int *attach_guide;     /* HK_IMPORT_ATTACH per strand: the guides it follows, nearest
                              root first, -1 unused */
    double *attach_weight; /* HK_IMPORT_ATTACH per strand, summing to 1 */
    double station_step;   /* m */
    hk_RodMaterial material;
} hk_ImportedGroom;

typedef struct hk_GroomImportReport {
    int strands, guides;
    int moved_strands; /* strands with points that started inside the body */
    long moved_points;
    double moved_max, moved_mean; /* how far those points moved (m) */
    double fit_mean;              /* mean over the guides of their mean fit error (m) */
    double fit_worst;             /* the worst guide's mean error (m) */
    double fit_max;               /* the largest point error of any guide (m) */
    double elements_mean;
    int unstable;     /* guides whose captured shape is an unstable equilibrium */
    int settled;      /* of them, settled to the stable rest nearby */
    double drift_max; /* the largest drift of a settled guide (m) */
    int unfollowed;   /* settled guides farther than HK_IMPORT_MAX_DRIFT: followed
                         by no strand */
    double seconds_push, seconds_choose, seconds_fit, seconds_attach; /* wall time of each stage */
    double task_seconds_fit, task_seconds_inverse;                    /* CPU time of the fit-and-inverse stage
                                                                         (seconds_fit): the guides' fits and
                                                                         inversions, summed over all threads */
} hk_GroomImportReport;

/* The guides and attachments of `hair` (metres, y up: scale it first), with the body
 * shapes (head space, e.g. hk_shape_field of the head; may be none): points of a strand
 * that start inside a body shape are moved out (keeping segment lengths); K guides are
 * chosen by farthest-point sampling of the roots; each guide is fitted
 * (hk_superhelix_fit) and inverted (hk_statics_invert) with the body shapes; every
 * strand follows its HK_IMPORT_ATTACH nearest guides (inverse distance of the roots)
 * among those that rest at their capture: an unstable guide settled more than
 * HK_IMPORT_MAX_DRIFT away is simulated but followed by no strand, its own included.
 * def NULL: the defaults. report may be NULL. */
HK_API hk_Status hk_groom_import(const hk_HairFile *hair, const hk_Shape *body, int body_count,
                                 const hk_GroomImportDef *def, hk_ImportedGroom *out, hk_GroomImportReport *report,
                                 hk_Error *err);

HK_API void hk_imported_groom_free(hk_ImportedGroom *g);

/* Every strand where the guides now are: guides_now[guide_count] (the same elements as
 * g->guide; NULL: g->guide themselves), each point p of a strand moved by the weighted
 * motion of its guides' stations nearest its arc length,
 *     p' = p + sum_a w_a [(r_a - r0_a) + (R_a - R0_a) R0_a^T (p - r0_a)],
 * r, R a station's position and material frame now, r0, R0 at rest: at rest every point
 * is its captured float, exactly. out: 3 floats per point, as g->points. */
HK_API hk_Status hk_imported_groom_strands(const hk_ImportedGroom *g, const hk_SuperHelix *const *guides_now,
                                           int threads, float *out, hk_Error *err);

/* The imported-guides file (docs/file-formats.md, "Imported guides"): text, versioned,
 * doubles with 17 digits, at most HK_MAX_IMPORT_FILE_BYTES (save refuses a larger one
 * and leaves nothing at path); the captured strands in a .hair file beside it
 * (strands_file, relative to the guides file's folder). Written atomically. */
HK_API hk_Status hk_imported_groom_save(const char *path, const char *strands_file, const hk_ImportedGroom *g,
                                        hk_Error *err);
HK_API hk_Status hk_imported_groom_load(const char *path, hk_ImportedGroom *out, hk_Error *err);

/* ---- hairkit import: a groom and a head made a setup (import_run.c) ----------------- */

typedef struct hk_ImportRunDef {
    const char *hair;        /* any format hk_hair_read reads */
    hk_HairFormat format;    /* HK_HAIR_FORMAT_AUTO: from the name, else the content */
    double scale;            /* the hair's units to metres (default 1) */
    hk_Axis up;              /* the hair's up axis (default +y) */
    const char *head;        /* OBJ or PLY (may be NULL: no head, no collider) */
    double head_scale;       /* default 1 */
    hk_Axis head_up;         /* default +y */
    const char *hairstyle;   /* NULL: DIR/hairstyle.txt gets the defaults (40 um radius,
                                3 GPa, Poisson 0.48, 1300 kg/m^3, 9.81 m/s^2) */
    const char *dir;         /* made if missing */
    double collider_volume;  /* the head field's envelope (m; default 0) */
    double collider_penalty; /* its penalty stiffness (default 10, as the example heads') */
    hk_GroomImportDef groom; /* guides, elements (groom.fit.elements), threads; the
                                material comes from the hairstyle */
} hk_ImportRunDef;

HK_API hk_ImportRunDef hk_default_import_run_def(void);

typedef struct hk_ImportRunReport {
    hk_GroomImportReport groom;
    long points; /* of the groom */
    int head_triangles;
    int field_size[3]; /* nodes of the head's field */
    double seconds_read, seconds_field, seconds_write, seconds;
} hk_ImportRunReport;

/* Reads the groom and the head, scales and turns them to metres and y up, builds the
 * head's signed distance field (the collider), imports the groom (hk_groom_import) and
 * writes DIR/setup.txt, DIR/hairstyle.txt, DIR/head.obj (the head as transformed),
 * DIR/guides.txt and DIR/strands.hair (docs/capture.md, "Importing a groom"). report
 * may be NULL. */
HK_API hk_Status hk_import_run(const hk_ImportRunDef *def, hk_ImportRunReport *report, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_CAPTURE_H */
