/* The viewer's state, shared by its loop (viewer.c), its drawing (draw.c) and its input
 * (input.c). */
#ifndef HK_VIEWER_INTERNAL_H
#define HK_VIEWER_INTERNAL_H

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "viewer/gl_geometry.h"
#include "viewer/gl_light_maps.h"
#include "viewer/gl_overlay.h"
#include "viewer/gl_target.h"
#include "viewer/orbit.h"
#include "viewer/viewer.h"

typedef struct hk_Viewer {
    const hk_ViewerInput *in;
    GLFWwindow *window;
    hk_Orbit orbit, home; /* home: the fitted camera, restored by R */
    double light_azimuth, light_elevation;
    int shadows, shading, show_head;
    int maps_stale; /* the light's maps must be drawn again */
    hk_Vec3 centre; /* the scene's bounding sphere */
    double radius, thickness;
    hk_Visuality colours; /* linear */
    GLuint head_program, hair_program;
    hk_GlHair hair;
    hk_GlHead head, wick;
    hk_GlLines shapes; /* the collision shapes' outlines (shapes.c) */
    GLuint line_program;
    hk_ViewerFigures *figures;   /* NULL: not asked for */
    hk_HairFile own_hair;        /* the hair grown again after the hairstyle changed */
    const hk_HairFile *hair_now; /* what the hair buffers hold: the input's or the live hair */
    int guide_count;
    int hair_dirty, head_dirty; /* to upload before the next frame */
    int guides_only, show_wick, show_shapes;
    /* live dynamics (live.c) */
    hk_LiveSim *live;
    hk_HeadMotion *follow; /* the input's motion moved by the drag */
    hk_Vec3 drag;          /* where the drag takes the head (world offset, m) */
    int playing, step_once;
    double play_wall;    /* wall time when playing last started (interactive) */
    long play_steps;     /* steps done then */
    double step_seconds; /* wall time of the last step and regrowth */
    int roomy;           /* the scene's sphere made larger for motion */
    /* files watched for changes (watch.c) */
    double watch_wall;
    long long watched[HK_VIEW_SHADER_COUNT + 1];
    hk_GlLightMaps maps;
    hk_GlTarget target;
    /* the text overlay (gl_overlay.h): what it says, refreshed before each frame */
    hk_GlOverlay overlay;
    int show_overlay;
    double fps; /* frames per second measured last (0: not yet) */
    char overlay_text[256];
    /* input */
    double mouse_x, mouse_y;
    int dragging;    /* 0 none, 1 orbit, 2 pan, 3 light, 4 the head */
    int screenshots; /* written with the P key */
} hk_Viewer;

/* Draws one frame into the target (draw.c). */
void hk_viewer_draw(hk_Viewer *v);
/* (Re)compiles the head and hair programs; 0 on failure, the old ones kept (draw.c). */
int hk_viewer_load_programs(hk_Viewer *v);
/* Writes the target's picture as a PNG; 0 on failure, with a message (draw.c). */
int hk_viewer_screenshot(hk_Viewer *v, const char *path);
/* GLFW's callbacks (input.c). */
void hk_viewer_input_install(hk_Viewer *v);

/* Live dynamics (live.c). Starts the simulation (0 with a message when the input has no
 * scene to simulate, or it fails). */
int hk_viewer_live_start(hk_Viewer *v);
/* The steps due at wall time `now` (one a frame when headless), the buffers updated;
 * 0 on failure (message printed). */
int hk_viewer_live_update(hk_Viewer *v, double now);
/* Back to time 0: the guides solved and settled again, the head at rest. */
int hk_viewer_live_reset(hk_Viewer *v);
/* A new simulation from the scene as it is now (its hairstyle read again); the old one
 * kept, and 0, when it fails. */
int hk_viewer_live_restart(hk_Viewer *v);
/* Play or pause (keeps the simulated time running from where it is). */
void hk_viewer_live_play(hk_Viewer *v, int playing, double now);
/* The head dragged by (dx, dy) pixels across the view. */
void hk_viewer_live_drag(hk_Viewer *v, double dx, double dy, int height);
void hk_viewer_live_free(hk_Viewer *v);
/* The scene's sphere made larger for the hair in motion (once). */
void hk_viewer_live_room(hk_Viewer *v);

/* Shader and hairstyle files changed on disk, polled once a second (watch.c): shaders
 * compiled again, the hairstyle solved again. 0 on a failure that must stop a headless
 * run. */
int hk_viewer_watch(hk_Viewer *v, double now);
void hk_viewer_watch_start(hk_Viewer *v, double now);

/* The collision shapes' outlines, posed (NULL: at rest; shapes.c). */
int hk_viewer_shapes_update(hk_Viewer *v, const hk_RigidState *pose);

/* The hair to show from the next frame on (viewer.c). */
int hk_viewer_set_hair(hk_Viewer *v, const hk_HairFile *hair, int guide_count);

#endif
