/* The hair of a frame from its guides as written to DIR/guides_kkkk.hair: one function
 * for the run and for the rebuild, so that both grow the same bytes (Bertails et al. 2006 §4.1:
 * the interpolated hair follows the guides; same seed, same roots and clumps), kept out
 * of the body where the head is at that frame (docs/grooming.md). */
#include <string.h>

#include "sim_internal.h"

void hk_sim_round_guides(double *guides, size_t values)
{
    for (size_t i = 0; i < values; i++) guides[i] = (double)(float)guides[i];
}

double hk_sim_frame_time(long frame, double fps) { return (double)frame * (1.0 / fps); }

hk_RigidState hk_sim_head_pose(const hk_HeadMotion *motion, double t)
{
    hk_RigidState pose = hk_rigid_identity();
    if (motion) hk_head_motion_eval(motion, t, &pose);
    return pose;
}

hk_Status hk_sim_interpolate_posed(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                                   const hk_RigidState *head, const hk_Mesh *wick, const hk_GroomDef *go, hk_Groom *g,
                                   hk_Error *err)
{
    hk_Shape *posed = NULL;
    if (shape_count > 0) {
        posed = hk_alloc_array((size_t)shape_count, sizeof *posed, err);
        if (!posed) return HK_ERR_NOMEM;
        hk_shapes_posed(shapes, shape_count, head, posed);
    }
    hk_Status st = hk_groom_interpolate_guides(&style->interpolation, posed, shape_count, wick, go, g, err);
    hk_free(posed);
    return st;
}

hk_Status hk_sim_grow_hair(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                           const hk_RigidState *head, const hk_Mesh *wick, uint64_t seed, int threads, int guides_only,
                           int reuse, hk_Groom *g, hk_HairFile *out, hk_Error *err)
{
    hk_Status st = HK_OK;
    if (!guides_only) {
        hk_GroomDef go = hk_default_groom_def();
        go.seed = seed;
        go.threads = threads;
        st = hk_sim_interpolate_posed(style, shapes, shape_count, head, wick, &go, g, err);
    }
    if (st != HK_OK) return st;
    return reuse ? hk_groom_to_hair_again(g, &style->strand, out, err) : hk_groom_to_hair(g, &style->strand, out, err);
}
