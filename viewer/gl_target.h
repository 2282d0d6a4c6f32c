/* The picture the viewer draws into: linear RGB in half floats, multisampled, resolved
 * into a texture that is shown on the window (encoded to sRGB) or read back for a
 * screenshot, so that a screenshot has the size asked for whatever the window's. */
#ifndef HK_VIEWER_GL_TARGET_H
#define HK_VIEWER_GL_TARGET_H

#include <epoxy/gl.h>

#include "hairkit/canvas.h"
#include "hairkit/vecmath.h"

typedef struct hk_GlTarget {
    int width, height, samples;
    GLuint fbo, color_rb, depth_rb; /* multisampled (or not, samples 0) */
    GLuint resolve_fbo, resolve_tex;
    GLuint background_program, present_program, empty_vao;
} hk_GlTarget;

int hk_gl_target_create(hk_GlTarget *t, int width, int height, int samples);
/* Binds the target, fills it with the CPU renderer's background gradient, clears depth. */
void hk_gl_target_begin(hk_GlTarget *t, hk_Vec3 top, hk_Vec3 bottom);
/* Resolves the samples; then shows the picture on the window (framebuffer 0) of the
 * given size. */
void hk_gl_target_end(hk_GlTarget *t);
void hk_gl_target_present(const hk_GlTarget *t, int window_width, int window_height);
/* The resolved picture as a linear-RGB canvas (hk_canvas_free); 0 when out of memory. */
int hk_gl_target_read(const hk_GlTarget *t, hk_Canvas *out);
void hk_gl_target_destroy(hk_GlTarget *t);

#endif
