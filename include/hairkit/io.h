/* Input files of the thesis framework (thesis 004 §4.2.1 and Appendix B).
 *
 * Every file is text: one `Key value...` per line, `#` starts a comment, keys match
 * without regard to case, values are separated by blanks, a value with blanks is
 * written in double quotes. All values are SI (metres, pascals, kg/m^3, m/s^2) except
 * HairDensity, which is hairs per square centimetre of wick surface. Every error
 * message names the file and the line: "hairstyle.txt:14: Young must be > 0, got -3". */
#ifndef HAIRKIT_IO_H
#define HAIRKIT_IO_H

#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits that keep absurd input from turning into absurd allocations or run times. */
#define HK_MAX_INPUT_FILE_BYTES ((long)16 << 20) /* 16 MiB for any text input file */
#define HK_MAX_ELEMENTS 1000                     /* Super-Helix elements per strand */
#define HK_MAX_SAMPLES_PER_STRAND 1000000        /* L / VisualityStep, L / CollisionStep */
#define HK_MAX_SHAPES 10000                      /* collision shapes in one file */

/* Hairstyle Info (thesis Appendix B, "Hairstyle Info"). */
typedef struct hk_Hairstyle {
    double visuality_step; /* VisualityStep: spacing of output vertices along s (m) */
    double collision_step; /* CollisionStep: spacing of collision samples along s (m) */
    int max_iter;          /* MaxIter: Rosenbrock stages */
    double epsilon;        /* Epsilon: Rosenbrock relative energy decrease per stage */
    int element_count;     /* N, the number of values of HairLengths */
    double *element_lengths; /* HairLengths: l_Q for Q = 1..N (m), owned */
    double hair_density;   /* HairDensity: hairs per cm^2 of wick surface */
    double radius1;        /* HairRadius1: semi-axis a of the section along n1 (m) */
    double radius2;        /* HairRadius2: semi-axis b of the section along n2 (m) */
    double helix_radius;   /* HelixRadius r_h (m); 0 means straight hair */
    double helix_step;     /* HelixStep Delta_h (m); negative gives a left-handed helix */
    double poisson;        /* Poisson: sigma in (-1, 0.5) */
    double young;          /* Young: E (Pa) */
    double density;        /* Density: rho (kg/m^3) */
    double gravity;        /* Gravity: |g| (m/s^2) */
    hk_Vec3 gravity_dir;   /* GravityDirection: unit vector, default (0, -1, 0) */
    /* Interpolation of the full head (thesis §4.1.4.3-4, paper 000 §4.1): */
    double clump;          /* ClumpFactor in [0, 1): spread of the tips around their nearest
                              guide (thesis: 0.25; 0 = tips on the guide) */
    double clump_profile;  /* ClumpProfile > 0: weights go from root to tip as t^profile
                              (1 = the thesis's linear blend; > 1 interpolates further
                              down before clumping, for straight hair) */
    int stray_hairs;       /* StrayHairs: the thesis's stray-hair behaviour (§4.1.4.4) */
    double max_tip_distance; /* MaxTipDistance (m): an interpolated strand does not blend
                              guides whose tips are this far or farther from its nearest
                              guide's tip, and fades them out from half of it (paper 000
                              Fig. 4d; docs/grooming.md); default 0.08, 0 = off */
    /* Dynamics (paper 000 eq. 5 and §4.2; docs/dynamics.md): */
    double internal_friction; /* InternalFriction gamma (kg m^3/s): visco-elastic dissipation
                                 of the curvatures, paper: 5e-11 .. 5e-10 */
    double air_drag;       /* AirDrag nu (kg/(m s)): viscous drag of the air at rest,
                              paper: 5e-6 (disciplined) .. 5e-5 (fuzzy hair) */
    double body_friction[2]; /* BodyFriction: friction coefficients against the body for a
                              hair sliding with its scales (root first, as when the body
                              sweeps from root to tip) and against them (tip first),
                              paper 000 §4.2 */
} hk_Hairstyle;

/* Defaults for every optional key (Density 1300, Gravity 9.81, Poisson 0.48, ...);
 * element_lengths is NULL and element_count 0. */
HK_API hk_Hairstyle hk_default_hairstyle(void);

/* Reads a hairstyle file. Required keys: HairLengths (alias HairLength), HairRadius1,
 * HairRadius2, HelixRadius, HelixStep, Young. The others are optional. On error `out`
 * is left empty (nothing to free) and err says file:line and what is wrong. */
HK_API hk_Status hk_hairstyle_load(const char *path, hk_Hairstyle *out, hk_Error *err);

/* Sum of the element lengths. */
HK_API double hk_hairstyle_length(const hk_Hairstyle *def);

/* Frees element_lengths and resets def to defaults. Safe on a default def. */
HK_API void hk_hairstyle_free(hk_Hairstyle *def);

/* Deep copy (element_lengths duplicated). */
HK_API hk_Status hk_hairstyle_copy(const hk_Hairstyle *src, hk_Hairstyle *dst, hk_Error *err);

/* Collision Info (thesis Appendix B): zero or more lines
 *   Sphere    Volume Penalty Cx Cy Cz Radius
 *   Ellipsoid Volume Penalty Cx Cy Cz A B C Ux Uy Uz Vx Vy Vz Wx Wy Wz   (alias Elipsoid)
 *   Cuboid    Volume Penalty Cx Cy Cz A B C Ux Uy Uz Vx Vy Vz Wx Wy Wz
 * Axes are normalised; they must be mutually orthogonal within 1e-3. On success
 * *shapes is an array of *count shapes to be released with hk_free (NULL when the
 * file lists none). */
HK_API hk_Status hk_collision_load(const char *path, hk_Shape **shapes, int *count, hk_Error *err);

/* Visuality Info (thesis Appendix B): colours of the Kajiya-Kay hair shader. */
typedef struct hk_Visuality {
    hk_Vec3 ambient;    /* AmbientColor: RGB in [0, 1] (values above 1 allowed: brighter) */
    hk_Vec3 diffuse;    /* DiffuseColor */
    hk_Vec3 specular;   /* SpecularColor */
    double glossiness;  /* Glossiness: Kajiya-Kay specular exponent p > 0 */
} hk_Visuality;

/* Brown hair of the thesis's sample file. */
HK_API hk_Visuality hk_default_visuality(void);
HK_API hk_Status hk_visuality_load(const char *path, hk_Visuality *out, hk_Error *err);

/* Setup (thesis Appendix B): which files make up a scene. Paths are resolved against
 * the setup file's folder; keys that are absent give NULL. HeadVert, HeadFrag,
 * HairVert and HairFrag (the thesis's GLSL shaders) are accepted and ignored: hairkit
 * renders on the CPU. */
typedef struct hk_Setup {
    int load;          /* Load: read the hair from load_file instead of growing it */
    int save;          /* Save: write the grown hair to save_file */
    char *load_file;   /* LoadFile (alias LoadPath) */
    char *save_file;   /* SaveFile (alias SavePath) */
    char *hairstyle;   /* HairstyleInfo */
    char *collision;   /* CollisionInfo */
    char *visuality;   /* VisualityInfo */
    char *head_model;  /* HeadModel: OBJ of the head */
    char *wick_model;  /* WickModel (alias HairModel): OBJ of the scalp the hair grows from */
} hk_Setup;

/* Reads a setup file. Growing hair (Load false) needs HairstyleInfo and WickModel;
 * Load true needs LoadFile, Save true SaveFile. Every file the setup names for reading
 * must exist (checked here, so that the message can name the setup file's line). */
HK_API hk_Status hk_setup_load(const char *path, hk_Setup *out, hk_Error *err);
HK_API void hk_setup_free(hk_Setup *def);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_IO_H */
