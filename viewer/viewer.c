/* hairkit view: the window, the scene's buffers and the frame loop (viewer.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "viewer/viewer_internal.h"

static char glfw_message[512];

static void on_glfw_error(int code, const char *message)
{
    (void)code;
    snprintf(glfw_message, sizeof glfw_message, "%s", message);
}

static double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

static hk_Vec3 linear(hk_Vec3 c) { return hk_v3(srgb_to_linear(c.x), srgb_to_linear(c.y), srgb_to_linear(c.z)); }

static void grow(hk_Vec3 *lo, hk_Vec3 *hi, hk_Vec3 p)
{
    lo->x = fmin(lo->x, p.x), lo->y = fmin(lo->y, p.y), lo->z = fmin(lo->z, p.z);
    hi->x = fmax(hi->x, p.x), hi->y = fmax(hi->y, p.y), hi->z = fmax(hi->z, p.z);
}

/* The bounding sphere of hair and head, the fitted camera and the colours. */
static int setup_scene(hk_Viewer *v)
{
    const hk_ViewerInput *in = v->in;
    const hk_RenderDef *r = &in->render;
    hk_Vec3 lo = hk_v3(1e300, 1e300, 1e300), hi = hk_v3(-1e300, -1e300, -1e300);
    const hk_HairFile *hair = v->hair_now;
    const float *pts = hair->points;
    for (uint32_t i = 0; i < hair->point_count; i++) grow(&lo, &hi, hk_v3(pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]));
    const int head_n = in->head ? in->head->vertex_count : 0;
    for (int i = 0; i < head_n; i++) grow(&lo, &hi, in->head->positions[i]);
    if (!(lo.x <= hi.x)) lo = hi = hk_v3(0, 0, 0);
    v->centre = hk_v3_scale(hk_v3_add(lo, hi), 0.5);
    v->radius = fmax(0.5 * hk_v3_norm(hk_v3_sub(hi, lo)), 1e-3);
    hk_Error err;
    hk_Vec3 target;
    double distance;
    if (hk_render_fit_camera(hair, head_n ? in->head : NULL, r, &target, &distance, &err) != HK_OK) {
        fprintf(stderr, "hairkit view: %s\n", err.message);
        return 0;
    }
    v->orbit.azimuth = r->azimuth_deg, v->orbit.elevation = r->elevation_deg;
    v->orbit.distance = distance, v->orbit.target = target;
    v->orbit.fov = r->fov_deg, v->orbit.radius = v->radius;
    v->home = v->orbit;
    if (v->live) hk_viewer_live_room(v);
    v->light_azimuth = r->light_azimuth_deg, v->light_elevation = r->light_elevation_deg;
    v->shadows = r->shadows, v->shading = r->shading == HK_SHADING_MARSCHNER, v->show_head = 1;
    v->maps_stale = 1;
    v->thickness = r->hair_thickness > 0.0 ? r->hair_thickness : hair->default_thickness;
    if (!(v->thickness > 0.0)) v->thickness = 7e-5;
    v->colours = in->visuality;
    v->colours.ambient = linear(in->visuality.ambient);
    v->colours.diffuse = linear(in->visuality.diffuse);
    v->colours.specular = linear(in->visuality.specular);
    return 1;
}

static int open_window(hk_Viewer *v)
{
    const hk_ViewerInput *in = v->in;
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        fprintf(stderr,
                "hairkit view: cannot open a window: %s (no display? set DISPLAY, or run headless under "
                "'xvfb-run -a hairkit view ... --frames N --screenshot OUT.png')\n",
                glfw_message[0] ? glfw_message : "GLFW failed to start");
        return 0;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_VISIBLE, in->frames > 0 ? GLFW_FALSE : GLFW_TRUE);
    v->window = glfwCreateWindow(in->render.width, in->render.height, "hairkit view", NULL, NULL);
    if (!v->window) {
        fprintf(stderr, "hairkit view: cannot create an OpenGL 3.3 core window: %s\n",
                glfw_message[0] ? glfw_message : "unknown reason");
        glfwTerminate();
        return 0;
    }
    glfwMakeContextCurrent(v->window);
    glfwSwapInterval(in->frames > 0 ? 0 : 1);
    return 1;
}

/* The simulated time, in the title and the headless summary. */
static int live_status(const hk_Viewer *v, char *buf, size_t size)
{
    if (!v->live) return snprintf(buf, size, "%s", "");
    return snprintf(buf, size, "; simulated %.2f s (%ld steps, %s, last %.0f ms)", hk_live_sim_time(v->live),
                    hk_live_sim_steps(v->live), v->playing ? "playing" : "paused", 1e3 * v->step_seconds);
}

/* The strands drawn: the guides alone (G) or all. */
static int shown_strands(const hk_Viewer *v, const char **what)
{
    const int guides = v->guides_only && v->hair.guides;
    *what = guides ? " (guides)" : "";
    return guides ? (int)v->hair.guides : (int)v->hair.strands;
}

/* The overlay's lines: frames per second, the counts, and when simulating the
 * simulated time and playing or paused. */
static void overlay_text(hk_Viewer *v)
{
    char *buf = v->overlay_text;
    const size_t size = sizeof v->overlay_text;
    const char *what;
    const int strands = shown_strands(v, &what);
    int n = v->fps > 0.0 ? snprintf(buf, size, "%.*f frames/s", v->fps < 10.0 ? 2 : 1, v->fps)
                         : snprintf(buf, size, "- frames/s");
    n += snprintf(buf + n, size - (size_t)n, "\n%d strands%s\n%ld points", strands, what, v->hair.points);
    if (v->live)
        snprintf(buf + n, size - (size_t)n, "\nsimulated %.2f s\n%s", hk_live_sim_time(v->live),
                 v->playing ? "playing" : "paused");
}

/* Frames per second and the counts: on stderr when headless (the first frame, which
 * uploads the buffers and draws the light's maps, apart), in the title otherwise (and
 * in the overlay drawn in the picture, key O). */
static void report(hk_Viewer *v, int frames, double seconds, double first)
{
    char line[512];
    const char *what;
    const int strands = shown_strands(v, &what);
    int n = snprintf(line, sizeof line, "hairkit view: %d strands%s, %ld points; ", strands, what, v->hair.points);
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    const double fps = seconds > 0.0 && frames > 0 ? frames / seconds : 0.0;
    if (first < 0.0) v->fps = fps;
    if (first >= 0.0)
        n += snprintf(line + n, sizeof line - (size_t)n, "first frame %.2f s, then %.2f frames/s (%s)", first, fps,
                      renderer);
    else
        n += snprintf(line + n, sizeof line - (size_t)n, "%.1f frames/s (%s)", fps, renderer);
    live_status(v, line + n, sizeof line - (size_t)n);
    if (v->figures) {
        v->figures->first_seconds = first, v->figures->frames_per_second = fps, v->figures->frames = frames;
        v->figures->strands = v->hair.strands, v->figures->points = v->hair.points;
        v->figures->simulated = v->live ? hk_live_sim_time(v->live) : 0.0;
        snprintf(v->figures->renderer, sizeof v->figures->renderer, "%s", renderer ? renderer : "?");
    }
    if (v->in->frames > 0) {
        if (!v->in->quiet) fprintf(stderr, "%s\n", line);
    } else {
        glfwSetWindowTitle(v->window, line);
    }
}

/* What changed since the last frame uploaded: the hair, the head where it moved. */
static int upload(hk_Viewer *v)
{
    if (v->hair_dirty) {
        if (!hk_gl_hair_update(&v->hair, v->hair_now, v->guide_count)) return 0;
        v->hair_dirty = 0, v->maps_stale = 1;
    }
    if (v->head_dirty) {
        const hk_RigidState pose = v->live ? hk_live_sim_head(v->live) : hk_rigid_identity();
        const hk_Scene *sc = v->in->scene;
        if (!hk_gl_head_pose(&v->head, v->in->head, &pose)) return 0;
        if (sc && !hk_gl_head_pose(&v->wick, &sc->wick, &pose)) return 0;
        if (!hk_viewer_shapes_update(v, &pose)) return 0;
        v->head_dirty = 0, v->maps_stale = 1;
    }
    return 1;
}

static int run(hk_Viewer *v)
{
    const hk_ViewerInput *in = v->in;
    if (!hk_viewer_load_programs(v)) return 0;
    if (!hk_gl_hair_create(&v->hair, v->hair_now, v->guide_count) || !hk_gl_head_create(&v->head, in->head) ||
        !hk_gl_head_create(&v->wick, in->scene ? &in->scene->wick : NULL) || !hk_viewer_shapes_update(v, NULL))
        return 0;
    v->hair_dirty = 0; /* just uploaded */
    if (!hk_gl_light_maps_create(&v->maps, hk_render_shadow_map_texels(&in->render)) ||
        !hk_gl_target_create(&v->target, in->render.width, in->render.height, 4) ||
        !hk_gl_overlay_create(&v->overlay)) {
        fprintf(stderr, "hairkit view: the OpenGL driver cannot make the viewer's framebuffers or its text overlay\n");
        return 0;
    }
    hk_viewer_input_install(v);
    const double start = hk_seconds_now();
    hk_viewer_watch_start(v, start);
    if (in->simulate) hk_viewer_live_play(v, 1, start);
    if (in->drag[0] != 0.0 || in->drag[1] != 0.0) hk_viewer_live_drag(v, in->drag[0], in->drag[1], v->target.height);
    double t0 = start, first = -1.0;
    int frames = 0, counted = 0;
    while (!glfwWindowShouldClose(v->window)) {
        int fw, fh;
        glfwGetFramebufferSize(v->window, &fw, &fh);
        if (in->frames == 0 && fw > 0 && fh > 0 && (fw != v->target.width || fh != v->target.height)) {
            hk_gl_target_destroy(&v->target);
            if (!hk_gl_target_create(&v->target, fw, fh, 4)) return 0;
        }
        if (!hk_viewer_watch(v, hk_seconds_now()) || !hk_viewer_live_update(v, hk_seconds_now()) || !upload(v))
            return 0;
        if (v->show_overlay) overlay_text(v);
        hk_viewer_draw(v);
        if (in->frames == 0) hk_gl_target_present(&v->target, fw, fh);
        glfwSwapBuffers(v->window);
        frames++, counted++;
        if (frames == 1 && in->frames > 0) {
            glFinish();
            t0 = hk_seconds_now();
            first = t0 - start;
            counted = 0;
        }
        const double now = hk_seconds_now();
        if (in->frames > 0 && counted > 0 && now > t0) v->fps = counted / (now - t0);
        if (in->frames > 0 && frames >= in->frames) {
            glFinish();
            report(v, counted, hk_seconds_now() - t0, first);
            break;
        }
        if (in->frames == 0 && now - t0 >= 1.0) {
            report(v, counted, now - t0, -1.0);
            t0 = now, counted = 0;
        }
        if (in->frames == 0) glfwPollEvents();
    }
    if (in->screenshot && !hk_viewer_screenshot(v, in->screenshot)) return 0;
    if (in->screenshot && !in->quiet)
        fprintf(stderr, "hairkit view: wrote %s (%dx%d)\n", in->screenshot, v->target.width, v->target.height);
    return 1;
}

int hk_viewer_set_hair(hk_Viewer *v, const hk_HairFile *hair, int guide_count)
{
    v->hair_now = hair;
    v->guide_count = guide_count;
    v->hair_dirty = 1;
    return 1;
}

int hk_viewer_run_measured(const hk_ViewerInput *in, hk_ViewerFigures *figures)
{
    hk_Viewer v;
    memset(&v, 0, sizeof v);
    v.in = in;
    v.figures = figures;
    v.hair_now = in->hair;
    v.guide_count = in->guide_count;
    v.guides_only = in->guides_only, v.show_wick = in->show_wick, v.show_shapes = in->show_shapes;
    v.show_overlay = in->overlay;
    int ok = !in->simulate || hk_viewer_live_start(&v);
    ok = ok && setup_scene(&v) && open_window(&v);
    if (ok) {
        ok = run(&v);
        if (v.head_program) glDeleteProgram(v.head_program);
        if (v.hair_program) glDeleteProgram(v.hair_program);
        if (v.line_program) glDeleteProgram(v.line_program);
        hk_gl_hair_destroy(&v.hair);
        hk_gl_head_destroy(&v.head);
        hk_gl_head_destroy(&v.wick);
        hk_gl_lines_destroy(&v.shapes);
        hk_gl_light_maps_destroy(&v.maps);
        hk_gl_target_destroy(&v.target);
        hk_gl_overlay_destroy(&v.overlay);
        glfwDestroyWindow(v.window);
        glfwTerminate();
    }
    hk_viewer_live_free(&v);
    hk_hair_free(&v.own_hair);
    return ok ? 0 : 1;
}

int hk_viewer_run(const hk_ViewerInput *in) { return hk_viewer_run_measured(in, NULL); }
