/* The hair, the head and line outlines in vertex buffers (gl_geometry.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/gl_geometry.h"

static void attribute(GLuint vbo, GLuint index, const float *data, size_t floats, GLenum usage)
{
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(floats * sizeof(float)), data, usage);
    glVertexAttribPointer(index, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(index);
}

/* The unit tangent at every point from its neighbours (one-sided at the ends). */
static void tangents(const hk_HairFile *hair, float *tangent)
{
    const float *p = hair->points;
    for (uint32_t s = 0; s < hair->strand_count; s++) {
        const uint32_t a = hair->first_point[s], b = hair->first_point[s + 1];
        for (uint32_t i = a; i < b; i++) {
            const uint32_t i0 = i > a ? i - 1 : i, i1 = i + 1 < b ? i + 1 : i;
            double t[3], len = 0.0;
            for (int c = 0; c < 3; c++) {
                t[c] = (double)p[3 * i1 + (uint32_t)c] - (double)p[3 * i0 + (uint32_t)c];
                len += t[c] * t[c];
            }
            len = len > 0.0 ? 1.0 / sqrt(len) : 0.0;
            for (int c = 0; c < 3; c++) tangent[3 * i + (uint32_t)c] = (float)(t[c] * len);
        }
    }
}

int hk_gl_hair_create(hk_GlHair *g, const hk_HairFile *hair, int guide_count)
{
    memset(g, 0, sizeof *g);
    const size_t n = hair->point_count;
    g->tangent = malloc(3 * (n ? n : 1) * sizeof *g->tangent);
    g->first = malloc((hair->strand_count + 1) * sizeof *g->first);
    g->count = malloc((hair->strand_count + 1) * sizeof *g->count);
    if (!g->tangent || !g->first || !g->count) {
        hk_gl_hair_destroy(g);
        fprintf(stderr, "hairkit view: out of memory for %lu hair points\n", (unsigned long)n);
        return 0;
    }
    for (uint32_t s = 0; s < hair->strand_count; s++) {
        const uint32_t a = hair->first_point[s], b = hair->first_point[s + 1];
        if (b - a < 2) continue;
        g->first[g->strands] = (GLint)a;
        g->count[g->strands++] = (GLsizei)(b - a);
        if ((long)s < (long)guide_count) g->guides = g->strands;
    }
    tangents(hair, g->tangent);
    g->points = (long)n;
    g->source_strands = hair->strand_count;
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(2, g->vbo);
    /* a live simulation writes them every step */
    attribute(g->vbo[0], 0, hair->points, 3 * n, GL_DYNAMIC_DRAW);
    attribute(g->vbo[1], 1, g->tangent, 3 * n, GL_DYNAMIC_DRAW);
    glBindVertexArray(0);
    return 1;
}

int hk_gl_hair_update(hk_GlHair *g, const hk_HairFile *hair, int guide_count)
{
    if (hair->strand_count != g->source_strands || (long)hair->point_count != g->points) {
        hk_gl_hair_destroy(g);
        return hk_gl_hair_create(g, hair, guide_count);
    }
    tangents(hair, g->tangent);
    const GLsizeiptr bytes = (GLsizeiptr)(3 * hair->point_count * sizeof(float));
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo[0]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, hair->points);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo[1]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, g->tangent);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return 1;
}

void hk_gl_hair_draw(const hk_GlHair *g, int guides_only)
{
    const GLsizei n = guides_only && g->guides > 0 ? g->guides : g->strands;
    if (!n) return;
    glBindVertexArray(g->vao);
    glMultiDrawArrays(GL_LINE_STRIP, g->first, g->count, n);
    glBindVertexArray(0);
}

void hk_gl_hair_destroy(hk_GlHair *g)
{
    if (g->vao) glDeleteVertexArrays(1, &g->vao);
    if (g->vbo[0]) glDeleteBuffers(2, g->vbo);
    free(g->first);
    free(g->count);
    free(g->tangent);
    memset(g, 0, sizeof *g);
}

/* Positions then normals of the mesh, posed (pose NULL: as they are). */
static float *posed_vertices(const hk_Mesh *head, const hk_RigidState *pose)
{
    const size_t n = (size_t)head->vertex_count;
    float *pos = malloc(6 * n * sizeof *pos);
    if (!pos) return NULL;
    float *nrm = pos + 3 * n;
    for (size_t i = 0; i < n; i++) {
        hk_Vec3 q = head->positions[i];
        hk_Vec3 m = head->normals ? head->normals[i] : hk_v3(0, 1, 0);
        if (pose) {
            hk_rigid_point(pose, head->positions[i], &q, NULL, NULL);
            m = hk_m3_mul_v3(&pose->rot, m);
        }
        pos[3 * i] = (float)q.x, pos[3 * i + 1] = (float)q.y, pos[3 * i + 2] = (float)q.z;
        nrm[3 * i] = (float)m.x, nrm[3 * i + 1] = (float)m.y, nrm[3 * i + 2] = (float)m.z;
    }
    return pos;
}

int hk_gl_head_create(hk_GlHead *g, const hk_Mesh *head)
{
    memset(g, 0, sizeof *g);
    if (!head || head->vertex_count <= 0 || head->triangle_count <= 0) return 1;
    const size_t n = (size_t)head->vertex_count, t = (size_t)head->triangle_count;
    float *pos = posed_vertices(head, NULL);
    GLuint *idx = malloc(3 * t * sizeof *idx);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        fprintf(stderr, "hairkit view: out of memory for the head\n");
        return 0;
    }
    for (size_t i = 0; i < 3 * t; i++) idx[i] = (GLuint)head->triangles[i];
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(2, g->vbo);
    attribute(g->vbo[0], 0, pos, 3 * n, GL_DYNAMIC_DRAW);
    attribute(g->vbo[1], 1, pos + 3 * n, 3 * n, GL_DYNAMIC_DRAW);
    glGenBuffers(1, &g->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(3 * t * sizeof *idx), idx, GL_STATIC_DRAW);
    glBindVertexArray(0);
    g->indices = (GLsizei)(3 * t);
    g->vertices = head->vertex_count;
    free(pos);
    free(idx);
    return 1;
}

int hk_gl_head_pose(hk_GlHead *g, const hk_Mesh *head, const hk_RigidState *pose)
{
    if (!g->indices || !head || head->vertex_count != g->vertices) return 1;
    float *pos = posed_vertices(head, pose);
    if (!pos) {
        fprintf(stderr, "hairkit view: out of memory for the head\n");
        return 0;
    }
    const size_t n = (size_t)head->vertex_count;
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo[0]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(3 * n * sizeof(float)), pos);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo[1]);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(3 * n * sizeof(float)), pos + 3 * n);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    free(pos);
    return 1;
}

void hk_gl_head_draw(const hk_GlHead *g)
{
    if (!g->indices) return;
    glBindVertexArray(g->vao);
    glDrawElements(GL_TRIANGLES, g->indices, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
}

void hk_gl_head_destroy(hk_GlHead *g)
{
    if (g->vao) glDeleteVertexArrays(1, &g->vao);
    if (g->vbo[0]) glDeleteBuffers(2, g->vbo);
    if (g->ebo) glDeleteBuffers(1, &g->ebo);
    memset(g, 0, sizeof *g);
}

int hk_gl_lines_set(hk_GlLines *g, const float *xyz, int vertices)
{
    if (!g->vao) {
        glGenVertexArrays(1, &g->vao);
        glGenBuffers(1, &g->vbo);
    }
    glBindVertexArray(g->vao);
    attribute(g->vbo, 0, xyz, 3 * (size_t)(vertices > 0 ? vertices : 0), GL_DYNAMIC_DRAW);
    glBindVertexArray(0);
    g->vertices = vertices;
    return 1;
}

void hk_gl_lines_draw(const hk_GlLines *g)
{
    if (g->vertices <= 0) return;
    glBindVertexArray(g->vao);
    glDrawArrays(GL_LINES, 0, g->vertices);
    glBindVertexArray(0);
}

void hk_gl_lines_destroy(hk_GlLines *g)
{
    if (g->vao) glDeleteVertexArrays(1, &g->vao);
    if (g->vbo) glDeleteBuffers(1, &g->vbo);
    memset(g, 0, sizeof *g);
}
