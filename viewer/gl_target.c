/* The picture the viewer draws into (gl_target.h). */
#include <stdlib.h>
#include <string.h>

#include "viewer/gl_program.h"
#include "viewer/gl_target.h"

static void storage(GLuint rb, int samples, GLenum format, int w, int h)
{
    glBindRenderbuffer(GL_RENDERBUFFER, rb);
    if (samples > 0)
        glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, format, w, h);
    else
        glRenderbufferStorage(GL_RENDERBUFFER, format, w, h);
}

int hk_gl_target_create(hk_GlTarget *t, int width, int height, int samples)
{
    memset(t, 0, sizeof *t);
    GLint most = 0;
    glGetIntegerv(GL_MAX_SAMPLES, &most);
    t->width = width, t->height = height, t->samples = samples < most ? samples : most;
    glGenRenderbuffers(1, &t->color_rb);
    glGenRenderbuffers(1, &t->depth_rb);
    storage(t->color_rb, t->samples, GL_RGBA16F, width, height);
    storage(t->depth_rb, t->samples, GL_DEPTH_COMPONENT24, width, height);
    glGenFramebuffers(1, &t->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth_rb);
    const GLenum ok = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glGenTextures(1, &t->resolve_tex);
    glBindTexture(GL_TEXTURE_2D, t->resolve_tex);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA16F, width, height, 0, GL_RGBA, GL_FLOAT, NULL);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glGenFramebuffers(1, &t->resolve_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, t->resolve_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->resolve_tex, 0);
    const GLenum ok2 = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    t->background_program = hk_gl_program(NULL, "screen.vert", NULL, "background.frag");
    t->present_program = hk_gl_program(NULL, "screen.vert", NULL, "present.frag");
    glGenVertexArrays(1, &t->empty_vao);
    return ok == GL_FRAMEBUFFER_COMPLETE && ok2 == GL_FRAMEBUFFER_COMPLETE && t->background_program &&
           t->present_program;
}

static void fullscreen(const hk_GlTarget *t)
{
    glBindVertexArray(t->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
}

void hk_gl_target_begin(hk_GlTarget *t, hk_Vec3 top, hk_Vec3 bottom)
{
    glBindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    glViewport(0, 0, t->width, t->height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(t->background_program);
    hk_gl_uniform3f(t->background_program, "Top", top.x, top.y, top.z);
    hk_gl_uniform3f(t->background_program, "Bottom", bottom.x, bottom.y, bottom.z);
    hk_gl_uniform1f(t->background_program, "Height", t->height);
    fullscreen(t);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
}

void hk_gl_target_end(hk_GlTarget *t)
{
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, t->resolve_fbo);
    glBlitFramebuffer(0, 0, t->width, t->height, 0, 0, t->width, t->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

void hk_gl_target_present(const hk_GlTarget *t, int window_width, int window_height)
{
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, window_width, window_height);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glUseProgram(t->present_program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, t->resolve_tex);
    hk_gl_uniform1i(t->present_program, "Picture", 0);
    fullscreen(t);
}

int hk_gl_target_read(const hk_GlTarget *t, hk_Canvas *out)
{
    const size_t w = (size_t)t->width, h = (size_t)t->height;
    hk_Error err;
    if (hk_canvas_alloc(t->width, t->height, hk_v3(0, 0, 0), out, &err) != HK_OK) return 0;
    float *rows = malloc(3 * w * h * sizeof *rows);
    if (!rows) {
        hk_canvas_free(out);
        return 0;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, t->resolve_fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, t->width, t->height, GL_RGB, GL_FLOAT, rows);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    /* OpenGL's rows start at the bottom, the canvas's at the top. */
    for (size_t y = 0; y < h; y++) memcpy(out->rgb + 3 * w * y, rows + 3 * w * (h - 1 - y), 3 * w * sizeof *rows);
    free(rows);
    return 1;
}

void hk_gl_target_destroy(hk_GlTarget *t)
{
    const GLuint fbo[2] = {t->fbo, t->resolve_fbo}, rb[2] = {t->color_rb, t->depth_rb};
    glDeleteFramebuffers(2, fbo);
    glDeleteRenderbuffers(2, rb);
    if (t->resolve_tex) glDeleteTextures(1, &t->resolve_tex);
    if (t->background_program) glDeleteProgram(t->background_program);
    if (t->present_program) glDeleteProgram(t->present_program);
    if (t->empty_vao) glDeleteVertexArrays(1, &t->empty_vao);
    memset(t, 0, sizeof *t);
}
