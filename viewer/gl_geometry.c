/* The hair and the head in vertex buffers (gl_geometry.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/gl_geometry.h"

static void attribute(GLuint vbo, GLuint index, const float *data, size_t floats)
{
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(floats * sizeof(float)), data, GL_STATIC_DRAW);
    glVertexAttribPointer(index, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(index);
}

int hk_gl_hair_create(hk_GlHair *g, const hk_HairFile *hair)
{
    memset(g, 0, sizeof *g);
    const size_t n = hair->point_count;
    float *tangent = malloc(3 * (n ? n : 1) * sizeof *tangent);
    g->first = malloc((hair->strand_count + 1) * sizeof *g->first);
    g->count = malloc((hair->strand_count + 1) * sizeof *g->count);
    if (!tangent || !g->first || !g->count) {
        free(tangent);
        hk_gl_hair_destroy(g);
        fprintf(stderr, "hairkit view: out of memory for %lu hair points\n", (unsigned long)n);
        return 0;
    }
    const float *p = hair->points;
    for (uint32_t s = 0; s < hair->strand_count; s++) {
        const uint32_t a = hair->first_point[s], b = hair->first_point[s + 1];
        if (b - a < 2) continue;
        g->first[g->strands] = (GLint)a;
        g->count[g->strands++] = (GLsizei)(b - a);
        /* The tangent from the neighbours (one-sided at the ends). */
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
    g->points = (long)n;
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(2, g->vbo);
    attribute(g->vbo[0], 0, p, 3 * n);
    attribute(g->vbo[1], 1, tangent, 3 * n);
    glBindVertexArray(0);
    free(tangent);
    return 1;
}

void hk_gl_hair_draw(const hk_GlHair *g)
{
    if (!g->strands) return;
    glBindVertexArray(g->vao);
    glMultiDrawArrays(GL_LINE_STRIP, g->first, g->count, g->strands);
    glBindVertexArray(0);
}

void hk_gl_hair_destroy(hk_GlHair *g)
{
    if (g->vao) glDeleteVertexArrays(1, &g->vao);
    if (g->vbo[0]) glDeleteBuffers(2, g->vbo);
    free(g->first);
    free(g->count);
    memset(g, 0, sizeof *g);
}

int hk_gl_head_create(hk_GlHead *g, const hk_Mesh *head)
{
    memset(g, 0, sizeof *g);
    if (!head || head->vertex_count <= 0 || head->triangle_count <= 0) return 1;
    const size_t n = (size_t)head->vertex_count, t = (size_t)head->triangle_count;
    float *pos = malloc(6 * n * sizeof *pos);
    GLuint *idx = malloc(3 * t * sizeof *idx);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        fprintf(stderr, "hairkit view: out of memory for the head\n");
        return 0;
    }
    float *nrm = pos + 3 * n;
    for (size_t i = 0; i < n; i++) {
        const hk_Vec3 q = head->positions[i];
        const hk_Vec3 m = head->normals ? head->normals[i] : hk_v3(0, 1, 0);
        pos[3 * i] = (float)q.x, pos[3 * i + 1] = (float)q.y, pos[3 * i + 2] = (float)q.z;
        nrm[3 * i] = (float)m.x, nrm[3 * i + 1] = (float)m.y, nrm[3 * i + 2] = (float)m.z;
    }
    for (size_t i = 0; i < 3 * t; i++) idx[i] = (GLuint)head->triangles[i];
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(2, g->vbo);
    attribute(g->vbo[0], 0, pos, 3 * n);
    attribute(g->vbo[1], 1, nrm, 3 * n);
    glGenBuffers(1, &g->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(3 * t * sizeof *idx), idx, GL_STATIC_DRAW);
    glBindVertexArray(0);
    g->indices = (GLsizei)(3 * t);
    free(pos);
    free(idx);
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
