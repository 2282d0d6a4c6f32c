/* The hair and the head in vertex buffers. */
#ifndef HK_VIEWER_GL_GEOMETRY_H
#define HK_VIEWER_GL_GEOMETRY_H

#include <epoxy/gl.h>

#include "hairkit/hairfile.h"
#include "hairkit/mesh.h"

/* Every strand a line strip: positions (attribute 0) and tangents (attribute 1). */
typedef struct hk_GlHair {
    GLuint vao, vbo[2];
    GLint *first;
    GLsizei *count;
    GLsizei strands;
    long points;
} hk_GlHair;

/* 0 when out of memory (message printed). */
int hk_gl_hair_create(hk_GlHair *g, const hk_HairFile *hair);
void hk_gl_hair_draw(const hk_GlHair *g);
void hk_gl_hair_destroy(hk_GlHair *g);

/* Triangles: positions (attribute 0) and normals (attribute 1). */
typedef struct hk_GlHead {
    GLuint vao, vbo[2], ebo;
    GLsizei indices;
} hk_GlHead;

int hk_gl_head_create(hk_GlHead *g, const hk_Mesh *head);
void hk_gl_head_draw(const hk_GlHead *g);
void hk_gl_head_destroy(hk_GlHead *g);

#endif
