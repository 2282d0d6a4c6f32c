/* A simulation written to a folder (docs/dynamics.md, "The full head"): the setup's
 * guides solved at rest and settled, then per frame advanced with the head's motion and
 * written as DIR/guides_kkkk.hair, the interpolated hair regrown from the guides as
 * written and rendered to DIR/frame_kkkk.png (the full .hair only when asked: 60 MB a
 * frame on the default head, rebuilt exactly from the guides by sim_rebuild.c). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hairkit/simulation_file.h"
#include "sim_internal.h"

hk_SimRunOptions hk_default_sim_run_options(void)
{
    hk_SimRunOptions o;
    memset(&o, 0, sizeof o);
    o.frames = 1;
    o.fps = 30.0;
    o.preroll = 1.0;
    o.preroll_max = 5.0;
    o.hair_contacts = 1;
    o.damping = 1;
    o.integrator = -1;
    o.video = 1;
    o.seed = 1;
    o.render = hk_default_render_options();
    return o;
}

typedef struct Run {
    const char *dir;
    const hk_SimRunOptions *o;
    hk_SetupDef setup;
    hk_HairstyleDef style;
    hk_Shape *shapes;
    int shape_count;
    hk_Mesh head, moved, wick;
    hk_VisualityDef vis;
    hk_HairSim *sim;
    hk_RenderOptions ro;  /* the camera fixed at frame 0 */
    hk_Renderer *renderer; /* its memory kept from frame to frame */
    hk_Groom groom;       /* the frame's guides and strands, arrays reused */
    hk_SimProgress p;
} Run;

static void run_free(Run *r)
{
    hk_hair_sim_destroy(r->sim);
    hk_renderer_destroy(r->renderer);
    hk_groom_free(&r->groom);
    hk_mesh_free(&r->head);
    hk_free(r->moved.positions);
    hk_free(r->moved.normals);
    hk_mesh_free(&r->wick);
    hk_free(r->shapes);
    hk_hairstyle_free(&r->style);
    hk_setup_free(&r->setup);
}

static hk_Status load_scene(Run *r, const char *setup_path, hk_Error *err)
{
    hk_Status st = hk_setup_load(setup_path, &r->setup, err);
    if (st != HK_OK) return st;
    if (!r->setup.hairstyle || !r->setup.wick_model)
        return hk_error_set(err, HK_ERR_PARSE, "%s: simulating needs HairstyleInfo and WickModel", setup_path);
    if ((st = hk_hairstyle_load(r->setup.hairstyle, &r->style, err)) != HK_OK) return st;
    if (r->setup.collision &&
        (st = hk_collision_load(r->setup.collision, &r->shapes, &r->shape_count, err)) != HK_OK)
        return st;
    if ((st = hk_obj_load(r->setup.wick_model, &r->wick, err)) != HK_OK) return st;
    if (r->setup.head_model) {
        if ((st = hk_obj_load(r->setup.head_model, &r->head, err)) != HK_OK) return st;
        r->moved = r->head;
        r->moved.positions = hk_alloc_array((size_t)r->head.vertex_count, sizeof(hk_Vec3), err);
        r->moved.normals = hk_alloc_array((size_t)r->head.vertex_count, sizeof(hk_Vec3), err);
        if (!r->moved.positions || !r->moved.normals) return HK_ERR_NOMEM;
    }
    if (r->setup.visuality && (st = hk_visuality_load(r->setup.visuality, &r->vis, err)) != HK_OK) return st;
    return HK_OK;
}

/* Made if missing, emptied of an earlier run's frames (whose pictures a new hair.mp4
 * would otherwise pick up). */
static hk_Status prepare_folder(Run *r, hk_Error *err)
{
    if (mkdir(r->dir, 0777) != 0 && errno != EEXIST)
        return hk_error_set(err, HK_ERR_IO, "%s: cannot make the folder: %s", r->dir, strerror(errno));
    struct stat s;
    if (stat(r->dir, &s) != 0 || !S_ISDIR(s.st_mode))
        return hk_error_set(err, HK_ERR_IO, "%s: not a folder", r->dir);
    return hk_simulation_clean_folder(r->dir, &r->p.removed, err);
}

static hk_Status write_manifest(Run *r, const char *setup_path, hk_Error *err)
{
    hk_SimulationManifest m;
    memset(&m, 0, sizeof m);
    /* Absolute: the folder may be moved or read from anywhere; the fingerprints catch a
     * setup that changed since. */
    m.setup = realpath(setup_path, NULL);
    if (!m.setup) return hk_error_set(err, HK_ERR_IO, "%s: %s", setup_path, strerror(errno));
    m.seed = r->o->seed;
    m.frames = r->o->frames;
    m.fps = r->o->fps;
    m.guides = hk_hair_sim_guide_count(r->sim);
    m.points = hk_hair_sim_points_per_strand(r->sim);
    m.interpolated = !r->o->guides_only;
    m.full_hair = r->o->full_hair;
    hk_Status st = hk_file_fingerprint(r->setup.hairstyle, &m.hairstyle_hash, err);
    if (st == HK_OK) st = hk_file_fingerprint(r->setup.wick_model, &m.wick_hash, err);
    m.has_collision = r->setup.collision != NULL;
    if (st == HK_OK && m.has_collision) st = hk_file_fingerprint(r->setup.collision, &m.collision_hash, err);
    /* The motion poses the body of every frame: made again by the rebuild. */
    const hk_HeadMotionSource src = r->o->motion ? hk_head_motion_source(r->o->motion)
                                                 : (hk_HeadMotionSource){"still", 0.0, 1.0, hk_default_head_pivot(), NULL};
    char script[32] = "";
    if (src.script) snprintf(script, sizeof script, "%s", src.script);
    m.motion_script = src.script ? script : NULL;
    m.motion_amplitude = src.amplitude;
    m.motion_frequency = src.frequency;
    m.motion_pivot[0] = src.pivot.x;
    m.motion_pivot[1] = src.pivot.y;
    m.motion_pivot[2] = src.pivot.z;
    if (st == HK_OK && src.file) {
        m.motion_file = realpath(src.file, NULL);
        if (!m.motion_file) st = hk_error_set(err, HK_ERR_IO, "%s: %s", src.file, strerror(errno));
        else st = hk_file_fingerprint(src.file, &m.motion_hash, err);
    }
    char path[4096];
    if (st == HK_OK && snprintf(path, sizeof path, "%s/%s", r->dir, HK_SIMULATION_FILE_NAME) >= (int)sizeof path)
        st = hk_error_set(err, HK_ERR_INVALID, "%s: output folder name too long", r->dir);
    if (st == HK_OK) st = hk_simulation_manifest_save(path, &m, err);
    if (st == HK_OK) r->p.bytes += hk_sim_file_size(path);
    free(m.setup);
    free(m.motion_file);
    return st;
}

static hk_Status create_sim(Run *r, hk_Error *err)
{
    const hk_SimRunOptions *o = r->o;
    hk_HairSimOptions so = hk_default_hair_sim_options(&r->style);
    so.threads = o->threads;
    so.hair_contacts = o->hair_contacts;
    if (!o->damping) so.dynamics.internal_friction = so.dynamics.air_drag = 0.0;
    if (o->integrator == HK_INTEGRATOR_TRBDF2) {
        const hk_DynamicsParams strand = hk_default_dynamics_params();
        so.dynamics.integrator = HK_INTEGRATOR_TRBDF2;
        so.dynamics.solver = strand.solver;
        so.dynamics.stiffness = strand.stiffness;
    } else if (o->integrator == HK_INTEGRATOR_LINEAR_EULER) {
        so.dynamics.integrator = HK_INTEGRATOR_LINEAR_EULER;
        so.dynamics.solver = HK_DYNAMICS_DENSE;
        so.dynamics.stiffness = HK_STIFFNESS_FULL;
    }
    so.progress = o->statics_progress;
    so.progress_user = o->statics_user;
    hk_Status st = hk_hair_sim_create(&r->style, r->shapes, r->shape_count, &r->wick, &so, &r->sim, err);
    if (st == HK_OK && (o->preroll > 0.0 || o->preroll_max > 0.0)) {
        const hk_RigidState pose = hk_sim_head_pose(o->motion, 0.0);
        hk_SettleOptions settle = hk_default_settle_options();
        settle.seconds = o->preroll;
        settle.max_seconds = fmax(o->preroll, o->preroll_max);
        hk_SettleReport report;
        st = hk_hair_sim_settle_until_still(r->sim, &pose, 1.0 / o->fps, &settle, &report, err);
        r->p.preroll = report.seconds;
        r->p.preroll_at_rest = report.at_rest;
    }
    if (st != HK_OK) return st;
    r->groom.points_per_strand = hk_hair_sim_points_per_strand(r->sim);
    r->groom.guide_count = hk_hair_sim_guide_count(r->sim);
    r->groom.guides = hk_alloc_array((size_t)r->groom.guide_count * (size_t)r->groom.points_per_strand,
                                     3 * sizeof(double), err);
    return r->groom.guides ? HK_OK : HK_ERR_NOMEM;
}

static hk_Status save_hair(Run *r, const hk_HairFile *hair, const char *stem, long k, hk_Error *err)
{
    char path[4096];
    hk_Status st = hk_simulation_frame_path(path, sizeof path, r->dir, stem, k, "hair", err);
    if (st == HK_OK) st = hk_hair_save(path, hair, err);
    if (st == HK_OK) r->p.bytes += hk_sim_file_size(path);
    return st;
}

/* The head mesh moved by the head's rigid state at t (positions and normals). */
static const hk_Mesh *moved_head(Run *r, double t)
{
    if (r->head.vertex_count == 0) return NULL;
    const hk_RigidState st = hk_sim_head_pose(r->o->motion, t);
    for (int i = 0; i < r->head.vertex_count; i++) {
        hk_rigid_point(&st, r->head.positions[i], &r->moved.positions[i], NULL, NULL);
        r->moved.normals[i] = hk_m3_mul_v3(&st.rot, r->head.normals[i]);
    }
    return &r->moved;
}

/* The picture of frame k. The camera is fixed at the first frame's fit, backed off by
 * 15 % to leave room for the hair's motion. */
static hk_Status render_frame(Run *r, const hk_HairFile *hair, long k, double t, hk_Error *err)
{
    double t0 = omp_get_wtime();
    const hk_Mesh *head = moved_head(r, t);
    hk_Status st = HK_OK;
    if (!(r->ro.camera_distance > 0.0)) {
        st = hk_render_fit_camera(hair, head, &r->ro, &r->ro.camera_target, &r->ro.camera_distance, err);
        r->ro.camera_distance *= 1.15;
    }
    if (st == HK_OK && !r->renderer) st = hk_renderer_create(&r->renderer, err);
    if (st == HK_OK) st = hk_renderer_draw(r->renderer, hair, head, &r->vis, &r->ro, NULL, err);
    const double t1 = omp_get_wtime();
    r->p.seconds_render += t1 - t0;
    char path[4096];
    if (st == HK_OK) st = hk_simulation_frame_path(path, sizeof path, r->dir, "frame", k, "png", err);
    if (st == HK_OK) st = hk_render_write_png(hk_renderer_picture(r->renderer), path, err);
    if (st == HK_OK) r->p.bytes += hk_sim_file_size(path);
    r->p.seconds_write += omp_get_wtime() - t1;
    return st;
}

/* Frame k at time t: the guides, then (unless guides only) the interpolated hair grown
 * from them as written, out of the body where the head is at t, and its picture. */
static hk_Status write_frame(Run *r, long k, double t, hk_Error *err)
{
    const hk_SimRunOptions *o = r->o;
    hk_Groom *g = &r->groom;
    double t0 = omp_get_wtime();
    hk_hair_sim_guides(r->sim, g->guides);
    hk_sim_round_guides(g->guides, (size_t)g->guide_count * (size_t)g->points_per_strand * 3);
    hk_Groom guides_view = *g;
    guides_view.strand_count = 0;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Status st = hk_groom_to_hair(&guides_view, &r->style, &hair, err);
    double t1 = omp_get_wtime();
    r->p.seconds_regrow += t1 - t0;
    if (st == HK_OK) st = save_hair(r, &hair, "guides", k, err);
    hk_hair_free(&hair);
    double t2 = omp_get_wtime();
    r->p.seconds_write += t2 - t1;
    if (st != HK_OK || o->guides_only) return st;
    const hk_RigidState head = hk_sim_head_pose(o->motion, t);
    st = hk_sim_grow_hair(&r->style, r->shapes, r->shape_count, &head, &r->wick, o->seed, o->threads, 0, g, &hair,
                          err);
    r->p.seconds_regrow += omp_get_wtime() - t2;
    if (st == HK_OK && o->full_hair) {
        t2 = omp_get_wtime();
        st = save_hair(r, &hair, "frame", k, err);
        r->p.seconds_write += omp_get_wtime() - t2;
    }
    if (st == HK_OK) st = render_frame(r, &hair, k, t, err);
    hk_hair_free(&hair);
    return st;
}

static hk_Status check_options(const hk_SimRunOptions *o, hk_Error *err)
{
    if (o->frames < 1 || o->frames > 100000)
        return hk_error_set(err, HK_ERR_INVALID, "%ld frames: must be 1 to 100000", o->frames);
    if (!(o->fps >= 1.0 && o->fps <= 100000.0))
        return hk_error_set(err, HK_ERR_INVALID, "%g frames per second: must be 1 to 100000", o->fps);
    if (!(o->preroll >= 0.0 && o->preroll <= 100.0))
        return hk_error_set(err, HK_ERR_INVALID, "preroll %g s: must be 0 to 100", o->preroll);
    if (!(o->preroll_max >= 0.0 && o->preroll_max <= 100.0))
        return hk_error_set(err, HK_ERR_INVALID, "longest preroll %g s: must be 0 to 100", o->preroll_max);
    return HK_OK;
}

hk_Status hk_simulation_run(const char *setup_path, const char *dir, const hk_SimRunOptions *options,
                            hk_SimProgress *progress, hk_Error *err)
{
    Run r;
    memset(&r, 0, sizeof r);
    r.dir = dir;
    r.o = options;
    r.vis = hk_default_visuality();
    r.ro = options->render;
    r.ro.threads = options->threads;
    r.p.frames = options->frames;
    const double t_start = omp_get_wtime();
    hk_Status st = check_options(options, err);
    if (st == HK_OK) st = load_scene(&r, setup_path, err);
    if (st == HK_OK) st = prepare_folder(&r, err);
    if (st == HK_OK) st = create_sim(&r, err);
    if (st == HK_OK) st = write_manifest(&r, setup_path, err);
    if (st == HK_OK) {
        r.p.guides = hk_hair_sim_guide_count(r.sim);
        r.p.elements = r.style.element_count;
        r.p.seconds_setup = omp_get_wtime() - t_start;
        if (options->progress) options->progress(options->progress_user, &r.p);
    }
    const double t_frames = omp_get_wtime(), dt = 1.0 / options->fps;
    for (long k = 0; st == HK_OK && k < options->frames; k++) {
        const double t = hk_sim_frame_time(k, options->fps); /* k * dt, as the rebuild poses the body */
        if (k > 0) {
            hk_HairSimStats stats;
            st = hk_hair_sim_advance(r.sim, options->motion, t - dt, dt, &stats, err);
            r.p.seconds_dynamics += stats.seconds;
            r.p.substeps += stats.substeps;
        }
        if (st == HK_OK) st = write_frame(&r, k, t, err);
        if (st != HK_OK) break;
        r.p.frame = k + 1;
        r.p.seconds = omp_get_wtime() - t_frames;
        if (options->progress) options->progress(options->progress_user, &r.p);
    }
    if (st == HK_OK && options->video && !options->guides_only) {
        char video[4096];
        r.p.video = hk_sim_make_video(dir, options->fps);
        if (r.p.video > 0 && snprintf(video, sizeof video, "%s/hair.mp4", dir) < (int)sizeof video)
            r.p.bytes += hk_sim_file_size(video);
        r.p.seconds = omp_get_wtime() - t_frames;
    }
    if (progress) *progress = r.p;
    run_free(&r);
    return st;
}
