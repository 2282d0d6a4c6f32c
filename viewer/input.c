/* The viewer's mouse and keys (docs/viewer.md lists them). */
#include <math.h>
#include <stdio.h>

#include "core/core_internal.h"
#include "viewer/viewer_internal.h"

static hk_Viewer *of(GLFWwindow *w) { return (hk_Viewer *)glfwGetWindowUserPointer(w); }

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    hk_Viewer *v = of(w);
    if (action == GLFW_RELEASE) {
        v->dragging = 0;
        return;
    }
    glfwGetCursorPos(w, &v->mouse_x, &v->mouse_y);
    const int light = glfwGetKey(w, GLFW_KEY_L) == GLFW_PRESS;
    if (button == GLFW_MOUSE_BUTTON_LEFT && (mods & GLFW_MOD_SHIFT)) {
        /* the head, simulated from now on if it was not */
        if (!v->live) hk_viewer_live_play(v, 1, hk_seconds_now());
        v->dragging = v->live ? 4 : 0;
    } else if (button == GLFW_MOUSE_BUTTON_LEFT)
        v->dragging = light ? 3 : 1;
    else if (button == GLFW_MOUSE_BUTTON_RIGHT || button == GLFW_MOUSE_BUTTON_MIDDLE)
        v->dragging = 2;
}

static void on_move(GLFWwindow *w, double x, double y)
{
    hk_Viewer *v = of(w);
    const double dx = x - v->mouse_x, dy = y - v->mouse_y;
    v->mouse_x = x, v->mouse_y = y;
    int win_h;
    glfwGetWindowSize(w, NULL, &win_h);
    switch (v->dragging) {
    case 1:
        hk_orbit_turn(&v->orbit, -0.4 * dx, 0.4 * dy);
        break;
    case 2:
        hk_orbit_pan(&v->orbit, dx, dy, win_h > 0 ? win_h : 1);
        break;
    case 3:
        v->light_azimuth = fmod(v->light_azimuth + 0.4 * dx, 360.0);
        v->light_elevation = fmin(89.0, fmax(-89.0, v->light_elevation - 0.4 * dy));
        v->maps_stale = 1;
        break;
    case 4:
        hk_viewer_live_drag(v, dx, dy, win_h);
        break;
    default:
        break;
    }
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    (void)dx;
    hk_orbit_zoom(&of(w)->orbit, pow(0.9, dy));
}

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    hk_Viewer *v = of(w);
    (void)scancode;
    (void)mods;
    if (action == GLFW_RELEASE) return;
    switch (key) {
    case GLFW_KEY_LEFT:
        hk_orbit_turn(&v->orbit, -5.0, 0.0);
        break;
    case GLFW_KEY_RIGHT:
        hk_orbit_turn(&v->orbit, 5.0, 0.0);
        break;
    case GLFW_KEY_UP:
        hk_orbit_turn(&v->orbit, 0.0, 5.0);
        break;
    case GLFW_KEY_DOWN:
        hk_orbit_turn(&v->orbit, 0.0, -5.0);
        break;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD:
        hk_orbit_zoom(&v->orbit, 0.9);
        break;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT:
        hk_orbit_zoom(&v->orbit, 1.0 / 0.9);
        break;
    case GLFW_KEY_R:
        v->orbit = v->home;
        break;
    case GLFW_KEY_S:
        v->shadows = !v->shadows;
        v->maps_stale = 1;
        break;
    case GLFW_KEY_M:
        v->shading = !v->shading;
        break;
    case GLFW_KEY_H:
        v->show_head = !v->show_head;
        break;
    case GLFW_KEY_G:
        v->guides_only = !v->guides_only;
        v->maps_stale = 1;
        break;
    case GLFW_KEY_W:
        v->show_wick = !v->show_wick;
        break;
    case GLFW_KEY_C:
        v->show_shapes = !v->show_shapes;
        break;
    case GLFW_KEY_O:
        v->show_overlay = !v->show_overlay;
        break;
    case GLFW_KEY_SPACE:
        hk_viewer_live_play(v, !v->playing, hk_seconds_now());
        break;
    case GLFW_KEY_N:
        /* one step, paused */
        if (hk_viewer_live_start(v)) v->playing = 0, v->step_once = 1;
        break;
    case GLFW_KEY_BACKSPACE:
        if (!hk_viewer_live_reset(v)) glfwSetWindowShouldClose(w, GLFW_TRUE);
        break;
    case GLFW_KEY_F5:
        if (hk_viewer_load_programs(v)) fprintf(stderr, "hairkit view: shaders reloaded\n");
        break;
    case GLFW_KEY_P: {
        char path[64];
        snprintf(path, sizeof path, "hairkit-view-%03d.png", ++v->screenshots);
        if (hk_viewer_screenshot(v, path)) fprintf(stderr, "hairkit view: wrote %s\n", path);
        break;
    }
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q:
        glfwSetWindowShouldClose(w, GLFW_TRUE);
        break;
    default:
        break;
    }
}

void hk_viewer_input_install(hk_Viewer *v)
{
    glfwSetWindowUserPointer(v->window, v);
    glfwSetMouseButtonCallback(v->window, on_button);
    glfwSetCursorPosCallback(v->window, on_move);
    glfwSetScrollCallback(v->window, on_scroll);
    glfwSetKeyCallback(v->window, on_key);
}
