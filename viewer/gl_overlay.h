/* Text drawn in the picture (issue 16's overlay: frames per second, counts, simulated
 * time): a built-in 5x7 bitmap font in one texture, one quad a glyph over a shaded
 * backing, in the top left corner. */
#ifndef HK_VIEWER_GL_OVERLAY_H
#define HK_VIEWER_GL_OVERLAY_H

#include <epoxy/gl.h>

typedef struct hk_GlOverlay {
    GLuint program, font, vao, vbo;
    float *corners; /* the quads of the text drawn last (4 floats a vertex, 6 a quad) */
    size_t capacity;
} hk_GlOverlay;

/* 0 when the program or the texture cannot be made. */
int hk_gl_overlay_create(hk_GlOverlay *o);
/* Draws `text` (lines separated by '\n', printable ASCII; other bytes as '?') into the
 * bound framebuffer of width x height pixels, over what is there. Each glyph is a cell
 * of 6 x 8 pixels times the scale (1, 2 from 600 pixels high, ...). */
void hk_gl_overlay_draw(hk_GlOverlay *o, const char *text, int width, int height);
void hk_gl_overlay_destroy(hk_GlOverlay *o);

#endif
