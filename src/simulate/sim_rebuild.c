/* Any frame's full hair from what a simulation wrote: DIR/simulation.txt names the
 * setup, the seed and the head's motion, DIR/guides_kkkk.hair holds the guides; the
 * interpolated strands are grown from them exactly as the run did, out of the body posed
 * at the frame's time (sim_grow.c), so the bytes are those of the run's
 * DIR/frame_kkkk.hair. */
#include <stdio.h>
#include <string.h>

#include "hairkit/scene.h"
#include "hairkit/simulation_file.h"
#include "io/io_internal.h"
#include "sim_internal.h"

/* What the regrowth reads besides the guides: the setup's hairstyle, wick and body
 * shapes, refused if any changed since the run (or the setup gained or lost its
 * collision file), and the head's motion, made again as the run had it. */
typedef struct Inputs {
    hk_Scene scene; /* the setup with its grooming parts */
    hk_HeadMotion *motion;
} Inputs;

static void inputs_free(Inputs *in)
{
    hk_scene_free(&in->scene);
    hk_head_motion_destroy(in->motion);
}

typedef hk_Status (*Fingerprint)(const char *path, uint64_t *out, hk_Error *err);

/* 1 if the file's fingerprint differs from the manifest's (or it cannot be read). */
static int changed_since_by(Fingerprint fingerprint, const char *path, uint64_t hash, hk_Status *st, hk_Error *err)
{
    uint64_t h = 0;
    *st = fingerprint(path, &h, err);
    return *st == HK_OK && h != hash;
}

static int changed_since(const char *path, uint64_t hash, hk_Status *st, hk_Error *err)
{
    return changed_since_by(hk_file_fingerprint, path, hash, st, err);
}

static hk_Status load_motion(const hk_SimulationManifest *m, const char *manifest_path, Inputs *in, hk_Error *err)
{
    hk_Status st;
    if (m->motion_file) {
        if (changed_since(m->motion_file, m->motion_hash, &st, err))
            return hk_error_set(err, HK_ERR_INVALID,
                                "%s has changed since the simulation (%s): its frames cannot be grown again exactly",
                                m->motion_file, manifest_path);
        return st == HK_OK ? hk_head_motion_load(m->motion_file, &in->motion, err) : st;
    }
    const hk_Vec3 pivot = hk_v3(m->motion_pivot[0], m->motion_pivot[1], m->motion_pivot[2]);
    st = hk_head_motion_scripted(m->motion_script, m->motion_amplitude, m->motion_frequency, pivot, &in->motion, err);
    if (st != HK_OK) {
        hk_Error inner = *err;
        st = hk_error_set(err, st, "%s: %s", manifest_path, inner.message);
    }
    return st;
}

static hk_Status load_inputs(const hk_SimulationManifest *m, const char *manifest_path, Inputs *in, hk_Error *err)
{
    hk_Status st = hk_scene_load(m->setup, 0, &in->scene, err);
    if (st != HK_OK) return st;
    if (in->scene.setup.import_file)
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: the simulation of an import (ImportFile) writes every frame whole: read its "
                            "frame_kkkk.hair",
                            manifest_path);
    const hk_Setup *setup = &in->scene.setup;
    if (!setup->hairstyle || !setup->wick_model)
        st = hk_error_set(err, HK_ERR_PARSE, "%s: no HairstyleInfo or WickModel", m->setup);
    const char *changed = NULL;
    if (st == HK_OK && changed_since(setup->hairstyle, m->hairstyle_hash, &st, err)) changed = setup->hairstyle;
    if (st == HK_OK && !changed && changed_since(setup->wick_model, m->wick_hash, &st, err))
        changed = setup->wick_model;
    if (st == HK_OK && !changed && !setup->collision != !m->has_collision)
        changed = setup->collision ? setup->collision : m->setup;
    if (st == HK_OK && !changed && setup->collision &&
        changed_since_by(hk_collision_fingerprint, setup->collision, m->collision_hash, &st, err))
        changed = setup->collision;
    if (changed)
        st = hk_error_set(err, HK_ERR_INVALID,
                          "%s has changed since the simulation (%s): its frames cannot be grown again exactly", changed,
                          manifest_path);
    if (st == HK_OK) st = hk_scene_load_parts(&in->scene, HK_SCENE_GROOMING, err);
    if (st == HK_OK) st = load_motion(m, manifest_path, in, err);
    return st;
}

/* The guides of a frame as doubles, checked against the manifest and the wick. */
static hk_Status load_guides(const char *path, const hk_SimulationManifest *m, const hk_Mesh *wick, hk_Groom *g,
                             hk_Error *err)
{
    hk_HairFile hair;
    hk_Status st = hk_hair_load(path, &hair, err);
    if (st != HK_OK) return st;
    const uint32_t guides = (uint32_t)m->guides, points = (uint32_t)m->points;
    if (hair.strand_count != guides || (int)guides != wick->vertex_count)
        st = hk_error_set(err, HK_ERR_PARSE, "%s: %u strands, the simulation had %d guides and the wick %d vertices",
                          path, hair.strand_count, m->guides, wick->vertex_count);
    for (uint32_t i = 0; st == HK_OK && i < guides; i++)
        if (hair.first_point[i + 1] - hair.first_point[i] != points)
            st = hk_error_set(err, HK_ERR_PARSE, "%s: strand %u has %u points, the simulation's guides have %d", path,
                              i, hair.first_point[i + 1] - hair.first_point[i], m->points);
    if (st == HK_OK) {
        g->guide_count = m->guides;
        g->points_per_strand = m->points;
        g->guides = hk_alloc_array((size_t)guides * points, 3 * sizeof(double), err);
        if (!g->guides) st = HK_ERR_NOMEM;
    }
    for (size_t i = 0; st == HK_OK && i < (size_t)guides * points * 3; i++) g->guides[i] = hair.points[i];
    hk_hair_free(&hair);
    return st;
}

hk_Status hk_simulation_rebuild(const char *dir, long frame, int threads, hk_HairFile *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    char manifest_path[4096], guides_path[4096];
    if (snprintf(manifest_path, sizeof manifest_path, "%s/%s", dir, HK_SIMULATION_FILE_NAME) >=
        (int)sizeof manifest_path)
        return hk_error_set(err, HK_ERR_INVALID, "%s: folder name too long", dir);
    hk_SimulationManifest m;
    hk_Status st = hk_simulation_manifest_load(manifest_path, &m, err);
    if (st != HK_OK) return st;
    if (frame < 0 || frame >= m.frames)
        st = hk_error_set(err, HK_ERR_INVALID, "frame %ld: the simulation in %s has frames 0 to %ld", frame, dir,
                          m.frames - 1);
    if (st == HK_OK) st = hk_simulation_frame_path(guides_path, sizeof guides_path, dir, "guides", frame, "hair", err);
    Inputs in;
    memset(&in, 0, sizeof in);
    hk_Groom g;
    memset(&g, 0, sizeof g);
    if (st == HK_OK) st = load_inputs(&m, manifest_path, &in, err);
    if (st == HK_OK) st = load_guides(guides_path, &m, &in.scene.wick, &g, err);
    if (st == HK_OK) {
        /* the body where the head was at this frame, as the run posed it */
        const hk_RigidState head = hk_sim_head_pose(in.motion, hk_sim_frame_time(frame, m.fps));
        st = hk_sim_grow_hair(&in.scene.style, in.scene.collision.shapes, in.scene.collision.count, &head,
                              &in.scene.wick, m.seed, threads, 0, 0, &g, out, err);
    }
    hk_groom_free(&g);
    inputs_free(&in);
    hk_simulation_manifest_free(&m);
    return st;
}
