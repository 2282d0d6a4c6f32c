/* hairkit view: the thesis's interactive OpenGL viewer (Lansink 2010 §4.1.5-4.1.6,
 * docs/viewer.md). Built only with HK_VIEWER (GLFW and libepoxy); cli/cmd_view.c
 * parses the command line and loads the files, this draws them. */
#ifndef HK_VIEWER_H
#define HK_VIEWER_H

#include "hairkit/hairfile.h"
#include "hairkit/io.h"
#include "hairkit/live_sim.h"
#include "hairkit/mesh.h"
#include "hairkit/render.h"

/* The shaders a setup (HeadVert, HeadFrag, HairVert, HairFrag) or the command line may
 * replace; NULL: the default of assets/shaders (built into the program). */
enum { HK_VIEW_HEAD_VERT, HK_VIEW_HEAD_FRAG, HK_VIEW_HAIR_VERT, HK_VIEW_HAIR_FRAG, HK_VIEW_SHADER_COUNT };

typedef struct hk_ViewerInput {
    const hk_HairFile *hair;
    const hk_Mesh *head;    /* NULL or no vertices: none */
    hk_Visuality visuality; /* colours as the files give them (sRGB) */
    hk_RenderDef render;    /* size, view, light, shading, shadows, shadow map, thickness */
    const char *shader[HK_VIEW_SHADER_COUNT];
    int guide_count;                         /* the hair's first strands that are guides (0: none known) */
    int guides_only, show_wick, show_shapes; /* the toggles' first state */
    int overlay;                             /* the text overlay (key O) shown at first */
    /* Live dynamics (a setup's scene only): the scene (loaded with HK_SCENE_ALL) whose
     * guides are simulated (NULL: none), simulated from the start (`simulate`) or when
     * the key asks, with these options, under the head motion (NULL: still). */
    hk_Scene *scene;
    int simulate;
    hk_LiveSimDef live;
    const hk_HeadMotion *motion;
    double drag[2];         /* pixels: a drag of the head before the first step (headless tests) */
    int frames;             /* > 0: headless, draw this many frames, then stop */
    const char *screenshot; /* with frames: the last frame written here (PNG) */
    int quiet;
} hk_ViewerInput;

/* Opens the window and runs until it is closed (or `frames` are drawn); the exit
 * status of the command (HK_EXIT_OK, or 1 with a message on stderr). */
int hk_viewer_run(const hk_ViewerInput *in);

/* What a headless run measured (hk_viewer_run_measured: `hairkit bench view`). */
typedef struct hk_ViewerFigures {
    double first_seconds; /* the first frame: uploads and light maps (and the first step) */
    double frames_per_second;
    int frames; /* after the first */
    long strands, points;
    double simulated;   /* seconds of hair time */
    char renderer[128]; /* GL_RENDERER */
} hk_ViewerFigures;

int hk_viewer_run_measured(const hk_ViewerInput *in, hk_ViewerFigures *figures);

#endif
