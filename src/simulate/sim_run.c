/* A simulation written to a folder (docs/dynamics.md, "The full head"): the setup's
 * guides solved at rest and settled, then per frame advanced with the head's motion and
 * written as DIR/guides_kkkk.hair, the interpolated hair regrown from the guides as
 * written and rendered to DIR/frame_kkkk.png (the full .hair only when asked: 60 MB a
 * frame on the default head, rebuilt exactly from the guides by sim_rebuild.c). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <math.h>
#include <omp.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hairkit/scene.h"
#include "hairkit/simulation_file.h"
#include "io/io_internal.h"
#include "sim_internal.h"

hk_SimRunDef hk_default_sim_run_def(void)
{
    hk_SimRunDef o;
    memset(&o, 0, sizeof o);
    o.frames = 1;
    o.fps = 30.0;
    o.preroll = 1.0;
    o.preroll_max = 5.0;
    o.hair_contacts = 1;
    o.damping = 1;
    o.integrator = HK_INTEGRATOR_AUTO;
    o.video = 1;
    o.seed = 1;
    o.render = hk_default_render_def();
    return o;
}

/* Frames drawn at once, each on a thread of its own (one OpenMP thread each on two
 * cores): a frame's regrowth, picture and files depend only on its guides, so frame k
 * can be drawn while frame k + 1 is, and the guides of k + 2 are stepped. Two pictures
 * with one thread each keep both cores busy, where one picture with two threads left
 * them waiting on each other at the ends of its parallel loops (libgomp's spinning was
 * 6 to 9 % of the run's samples) and in its serial parts (compressing the PNG,
 * the bins' offsets, the light's maps cleared). Every file is the same bytes: nothing a
 * frame writes depends on the threads (docs/dynamics.md). */
#define MAX_AT_ONCE 2

struct Run;

/* One frame's regrowth, picture and files; its buffers kept for its next frame. */
typedef struct FrameJob {
    struct Run *run;
    hk_Renderer *renderer; /* its memory kept from frame to frame */
    hk_Groom groom;        /* the frame's guides (a copy) and strands, arrays reused */
    hk_HairFile hair;      /* the frame's hair, arrays reused */
    hk_Mesh moved;         /* the head where it is at the frame */
    long k;
    double t;
    int threads;  /* OpenMP threads of the job */
    int busy;     /* started and not yet collected */
    int threaded; /* on a thread of its own */
    pthread_t thread;
    hk_Status st;
    hk_Error err;
    double seconds_regrow, seconds_render, seconds_write;
    long long bytes;
} FrameJob;

typedef struct Run {
    const char *dir;
    const hk_SimRunDef *o;
    hk_Scene scene; /* the setup and every part of it */
    hk_HairSim *sim;
    hk_RenderDef ro; /* the camera fixed at frame 0 */
    hk_Groom groom;  /* the guides being stepped (guides array only) */
    int imported;    /* the setup's ImportFile: guides of an import, every strand
                        rebuilt from them (hk_imported_groom_strands) */
    hk_ImportedGroom import;
    hk_HairFile strands; /* imported: the frame's strands, in input order */
    FrameJob jobs[MAX_AT_ONCE];
    int threads;     /* the run's threads (options, or OpenMP's default) */
    int at_once;     /* jobs in use */
    double t_frames; /* when the first frame began */
    hk_SimProgress p;
} Run;

static void run_free(Run *r)
{
    hk_hair_sim_destroy(r->sim);
    for (int j = 0; j < MAX_AT_ONCE; j++) {
        hk_renderer_destroy(r->jobs[j].renderer);
        hk_groom_free(&r->jobs[j].groom);
        hk_hair_free(&r->jobs[j].hair);
        hk_free(r->jobs[j].moved.positions);
        hk_free(r->jobs[j].moved.normals);
    }
    hk_groom_free(&r->groom);
    hk_imported_groom_free(&r->import);
    hk_hair_free(&r->strands);
    hk_scene_free(&r->scene);
}

static hk_Status load_scene(Run *r, const char *setup_path, hk_Error *err)
{
    hk_Status st = hk_scene_load(setup_path, 0, &r->scene, err);
    if (st != HK_OK) return st;
    /* The guides are grown from the hairstyle and the wick: hair read from LoadFile
     * cannot be simulated yet (its strands are no Super-Helices; issue 15), and growing
     * other hair in its place would ignore the setup's key silently. */
    r->imported = r->scene.setup.import_file != NULL;
    if (r->imported) {
        if (!r->scene.setup.hairstyle)
            return hk_error_set(err, HK_ERR_PARSE, "%s: simulating an import needs HairstyleInfo", setup_path);
        st = hk_scene_load_parts(&r->scene, HK_SCENE_HAIRSTYLE | HK_SCENE_COLLISION | HK_SCENE_RENDERING, err);
        if (st == HK_OK) st = hk_imported_groom_load(r->scene.setup.import_file, &r->import, err);
        /* the frames' hair: the captured strands' layout (a .hair of every strand) */
        hk_HairFile *h = &r->strands;
        if (st == HK_OK) {
            h->strand_count = (uint32_t)r->import.strand_count;
            h->point_count = r->import.first_point[r->import.strand_count];
            h->flags = HK_HAIR_POINTS | HK_HAIR_SEGMENTS;
            h->default_thickness = (float)(r->scene.style.strand.radius1 + r->scene.style.strand.radius2);
            h->segments = hk_alloc_array(h->strand_count, sizeof(uint16_t), err);
            h->points = hk_alloc_array(h->point_count, 3 * sizeof(float), err);
            h->first_point = hk_alloc_array((size_t)h->strand_count + 1, sizeof(uint32_t), err);
            if (!h->segments || !h->points || !h->first_point) return HK_ERR_NOMEM;
            memcpy(h->first_point, r->import.first_point, ((size_t)h->strand_count + 1) * sizeof(uint32_t));
            for (uint32_t i = 0; i < h->strand_count; i++)
                h->segments[i] = (uint16_t)(h->first_point[i + 1] - h->first_point[i] - 1);
        }
    }
    if (r->imported && st == HK_OK) {
        const hk_Mesh *head = &r->scene.head;
        for (int j = 0; head->vertex_count > 0 && j < MAX_AT_ONCE; j++) {
            hk_Mesh *m = &r->jobs[j].moved;
            *m = *head;
            m->positions = hk_alloc_array((size_t)head->vertex_count, sizeof(hk_Vec3), err);
            m->normals = hk_alloc_array((size_t)head->vertex_count, sizeof(hk_Vec3), err);
            if (!m->positions || !m->normals) return HK_ERR_NOMEM;
        }
    }
    if (r->imported) return st;
    if (r->scene.setup.load)
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: Load true: simulate grows its guides from HairstyleInfo and WickModel and cannot "
                            "simulate the hair of LoadFile (%s); set Load false",
                            setup_path, r->scene.setup.load_file);
    if (!r->scene.setup.hairstyle || !r->scene.setup.wick_model)
        return hk_error_set(err, HK_ERR_PARSE, "%s: simulating needs HairstyleInfo and WickModel", setup_path);
    if ((st = hk_scene_load_parts(&r->scene, HK_SCENE_ALL, err)) != HK_OK) return st;
    const hk_Mesh *head = &r->scene.head;
    for (int j = 0; head->vertex_count > 0 && j < MAX_AT_ONCE; j++) {
        hk_Mesh *m = &r->jobs[j].moved;
        *m = *head;
        m->positions = hk_alloc_array((size_t)head->vertex_count, sizeof(hk_Vec3), err);
        m->normals = hk_alloc_array((size_t)head->vertex_count, sizeof(hk_Vec3), err);
        if (!m->positions || !m->normals) return HK_ERR_NOMEM;
    }
    return HK_OK;
}

/* Made if missing, emptied of an earlier run's frames (whose pictures a new hair.mp4
 * would otherwise pick up). */
static hk_Status prepare_folder(Run *r, hk_Error *err)
{
    if (mkdir(r->dir, 0777) != 0 && errno != EEXIST)
        return hk_error_set(err, HK_ERR_IO, "%s: cannot make the folder: %s", r->dir, strerror(errno));
    struct stat s;
    if (stat(r->dir, &s) != 0 || !S_ISDIR(s.st_mode)) return hk_error_set(err, HK_ERR_IO, "%s: not a folder", r->dir);
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
    hk_Status st = hk_file_fingerprint(r->scene.setup.hairstyle, &m.hairstyle_hash, err);
    /* an import has no wick: its frames are written whole (hk_simulation_rebuild refuses it) */
    if (st == HK_OK && r->scene.setup.wick_model)
        st = hk_file_fingerprint(r->scene.setup.wick_model, &m.wick_hash, err);
    m.has_collision = r->scene.setup.collision != NULL;
    if (st == HK_OK && m.has_collision) st = hk_collision_fingerprint(r->scene.setup.collision, &m.collision_hash, err);
    /* The motion poses the body of every frame: made again by the rebuild. */
    const hk_HeadMotionSource src = r->o->motion
                                        ? hk_head_motion_source(r->o->motion)
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
        if (!m.motion_file)
            st = hk_error_set(err, HK_ERR_IO, "%s: %s", src.file, strerror(errno));
        else
            st = hk_file_fingerprint(src.file, &m.motion_hash, err);
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
    const hk_SimRunDef *o = r->o;
    hk_HairSimDef so = hk_hair_sim_def_for(&r->scene.style);
    so.threads = r->threads; /* all of them until frame 0 is drawn, then fewer (hk_hair_sim_set_threads) */
    so.hair_contacts = o->hair_contacts;
    if (!o->damping) so.dynamics.internal_friction = so.dynamics.air_drag = 0.0;
    if (o->integrator == HK_INTEGRATOR_TRBDF2) {
        const hk_DynamicsDef strand = hk_default_dynamics_def();
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
    hk_Status st = r->imported ? hk_hair_sim_create_imported(&r->scene.style, r->scene.collision.shapes,
                                                             r->scene.collision.count, &r->import, &so, &r->sim, err)
                               : hk_hair_sim_create(&r->scene.style, r->scene.collision.shapes,
                                                    r->scene.collision.count, &r->scene.wick, &so, &r->sim, err);
    if (st == HK_OK && (o->preroll > 0.0 || o->preroll_max > 0.0)) {
        const hk_RigidState pose = hk_sim_head_pose(o->motion, 0.0);
        hk_SettleDef settle = hk_default_settle_def();
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
    r->groom.guides =
        hk_alloc_array((size_t)r->groom.guide_count * (size_t)r->groom.points_per_strand, 3 * sizeof(double), err);
    return r->groom.guides ? HK_OK : HK_ERR_NOMEM;
}

static hk_Status save_hair(Run *r, const hk_HairFile *hair, const char *stem, long k, long long *bytes, hk_Error *err)
{
    char path[4096];
    hk_Status st = hk_simulation_frame_path(path, sizeof path, r->dir, stem, k, "hair", err);
    if (st == HK_OK) st = hk_hair_save(path, hair, err);
    if (st == HK_OK) *bytes += hk_sim_file_size(path);
    return st;
}

/* The head mesh moved by the head's rigid state at t (positions and normals). */
static const hk_Mesh *moved_head(Run *r, hk_Mesh *moved, double t)
{
    if (r->scene.head.vertex_count == 0) return NULL;
    const hk_RigidState st = hk_sim_head_pose(r->o->motion, t);
    for (int i = 0; i < r->scene.head.vertex_count; i++) {
        hk_rigid_point(&st, r->scene.head.positions[i], &moved->positions[i], NULL, NULL);
        moved->normals[i] = hk_m3_mul_v3(&st.rot, r->scene.head.normals[i]);
    }
    return moved;
}

/* The camera, fixed at the first frame's fit, backed off by 15 % to leave room for the
 * hair's motion: fitted to the job's frame (its hair, its head moved to j->t) when none
 * is yet. */
static hk_Status fit_camera(FrameJob *j, const hk_HairFile *hair, const hk_Mesh *head)
{
    Run *r = j->run;
    if (r->ro.camera_distance > 0.0) return HK_OK;
    const hk_Status st =
        hk_render_fit_camera(hair, head, &r->ro, &r->ro.camera_target, &r->ro.camera_distance, &j->err);
    r->ro.camera_distance *= 1.15;
    return st;
}

/* The picture of the job's frame, with the camera of the first frame (fit_camera:
 * fitted before any other frame is drawn). */
static hk_Status render_frame(FrameJob *j, const hk_HairFile *hair)
{
    Run *r = j->run;
    hk_Error *err = &j->err;
    double t0 = omp_get_wtime();
    const hk_Mesh *head = moved_head(r, &j->moved, j->t);
    hk_Status st = fit_camera(j, hair, head);
    hk_RenderDef ro = r->ro;
    ro.threads = j->threads;
    if (st == HK_OK && !j->renderer) st = hk_renderer_create(&j->renderer, err);
    if (st == HK_OK) st = hk_renderer_draw(j->renderer, hair, head, &r->scene.visuality, &ro, NULL, err);
    const double t1 = omp_get_wtime();
    j->seconds_render += t1 - t0;
    char path[4096];
    if (st == HK_OK) st = hk_simulation_frame_path(path, sizeof path, r->dir, "frame", j->k, "png", err);
    if (st == HK_OK) st = hk_render_write_png(hk_renderer_picture(j->renderer), path, err);
    if (st == HK_OK) j->bytes += hk_sim_file_size(path);
    j->seconds_write += omp_get_wtime() - t1;
    return st;
}

/* The job's interpolated hair, grown from its guides as written, out of the body where
 * the head is at t. */
static void regrow_frame(FrameJob *j)
{
    Run *r = j->run;
    const hk_SimRunDef *o = r->o;
    const double t0 = omp_get_wtime();
    const hk_RigidState head = hk_sim_head_pose(o->motion, j->t);
    j->st = hk_sim_grow_hair(&r->scene.style, r->scene.collision.shapes, r->scene.collision.count, &head,
                             &r->scene.wick, o->seed, j->threads, 0, 1, &j->groom, &j->hair, &j->err);
    j->seconds_regrow += omp_get_wtime() - t0;
}

/* The job's full hair when asked, and its picture (on the job's thread). */
static void *draw_job(void *arg)
{
    FrameJob *j = arg;
    Run *r = j->run;
    if (j->st == HK_OK && r->o->full_hair) {
        const double t0 = omp_get_wtime();
        j->st = save_hair(r, &j->hair, "frame", j->k, &j->bytes, &j->err);
        j->seconds_write += omp_get_wtime() - t0;
    }
    if (j->st == HK_OK) j->st = render_frame(j, &j->hair);
    return NULL;
}

/* The job's frame: its hair regrown and drawn (on the job's thread). */
static void *frame_job(void *arg)
{
    regrow_frame(arg);
    return draw_job(arg);
}

/* Frame k is written, and every frame before it. */
static void report_frame(Run *r, long k)
{
    r->p.frame = k + 1;
    r->p.seconds = omp_get_wtime() - r->t_frames;
    if (r->o->progress) r->o->progress(r->o->progress_user, &r->p);
}

/* Waits for a job's frame and adds its figures (reported when `report`); its status,
 * with its error in err. */
static hk_Status collect(Run *r, FrameJob *j, int report, hk_Error *err)
{
    if (!j->busy) return HK_OK;
    if (j->threaded) pthread_join(j->thread, NULL);
    j->busy = j->threaded = 0;
    r->p.seconds_regrow += j->seconds_regrow, r->p.seconds_render += j->seconds_render;
    r->p.seconds_write += j->seconds_write, r->p.bytes += j->bytes;
    j->seconds_regrow = j->seconds_render = j->seconds_write = 0.0, j->bytes = 0;
    if (j->st != HK_OK) {
        if (err) *err = j->err;
        return j->st;
    }
    if (report) report_frame(r, j->k);
    return HK_OK;
}

/* Frame k at time t: the guides written (here, in frame order), then the rest handed to
 * a job: on a thread of its own when frames are drawn at once, else here. */
/* An import's frame k: every strand rebuilt from the guides, written whole
 * (DIR/frame_kkkk.hair, input order) and drawn unless guides_only. */
static hk_Status write_imported_frame(Run *r, long k, double t, hk_Error *err)
{
    double t0 = omp_get_wtime();
    hk_Status st =
        hk_imported_groom_strands(&r->import, hk_hair_sim_strands(r->sim), r->threads, r->strands.points, err);
    double t1 = omp_get_wtime();
    r->p.seconds_regrow += t1 - t0;
    if (st == HK_OK) st = save_hair(r, &r->strands, "frame", k, &r->p.bytes, err);
    r->p.seconds_write += omp_get_wtime() - t1;
    if (st == HK_OK && !r->o->guides_only) {
        FrameJob *j = &r->jobs[0];
        j->run = r, j->k = k, j->t = t, j->threads = r->threads;
        st = render_frame(j, &r->strands);
        r->p.seconds_render += j->seconds_render, r->p.seconds_write += j->seconds_write, r->p.bytes += j->bytes;
        j->seconds_render = j->seconds_write = 0.0, j->bytes = 0;
        if (st != HK_OK) *err = j->err;
    }
    if (st == HK_OK) report_frame(r, k);
    return st;
}

static hk_Status write_frame(Run *r, long k, double t, int job_threads, hk_Error *err)
{
    if (r->imported) return write_imported_frame(r, k, t, err);
    const hk_SimRunDef *o = r->o;
    hk_Groom *g = &r->groom;
    double t0 = omp_get_wtime();
    hk_hair_sim_guides(r->sim, g->guides);
    hk_sim_round_guides(g->guides, (size_t)g->guide_count * (size_t)g->points_per_strand * 3);
    hk_Groom guides_view = *g;
    guides_view.strand_count = 0;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Status st = hk_groom_to_hair(&guides_view, &r->scene.style.strand, &hair, err);
    double t1 = omp_get_wtime();
    r->p.seconds_regrow += t1 - t0;
    if (st == HK_OK) st = save_hair(r, &hair, "guides", k, &r->p.bytes, err);
    hk_hair_free(&hair);
    r->p.seconds_write += omp_get_wtime() - t1;
    if (st != HK_OK) return st;
    if (o->guides_only) {
        report_frame(r, k);
        return HK_OK;
    }
    FrameJob *j = &r->jobs[k % r->at_once];
    if ((st = collect(r, j, 1, err)) != HK_OK) return st; /* frame k - at_once */
    const size_t values = (size_t)g->guide_count * (size_t)g->points_per_strand * 3;
    if (!j->groom.guides) {
        j->groom.guide_count = g->guide_count, j->groom.points_per_strand = g->points_per_strand;
        j->groom.guides = hk_alloc_array(values, sizeof(double), err);
        if (!j->groom.guides) return HK_ERR_NOMEM;
    }
    memcpy(j->groom.guides, g->guides, values * sizeof(double));
    j->run = r, j->k = k, j->t = t, j->threads = job_threads, j->busy = 1;
    if (r->at_once == 1) {
        frame_job(j);
        return collect(r, j, 1, err);
    }
    void *(*job)(void *) = frame_job;
    if (k == 0) {
        /* Frame 0 fixes the camera of every frame: its hair is regrown here with every
         * thread and the camera fitted to it; its picture is then drawn as the others
         * are, on a thread of its own beside frame 1's. Drawn alone with every thread,
         * it left a core idle in its serial parts and at its loops' ends, and the frames
         * after it went in pairs (1 and 2, 3 and 4, ...): of an even count the last was
         * drawn alone, one core idle. */
        j->threads = r->threads;
        regrow_frame(j);
        j->threads = job_threads;
        if (j->st == HK_OK) j->st = fit_camera(j, &j->hair, moved_head(r, &j->moved, j->t));
        if (j->st != HK_OK) return collect(r, j, 1, err);
        job = draw_job;
    }
    if (pthread_create(&j->thread, NULL, job, j) != 0) {
        j->busy = 0;
        return hk_error_set(err, HK_ERR_NOMEM, "cannot start a thread for frame %ld", k);
    }
    j->threaded = 1;
    return HK_OK;
}

/* Every job's frame waited for, in frame order; the first failure kept, and no frame
 * reported after it. */
static hk_Status collect_all(Run *r, long next, hk_Status st, hk_Error *err)
{
    for (long k = next - r->at_once; k < next; k++) {
        if (k < 0) continue;
        hk_Error e;
        const hk_Status s = collect(r, &r->jobs[k % r->at_once], st == HK_OK, &e);
        if (st == HK_OK && s != HK_OK) {
            st = s;
            if (err) *err = e;
        }
    }
    return st;
}

static hk_Status check_options(const hk_SimRunDef *o, hk_Error *err)
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

hk_Status hk_simulation_run(const char *setup_path, const char *dir, const hk_SimRunDef *options,
                            hk_SimProgress *progress, hk_Error *err)
{
    const hk_SimRunDef defaults = hk_default_sim_run_def();
    if (!options) options = &defaults;
    Run r;
    memset(&r, 0, sizeof r);
    r.dir = dir;
    r.o = options;
    r.ro = options->render;
    r.p.frames = options->frames;
    /* The threads of the statics, the preroll and the steps (every loop is given its
     * threads: nothing is set for the calling thread). */
    const int threads = options->threads > 0 ? options->threads : omp_get_max_threads();
    r.threads = threads;
    const double t_start = omp_get_wtime();
    hk_Status st = check_options(options, err);
    if (st == HK_OK) st = load_scene(&r, setup_path, err);
    /* an import's frames are rebuilt and drawn one at a time, with every thread */
    r.at_once = threads >= MAX_AT_ONCE && !r.imported ? MAX_AT_ONCE : 1;
    const int job_threads = threads / r.at_once;
    /* While frames are drawn, the steps take the threads the jobs leave (at least one). */
    const int step_threads =
        r.at_once > 1 ? (threads > r.at_once * job_threads ? threads - r.at_once * job_threads : 1) : threads;
    if (st == HK_OK) st = prepare_folder(&r, err);
    if (st == HK_OK) st = create_sim(&r, err);
    if (st == HK_OK) st = write_manifest(&r, setup_path, err);
    if (st == HK_OK) {
        r.p.guides = hk_hair_sim_guide_count(r.sim);
        /* An import's guides each have their own N (hk_superhelix_fit): the range. */
        const hk_SuperHelix *const *strands = hk_hair_sim_strands(r.sim);
        r.p.elements = r.p.elements_min = r.p.guides > 0 ? strands[0]->n : 0;
        for (int g = 1; g < r.p.guides; g++) {
            if (strands[g]->n > r.p.elements) r.p.elements = strands[g]->n;
            if (strands[g]->n < r.p.elements_min) r.p.elements_min = strands[g]->n;
        }
        r.p.seconds_setup = omp_get_wtime() - t_start;
        r.p.frames_at_once = options->guides_only ? 1 : r.at_once;
        if (options->progress) options->progress(options->progress_user, &r.p);
    }
    const double dt = 1.0 / options->fps;
    r.t_frames = omp_get_wtime();
    long k = 0;
    for (; st == HK_OK && k < options->frames; k++) {
        const double t = hk_sim_frame_time(k, options->fps); /* k * dt, as the rebuild poses the body */
        if (k > 0) {
            hk_HairSimStats stats;
            st = hk_hair_sim_advance(r.sim, options->motion, t - dt, dt, &stats, err);
            r.p.seconds_dynamics += stats.seconds;
            r.p.substeps += stats.substeps;
            r.p.recovered += stats.recovered;
        }
        if (st == HK_OK) st = write_frame(&r, k, t, job_threads, err);
        if (k == 0 && r.sim) hk_hair_sim_set_threads(r.sim, step_threads);
    }
    st = collect_all(&r, k, st, err);
    r.p.seconds = omp_get_wtime() - r.t_frames;
    if (st == HK_OK && options->video && !options->guides_only) {
        char video[4096];
        r.p.video = hk_sim_make_video(dir, options->fps);
        if (r.p.video > 0 && snprintf(video, sizeof video, "%s/hair.mp4", dir) < (int)sizeof video)
            r.p.bytes += hk_sim_file_size(video);
        r.p.seconds = omp_get_wtime() - r.t_frames;
    }
    if (progress) *progress = r.p;
    run_free(&r);
    return st;
}
