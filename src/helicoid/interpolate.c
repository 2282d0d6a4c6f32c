/* Inverse-distance (Shepard) interpolation of p-helicoids, paper 003 §4.1-4.2: the new strand's
 * parameters are weighted averages of the guides' (canonical) parameters with weights
 * |x - x_i|^-power. Two passes over the guides and no allocation: interpolating 90,000
 * strands must cost little next to tracing them. */
#include <string.h>

#include "helicoid_internal.h"

/* Weight relative to the nearest guide, (d_min / d)^power <= 1: no overflow however close x
 * is to a guide. The paper's power 3 avoids pow(). */
static double relative_weight(double dmin, double d, double power)
{
    const double r = dmin / d;
    return power == 3.0 ? r * r * r : pow(r, power);
}

/* The root frame of a guide in canonical form (§4.1 rule, canonical.c) as a unit quaternion. */
static void canonical_quat(const hk_PHelicoid *g, double q[4])
{
    hk_Mat3 f = g->frame;
    if (g->k[0].kt < 0.0)
        for (int r = 0; r < 3; r++) {
            f.m[r][1] = -f.m[r][1];
            f.m[r][2] = -f.m[r][2];
        }
    hk_helicoid_quat_from_rotation(&f, q);
}

/* Smallest rotation that brings E_T = Q e_1 out of the surface of outward normal n (unit):
 * onto the tangent plane when it points inwards. */
static hk_Mat3 keep_outside(const hk_Mat3 *q, hk_Vec3 n)
{
    const hk_Vec3 t = hk_m3_col(q, 0);
    const double d = hk_v3_dot(t, n);
    if (d >= 0.0) return *q;
    const hk_Vec3 tp = hk_v3_madd(t, n, -d);
    const double len = hk_v3_norm(tp);
    hk_Mat3 r;
    if (len > 1e-12) {
        /* R = I + [v]x + [v]x^2 / (1 + c), v = t x u, c = t . u >= 0: maps t to u exactly. */
        const hk_Vec3 u = hk_v3_scale(tp, 1.0 / len);
        const hk_Vec3 v = hk_v3_cross(t, u);
        const hk_Mat3 k = hk_m3_skew(v), k2 = hk_m3_mul(&k, &k);
        const hk_Mat3 k2s = hk_m3_scale(&k2, 1.0 / (1.0 + hk_v3_dot(t, u)));
        const hk_Mat3 i = hk_m3_identity();
        r = hk_m3_add(&i, &k);
        r = hk_m3_add(&r, &k2s);
    } else {
        /* E_T = -n: a quarter turn about E_N (perpendicular to both) lays it on the surface. */
        const hk_Vec3 a = hk_m3_col(q, 1);
        const hk_Mat3 k = hk_m3_skew(a), k2 = hk_m3_mul(&k, &k), i = hk_m3_identity();
        r = hk_m3_add(&i, &k);
        r = hk_m3_add(&r, &k2);
    }
    return hk_m3_mul(&r, q);
}

hk_Status hk_phelicoid_interpolate(const hk_PHelicoid *guides, int guide_count, hk_Vec3 x, const hk_Vec3 *normal,
                                   double power, hk_PHelicoid *out, hk_Error *err)
{
    if (!guides || guide_count < 1)
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: needs at least one guide, got %d",
                            guides ? guide_count : 0);
    if (!out) return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: NULL output");
    if (!hk_v3_isfinite(x)) return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: root is not finite");
    if (!(power > 0.0) || !isfinite(power))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: power must be > 0, got %g", power);
    hk_Vec3 n = hk_v3_zero();
    if (normal) {
        const double len = hk_v3_norm(*normal);
        if (!(len > 0.0) || !isfinite(len))
            return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: normal must be finite and non-zero");
        n = hk_v3_scale(*normal, 1.0 / len);
    }

    /* Pass 1: validity, the nearest guide (the reference for quaternion signs), the most pieces. */
    int nearest = 0, max_pieces = 1;
    double dmin = INFINITY;
    for (int i = 0; i < guide_count; i++) {
        hk_Error e;
        if (hk_phelicoid_check(&guides[i], &e) != HK_OK)
            return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: guide %d: %s", i, e.message);
        const double d = hk_v3_dist(x, guides[i].root);
        if (d < dmin) {
            dmin = d;
            nearest = i;
        }
        if (guides[i].piece_count > max_pieces) max_pieces = guides[i].piece_count;
    }
    if (!isfinite(dmin))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: root too far from the guides");
    if (dmin == 0.0) {
        /* The guide itself, in the canonical form its neighbours are interpolated from, so
         * that the parameters (not only the strand) are continuous at the guide's root. */
        *out = guides[nearest];
        hk_phelicoid_canonical(out);
        return HK_OK;
    }

    /* Pass 2: weighted sums. */
    hk_PHelicoid r;
    memset(&r, 0, sizeof r);
    double qref[4], qsum[4] = {0.0, 0.0, 0.0, 0.0};
    canonical_quat(&guides[nearest], qref);
    double wsum = 0.0, nsum = 0.0, lsum = 0.0;
    for (int i = 0; i < guide_count; i++) {
        const hk_PHelicoid *g = &guides[i];
        const double w = relative_weight(dmin, hk_v3_dist(x, g->root), power);
        if (w == 0.0) continue; /* underflow far away (large powers) */
        const double sign = g->k[0].kt < 0.0 ? -1.0 : 1.0;
        double q[4];
        canonical_quat(g, q);
        /* q and -q are the same rotation: take the one on the reference's side. */
        const double ws = q[0] * qref[0] + q[1] * qref[1] + q[2] * qref[2] + q[3] * qref[3] < 0.0 ? -w : w;
        for (int c = 0; c < 4; c++) qsum[c] += ws * q[c];
        wsum += w;
        nsum += w * g->piece_count;
        lsum += w * hk_phelicoid_length(g);
        for (int j = 0; j < max_pieces; j++) {
            /* §4.2, piece by piece; a guide with fewer pieces lends its last one. */
            const int jj = j < g->piece_count ? j : g->piece_count - 1;
            const hk_Helicoid *k = &g->k[jj];
            r.length[j] += w * g->length[jj];
            r.k[j].kt += w * sign * k->kt;
            r.k[j].kn += w * k->kn;
            r.k[j].kb += w * k->kb;
            r.k[j].alpha += w * k->alpha;
        }
    }

    int pieces = (int)floor(nsum / wsum + 0.5);
    pieces = pieces < 1 ? 1 : (pieces > max_pieces ? max_pieces : pieces);
    r.piece_count = pieces;
    double later = 0.0;
    for (int j = 0; j < pieces; j++) {
        r.k[j].kt /= wsum;
        r.k[j].kn /= wsum;
        r.k[j].kb /= wsum;
        r.k[j].alpha /= wsum;
        r.length[j] /= wsum;
        if (j > 0) later += r.length[j];
    }
    for (int j = pieces; j < max_pieces; j++) {
        memset(&r.k[j], 0, sizeof r.k[j]);
        r.length[j] = 0.0;
    }
    /* Total length sum w_i L_i and first piece sum w_i L_i1 as in §4.2. The paper makes the
     * later pieces equal; here they keep the proportions of their interpolated lengths, which
     * is the same when the guides' later pieces are equal and otherwise keeps the strand next
     * to a guide equal to that guide (equal pieces would not be). */
    const double total = lsum / wsum, rest = total - r.length[0];
    if (pieces == 1) {
        r.length[0] = total;
    } else if (rest > 1e-9 * total && later > 0.0) {
        for (int j = 1; j < pieces; j++) r.length[j] *= rest / later;
    } else {
        for (int j = 0; j < pieces; j++) r.length[j] = total / pieces;
    }

    /* The weighted sum is never zero: it has a component >= w_nearest along qref. */
    const double qn = sqrt(qsum[0] * qsum[0] + qsum[1] * qsum[1] + qsum[2] * qsum[2] + qsum[3] * qsum[3]);
    for (int c = 0; c < 4; c++) qsum[c] /= qn;
    r.frame = hk_helicoid_rotation_from_quat(qsum);
    if (normal) r.frame = keep_outside(&r.frame, n);
    r.root = x;
    *out = r;
    return HK_OK;
}
