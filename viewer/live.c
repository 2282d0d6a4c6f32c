/* Live dynamics in the viewer (issue 16): the setup's guides stepped by hk_live_sim
 * (src/simulate/sim_live.c, the steps and regrowth of `hairkit simulate`), the head
 * moved by the input's motion and by the mouse (hk_head_motion_follow). The hair
 * advances by simulated time, a fixed step at a time: one step a frame when headless
 * (the same pictures whatever the machine), as many as the wall clock asks (at most two
 * a frame) when interactive. */
#include <math.h>
#include <stdio.h>

#include "core/core_internal.h"
#include "viewer/viewer_internal.h"

/* 1/s: the dragged head follows the mouse within about 1/rate = 80 ms, critically
 * damped (no overshoot), so that the hair sees a smooth acceleration. */
#define HK_DRAG_RATE 12.0

/* At most this many steps a frame when the simulation is slower than the clock: it
 * then runs slower than real time rather than ever further behind. */
#define HK_MAX_STEPS_A_FRAME 2

/* Room for the hair and the head in motion: the light's maps and the depth range cover
 * the scene's sphere, made 30% larger once (a still scene keeps its tighter maps). */
void hk_viewer_live_room(hk_Viewer *v)
{
    if (v->roomy || !(v->radius > 0.0)) return;
    v->roomy = 1;
    v->radius *= 1.3;
    v->orbit.radius = v->home.radius = v->radius;
    v->maps_stale = 1;
}

static int live_create(hk_Viewer *v)
{
    const hk_ViewerInput *in = v->in;
    hk_Error err;
    const double t0 = hk_seconds_now();
    hk_Status st = hk_live_sim_create(in->scene, &in->live, &v->live, &err);
    if (st == HK_OK && !v->follow) st = hk_head_motion_follow(in->motion, HK_DRAG_RATE, &v->follow, &err);
    if (st != HK_OK) {
        fprintf(stderr, "hairkit view: %s\n", err.message);
        return 0;
    }
    hk_head_motion_follow_reset(v->follow);
    v->drag = hk_v3_zero();
    if (!in->quiet) {
        int at_rest = 0;
        const double preroll = hk_live_sim_preroll(v->live, &at_rest);
        fprintf(stderr, "hairkit view: %d guides solved and settled %.2f s%s in %.2f s; simulating at %g steps/s\n",
                hk_live_sim_guide_count(v->live), preroll, at_rest ? " (at rest)" : " (not yet at rest)",
                hk_seconds_now() - t0, 1.0 / hk_live_sim_time_step(v->live));
    }
    v->hair_now = hk_live_sim_hair(v->live);
    v->guide_count = hk_live_sim_guide_count(v->live);
    v->hair_dirty = v->head_dirty = 1;
    hk_viewer_live_room(v);
    return 1;
}

int hk_viewer_live_start(hk_Viewer *v)
{
    if (v->live) return 1;
    const hk_Scene *sc = v->in->scene;
    if (!sc || !(sc->parts & HK_SCENE_WICK) || !sc->wick.vertex_count) {
        fprintf(stderr, "hairkit view: nothing to simulate: live dynamics needs a setup file that grows its hair "
                        "(HairstyleInfo, WickModel, Load false)\n");
        return 0;
    }
    return live_create(v);
}

void hk_viewer_live_play(hk_Viewer *v, int playing, double now)
{
    if (playing && !hk_viewer_live_start(v)) playing = 0;
    v->playing = playing;
    if (playing) v->play_wall = now, v->play_steps = v->live ? hk_live_sim_steps(v->live) : 0;
}

static int step(hk_Viewer *v)
{
    hk_Error err;
    hk_HairSimStats stats;
    const double t0 = hk_seconds_now();
    /* the drag's target from now on (the head starts towards it within the step) */
    hk_head_motion_follow_target(v->follow, hk_live_sim_time(v->live), v->drag);
    if (hk_live_sim_step(v->live, v->follow, &stats, &err) != HK_OK) {
        fprintf(stderr, "hairkit view: at %.3f s: %s\n", hk_live_sim_time(v->live), err.message);
        return 0;
    }
    v->step_seconds = hk_seconds_now() - t0;
    v->hair_dirty = v->head_dirty = 1;
    return 1;
}

int hk_viewer_live_update(hk_Viewer *v, double now)
{
    if (!v->live) return 1;
    int due = 0;
    if (v->step_once) {
        due = 1, v->step_once = 0;
        if (v->playing) v->play_wall = now, v->play_steps = hk_live_sim_steps(v->live) + 1;
    } else if (v->playing && v->in->frames > 0) {
        due = 1;
    } else if (v->playing) {
        const long target = v->play_steps + (long)floor((now - v->play_wall) / hk_live_sim_time_step(v->live));
        const long behind = target - hk_live_sim_steps(v->live);
        due = behind > HK_MAX_STEPS_A_FRAME ? HK_MAX_STEPS_A_FRAME : (int)behind;
        /* behind the clock: count from here, slower than real time */
        if (behind > HK_MAX_STEPS_A_FRAME) v->play_wall = now, v->play_steps = hk_live_sim_steps(v->live) + due;
    }
    for (int i = 0; i < due; i++)
        if (!step(v)) return 0;
    return 1;
}

int hk_viewer_live_reset(hk_Viewer *v) { return !v->live || hk_viewer_live_restart(v); }

int hk_viewer_live_restart(hk_Viewer *v)
{
    hk_LiveSim *old = v->live;
    v->live = NULL;
    if (!live_create(v)) {
        v->live = old;
        return 0;
    }
    hk_live_sim_destroy(old);
    v->play_wall = hk_seconds_now(), v->play_steps = 0;
    return 1;
}

void hk_viewer_live_drag(hk_Viewer *v, double dx, double dy, int height)
{
    if (!v->live || height <= 0) return;
    /* across the view plane through the camera's target, as the pan moves it */
    const hk_OrbitFrame f = hk_orbit_frame(&v->orbit, height, height);
    const double per_pixel = v->orbit.distance / f.focal;
    v->drag = hk_v3_madd(v->drag, f.right, dx * per_pixel);
    v->drag = hk_v3_madd(v->drag, f.up, -dy * per_pixel);
}

void hk_viewer_live_free(hk_Viewer *v)
{
    hk_live_sim_destroy(v->live);
    hk_head_motion_destroy(v->follow);
    v->live = NULL, v->follow = NULL;
}
