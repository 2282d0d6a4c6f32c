/* Follicles from a wick mesh (Lansink 2010 §4.1.4.1): one per vertex, along its normal,
 * with the envelope level of §4.1.2.2 from the follicle's height. */
#include <float.h>
#include <string.h>

#include "hairkit/groom.h"

hk_Status hk_follicles_from_wick(const hk_Mesh *wick, hk_Follicles *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    const int n = wick->vertex_count;
    if (n < 3 || wick->triangle_count < 1)
        return hk_error_set(err, HK_ERR_INVALID, "the wick needs at least one triangle");
    out->position = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    out->normal = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    out->alpha = hk_alloc_array((size_t)n, sizeof(double), err);
    if (!out->position || !out->normal || !out->alpha) {
        hk_follicles_free(out);
        return HK_ERR_NOMEM;
    }
    double ymin = DBL_MAX, ymax = -DBL_MAX;
    for (int i = 0; i < n; i++) {
        ymin = fmin(ymin, wick->positions[i].y);
        ymax = fmax(ymax, wick->positions[i].y);
    }
    for (int i = 0; i < n; i++) {
        out->position[i] = wick->positions[i];
        if (!(hk_v3_norm(wick->normals[i]) > 0.5)) {
            hk_follicles_free(out);
            return hk_error_set(err, HK_ERR_INVALID, "wick vertex %d has no normal (it belongs to no face?)", i + 1);
        }
        out->normal[i] = hk_v3_normalize(wick->normals[i]);
        out->alpha[i] = ymax > ymin ? (wick->positions[i].y - ymin) / (ymax - ymin) : 0.0;
    }
    out->count = n;
    return HK_OK;
}

void hk_follicles_free(hk_Follicles *f)
{
    hk_free(f->position);
    hk_free(f->normal);
    hk_free(f->alpha);
    memset(f, 0, sizeof *f);
}
