/* The hair of a frame from its guides as written to DIR/guides_kkkk.hair: one function
 * for the run and for the rebuild, so that both grow the same bytes (paper 000 §4.1:
 * the interpolated hair follows the guides; same seed, same roots and clumps). */
#include <string.h>

#include "sim_internal.h"

void hk_sim_round_guides(double *guides, size_t values)
{
    for (size_t i = 0; i < values; i++) guides[i] = (double)(float)guides[i];
}

hk_Status hk_sim_grow_hair(const hk_HairstyleDef *style, const hk_Mesh *wick, uint64_t seed, int threads,
                           int guides_only, hk_Groom *g, hk_HairFile *out, hk_Error *err)
{
    hk_Status st = HK_OK;
    if (!guides_only) {
        hk_GroomOptions go = hk_default_groom_options();
        go.seed = seed;
        go.threads = threads;
        st = hk_groom_interpolate_guides(style, NULL, 0, wick, &go, g, err); /* TODO(merge): posed body shapes */
    }
    return st == HK_OK ? hk_groom_to_hair(g, style, out, err) : st;
}
