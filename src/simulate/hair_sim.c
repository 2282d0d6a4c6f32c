/* A full head of hair in motion (Bertails et al. 2006 §4.1; docs/dynamics.md): the guides of the
 * groom as Super-Helices in motion, guide-guide interactions, and the interpolated hair
 * regrown from the guides per frame. */
#include <math.h>
#include <omp.h>
#include <stdatomic.h>
#include <string.h>

#include "core/core_internal.h"
#include "hairkit/simulate.h"
#include "hairkit/statics.h"
#include "dynamics/hair_contact_solve.h"
#include "dynamics/hair_contacts_internal.h"
#include "sim_internal.h"

struct hk_HairSim {
    hk_Hairstyle style; /* own copy */
    hk_HairSimDef options;
    hk_Shape *shapes; /* own copy (head space) */
    int shape_count;
    int guide_count, points;
    hk_SuperHelix **strand;
    hk_StrandDynamics **dyn;
    /* guide-guide contacts: samples every CollisionStep along each guide */
    hk_HairContacts *contacts;
    hk_ContactSolve *contact_solve; /* the contacts' impulses, solved over all guides */
    int sample_count;
    double *sample_s;                 /* sample_count arc lengths, shared by all guides */
    hk_Vec3 *sample_pos, *sample_vel; /* guide_count x sample_count */
    hk_StrandSamples *samples;        /* guide_count views of the above */
    int sampled;                      /* the samples are the guides' now, with the head in */
    hk_RigidState sampled_head;       /* this pose (taken at the end of the last step) */
    hk_RigidState head;               /* the head's pose at the end of the last step: the
                                         guides are in world space, the shapes in head space */
    double longest;                   /* imported guides: the longest (m); 0: grown guides,
                                         all of the hairstyle's length */
};

/* Length of hair whose weight a guide-guide contact pushes with at full overlap. */
#define HK_CONTACT_HAIR_LENGTH 0.2

/* The defaults for hair of this section and material, contacts scaled to `length` of it. */
static hk_HairSimDef sim_def(const hk_Hairstyle *style, double length)
{
    hk_HairSimDef o;
    memset(&o, 0, sizeof o);
    o.threads = 0;
    o.dynamics = style->dynamics;
    /* Every guide takes the linearly implicit Euler step, whatever its length, with the
     * guide-guide contacts solved together over all guides (advance, below), long
     * guides in several steps a frame (euler_steps). TR-BDF2 is the better integrator
     * for a strand alone (docs/dynamics.md, "Time stepping"), but its guides can only
     * take the contacts as penalty forces, each in its own step with its partners held
     * still (block Jacobi), and a full head of 1 m guides then whipped: under a 25
     * degree shake at 1 Hz tips jumped up to 1.4 m in a frame after 0.8 s, and Newton's
     * iteration needed 240 evaluations per guide and frame. The contacts' solve holds
     * the pile together instead (tests/test_long_guides.c, docs/dynamics.md "Long
     * guides on a head"). The guide's own step must be stable by itself: with G+ four
     * steps old, guides pushed by the contacts gained speed from step to step until
     * they flew off (all 201 guides of examples/guides200 within a second); refreshed
     * every step, none. */
    o.dynamics.integrator = HK_INTEGRATOR_LINEAR_EULER;
    o.dynamics.solver = HK_DYNAMICS_DENSE;
    o.dynamics.stiffness = HK_STIFFNESS_FULL;
    o.dynamics.hessian_interval = 1;
    o.hair_contacts = 1;
    o.contacts = hk_default_hair_contact_def();
    /* Contacts scaled to this hair (docs/dynamics.md): guides keep 2.5 mm apart, less
     * than the spacing of neighbouring follicles near the crown (about 3 mm on the
     * generated wick), so the groomed rest state is nearly free of contacts; a full
     * overlap pushes with the weight of the strand, or of 20 cm of it when it is longer
     * (several contacts add up: five times as much flung crown guides over the head in
     * our tests); the normal damping is critical for a quarter of that mass on that
     * spring, the friction a fifth of it. A contact's stiffness is a property of the hair
     * where it touches, not of the strand's length, while the contacts along a strand grow
     * with its length: with the whole strand's weight, a 1 m guide on a full head was
     * pushed by up to 1,400 contacts each as strong as its weight, and Newton's iteration
     * failed in 29 % of its stages (docs/dynamics.md, "Limitations"). */
    const double mass = style->strand.density * HK_PI * style->strand.radius1 * style->strand.radius2 *
                        fmin(length, HK_CONTACT_HAIR_LENGTH);
    o.contacts.distance = 0.0025;
    o.contacts.stiffness =
        1.0 * mass * (style->strand.gravity > 0.0 ? style->strand.gravity : 9.81) / o.contacts.distance;
    o.contacts.damping = 2.0 * sqrt(o.contacts.stiffness * 0.25 * mass);
    o.contacts.friction = 0.2 * o.contacts.damping;
    /* Guides side by side are held along their length: with one pair at their closest
     * point, that point jumped along them from step to step and neighbouring guides at
     * rest jittered by up to 4 mm a frame (docs/dynamics.md, "Contacts solved
     * together"). The pairs are then found afresh at every step (rescan_interval does
     * not apply). */
    o.contacts.along = 1;
    return o;
}

hk_HairSimDef hk_hair_sim_def_for(const hk_Hairstyle *style)
{
    return sim_def(style, hk_strand_def_length(&style->strand));
}

hk_HairSimDef hk_default_hair_sim_def(void)
{
    /* The hairstyle's defaults with a hair of 40 um radius (examples/default), 20 cm long */
    hk_Hairstyle style = hk_default_hairstyle();
    style.strand.radius1 = style.strand.radius2 = 4e-5;
    return sim_def(&style, HK_CONTACT_HAIR_LENGTH);
}

void hk_hair_sim_destroy(hk_HairSim *sim)
{
    if (!sim) return;
    for (int i = 0; sim->dyn && i < sim->guide_count; i++) hk_strand_dynamics_destroy(sim->dyn[i]);
    for (int i = 0; sim->strand && i < sim->guide_count; i++) hk_superhelix_destroy(sim->strand[i]);
    hk_free(sim->dyn);
    hk_free(sim->strand);
    hk_hair_contacts_destroy(sim->contacts);
    hk_contact_solve_destroy(sim->contact_solve);
    hk_free(sim->sample_s);
    hk_free(sim->sample_pos);
    hk_free(sim->sample_vel);
    hk_free(sim->samples);
    hk_free(sim->shapes);
    hk_hairstyle_free(&sim->style);
    hk_free(sim);
}

/* The groom's guide (guides.c): the statics rest shape with the envelope of its
 * follicle's level, then its dynamics. */
static hk_Status make_guide(hk_HairSim *sim, const hk_Follicles *f, int i, hk_Error *err)
{
    hk_Status st = hk_superhelix_from_def(&sim->style.strand, f->position[i], f->normal[i], &sim->strand[i], err);
    if (st != HK_OK) return st;
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = sim->shapes;
    env.shape_count = sim->shape_count;
    env.envelope_alpha = f->alpha[i];
    env.collision_step = sim->style.strand.collision_step;
    hk_StaticsDef opt = hk_default_statics_def();
    hk_MinimizeResult res;
    st = hk_statics_solve(sim->strand[i], &env, &opt, &res, err);
    if (st == HK_OK) st = hk_strand_dynamics_create(sim->strand[i], &sim->options.dynamics, &env, &sim->dyn[i], err);
    return st;
}

/* The threads of the simulation's parallel loops: options.threads, or OpenMP's default. */
static int sim_threads(const hk_HairSim *sim)
{
    return sim->options.threads > 0 ? sim->options.threads : omp_get_max_threads();
}

static hk_Status make_guides(hk_HairSim *sim, const hk_Follicles *f, hk_Error *err)
{
    hk_FirstError first;
    hk_first_error_init(&first);
    long done = 0;
#pragma omp parallel for schedule(dynamic, 2) num_threads(sim_threads(sim))
    for (int i = 0; i < f->count; i++) {
        if (hk_first_error_skip(&first, i)) continue;
        hk_Error e;
        if (make_guide(sim, f, i, &e) != HK_OK) hk_first_error_record(&first, i, &e);
        long d;
#pragma omp atomic capture
        d = ++done;
        if (sim->options.progress && omp_get_thread_num() == 0)
            sim->options.progress(sim->options.progress_user, "guides", (double)d / f->count);
    }
    return hk_first_error_status(&first, err);
}

static hk_Status make_contacts(hk_HairSim *sim, hk_Error *err)
{
    const double len = hk_strand_def_length(&sim->style.strand);
    double m = ceil(len / sim->style.strand.collision_step - 1e-9);
    if (m < 1.0) m = 1.0;
    if (m > 10000.0) m = 10000.0;
    sim->sample_count = (int)m + 1;
    const size_t total = (size_t)sim->guide_count * (size_t)sim->sample_count;
    sim->sample_s = hk_alloc_array((size_t)sim->sample_count, sizeof(double), err);
    sim->sample_pos = hk_alloc_array(total, sizeof(hk_Vec3), err);
    sim->sample_vel = hk_alloc_array(total, sizeof(hk_Vec3), err);
    sim->samples = hk_alloc_array((size_t)sim->guide_count, sizeof(hk_StrandSamples), err);
    if (!sim->sample_s || !sim->sample_pos || !sim->sample_vel || !sim->samples) return HK_ERR_NOMEM;
    for (int j = 0; j < sim->sample_count; j++) sim->sample_s[j] = len * j / (sim->sample_count - 1);
    for (int i = 0; i < sim->guide_count; i++) {
        const size_t o = (size_t)i * (size_t)sim->sample_count;
        sim->samples[i] =
            (hk_StrandSamples){sim->sample_count, sim->sample_s, sim->sample_pos + o, sim->sample_vel + o};
    }
    /* The contacts' threads follow the simulation's unless they are set. */
    hk_HairContactDef params = sim->options.contacts;
    if (params.threads <= 0) params.threads = sim->options.threads;
    hk_Status st = hk_hair_contacts_create(sim->guide_count, &params, &sim->contacts, err);
    if (st == HK_OK) st = hk_contact_solve_create(sim->guide_count, &sim->contact_solve, err);
    return st;
}

hk_Status hk_hair_sim_create(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count, const hk_Mesh *wick,
                             const hk_HairSimDef *options, hk_HairSim **out, hk_Error *err)
{
    *out = NULL;
    hk_HairSim *sim = hk_calloc_array(1, sizeof *sim, err);
    if (!sim) return HK_ERR_NOMEM;
    sim->options = options ? *options : hk_hair_sim_def_for(style);
    sim->head = hk_rigid_identity();
    hk_Follicles f = {0, NULL, NULL, NULL};
    hk_Status st = hk_hairstyle_copy(style, &sim->style, err);
    if (st == HK_OK && shape_count > 0) {
        sim->shapes = hk_alloc_array((size_t)shape_count, sizeof(hk_Shape), err);
        if (!sim->shapes)
            st = HK_ERR_NOMEM;
        else
            memcpy(sim->shapes, shapes, (size_t)shape_count * sizeof(hk_Shape));
        sim->shape_count = shape_count;
    }
    if (st == HK_OK) st = hk_follicles_from_wick(wick, &f, err);
    if (st == HK_OK) {
        sim->guide_count = f.count;
        sim->strand = hk_calloc_array((size_t)f.count, sizeof(hk_SuperHelix *), err);
        sim->dyn = hk_calloc_array((size_t)f.count, sizeof(hk_StrandDynamics *), err);
        if (!sim->strand || !sim->dyn) st = HK_ERR_NOMEM;
    }
    if (st == HK_OK) st = make_guides(sim, &f, err);
    if (st == HK_OK) {
        sim->points = hk_superhelix_sample_count(sim->strand[0], sim->style.strand.visuality_step);
        if (sim->options.hair_contacts) st = make_contacts(sim, err);
    }
    hk_follicles_free(&f);
    if (st != HK_OK) {
        hk_hair_sim_destroy(sim);
        return st;
    }
    *out = sim;
    return HK_OK;
}

/* An imported guide: a copy of the fitted, inverted Super-Helix (its q the captured rest,
 * q_rest the natural shape found), then its dynamics; no statics: the inverse made the
 * capture the rest. */
static hk_Status import_guide(hk_HairSim *sim, const hk_SuperHelix *from, int i, hk_Error *err)
{
    hk_Status st = hk_superhelix_create(from->n, from->length, &sim->strand[i], err);
    if (st != HK_OK) return st;
    hk_SuperHelix *sh = sim->strand[i];
    memcpy(sh->q, from->q, 3 * (size_t)from->n * sizeof(double));
    memcpy(sh->q_rest, from->q_rest, 3 * (size_t)from->n * sizeof(double));
    sh->root = from->root;
    sh->root_frame = from->root_frame;
    sh->material = from->material;
    hk_StrandEnvDef env = hk_default_strand_env_def();
    env.shapes = sim->shapes;
    env.shape_count = sim->shape_count;
    env.envelope_alpha = 0.0;
    env.collision_step = sim->style.strand.collision_step;
    return hk_strand_dynamics_create(sh, &sim->options.dynamics, &env, &sim->dyn[i], err);
}

hk_Status hk_hair_sim_create_imported(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                                      const hk_ImportedGroom *groom, const hk_HairSimDef *options, hk_HairSim **out,
                                      hk_Error *err)
{
    *out = NULL;
    hk_HairSim *sim = hk_calloc_array(1, sizeof *sim, err);
    if (!sim) return HK_ERR_NOMEM;
    sim->options = options ? *options : hk_hair_sim_def_for(style);
    sim->options.hair_contacts = 0;
    sim->head = hk_rigid_identity();
    hk_Status st = hk_hairstyle_copy(style, &sim->style, err);
    if (st == HK_OK && shape_count > 0) {
        sim->shapes = hk_alloc_array((size_t)shape_count, sizeof(hk_Shape), err);
        if (!sim->shapes)
            st = HK_ERR_NOMEM;
        else
            memcpy(sim->shapes, shapes, (size_t)shape_count * sizeof(hk_Shape));
        sim->shape_count = shape_count;
    }
    if (st == HK_OK) {
        sim->guide_count = groom->guide_count;
        sim->strand = hk_calloc_array((size_t)groom->guide_count, sizeof(hk_SuperHelix *), err);
        sim->dyn = hk_calloc_array((size_t)groom->guide_count, sizeof(hk_StrandDynamics *), err);
        if (!sim->strand || !sim->dyn) st = HK_ERR_NOMEM;
    }
    if (st == HK_OK) {
        hk_FirstError first;
        hk_first_error_init(&first);
#pragma omp parallel for schedule(dynamic, 2) num_threads(sim_threads(sim))
        for (int i = 0; i < groom->guide_count; i++) {
            hk_Error e;
            if (import_guide(sim, groom->guide[i], i, &e) != HK_OK) hk_first_error_record(&first, i, &e);
        }
        st = hk_first_error_status(&first, err);
    }
    for (int i = 0; st == HK_OK && i < sim->guide_count; i++) {
        sim->longest = fmax(sim->longest, sim->strand[i]->total_length);
        const int p = hk_superhelix_sample_count(sim->strand[i], sim->style.strand.visuality_step);
        if (p > sim->points) sim->points = p;
    }
    if (st != HK_OK) {
        hk_hair_sim_destroy(sim);
        return st;
    }
    *out = sim;
    return HK_OK;
}

const hk_SuperHelix *const *hk_hair_sim_strands(const hk_HairSim *sim)
{
    return (const hk_SuperHelix *const *)sim->strand;
}

void hk_hair_sim_set_threads(hk_HairSim *sim, int threads)
{
    sim->options.threads = threads;
    if (sim->contacts && sim->options.contacts.threads <= 0) hk_hc_set_threads(sim->contacts, threads);
}

int hk_hair_sim_guide_count(const hk_HairSim *sim) { return sim->guide_count; }
int hk_hair_sim_points_per_strand(const hk_HairSim *sim) { return sim->points; }

static void head_state(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

/* A head held still in one pose. */
static void held_state(void *user, double t, hk_RigidState *out)
{
    (void)t;
    *out = *(const hk_RigidState *)user;
    out->vel = out->acc = out->omega = out->alpha = hk_v3_zero();
}

static hk_Status advance(hk_HairSim *sim, hk_HeadStateFn head_fn, void *user, double t, double dt,
                         hk_HairSimStats *stats, hk_Error *err);

/* Longest linearly implicit Euler step for guides of `length` metres: 1/24 s up to
 * HK_EULER_FULL_STEP_LENGTH, shorter in proportion beyond (two steps a frame for 50 cm,
 * four for 1 m, at 24 or 30 frames/s). The Euler step treats the velocity products and
 * the negative geometric stiffness explicitly, and a long guide swinging fast gains
 * energy from them. Measured on the default head nodding 25 degrees at 1 Hz
 * (docs/dynamics.md, "Long guides on a head"): at one step a frame, 201 guides of 1 m
 * (examples/guides200's loose wave) blew up after 1.8 s at 24 frames/s and 3.4 s at 30
 * (guides recovered by the hundred), Appendix B's wavy hair of 50 cm after 0.6 s at 24;
 * at two steps a frame both ran 10 s. Four for 1 m leave a margin for curlier hair. */
#define HK_EULER_FULL_STEP_LENGTH 0.25

static int euler_steps(const hk_HairSim *sim, double dt)
{
    if (sim->options.dynamics.integrator != HK_INTEGRATOR_LINEAR_EULER) return 1; /* TR-BDF2 splits by itself */
    const double length = sim->longest > 0.0 ? sim->longest : hk_strand_def_length(&sim->style.strand);
    const double longest = (1.0 / 24.0) * fmin(1.0, HK_EULER_FULL_STEP_LENGTH / length);
    const double n = ceil(dt / longest - 1e-9);
    return n < 1.0 ? 1 : n > 64.0 ? 64 : (int)n;
}

/* Steps from t to t + dt in euler_steps equal steps; stats sums the steps' work and
 * gives the last one's contacts. */
static hk_Status advance_frame(hk_HairSim *sim, hk_HeadStateFn head_fn, void *user, double t, double dt,
                               hk_HairSimStats *stats, hk_Error *err)
{
    const int n = euler_steps(sim, dt);
    hk_HairSimStats sum, one;
    memset(&sum, 0, sizeof sum);
    hk_Status st = HK_OK;
    for (int k = 0; k < n && st == HK_OK; k++) {
        const double from = t + dt * k / n, to = k == n - 1 ? t + dt : t + dt * (k + 1) / n;
        st = advance(sim, head_fn, user, from, to - from, &one, err);
        one.seconds += sum.seconds; /* the work summed, the last step's contacts */
        one.substeps += sum.substeps;
        one.recovered += sum.recovered;
        one.iterations += sum.iterations;
        sum = one;
    }
    if (stats) *stats = sum;
    return st;
}

hk_Status hk_hair_sim_advance(hk_HairSim *sim, const hk_HeadMotion *motion, double t, double dt, hk_HairSimStats *stats,
                              hk_Error *err)
{
    if (!(dt > 0.0) || !isfinite(dt) || !isfinite(t))
        return hk_error_set(err, HK_ERR_INVALID, "advancing from t = %g by %g s", t, dt);
    return advance_frame(sim, motion ? head_state : NULL, (void *)motion, t, dt, stats, err);
}

hk_Status hk_hair_sim_settle(hk_HairSim *sim, const hk_RigidState *head, double seconds, double dt, hk_Error *err)
{
    if (!(dt > 0.0) || !isfinite(dt) || !(seconds >= 0.0) || seconds / dt > 1e7)
        return hk_error_set(err, HK_ERR_INVALID, "settling %g s in steps of %g s", seconds, dt);
    hk_RigidState pose = head ? *head : hk_rigid_identity();
    const long steps = (long)ceil(seconds / dt - 1e-9);
    for (long i = 0; i < steps; i++) {
        hk_Status st = advance_frame(sim, held_state, &pose, 0.0, dt, NULL, err);
        if (st != HK_OK) return st;
    }
    return HK_OK;
}

/* Guide i's penalty contact forces for a step of its own with its partners held where
 * they are (block Jacobi), in buffer when they fit in cap, else in *own (to free; NULL
 * with *count > 0 when out of memory). Both sides of a contact move, so the relative
 * stiffness and damping are twice the one-sided ones: doubling the linearisation (not
 * the force) makes the splitting damped; with the one-sided values guides in contact
 * jittered by over a millimetre a frame at rest, with twice them by a third of that. */
static const hk_PointForce *penalty_forces(const hk_HairContacts *c, int i, hk_PointForce *buffer, int cap,
                                           hk_PointForce **own, int *count)
{
    const hk_PointForce *given = hk_hair_contacts_forces(c, i, count);
    hk_PointForce *forces = *count <= cap ? buffer : (*own = hk_alloc_array((size_t)*count, sizeof *forces, NULL));
    for (int k = 0; forces && k < *count; k++) {
        forces[k] = given[k];
        forces[k].stiffness = hk_m3_scale(&given[k].stiffness, 2.0);
        forces[k].damping = hk_m3_scale(&given[k].damping, 2.0);
    }
    return forces;
}

hk_SettleDef hk_default_settle_def(void)
{
    hk_SettleDef o;
    o.seconds = 1.0;
    o.max_seconds = 5.0;
    o.rest_speed = 1e-4;
    o.rest_steps = 5;
    return o;
}

/* The guides' tips, world space. */
static void guide_tips(hk_HairSim *sim, hk_Vec3 *tip)
{
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
    for (int i = 0; i < sim->guide_count; i++) {
        const hk_SuperHelix *sh = sim->strand[i];
        const double end = sh->s_start[sh->n - 1] + sh->length[sh->n - 1];
        hk_strand_dynamics_points(sim->dyn[i], &sim->head, &end, 1, &tip[i], NULL);
    }
}

hk_Status hk_hair_sim_settle_until_still(hk_HairSim *sim, const hk_RigidState *head, double dt, const hk_SettleDef *o,
                                         hk_SettleReport *report, hk_Error *err)
{
    const hk_SettleDef def = hk_default_settle_def();
    if (!o) o = &def;
    if (report) memset(report, 0, sizeof *report);
    if (!(dt > 0.0) || !isfinite(dt) || !(o->seconds >= 0.0) || !(o->max_seconds >= o->seconds) ||
        o->max_seconds / dt > 1e7 || !(o->rest_speed >= 0.0) || o->rest_steps < 1)
        return hk_error_set(err, HK_ERR_INVALID,
                            "settling %g to %g s in steps of %g s until tips move slower than %g m/s for %d steps",
                            o->seconds, o->max_seconds, dt, o->rest_speed, o->rest_steps);
    hk_RigidState pose = head ? *head : hk_rigid_identity();
    const long least = (long)ceil(o->seconds / dt - 1e-9), most = (long)ceil(o->max_seconds / dt - 1e-9);
    hk_Vec3 *tips = hk_alloc_array(2 * (size_t)sim->guide_count, sizeof(hk_Vec3), err);
    if (!tips) return HK_ERR_NOMEM;
    hk_Vec3 *before = tips, *after = tips + sim->guide_count;
    long steps = 0;
    int resting = 0;
    double fastest = 0.0;
    hk_Status st = HK_OK;
    guide_tips(sim, before);
    while (st == HK_OK && steps < most && (steps < least || resting < o->rest_steps)) {
        st = advance_frame(sim, held_state, &pose, 0.0, dt, NULL, err);
        if (st != HK_OK) break;
        steps++;
        guide_tips(sim, after);
        fastest = 0.0;
        for (int i = 0; i < sim->guide_count; i++)
            fastest = fmax(fastest, hk_v3_norm(hk_v3_sub(after[i], before[i])) / dt);
        resting = fastest <= o->rest_speed ? resting + 1 : 0;
        hk_Vec3 *swap = before; /* this step's end is the next one's start */
        before = after, after = swap;
    }
    hk_free(tips);
    if (report) {
        report->seconds = (double)steps * dt;
        report->at_rest = resting >= o->rest_steps;
        report->tip_speed = fastest;
    }
    return st;
}

/* What a guide's step took: its substeps, 1 when it had to be recovered, the
 * evaluations. */
typedef struct GuideStep {
    int taken, recovered;
    long iterations;
} GuideStep;

/* Guide i's step from t to t + dt: the contacts' solve's (coupled) when it can take it,
 * else its own with the contacts' forces; an error goes to first. */
static GuideStep step_guide(hk_HairSim *sim, int i, hk_HeadStateFn head_fn, void *user, double t, double dt,
                            int coupled, const hk_RigidState *head_end, hk_FirstError *first)
{
    GuideStep out = {0, 0, 0};
    int count = 0;
    hk_Error e;
    hk_PointForce buffer[64], *own = NULL;
    const hk_PointForce *forces = NULL;
    if (sim->contacts && coupled)
        forces = hk_contact_solve_forces(sim->contact_solve, i, &count);
    else if (sim->contacts)
        forces = penalty_forces(sim->contacts, i, buffer, 64, &own, &count);
    const long before = hk_strand_dynamics_stats(sim->dyn[i]).iterations;
    hk_Status gst = HK_OK;
    if (count > 0 && !forces)
        gst = hk_error_set(&e, HK_ERR_NOMEM, "out of memory for %d contact forces", count);
    else if (sim->contacts && coupled && hk_contact_solve_commit(sim->contact_solve, sim->dyn[i], i, head_end, dt))
        out.taken = 1; /* the solve's step, as advance would have taken it */
    else
        gst = hk_strand_dynamics_advance(sim->dyn[i], head_fn, user, t, dt, forces, count, &out.taken, &e);
    if (gst == HK_ERR_NUMERIC) {
        /* One guide that cannot be advanced, even split down to dt / 2^max_depth,
         * must not stop the head: it is left where it was at t, at rest
         * relative to the head, then advanced once more (counted in
         * stats->recovered; the next frames go on from there). */
        memset(hk_strand_dynamics_velocity(sim->dyn[i]), 0, sizeof(double) * 3 * (size_t)sim->strand[i]->n);
        out.recovered = 1;
        int again = 0;
        gst = hk_strand_dynamics_advance(sim->dyn[i], head_fn, user, t, dt, forces, count, &again, &e);
        if (gst == HK_ERR_NUMERIC) gst = HK_OK; /* held at rest relative to the head */
        out.taken += again;
    }
    out.iterations = hk_strand_dynamics_stats(sim->dyn[i]).iterations - before;
    if (gst != HK_OK) hk_first_error_record(first, i, &e);
    hk_free(own);
    return out;
}

/* Guide i's contact samples (positions and velocities) with the head in pose head. */
static void sample_guide(hk_HairSim *sim, int i, const hk_RigidState *head)
{
    const size_t o = (size_t)i * (size_t)sim->sample_count;
    hk_strand_dynamics_points(sim->dyn[i], head, sim->sample_s, sim->sample_count, sim->sample_pos + o,
                              sim->sample_vel + o);
}

/* The pairs found by one thread while the others (and then it) find every guide's step
 * without the contacts, which needs the guide alone: the contacts' update gained 1.48
 * times on two threads, the guides' steps 1.92; one after the other they took 11.2 ms
 * a frame on two threads (examples/guides200 shaking, N = 10, omp_get_wtime), side by
 * side 8.7-9.5 ms (with the cheaper broad phase that came after). The pairs are the
 * same whatever the threads. The thread of the pairs then deals their points to the
 * guides (the solve's layout), and the guides stepped after that get their points'
 * Jacobians at once, their state still in the cache; the rest, and the pairs' laws,
 * follow in the same parallel region (hk_contact_solve_layout to _prepare). */
static hk_Status overlapped_step(hk_HairSim *sim, const hk_RigidState *head_end, double dt, int threads, hk_Error *err)
{
    hk_ContactSolve *cs = sim->contact_solve;
    hk_Status update_st = HK_OK, layout_st = HK_OK;
    hk_Error update_err;
    const int contact_threads = hk_hc_threads(sim->contacts);
    atomic_int laid_out; /* 0 while the pairs' thread is at it, then 1, or -1 when it failed */
    atomic_init(&laid_out, 0);
#pragma omp parallel num_threads(threads)
    {
#pragma omp single nowait
        {
            hk_hc_set_threads(sim->contacts, 1);
            update_st = hk_hair_contacts_update(sim->contacts, sim->samples, sim->guide_count, &update_err);
            hk_hc_set_threads(sim->contacts, contact_threads);
            if (update_st == HK_OK)
                layout_st = hk_contact_solve_layout(cs, sim->contacts, sim->dyn, sim->guide_count, dt, &update_err);
            atomic_store_explicit(&laid_out, update_st == HK_OK && layout_st == HK_OK ? 1 : -1, memory_order_release);
        }
#pragma omp for schedule(dynamic, 2) nowait
        for (int i = 0; i < sim->guide_count; i++) {
            hk_contact_solve_predict(cs, sim->dyn[i], i, head_end, dt);
            if (atomic_load_explicit(&laid_out, memory_order_acquire) > 0)
                hk_contact_solve_points(cs, sim->dyn[i], i, head_end);
        }
        /* No barrier: a thread done with its guides goes on to the points of those
         * stepped before the layout (hk_contact_solve_points waits for a guide's step
         * still under way on another thread), then to the pairs' laws (each waits for
         * its two guides' points). Only the layout itself is waited for here. */
        long spins = 0;
        while (atomic_load_explicit(&laid_out, memory_order_acquire) == 0) hk_spin_pause(&spins);
        if (atomic_load_explicit(&laid_out, memory_order_relaxed) > 0) {
#pragma omp for schedule(dynamic, 8) nowait
            for (int i = 0; i < sim->guide_count; i++) hk_contact_solve_points(cs, sim->dyn[i], i, head_end);
            hk_contact_solve_prepare(cs, sim->contacts, dt);
        }
    }
    const hk_Status st = update_st != HK_OK ? update_st : layout_st;
    if (st != HK_OK && err) *err = update_err;
    return st;
}

static hk_Status advance(hk_HairSim *sim, hk_HeadStateFn head_fn, void *user, double t, double dt,
                         hk_HairSimStats *stats, hk_Error *err)
{
    const double t0 = hk_seconds_now();
    hk_HairSimStats local;
    memset(&local, 0, sizeof local);
    hk_RigidState head = hk_rigid_identity();
    if (head_fn) head_fn(user, t, &head);
    const int threads = sim_threads(sim);
    /* Guide-guide interactions (Bertails et al. 2006 §4.1): the pairs from the state at t. With the
     * linearly implicit Euler step (the default) their impulses are solved over all
     * guides together with static friction (dynamics/hair_contact_solve.h), then held
     * over the step as point forces. The solve predicts with each guide's Euler step;
     * guides given TR-BDF2 take the penalty forces instead, implicit through their
     * linearisation in each guide's own step (block Jacobi, penalty_forces): with the
     * solve's impulses held constant in TR-BDF2 steps, a full head of 1 m guides flew
     * apart (pairs 54,000 to 1,800 in 8 frames, 103 guides recovered), and correcting
     * the TR-BDF2 steps afterwards with the impulses (a splitting) threw 20 cm guides
     * 10 cm a frame; block Jacobi holds them together but long guides whip
     * (hk_hair_sim_def_for). */
    const int coupled = sim->options.dynamics.integrator == HK_INTEGRATOR_LINEAR_EULER;
    hk_Status st = HK_OK;
    /* The evaluations of the solve's predictions, counted by the solve: summed here
     * from the guides' stats before and after, on the master between the parallel
     * regions, they read a line of every guide last written on either core. */
    long predicted = 0;
    int swept = 0; /* the solve's impulses are found, to be finished with the commits */
    hk_RigidState head_end = hk_rigid_identity();
    if (head_fn) head_fn(user, t + dt, &head_end);
    if (sim->contacts) {
        /* The samples at t: those the last step took at its end when the head is where
         * it was then (to the bit), else taken now. */
        if (!sim->sampled || memcmp(&head, &sim->sampled_head, sizeof head) != 0) {
#pragma omp parallel for schedule(static) num_threads(threads)
            for (int i = 0; i < sim->guide_count; i++) sample_guide(sim, i, &head);
        }
        sim->sampled = 0;
        hk_hc_set_geometry_only(sim->contacts, coupled); /* the solve takes no penalty forces */
        if (coupled && threads > 1) {
            st = hk_contact_solve_open(sim->contact_solve, sim->dyn, sim->guide_count, err);
            if (st == HK_OK) st = overlapped_step(sim, &head_end, dt, threads, err);
        } else {
            st = hk_hair_contacts_update(sim->contacts, sim->samples, sim->guide_count, err);
        }
        local.contact_pairs = hk_hair_contacts_pair_count(sim->contacts);
        if (st == HK_OK && !coupled) local.contacts = hk_hair_contacts_contact_count(sim->contacts);
        if (st == HK_OK && coupled) {
            hk_ContactSolveStats cstats;
            st = hk_contact_solve_sweep(sim->contact_solve, sim->contacts, sim->dyn, sim->guide_count, &head_end, dt,
                                        &cstats, err);
            swept = st == HK_OK;
            predicted = swept ? cstats.evaluations : 0;
            local.contacts = cstats.pushing;
            local.sticking = cstats.sticking;
            local.contact_sweeps = cstats.sweeps;
        }
    }
    int substeps = 0, body = 0, recovered = 0;
    long iterations = 0;
    hk_FirstError first;
    hk_first_error_init(&first);
    if (st == HK_OK) {
        /* The solve finished (its forces and the guide's velocity change) guide by
         * guide, each just before its commit: no parallel region of its own, and no
         * barrier in this one. */
#pragma omp parallel reduction(+ : substeps, body, recovered, iterations) num_threads(threads)
        {
#pragma omp for schedule(dynamic, 4)
            for (int i = 0; i < sim->guide_count; i++) {
                if (swept) hk_contact_solve_finish_strand(sim->contact_solve, i);
                const GuideStep g = step_guide(sim, i, head_fn, user, t, dt, coupled, &head_end, &first);
                substeps += g.taken, recovered += g.recovered, iterations += g.iterations;
                body += hk_strand_dynamics_contact_count(sim->dyn[i]);
                /* The next step's samples of the guide, at its state and the head's pose
                 * at t + dt (where its step placed it), while both are in the cache: the
                 * next step takes them when its head is in that pose. */
                if (sim->contacts) sample_guide(sim, i, &head_end);
            }
        }
    }
    if (st == HK_OK && first.index >= 0)
        st = hk_error_set(err, first.error.code, "guide %ld at t = %.4g s: %s", first.index, t, first.error.message);
    if (st == HK_OK) {
        if (head_fn)
            head_fn(user, t + dt, &sim->head);
        else
            sim->head = hk_rigid_identity();
        sim->sampled = sim->contacts != NULL;
        sim->sampled_head = head_end;
    }
    local.substeps = substeps;
    local.iterations = iterations + predicted;
    local.recovered = recovered;
    local.body_contacts = body;
    local.seconds = hk_seconds_now() - t0;
    if (stats) *stats = local;
    return st;
}

void hk_hair_sim_guides(const hk_HairSim *sim, double *out)
{
#pragma omp parallel for schedule(static) num_threads(sim_threads(sim))
    for (int i = 0; i < sim->guide_count; i++) {
        hk_Vec3 buf[512], *p = sim->points <= 512 ? buf : hk_alloc_array((size_t)sim->points, sizeof(hk_Vec3), NULL);
        if (!p) continue;
        hk_superhelix_sample(sim->strand[i], NULL, sim->style.strand.visuality_step, NULL, p, NULL);
        double *o = out + (size_t)i * (size_t)sim->points * 3;
        for (int j = 0; j < sim->points; j++) {
            o[3 * j] = p[j].x;
            o[3 * j + 1] = p[j].y;
            o[3 * j + 2] = p[j].z;
        }
        if (p != buf) hk_free(p);
    }
}

hk_RigidState hk_sim_head_now(const hk_HairSim *sim) { return sim->head; }

hk_Status hk_hair_sim_groom(const hk_HairSim *sim, const hk_Mesh *wick, const hk_GroomDef *go, hk_Groom *g,
                            hk_Error *err)
{
    memset(g, 0, sizeof *g);
    g->points_per_strand = sim->points;
    g->guide_count = sim->guide_count;
    g->guides = hk_alloc_array((size_t)sim->guide_count * (size_t)sim->points, 3 * sizeof(double), err);
    if (!g->guides) return HK_ERR_NOMEM;
    hk_hair_sim_guides(sim, g->guides);
    /* The strands are kept out of the body where it is now: the shapes go where the
     * head took them (the guides, and so the strands, are in world space). */
    hk_GroomDef o = go ? *go : hk_default_groom_def();
    if (o.threads <= 0) o.threads = sim->options.threads;
    hk_Status st = hk_sim_interpolate_posed(&sim->style, sim->shapes, sim->shape_count, &sim->head, wick, &o, g, err);
    if (st != HK_OK) hk_groom_free(g);
    return st;
}
