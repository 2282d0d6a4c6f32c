/* Inverse-distance (Shepard) interpolation of p-helicoids, Piuze et al. 2011 §4.1-4.2: the new strand's
 * parameters are weighted averages of the guides' (canonical) parameters with weights
 * |x - x_i|^-power. Two passes over the guides and no allocation: interpolating 90,000
 * strands must cost little next to tracing them. On a surface (§4.3) the root frames are
 * averaged relative to the surface normal (hk_phelicoid_interpolate_on_surface). */
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

/* Smallest rotation taking the unit vector a to the unit vector b, from the half-way
 * quaternion (1 + a.b, a x b) (its norm is sqrt(2 (1 + a.b)): no loss of accuracy until a
 * and b are opposite). Opposite vectors: a half turn about an axis perpendicular to a (any
 * would do; this one is fixed by a alone, so the result is reproducible). */
static hk_Mat3 smallest_rotation(hk_Vec3 a, hk_Vec3 b)
{
    const double c = hk_v3_dot(a, b);
    double q[4];
    if (1.0 + c > 1e-15) {
        const hk_Vec3 v = hk_v3_cross(a, b);
        q[0] = 1.0 + c, q[1] = v.x, q[2] = v.y, q[3] = v.z;
    } else {
        const int k = fabs(a.x) <= fabs(a.y) && fabs(a.x) <= fabs(a.z) ? 0 : (fabs(a.y) <= fabs(a.z) ? 1 : 2);
        const hk_Vec3 v = hk_v3_cross(a, hk_v3_unit(k));
        q[0] = 0.0, q[1] = v.x, q[2] = v.y, q[3] = v.z;
    }
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++) q[i] /= n;
    return hk_helicoid_rotation_from_quat(q);
}

/* §4.3: the frame W at x turned so that E_T . n >= sin(min_elevation): the smallest rotation
 * that raises E_T to that elevation above the tangent plane, keeping its azimuth (E_T = -n:
 * towards E_N, which is then tangent). */
static hk_Mat3 lift_off_surface(const hk_Mat3 *q, hk_Vec3 n, double min_elevation)
{
    const hk_Vec3 t = hk_m3_col(q, 0);
    const double d = hk_v3_dot(t, n), s = sin(min_elevation);
    if (d >= s) return *q;
    hk_Vec3 tangent = hk_v3_madd(t, n, -d);
    if (!(hk_v3_norm(tangent) > 1e-12)) {
        const hk_Vec3 en = hk_m3_col(q, 1);
        tangent = hk_v3_madd(en, n, -hk_v3_dot(en, n));
    }
    const hk_Vec3 u = hk_v3_add(hk_v3_scale(hk_v3_normalize(tangent), cos(min_elevation)), hk_v3_scale(n, s));
    const hk_Mat3 r = smallest_rotation(t, hk_v3_normalize(u));
    return hk_m3_mul(&r, q);
}

/* Argument checks shared by both interpolations. */
static hk_Status check_args(const hk_PHelicoid *guides, int guide_count, hk_Vec3 x, double power,
                            const hk_PHelicoid *out, hk_Error *err)
{
    if (!guides || guide_count < 1)
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: needs at least one guide, got %d",
                            guides ? guide_count : 0);
    if (!out) return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: NULL output");
    if (!hk_v3_isfinite(x)) return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: root is not finite");
    if (!(power > 0.0) || !isfinite(power))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: power must be > 0, got %g", power);
    return HK_OK;
}

/* A normal of any non-zero finite length, made unit; `what` names it in the error. */
static hk_Status unit_normal(hk_Vec3 normal, const char *what, hk_Vec3 *n, hk_Error *err)
{
    const double len = hk_v3_norm(normal);
    if (!(len > 0.0) || !isfinite(len))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: %s must be finite and non-zero", what);
    *n = hk_v3_scale(normal, 1.0 / len);
    return HK_OK;
}

/* Pass 1: validity, the nearest guide (the reference for quaternion signs), the most pieces. */
static hk_Status nearest_guide(const hk_PHelicoid *guides, int guide_count, hk_Vec3 x, int *nearest, double *dmin,
                               int *max_pieces, hk_Error *err)
{
    *nearest = 0, *dmin = INFINITY, *max_pieces = 1;
    for (int i = 0; i < guide_count; i++) {
        hk_Error e;
        if (hk_phelicoid_check(&guides[i], &e) != HK_OK)
            return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: guide %d: %s", i, e.message);
        const double d = hk_v3_dist(x, guides[i].root);
        if (d < *dmin) {
            *dmin = d;
            *nearest = i;
        }
        if (guides[i].piece_count > *max_pieces) *max_pieces = guides[i].piece_count;
    }
    if (!isfinite(*dmin))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: root too far from the guides");
    return HK_OK;
}

/* The root frame of guide i as averaged: canonical, and with surface normals (normals not NULL)
 * carried from the guide's normal to n, the normal at the new root. */
static void averaged_quat(const hk_PHelicoid *guides, const hk_Vec3 *normals, hk_Vec3 n, int i, double q[4])
{
    if (!normals) {
        canonical_quat(&guides[i], q);
        return;
    }
    hk_Mat3 f = guides[i].frame;
    if (guides[i].k[0].kt < 0.0)
        for (int r = 0; r < 3; r++) {
            f.m[r][1] = -f.m[r][1];
            f.m[r][2] = -f.m[r][2];
        }
    const hk_Mat3 carry = smallest_rotation(hk_v3_normalize(normals[i]), n);
    const hk_Mat3 g = hk_m3_mul(&carry, &f);
    hk_helicoid_quat_from_rotation(&g, q);
}

/* Pass 2: the weighted sums, normalised. Frames as in averaged_quat. */
static void blend(const hk_PHelicoid *guides, const hk_Vec3 *normals, int guide_count, hk_Vec3 x, hk_Vec3 n,
                  int nearest, double dmin, int max_pieces, double power, hk_PHelicoid *out)
{
    hk_PHelicoid r;
    memset(&r, 0, sizeof r);
    double qref[4], qsum[4] = {0.0, 0.0, 0.0, 0.0};
    averaged_quat(guides, normals, n, nearest, qref);
    double wsum = 0.0, nsum = 0.0, lsum = 0.0;
    for (int i = 0; i < guide_count; i++) {
        const hk_PHelicoid *g = &guides[i];
        const double w = relative_weight(dmin, hk_v3_dist(x, g->root), power);
        if (w == 0.0) continue; /* underflow far away (large powers) */
        const double sign = g->k[0].kt < 0.0 ? -1.0 : 1.0;
        double q[4];
        averaged_quat(guides, normals, n, i, q);
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

    for (int j = 0; j < max_pieces; j++) {
        r.k[j].kt /= wsum;
        r.k[j].kn /= wsum;
        r.k[j].kb /= wsum;
        r.k[j].alpha /= wsum;
        r.length[j] /= wsum;
    }
    int pieces = (int)floor(nsum / wsum + 0.5);
    pieces = pieces < 1 ? 1 : (pieces > max_pieces ? max_pieces : pieces);
    double later = 0.0;
    for (int j = 1; j < pieces; j++) later += r.length[j];
    /* Total length sum w_i L_i and first piece sum w_i L_i1 as in §4.2. The paper makes
     * the later pieces equal; here they keep the proportions of their interpolated
     * lengths, which is the same when the guides' later pieces are equal and otherwise
     * keeps the strand next to a guide equal to that guide (equal pieces would not be). */
    const double total = lsum / wsum, rest = total - r.length[0];
    if (pieces == 1) {
        r.length[0] = total;
    } else if (rest > 1e-9 * total && later > 0.0) {
        for (int j = 1; j < pieces; j++) r.length[j] *= rest / later;
    } else {
        for (int j = 0; j < pieces; j++) r.length[j] = total / pieces;
    }
    r.piece_count = pieces;
    for (int j = pieces; j < max_pieces; j++) {
        memset(&r.k[j], 0, sizeof r.k[j]);
        r.length[j] = 0.0;
    }

    /* The weighted sum is never zero: it has a component >= w_nearest along qref. */
    const double qn = sqrt(qsum[0] * qsum[0] + qsum[1] * qsum[1] + qsum[2] * qsum[2] + qsum[3] * qsum[3]);
    for (int c = 0; c < 4; c++) qsum[c] /= qn;
    r.frame = hk_helicoid_rotation_from_quat(qsum);
    r.root = x;
    *out = r;
}

hk_Status hk_phelicoid_interpolate(const hk_PHelicoid *guides, int guide_count, hk_Vec3 x, const hk_Vec3 *normal,
                                   double power, hk_PHelicoid *out, hk_Error *err)
{
    hk_Status st = check_args(guides, guide_count, x, power, out, err);
    hk_Vec3 n = hk_v3_zero();
    if (st == HK_OK && normal) st = unit_normal(*normal, "normal", &n, err);
    int nearest, max_pieces;
    double dmin;
    if (st == HK_OK) st = nearest_guide(guides, guide_count, x, &nearest, &dmin, &max_pieces, err);
    if (st != HK_OK) return st;
    if (dmin == 0.0) {
        /* The guide itself, in the canonical form its neighbours are interpolated from, so
         * that the parameters (not only the strand) are continuous at the guide's root. */
        *out = guides[nearest];
        hk_phelicoid_canonical(out);
        return HK_OK;
    }
    blend(guides, NULL, guide_count, x, n, nearest, dmin, max_pieces, power, out);
    if (normal) out->frame = keep_outside(&out->frame, n);
    return HK_OK;
}

hk_Status hk_phelicoid_interpolate_on_surface(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                              hk_Vec3 x, hk_Vec3 normal, double power, double min_elevation,
                                              hk_PHelicoid *out, hk_Error *err)
{
    hk_Status st = check_args(guides, guide_count, x, power, out, err);
    if (st != HK_OK) return st;
    if (!guide_normals) return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: NULL guide normals");
    if (!(min_elevation >= 0.0 && min_elevation < HK_PI / 2.0))
        return hk_error_set(err, HK_ERR_INVALID, "helicoid interpolation: min_elevation must be in [0, pi/2), got %g",
                            min_elevation);
    hk_Vec3 n;
    if ((st = unit_normal(normal, "normal", &n, err)) != HK_OK) return st;
    for (int i = 0; i < guide_count; i++) {
        const double len = hk_v3_norm(guide_normals[i]);
        if (!(len > 0.0) || !isfinite(len))
            return hk_error_set(err, HK_ERR_INVALID,
                                "helicoid interpolation: the normal of guide %d must be finite and non-zero", i);
    }
    int nearest, max_pieces;
    double dmin;
    if ((st = nearest_guide(guides, guide_count, x, &nearest, &dmin, &max_pieces, err)) != HK_OK) return st;
    if (dmin == 0.0) {
        *out = guides[nearest]; /* as hk_phelicoid_interpolate: the guide itself */
        hk_phelicoid_canonical(out);
        return HK_OK;
    }
    blend(guides, guide_normals, guide_count, x, n, nearest, dmin, max_pieces, power, out);
    out->frame = lift_off_surface(&out->frame, n, min_elevation);
    return HK_OK;
}
