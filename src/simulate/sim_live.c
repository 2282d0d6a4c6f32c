/* A full head simulated live (hairkit/live_sim.h): hk_hair_sim's guides stepped one
 * fixed step at a time and the hair regrown after each, by the regrowth of
 * `hairkit simulate` (hk_sim_grow_hair, sim_grow.c) with its arrays reused. */
#include <omp.h>
#include <string.h>

#include "hairkit/live_sim.h"
#include "sim_internal.h"

struct hk_LiveSim {
    const hk_Scene *scene;
    hk_LiveSimDef options;
    int threads;
    hk_HairSim *sim;
    hk_Groom groom;   /* the guides now (world) and the strands grown from them */
    hk_HairFile hair; /* guides, then strands; arrays reused from step to step */
    long steps;
    double preroll;
    int preroll_at_rest;
};

hk_LiveSimDef hk_default_live_sim_def(void)
{
    hk_LiveSimDef o;
    memset(&o, 0, sizeof o);
    o.fps = 30.0;
    o.preroll = 1.0;
    o.preroll_max = 5.0;
    o.hair_contacts = 1;
    o.seed = 1;
    return o;
}

/* The hair of the guides as they are now, out of the body where the head is. */
static hk_Status regrow(hk_LiveSim *s, hk_Error *err)
{
    const hk_Scene *sc = s->scene;
    hk_hair_sim_guides(s->sim, s->groom.guides);
    const hk_RigidState head = hk_live_sim_head(s);
    return hk_sim_grow_hair(&sc->style, sc->collision.shapes, sc->collision.count, &head, &sc->wick, s->options.seed,
                            s->threads, s->options.guides_only, 1, &s->groom, &s->hair, err);
}

hk_Status hk_live_sim_create(const hk_Scene *scene, const hk_LiveSimDef *options, hk_LiveSim **out, hk_Error *err)
{
    *out = NULL;
    const hk_LiveSimDef defaults = hk_default_live_sim_def();
    const hk_LiveSimDef *o = options ? options : &defaults;
    if (!(o->fps >= 1.0 && o->fps <= 100000.0))
        return hk_error_set(err, HK_ERR_INVALID, "%g frames per second: must be 1 to 100000", o->fps);
    if (!(o->preroll >= 0.0 && o->preroll <= 100.0 && o->preroll_max >= 0.0 && o->preroll_max <= 100.0))
        return hk_error_set(err, HK_ERR_INVALID, "preroll %g s (at most %g s): must be 0 to 100", o->preroll,
                            o->preroll_max);
    if (!(scene->parts & HK_SCENE_HAIRSTYLE) || !(scene->parts & HK_SCENE_WICK) || !scene->wick.vertex_count)
        return hk_error_set(err, HK_ERR_INVALID, "%s: simulating needs HairstyleInfo and WickModel",
                            scene->setup_path ? scene->setup_path : "the setup");
    hk_LiveSim *s = hk_calloc_array(1, sizeof *s, err);
    if (!s) return HK_ERR_NOMEM;
    s->scene = scene;
    s->options = *o;
    s->threads = o->threads > 0 ? o->threads : omp_get_max_threads();
    hk_HairSimDef so = hk_hair_sim_def_for(&scene->style);
    so.threads = s->threads;
    so.hair_contacts = o->hair_contacts;
    hk_Status st = hk_hair_sim_create(&scene->style, scene->collision.shapes, scene->collision.count, &scene->wick, &so,
                                      &s->sim, err);
    if (st == HK_OK && (o->preroll > 0.0 || o->preroll_max > 0.0)) {
        /* As hairkit simulate: the groomed rest shape ignores guide-guide contacts, which
         * push neighbouring guides apart at first (hk_hair_sim_settle). */
        const hk_RigidState rest = hk_rigid_identity();
        hk_SettleDef settle = hk_default_settle_def();
        settle.seconds = o->preroll;
        settle.max_seconds = o->preroll_max > o->preroll ? o->preroll_max : o->preroll;
        hk_SettleReport report;
        st = hk_hair_sim_settle_until_still(s->sim, &rest, 1.0 / o->fps, &settle, &report, err);
        s->preroll = report.seconds;
        s->preroll_at_rest = report.at_rest;
    }
    if (st == HK_OK) {
        s->groom.points_per_strand = hk_hair_sim_points_per_strand(s->sim);
        s->groom.guide_count = hk_hair_sim_guide_count(s->sim);
        s->groom.guides =
            hk_alloc_array((size_t)s->groom.guide_count * (size_t)s->groom.points_per_strand, 3 * sizeof(double), err);
        st = s->groom.guides ? regrow(s, err) : HK_ERR_NOMEM;
    }
    if (st != HK_OK) {
        hk_live_sim_destroy(s);
        return st;
    }
    *out = s;
    return HK_OK;
}

void hk_live_sim_destroy(hk_LiveSim *s)
{
    if (!s) return;
    hk_hair_sim_destroy(s->sim);
    hk_groom_free(&s->groom);
    hk_hair_free(&s->hair);
    hk_free(s);
}

hk_Status hk_live_sim_step(hk_LiveSim *s, const hk_HeadMotion *motion, hk_HairSimStats *stats, hk_Error *err)
{
    const double dt = 1.0 / s->options.fps;
    hk_HairSimStats local;
    /* t as hairkit simulate computes frame times (k / fps), so the steps of both match */
    const double t = hk_sim_frame_time(s->steps, s->options.fps);
    hk_Status st = hk_hair_sim_advance(s->sim, motion, t, dt, stats ? stats : &local, err);
    if (st != HK_OK) return st;
    s->steps++;
    return regrow(s, err);
}

const hk_HairFile *hk_live_sim_hair(const hk_LiveSim *s) { return &s->hair; }
int hk_live_sim_guide_count(const hk_LiveSim *s) { return s->groom.guide_count; }
hk_RigidState hk_live_sim_head(const hk_LiveSim *s) { return hk_sim_head_now(s->sim); }
double hk_live_sim_time(const hk_LiveSim *s) { return hk_sim_frame_time(s->steps, s->options.fps); }
long hk_live_sim_steps(const hk_LiveSim *s) { return s->steps; }
double hk_live_sim_time_step(const hk_LiveSim *s) { return 1.0 / s->options.fps; }

double hk_live_sim_preroll(const hk_LiveSim *s, int *at_rest)
{
    if (at_rest) *at_rest = s->preroll_at_rest;
    return s->preroll;
}
