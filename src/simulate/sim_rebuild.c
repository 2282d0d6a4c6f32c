/* Any frame's full hair from what a simulation wrote: DIR/simulation.txt names the
 * setup and the seed, DIR/guides_kkkk.hair holds the guides; the interpolated strands are
 * grown from them exactly as the run did (sim_grow.c), so the bytes are those of the
 * run's DIR/frame_kkkk.hair. */
#include <stdio.h>
#include <string.h>

#include "hairkit/simulation_file.h"
#include "sim_internal.h"

/* The setup's hairstyle and wick, refused if either changed since the run. */
static hk_Status load_inputs(const hk_SimulationManifest *m, const char *manifest_path, hk_HairstyleDef *style,
                             hk_Mesh *wick, hk_Error *err)
{
    hk_SetupDef setup;
    hk_Status st = hk_setup_load(m->setup, &setup, err);
    if (st != HK_OK) return st;
    if (!setup.hairstyle || !setup.wick_model)
        st = hk_error_set(err, HK_ERR_PARSE, "%s: no HairstyleInfo or WickModel", m->setup);
    const char *changed = NULL;
    uint64_t h;
    if (st == HK_OK && (st = hk_file_fingerprint(setup.hairstyle, &h, err)) == HK_OK && h != m->hairstyle_hash)
        changed = setup.hairstyle;
    if (st == HK_OK && !changed && (st = hk_file_fingerprint(setup.wick_model, &h, err)) == HK_OK &&
        h != m->wick_hash)
        changed = setup.wick_model;
    if (changed)
        st = hk_error_set(err, HK_ERR_INVALID,
                          "%s has changed since the simulation (%s): its frames cannot be grown again exactly",
                          changed, manifest_path);
    if (st == HK_OK) st = hk_hairstyle_load(setup.hairstyle, style, err);
    if (st == HK_OK) st = hk_obj_load(setup.wick_model, wick, err);
    hk_setup_free(&setup);
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
    hk_HairstyleDef style;
    memset(&style, 0, sizeof style);
    hk_Mesh wick;
    memset(&wick, 0, sizeof wick);
    hk_Groom g;
    memset(&g, 0, sizeof g);
    if (st == HK_OK) st = load_inputs(&m, manifest_path, &style, &wick, err);
    if (st == HK_OK) st = load_guides(guides_path, &m, &wick, &g, err);
    if (st == HK_OK) st = hk_sim_grow_hair(&style, &wick, m.seed, threads, 0, &g, out, err);
    hk_groom_free(&g);
    hk_mesh_free(&wick);
    hk_hairstyle_free(&style);
    hk_simulation_manifest_free(&m);
    return st;
}
