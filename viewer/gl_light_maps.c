/* The light's maps (gl_light_maps.h). */
#include <math.h>
#include <string.h>

#include "viewer/gl_light_maps.h"
#include "viewer/gl_program.h"

static GLuint texture(GLenum internal, GLenum format, GLenum type, int size, int compare)
{
    GLuint t;
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, (GLint)internal, size, size, 0, format, type, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    if (compare) {
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    return t;
}

static GLuint framebuffer(GLenum attachment, GLuint tex)
{
    GLuint f;
    glGenFramebuffers(1, &f);
    glBindFramebuffer(GL_FRAMEBUFFER, f);
    glFramebufferTexture2D(GL_FRAMEBUFFER, attachment, GL_TEXTURE_2D, tex, 0);
    if (attachment == GL_DEPTH_ATTACHMENT) {
        glDrawBuffer(GL_NONE);
        glReadBuffer(GL_NONE);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return f;
}

int hk_gl_light_maps_create(hk_GlLightMaps *m, int size)
{
    memset(m, 0, sizeof *m);
    m->size = size;
    m->depth_program = hk_gl_program(NULL, "light.vert", NULL, "depth.frag");
    m->opacity_program = hk_gl_program(NULL, "light.vert", NULL, "opacity.frag");
    if (!m->depth_program || !m->opacity_program) return 0;
    m->head_depth = texture(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, size, 1);
    m->hair_depth = texture(GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, size, 0);
    m->opacity = texture(GL_RGBA16F, GL_RGBA, GL_FLOAT, size, 0);
    m->fbo_head = framebuffer(GL_DEPTH_ATTACHMENT, m->head_depth);
    m->fbo_hair = framebuffer(GL_DEPTH_ATTACHMENT, m->hair_depth);
    m->fbo_opacity = framebuffer(GL_COLOR_ATTACHMENT0, m->opacity);
    return 1;
}

void hk_gl_light_maps_draw(hk_GlLightMaps *m, const hk_GlHair *hair, const hk_GlHead *head, hk_Vec3 light,
                           hk_Vec3 centre, double radius, double thickness, double layer_size, int guides_only)
{
    /* An orthographic view along the light: x, y across it, depth increasing away from
     * the light, all mapped to [0, 1] over the scene's sphere. */
    const hk_Vec3 forward = hk_v3_neg(light);
    hk_Vec3 side = hk_v3_cross(forward, hk_v3(0, 1, 0));
    if (hk_v3_norm(side) < 1e-9) side = hk_v3(1, 0, 0);
    const hk_Vec3 right = hk_v3_normalize(side), up = hk_v3_cross(right, forward);
    const double s = 0.5 / radius;
    m->matrix = hk_mat4_affine(centre, right, up, forward, hk_v3(s, s, s), hk_v3(0.5, 0.5, 0.5));
    double end = 0.0, depth = layer_size;
    for (int k = 0; k < 4; k++, depth *= 2.0) m->layer_end[k] = (float)((end += depth) * s);

    GLint viewport[4];
    glGetIntegerv(GL_VIEWPORT, viewport);
    glViewport(0, 0, m->size, m->size);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glUseProgram(m->depth_program);
    hk_gl_uniform_mat4(m->depth_program, "LightMatrix", m->matrix.m);
    glBindFramebuffer(GL_FRAMEBUFFER, m->fbo_head);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_POLYGON_OFFSET_FILL); /* slope-scaled bias: no acne where the light grazes */
    glPolygonOffset(2.0f, 4.0f);
    hk_gl_head_draw(head);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glBindFramebuffer(GL_FRAMEBUFFER, m->fbo_hair);
    glClear(GL_DEPTH_BUFFER_BIT);
    hk_gl_hair_draw(hair, guides_only);

    /* Every hair fragment adds its opacity, a hair's share of a texel, to the layers. */
    glBindFramebuffer(GL_FRAMEBUFFER, m->fbo_opacity);
    glClearColor(0, 0, 0, 0);
    glClear(GL_COLOR_BUFFER_BIT);
    glDisable(GL_DEPTH_TEST);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glUseProgram(m->opacity_program);
    hk_gl_uniform_mat4(m->opacity_program, "LightMatrix", m->matrix.m);
    hk_gl_uniform4f(m->opacity_program, "LayerEnd", m->layer_end[0], m->layer_end[1], m->layer_end[2], m->layer_end[3]);
    const double texel = 2.0 * radius / m->size;
    hk_gl_uniform1f(m->opacity_program, "Alpha", fmin(1.0, thickness / texel));
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, m->hair_depth);
    hk_gl_uniform1i(m->opacity_program, "HairDepth", 1);
    hk_gl_hair_draw(hair, guides_only);
    glActiveTexture(GL_TEXTURE0);

    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
}

void hk_gl_light_maps_bind(const hk_GlLightMaps *m, GLuint program)
{
    const GLuint tex[3] = {m->hair_depth, m->opacity, m->head_depth};
    for (int i = 0; i < 3; i++) {
        glActiveTexture(GL_TEXTURE1 + (GLenum)i);
        glBindTexture(GL_TEXTURE_2D, tex[i]);
    }
    glActiveTexture(GL_TEXTURE0);
    hk_gl_uniform1i(program, "HairDepth", 1);
    hk_gl_uniform1i(program, "OpacityMap", 2);
    hk_gl_uniform1i(program, "HeadDepth", 3);
    hk_gl_uniform_mat4(program, "LightMatrix", m->matrix.m);
    hk_gl_uniform4f(program, "LayerEnd", m->layer_end[0], m->layer_end[1], m->layer_end[2], m->layer_end[3]);
}

void hk_gl_light_maps_destroy(hk_GlLightMaps *m)
{
    const GLuint fbo[3] = {m->fbo_head, m->fbo_hair, m->fbo_opacity};
    const GLuint tex[3] = {m->head_depth, m->hair_depth, m->opacity};
    glDeleteFramebuffers(3, fbo);
    glDeleteTextures(3, tex);
    if (m->depth_program) glDeleteProgram(m->depth_program);
    if (m->opacity_program) glDeleteProgram(m->opacity_program);
    memset(m, 0, sizeof *m);
}
