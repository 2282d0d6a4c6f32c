/* p-helicoid bookkeeping (Piuze et al. 2011 §3.4): validation, total length and the number of points a
 * trace has, so that callers can size their buffers before tracing. */
#include "helicoid_internal.h"

/* |Q^T Q - I| entries allowed: frames from files or other code are rotations up to rounding. */
#define FRAME_TOLERANCE 1e-6

static int frame_is_rotation(const hk_Mat3 *q)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!isfinite(q->m[i][j])) return 0;
    /* Q^T Q is symmetric (a . b and b . a are the same products summed in the same
     * order): its upper triangle decides */
    for (int i = 0; i < 3; i++)
        for (int j = i; j < 3; j++) {
            const hk_Vec3 a = hk_m3_col(q, i), b = hk_m3_col(q, j);
            if (fabs(hk_v3_dot(a, b) - (i == j)) > FRAME_TOLERANCE) return 0;
        }
    const double det = hk_v3_dot(hk_m3_col(q, 0), hk_v3_cross(hk_m3_col(q, 1), hk_m3_col(q, 2)));
    return det > 0.0;
}

hk_Status hk_phelicoid_check(const hk_PHelicoid *h, hk_Error *err)
{
    if (!h) return hk_error_set(err, HK_ERR_INVALID, "p-helicoid: NULL");
    if (h->piece_count < 1 || h->piece_count > HK_HELICOID_MAX_PIECES)
        return hk_error_set(err, HK_ERR_INVALID, "p-helicoid: piece count must be in 1..%d, got %d",
                            HK_HELICOID_MAX_PIECES, h->piece_count);
    if (!hk_v3_isfinite(h->root)) return hk_error_set(err, HK_ERR_INVALID, "p-helicoid: root is not finite");
    if (!frame_is_rotation(&h->frame))
        return hk_error_set(err, HK_ERR_INVALID,
                            "p-helicoid: root frame is not a rotation (columns orthonormal "
                            "to %g, determinant +1)",
                            FRAME_TOLERANCE);
    for (int i = 0; i < h->piece_count; i++) {
        const hk_Helicoid *k = &h->k[i];
        if (!isfinite(k->kt) || !isfinite(k->kn) || !isfinite(k->kb) || !isfinite(k->alpha))
            return hk_error_set(err, HK_ERR_INVALID, "p-helicoid: piece %d: k = (%g, %g, %g, %g) is not finite", i + 1,
                                k->kt, k->kn, k->kb, k->alpha);
        if (!(h->length[i] > 0.0) || !isfinite(h->length[i]))
            return hk_error_set(err, HK_ERR_INVALID, "p-helicoid: piece %d: length must be > 0, got %g", i + 1,
                                h->length[i]);
    }
    return HK_OK;
}

double hk_phelicoid_length(const hk_PHelicoid *h)
{
    if (!h || h->piece_count < 1 || h->piece_count > HK_HELICOID_MAX_PIECES) return 0.0;
    double sum = 0.0;
    for (int i = 0; i < h->piece_count; i++) sum += h->length[i];
    return sum;
}

int hk_helicoid_piece_steps(double length, double step)
{
    const double q = length / step;
    if (!(q > 0.0) || !(q <= HK_HELICOID_MAX_POINTS)) return -1;
    /* 0.3 / 0.1 = 2.9999999999999996 and (3 * 0.1) / 0.1 = 3.0000000000000004 both mean 3. */
    const int n = (int)ceil(q * (1.0 - 1e-12));
    return n < 1 ? 1 : n;
}

int hk_phelicoid_point_count(const hk_PHelicoid *h, double step)
{
    if (hk_phelicoid_check(h, NULL) != HK_OK || !(step > 0.0) || !isfinite(step)) return -1;
    int count = 1;
    for (int i = 0; i < h->piece_count; i++) {
        const int n = hk_helicoid_piece_steps(h->length[i], step);
        if (n < 0 || n > HK_HELICOID_MAX_POINTS - count) return -1;
        count += n;
    }
    return count;
}
