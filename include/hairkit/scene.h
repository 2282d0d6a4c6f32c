/* A scene: everything a setup file names (Lansink 2010, "Hair simulation and rendering",
 * Appendix B: the setup, hairstyle, collision and visuality files, the head and the wick),
 * loaded once for every job that starts from a setup file: growing or loading the hair,
 * rendering it, simulating it, benchmarks. */
#ifndef HAIRKIT_SCENE_H
#define HAIRKIT_SCENE_H

#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/groom.h"
#include "hairkit/hairfile.h"
#include "hairkit/io.h"
#include "hairkit/mesh.h"
#include "hairkit/render.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The parts of a scene to read (hk_scene_load): a job reads only what it uses, so that
 * a setup with Load true need not name a wick it does not grow from. */
typedef enum hk_ScenePart {
    HK_SCENE_HAIRSTYLE = 1 << 0, /* HairstyleInfo */
    HK_SCENE_COLLISION = 1 << 1, /* CollisionInfo (none when the setup names none) */
    HK_SCENE_VISUALITY = 1 << 2, /* VisualityInfo (the defaults when the setup names none) */
    HK_SCENE_HEAD = 1 << 3,      /* HeadModel, OBJ or PLY (an empty mesh when the setup names none) */
    HK_SCENE_WICK = 1 << 4,      /* WickModel */
    /* What hk_scene_hair needs: the grooming parts when the setup grows the hair (Load
     * false), none when it reads it (Load true). */
    HK_SCENE_HAIR = 1 << 5,
    /* What growing the hair reads, and what rendering it reads. */
    HK_SCENE_GROOMING = HK_SCENE_HAIRSTYLE | HK_SCENE_COLLISION | HK_SCENE_WICK,
    HK_SCENE_RENDERING = HK_SCENE_VISUALITY | HK_SCENE_HEAD,
    HK_SCENE_ALL = HK_SCENE_GROOMING | HK_SCENE_RENDERING
} hk_ScenePart;

/* A value: its arrays belong to it and are freed by hk_scene_free. A part not read
 * holds its defaults (hk_default_hairstyle, hk_default_visuality) or is empty. */
typedef struct hk_Scene {
    char *setup_path; /* as given to hk_scene_load */
    hk_Setup setup;
    unsigned parts; /* hk_ScenePart bits read (HK_SCENE_HAIR resolved) */
    hk_Hairstyle style;
    hk_CollisionSet collision; /* the collision file's shapes, in head space, then the
                                  HeadModel's field (2 mm grid) when the setup says
                                  HeadCollider; the set owns the fields of its meshes */
    hk_Visuality visuality;
    hk_Mesh head; /* vertex_count 0 when there is none */
    hk_Mesh wick;
} hk_Scene;

/* Reads the setup file and the parts of it asked for (hk_ScenePart bits; 0: the setup
 * alone), the small files first so that their errors come before any long work.
 * HairstyleInfo and WickModel must be named when asked for (the message names the
 * setup file); the others are optional. On error *out is empty (safe to free). */
HK_API hk_Status hk_scene_load(const char *setup_path, unsigned parts, hk_Scene *out, hk_Error *err);
/* Reads more parts of a loaded scene (those already read are kept). On error the
 * scene keeps what it had. */
HK_API hk_Status hk_scene_load_parts(hk_Scene *s, unsigned parts, hk_Error *err);
HK_API void hk_scene_free(hk_Scene *s);

/* What hk_scene_hair did. */
typedef struct hk_SceneHairReport {
    int grown; /* 1: grown from the hairstyle; 0: read from LoadFile */
    int guides, strands, points_per_strand;
    hk_GroomStats stats; /* of the growing */
} hk_SceneHairReport;

/* The scene's hair: read from LoadFile (Load true; any format, hk_hair_read) or grown from the hairstyle, the
 * collision shapes and the wick (loaded with HK_SCENE_GROOMING) with `options` (NULL:
 * hk_default_groom_def); then written to SaveFile when the setup says Save true
 * (Lansink 2010, §4.2.2). `hair` is filled (free with hk_hair_free; empty on error);
 * report may be NULL. */
HK_API hk_Status hk_scene_hair(const hk_Scene *s, const hk_GroomDef *options, hk_HairFile *hair,
                               hk_SceneHairReport *report, hk_Error *err);

/* Renders `hair` over the scene's head with its visuality's colours (hk_render; the
 * scene loaded with HK_SCENE_RENDERING). options NULL: hk_default_render_def. */
HK_API hk_Status hk_scene_render(const hk_Scene *s, const hk_HairFile *hair, const hk_RenderDef *options,
                                 hk_Canvas *out, hk_RenderStats *stats, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_SCENE_H */
