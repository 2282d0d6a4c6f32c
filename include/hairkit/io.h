/* Input files of the thesis framework (Lansink 2010 §4.2.1 and Appendix B).
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
#include "hairkit/dynamics.h"
#include "hairkit/export.h"
#include "hairkit/groom.h"
#include "hairkit/rod.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Limits that keep absurd input from turning into absurd allocations or run times
 * (HK_MAX_ELEMENTS and HK_MAX_SAMPLES_PER_STRAND: hairkit/rod.h). */
#define HK_MAX_INPUT_FILE_BYTES ((long)16 << 20) /* 16 MiB for any text input file */
#define HK_MAX_SHAPES           10000            /* collision shapes in one file */

/* Hairstyle Info (thesis Appendix B, "Hairstyle Info"): the parameters of the three
 * parts of hairkit that use them. */
typedef struct hk_Hairstyle {
    /* The strand, its material and its statics (hairkit/rod.h): HairLengths (the
     * element lengths, owned by the hairstyle), HairRadius1, HairRadius2, HelixRadius,
     * HelixStep, Poisson, Young, Density, Gravity, GravityDirection, VisualityStep,
     * CollisionStep, MaxIter, Epsilon */
    hk_StrandDef strand;
    /* The interpolation of the full head (hairkit/groom.h): HairDensity, ClumpFactor,
     * ClumpProfile, StrayHairs, MaxTipDistance */
    hk_InterpolationDef interpolation;
    /* The dynamics (hairkit/dynamics.h): InternalFriction, AirDrag and BodyFriction
     * (friction_with, friction_against); the other fields hk_default_dynamics_def's */
    hk_DynamicsDef dynamics;
} hk_Hairstyle;

/* Defaults for every optional key (hk_default_strand_def, hk_default_interpolation_def,
 * hk_default_dynamics_def); strand.element_lengths is NULL and element_count 0. */
HK_API hk_Hairstyle hk_default_hairstyle(void);

/* Reads a hairstyle file. Required keys: HairLengths (alias HairLength), HairRadius1,
 * HairRadius2, HelixRadius, HelixStep, Young. The others are optional. On error `out`
 * is left empty (nothing to free) and err says file:line and what is wrong. */
HK_API hk_Status hk_hairstyle_load(const char *path, hk_Hairstyle *out, hk_Error *err);

/* Frees strand.element_lengths and resets def to defaults. Safe on a default def. */
HK_API void hk_hairstyle_free(hk_Hairstyle *def);

/* Deep copy (element_lengths duplicated). */
HK_API hk_Status hk_hairstyle_copy(const hk_Hairstyle *src, hk_Hairstyle *dst, hk_Error *err);

/* Collision Info (thesis Appendix B): zero or more lines
 *   Sphere    Volume Penalty Cx Cy Cz Radius
 *   Ellipsoid Volume Penalty Cx Cy Cz A B C Ux Uy Uz Vx Vy Vz Wx Wy Wz   (alias Elipsoid)
 *   Cuboid    Volume Penalty Cx Cy Cz A B C Ux Uy Uz Vx Vy Vz Wx Wy Wz
 *   Mesh      Volume Penalty PATH [Scale [Up]]                       (a hairkit addition)
 * each with an optional last word Body or Styling. Axes are normalised; they must be
 * mutually orthogonal within 1e-3. A Mesh line names an OBJ or PLY file relative to the
 * collision file; the mesh, multiplied by Scale (default 1) and turned so that its Up
 * axis (default +y) is +y, becomes a signed distance field (hk_collision_add_mesh, the
 * default 2 mm grid), built after every line has been read. On success *out holds the
 * shapes in file order (free with hk_collision_free); on error it is empty and err says
 * file:line and what is wrong. */
HK_API hk_Status hk_collision_load(const char *path, hk_CollisionSet *out, hk_Error *err);

/* Visuality Info (thesis Appendix B): colours of the Kajiya-Kay hair shader. */
typedef struct hk_Visuality {
    hk_Vec3 ambient;   /* AmbientColor: RGB in [0, 1] (values above 1 allowed: brighter) */
    hk_Vec3 diffuse;   /* DiffuseColor */
    hk_Vec3 specular;  /* SpecularColor */
    double glossiness; /* Glossiness: Kajiya-Kay specular exponent p > 0 */
} hk_Visuality;

/* Brown hair of the thesis's sample file. */
HK_API hk_Visuality hk_default_visuality(void);
HK_API hk_Status hk_visuality_load(const char *path, hk_Visuality *out, hk_Error *err);

/* Setup (thesis Appendix B): which files make up a scene. Paths are resolved against
 * the setup file's folder; keys that are absent give NULL. HeadVert, HeadFrag,
 * HairVert and HairFrag name the thesis's GLSL shaders: `hairkit view` compiles them
 * instead of its own (docs/viewer.md); the CPU renderer does not use them. */
typedef struct hk_Setup {
    int load;          /* Load: read the hair from load_file instead of growing it */
    int save;          /* Save: write the grown hair to save_file */
    char *load_file;   /* LoadFile (alias LoadPath): hair in any format hk_hair_read reads */
    char *save_file;   /* SaveFile (alias SavePath) */
    char *hairstyle;   /* HairstyleInfo */
    char *collision;   /* CollisionInfo */
    char *visuality;   /* VisualityInfo */
    char *head_model;  /* HeadModel: OBJ or PLY of the head (hk_mesh_load) */
    char *wick_model;  /* WickModel (alias HairModel): OBJ or PLY of the scalp the hair grows from */
    char *import_file; /* ImportFile: guides made by `hairkit import` (hairkit/capture.h),
                          which `simulate` moves instead of growing guides from the wick */
    int head_collider; /* HeadCollider Volume Penalty given: the HeadModel's signed
                          distance field is a body shape besides CollisionInfo's */
    double head_collider_volume, head_collider_penalty;
    char *head_vert, *head_frag; /* HeadVert, HeadFrag: GLSL of the viewer's head */
    char *hair_vert, *hair_frag; /* HairVert, HairFrag: GLSL of the viewer's hair */
} hk_Setup;

/* Reads a setup file. Growing hair (Load false, no ImportFile) needs HairstyleInfo and WickModel;
 * Load true needs LoadFile, Save true SaveFile. Every file the setup names for reading
 * must exist (checked here, so that the message can name the setup file's line). */
HK_API hk_Status hk_setup_load(const char *path, hk_Setup *out, hk_Error *err);
HK_API void hk_setup_free(hk_Setup *def);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_IO_H */
