/* The groom pipeline (Lansink 2010 §4.1.4, Fig. 37): follicles from the wick, guides,
 * interpolated strands; and its conversion to cyHair data. */
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "groom_internal.h"

hk_GroomDef hk_default_groom_def(void)
{
    hk_GroomDef o = {1, 0, NULL, NULL, 1};
    return o;
}

hk_InterpolationDef hk_default_interpolation_def(void)
{
    hk_InterpolationDef d;
    d.hair_density = 250.0;
    d.clump = 0.25;        /* the thesis's clumping (§4.1.4.4) */
    d.clump_profile = 1.0; /* the thesis's linear root-to-tip blend */
    d.stray_hairs = 0;
    /* The three guides of 84 % of the default head's wick triangles end within 4 cm of
     * each other; of the rest, most (73 of 122 triangles) hold guides that fell to
     * different sides of the head, more than 8 cm apart. The fade from 4 to 8 cm keeps
     * the first blended and parts the second (docs/grooming.md, "Keeping hair outside
     * the body"). */
    d.max_tip_distance = 0.08;
    return d;
}

int hk_groom_threads(const hk_GroomDef *o) { return o->threads > 0 ? o->threads : omp_get_max_threads(); }

void hk_groom_report(const hk_GroomDef *o, const char *stage, long done, long total)
{
    if (!o->progress || total <= 0) return;
    /* Only at whole steps of 1/200, so that reporting costs nothing. */
    const long step = total / 200 + 1;
    if (done == total || done % step == 0) o->progress(o->progress_user, stage, (double)done / (double)total);
}

void hk_groom_free(hk_Groom *g)
{
    hk_free(g->guides);
    hk_free(g->strands);
    hk_free(g->strand_triangle);
    hk_free(g->strand_root_weights);
    memset(g, 0, sizeof *g);
}

hk_Status hk_groom_grow(const hk_StrandDef *strand, const hk_InterpolationDef *interpolation, const hk_Shape *shapes,
                        int shape_count, const hk_Mesh *wick, const hk_GroomDef *options, hk_Groom *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_GroomDef o = options ? *options : hk_default_groom_def();
    hk_Follicles f;
    /* The strand count and the memory it takes are known from the wick and the
     * hairstyle alone: refused here, before the guides are solved. */
    hk_Status st = hk_groom_check_size(strand, interpolation, wick, &o, NULL, err);
    if (st == HK_OK) st = hk_follicles_from_wick(wick, &f, err);
    if (st == HK_OK) {
        double t0 = hk_seconds_now();
        st = hk_groom_solve_guides(strand, shapes, shape_count, &f, &o, out, err);
        double t1 = hk_seconds_now();
        if (st == HK_OK) st = hk_groom_interpolate(interpolation, shapes, shape_count, wick, &o, out, err);
        out->stats.seconds_guides = t1 - t0;
        out->stats.seconds_strands = hk_seconds_now() - t1;
        hk_follicles_free(&f);
    }
    if (st != HK_OK) hk_groom_free(out);
    return st;
}

/* out's points (the guides rounded to float, then the strands), thickness and info. */
static void fill_hair(const hk_Groom *g, const hk_StrandDef *strand, hk_HairFile *out)
{
    const int points = g->points_per_strand;
    const size_t guide_values = (size_t)g->guide_count * (size_t)points * 3;
    for (size_t i = 0; i < guide_values; i++) out->points[i] = (float)g->guides[i];
    if (g->strand_count > 0) /* a groom of guides alone has no strands array */
        memcpy(out->points + guide_values, g->strands, (size_t)g->strand_count * (size_t)points * 3 * sizeof(float));
    /* cyHair thickness is a diameter in the file's units (metres here). */
    out->default_thickness = (float)(strand->radius1 + strand->radius2);
    char info[HK_HAIR_INFO_SIZE + 1];
    snprintf(info, sizeof info, "hairkit %s guides=%d strands=%d", HK_VERSION_STRING, g->guide_count, g->strand_count);
    hk_hair_set_info(out, info);
}

hk_Status hk_groom_to_hair(const hk_Groom *g, const hk_StrandDef *strand, hk_HairFile *out, hk_Error *err)
{
    const uint32_t n = (uint32_t)g->guide_count + (uint32_t)g->strand_count;
    const int points = g->points_per_strand;
    if (points > 65536)
        return hk_error_set(err, HK_ERR_INVALID, "%d points per strand exceeds the .hair limit of 65536", points);
    uint32_t *counts = hk_alloc_array(n, sizeof(uint32_t), err);
    if (!counts) return HK_ERR_NOMEM;
    for (uint32_t i = 0; i < n; i++) counts[i] = (uint32_t)points;
    hk_Status st = hk_hair_alloc(out, n, counts, err);
    hk_free(counts);
    if (st != HK_OK) return st;
    fill_hair(g, strand, out);
    return HK_OK;
}

hk_Status hk_groom_to_hair_again(const hk_Groom *g, const hk_StrandDef *strand, hk_HairFile *out, hk_Error *err)
{
    const uint32_t n = (uint32_t)g->guide_count + (uint32_t)g->strand_count;
    /* What hk_groom_to_hair made for as many strands of as many points: everything
     * but the points and the info is the same. */
    if (out->points && out->strand_count == n && out->point_count == (uint64_t)n * (uint64_t)g->points_per_strand &&
        !out->thickness && !out->transparency && !out->colors) {
        fill_hair(g, strand, out);
        return HK_OK;
    }
    hk_hair_free(out);
    return hk_groom_to_hair(g, strand, out, err);
}

hk_Status hk_groom_interpolate_guides(const hk_InterpolationDef *interpolation, const hk_Shape *shapes, int shape_count,
                                      const hk_Mesh *wick, const hk_GroomDef *options, hk_Groom *g, hk_Error *err)
{
    if (g->guide_count != wick->vertex_count || !g->guides || g->points_per_strand < 2)
        return hk_error_set(err, HK_ERR_INVALID, "%d guides for a wick of %d vertices", g->guide_count,
                            wick->vertex_count);
    hk_GroomDef o = options ? *options : hk_default_groom_def();
    const double t0 = hk_seconds_now();
    hk_Status st = hk_groom_interpolate(interpolation, shapes, shape_count, wick, &o, g, err);
    g->stats.seconds_strands = hk_seconds_now() - t0;
    return st;
}
