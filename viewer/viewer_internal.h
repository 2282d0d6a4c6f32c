/* The viewer's state, shared by its loop (viewer.c), its drawing (draw.c) and its input
 * (input.c). */
#ifndef HK_VIEWER_INTERNAL_H
#define HK_VIEWER_INTERNAL_H

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "viewer/gl_geometry.h"
#include "viewer/gl_light_maps.h"
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
    hk_GlHead head;
    hk_GlLightMaps maps;
    hk_GlTarget target;
    /* input */
    double mouse_x, mouse_y;
    int dragging;    /* 0 none, 1 orbit, 2 pan, 3 light */
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

#endif
