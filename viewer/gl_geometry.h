/* The hair, the head and line outlines in vertex buffers. */
#ifndef HK_VIEWER_GL_GEOMETRY_H
#define HK_VIEWER_GL_GEOMETRY_H

#include <epoxy/gl.h>

#include "hairkit/hairfile.h"
#include "hairkit/mesh.h"
#include "hairkit/motion.h"

/* Every strand a line strip: positions (attribute 0) and tangents (attribute 1). */
typedef struct hk_GlHair {
    GLuint vao, vbo[2];
    GLint *first;
    GLsizei *count;
    GLsizei strands; /* drawn (two points or more) */
    GLsizei guides;  /* of them, among the hair's first guide_count strands */
    long points;
    uint32_t source_strands; /* the hair's layout, for updates */
    float *tangent;          /* scratch, 3 per point */
} hk_GlHair;

/* 0 when out of memory (message printed). guide_count: the hair's first strands that
 * are guides (0: none). */
int hk_gl_hair_create(hk_GlHair *g, const hk_HairFile *hair, int guide_count);
/* New positions for the same strands (made again when the layout changed); 0 when out
 * of memory. */
int hk_gl_hair_update(hk_GlHair *g, const hk_HairFile *hair, int guide_count);
/* guides_only: the guides (all strands when there are none). */
void hk_gl_hair_draw(const hk_GlHair *g, int guides_only);
void hk_gl_hair_destroy(hk_GlHair *g);

/* Triangles: positions (attribute 0) and normals (attribute 1). */
typedef struct hk_GlHead {
    GLuint vao, vbo[2], ebo;
    GLsizei indices;
    int vertices;
} hk_GlHead;

/* The mesh posed by `pose` (NULL: as it is). */
int hk_gl_head_create(hk_GlHead *g, const hk_Mesh *head);
int hk_gl_head_pose(hk_GlHead *g, const hk_Mesh *head, const hk_RigidState *pose);
void hk_gl_head_draw(const hk_GlHead *g);
void hk_gl_head_destroy(hk_GlHead *g);

/* Line segments (GL_LINES), positions only (attribute 0). */
typedef struct hk_GlLines {
    GLuint vao, vbo;
    GLsizei vertices;
} hk_GlLines;

/* xyz: 3 floats a vertex, two vertices a segment; replaces what g held. */
int hk_gl_lines_set(hk_GlLines *g, const float *xyz, int vertices);
void hk_gl_lines_draw(const hk_GlLines *g);
void hk_gl_lines_destroy(hk_GlLines *g);

#endif
