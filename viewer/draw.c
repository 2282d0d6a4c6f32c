/* One frame of the viewer: the light's maps when they are stale, the head (Lambert),
 * the hair (Kajiya-Kay or Marschner, line strips of sub-pixel opacity blended over it). */
#include <stdio.h>

#include "viewer/gl_program.h"
#include "viewer/viewer_internal.h"

int hk_viewer_load_programs(hk_Viewer *v)
{
    const char *const *s = v->in->shader;
    GLuint head = hk_gl_program(s[HK_VIEW_HEAD_VERT], "head.vert", s[HK_VIEW_HEAD_FRAG], "head.frag");
    GLuint hair = head ? hk_gl_program(s[HK_VIEW_HAIR_VERT], "hair.vert", s[HK_VIEW_HAIR_FRAG], "hair.frag") : 0;
    if (!hair) {
        if (head) glDeleteProgram(head);
        return 0;
    }
    if (v->head_program) glDeleteProgram(v->head_program);
    if (v->hair_program) glDeleteProgram(v->hair_program);
    v->head_program = head;
    v->hair_program = hair;
    /* the outlines' program is the built-in one only */
    if (!v->line_program) v->line_program = hk_gl_program(NULL, "line.vert", NULL, "line.frag");
    return v->line_program != 0;
}

static void common_uniforms(const hk_Viewer *v, GLuint p, const hk_OrbitFrame *f, hk_Vec3 light)
{
    const hk_RenderDef *r = &v->in->render;
    hk_gl_uniform_mat4(p, "ViewMatrix", f->view.m);
    hk_gl_uniform_mat4(p, "ProjectionMatrix", f->projection.m);
    hk_gl_uniform3f(p, "LightDirection", light.x, light.y, light.z);
    hk_gl_uniform3f(p, "EyePosition", f->origin.x, f->origin.y, f->origin.z);
    hk_gl_uniform1f(p, "Ambient", r->ambient_intensity);
    hk_gl_uniform1i(p, "Shadows", v->shadows);
    hk_gl_uniform1f(p, "ScatterFloor", r->scatter_floor);
    hk_gl_light_maps_bind(&v->maps, p);
}

void hk_viewer_draw(hk_Viewer *v)
{
    const hk_RenderDef *r = &v->in->render;
    const hk_Vec3 light = hk_view_direction(v->light_azimuth, v->light_elevation);
    if (v->maps_stale && v->shadows) {
        const double layer = r->layer_size > 0.0 ? r->layer_size : 0.002;
        hk_gl_light_maps_draw(&v->maps, &v->hair, &v->head, light, v->centre, v->radius, v->thickness, layer,
                              v->guides_only);
        v->maps_stale = 0;
    }
    hk_gl_target_begin(&v->target, r->background_top, r->background_bottom);
    const hk_OrbitFrame f = hk_orbit_frame(&v->orbit, v->target.width, v->target.height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    if (v->show_head && v->head.indices) {
        glUseProgram(v->head_program);
        common_uniforms(v, v->head_program, &f, light);
        hk_gl_uniform3f(v->head_program, "SkinColor", r->skin.x, r->skin.y, r->skin.z);
        hk_gl_head_draw(&v->head);
    }
    /* The wick (the scalp mesh the guides grow from, Lansink 2010 §4.1.3) as a green
     * wireframe, lit as the head, unshadowed. */
    if (v->show_wick && v->wick.indices) {
        glUseProgram(v->head_program);
        common_uniforms(v, v->head_program, &f, light);
        hk_gl_uniform1i(v->head_program, "Shadows", 0);
        hk_gl_uniform3f(v->head_program, "SkinColor", 0.05, 0.6, 0.1);
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_POLYGON_OFFSET_LINE);
        glPolygonOffset(-1.0f, -1.0f);
        hk_gl_head_draw(&v->wick);
        glDisable(GL_POLYGON_OFFSET_LINE);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    }
    if (v->show_shapes && v->shapes.vertices) {
        glUseProgram(v->line_program);
        hk_gl_uniform_mat4(v->line_program, "ViewMatrix", f.view.m);
        hk_gl_uniform_mat4(v->line_program, "ProjectionMatrix", f.projection.m);
        hk_gl_uniform3f(v->line_program, "LineColor", 0.0, 0.45, 0.9);
        hk_gl_lines_draw(&v->shapes);
    }
    /* The hair: tested against the head's depth, not written (each strand a fraction of
     * a pixel, blended over what is behind it). */
    glUseProgram(v->hair_program);
    common_uniforms(v, v->hair_program, &f, light);
    const hk_Visuality *c = &v->colours;
    hk_gl_uniform3f(v->hair_program, "AColor", c->ambient.x, c->ambient.y, c->ambient.z);
    hk_gl_uniform3f(v->hair_program, "DColor", c->diffuse.x, c->diffuse.y, c->diffuse.z);
    hk_gl_uniform3f(v->hair_program, "SColor", c->specular.x, c->specular.y, c->specular.z);
    hk_gl_uniform1f(v->hair_program, "Glossiness", c->glossiness);
    hk_gl_uniform1i(v->hair_program, "Shading", v->shading);
    hk_gl_uniform1f(v->hair_program, "Focal", f.focal);
    hk_gl_uniform1f(v->hair_program, "Thickness", v->thickness);
    hk_gl_uniform1f(v->hair_program, "Opacity", 1.0);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    hk_gl_hair_draw(&v->hair, v->guides_only);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    if (v->show_overlay) hk_gl_overlay_draw(&v->overlay, v->overlay_text, v->target.width, v->target.height);
    hk_gl_target_end(&v->target);
}

int hk_viewer_screenshot(hk_Viewer *v, const char *path)
{
    hk_Canvas picture = {0, 0, NULL};
    hk_Error err;
    if (!hk_gl_target_read(&v->target, &picture)) {
        fprintf(stderr, "hairkit view: out of memory for the screenshot\n");
        return 0;
    }
    const hk_Status st = hk_render_write_png(&picture, path, &err);
    hk_canvas_free(&picture);
    if (st != HK_OK) fprintf(stderr, "hairkit view: %s\n", err.message);
    return st == HK_OK;
}
