/* Multiple scattering in hair by the dual scattering approximation of Zinke, Yuksel,
 * Weber and Keyser ("Dual Scattering Approximation for Fast Multiple Scattering in
 * Hair", SIGGRAPH 2008). Light reaching a fibre inside hair has been scattered by the
 * fibres around it; the approximation splits it in two:
 *
 *  - global multiple scattering: the light that went forward through the fibres
 *    between the fibre and the light, each passing on the fraction a_f it scatters
 *    into the forward half-space and widening its direction by the variance of the
 *    forward lobes (§4.2). The count of those fibres comes from the deep opacity
 *    map: its opacity, the sum of the coverages of the fibres in front, is the mean
 *    number of fibres a ray crosses.
 *  - local multiple scattering: the light that the neighbouring fibres send back
 *    (backscattering, a_b, after any number of forward scatterings), A_b of the light
 *    arriving, as a broad longitudinal lobe (§4.3).
 *
 * a_f and a_b and the lobes' spreads are those of the single-scattering model itself:
 * integrated numerically from hk_marschner_lobes at render start, for the hair colour,
 * at 18 incidences. What is approximated, beyond the paper's own assumptions (all the
 * fibres in front with about the same incidence, a density factor of 0.7 for both
 * parts): the count of fibres in front is a Poisson variable of the opacity's mean
 * (so the transmittance is the mean of a_f^n, exp(-opacity (1 - a_f)), and the
 * unscattered part exp(-opacity) is the single models' shadow), and the light arriving
 * after forward scattering is taken as spread evenly in azimuth around the fibre (the
 * paper averages the azimuthal terms over the forward half; after two scatterings the
 * two differ little). Longitudinal lobes are normalised over the outgoing direction as
 * in marschner.c: the paper's Gaussians in theta_h integrate to 2 over theta_o, so its
 * factor 2 / pi of the backscattering lobe is 1 / pi here, which sends A_b into the
 * backward half-space. */
#include <string.h>

#include "shading.h"


/* Normalised Gaussian of variance v at x. */
static double gauss(double v, double x) { return exp(-x * x / (2.0 * v)) / sqrt(2.0 * HK_PI * v); }

/* fmax(lo, fmin(hi, x)) by comparisons, as the same values (x NaN: hi; -0.0 kept),
 * without two calls into libm per use, a few a vertex shaded. */
static inline double clamp_to(double x, double lo, double hi)
{
    const double below = x < hi ? x : hi;
    return below > lo ? below : lo;
}

static double channel(hk_Vec3 v, int c) { return c == 0 ? v.x : c == 1 ? v.y : v.z; }
static void set_channel(hk_Vec3 *v, int c, double x)
{
    if (c == 0)
        v->x = x;
    else if (c == 1)
        v->y = x;
    else
        v->z = x;
}

/* Longitudinal shift and width of lobe p (R, TT, TRT), as in marschner.c. */
static void lobe_shape(const hk_MarschnerParams *f, int p, double *alpha, double *beta)
{
    static const double shift[3] = {1.0, -0.5, -1.5}, width[3] = {1.0, 0.5, 2.0};
    *alpha = shift[p] * f->alpha_r;
    *beta = width[p] * f->beta_r;
}

static double theta_of(int k) { return -0.5 * HK_PI + HK_PI * (k + 0.5) / HK_DUAL_THETA; }

enum { OUT_THETA = 60, OUT_PHI = 24 }; /* midpoints over [-pi/2, pi/2] x [0, pi] */

void hk_dual_scattering_init(const hk_MarschnerParams *fibre, hk_DualScattering *ds)
{
    memset(ds, 0, sizeof *ds);
    ds->fibre = *fibre;
    const hk_Vec3 t = hk_v3(1, 0, 0);
    double alpha[3], beta[3];
    for (int p = 0; p < 3; p++) lobe_shape(fibre, p, &alpha[p], &beta[p]);
    /* cos(phi) at the azimuth midpoints, and the directions' weights: phi and -phi
     * scatter alike, so [0, pi] is integrated twice. */
    const double dth = HK_PI / OUT_THETA, dph = HK_PI / OUT_PHI;
    for (int k = 0; k < HK_DUAL_THETA; k++) {
        const double ti = theta_of(k);
        const hk_Vec3 l = hk_v3(sin(ti), cos(ti), 0.0);
        hk_Vec3 fwd[3], back[3];
        for (int p = 0; p < 3; p++) fwd[p] = back[p] = hk_v3_zero();
        for (int a = 0; a < OUT_THETA; a++) {
            const double to = -0.5 * HK_PI + (a + 0.5) * dth;
            /* int S cos(theta_o) d omega, d omega = cos(theta_o) d theta d phi; S is the
             * returned value over cos(theta_i). */
            const double w = 2.0 * cos(to) * cos(to) * dth * dph / cos(ti);
            for (int b = 0; b < OUT_PHI; b++) {
                const double ph = (b + 0.5) * dph;
                const hk_Vec3 e = hk_v3(sin(to), cos(to) * cos(ph), cos(to) * sin(ph));
                hk_Vec3 lobe[3];
                hk_marschner_lobes(t, l, e, fibre, lobe);
                for (int p = 0; p < 3; p++) {
                    hk_Vec3 *sum = cos(ph) < 0.0 ? &fwd[p] : &back[p];
                    *sum = hk_v3_madd(*sum, lobe[p], w);
                }
            }
        }
        hk_DualEntry *en = &ds->at[k];
        for (int c = 0; c < 3; c++) {
            /* Marschner's 1 / cos^2(theta_d) lets a fibre that absorbs little return up
             * to 13% more than it receives at oblique incidence (d'Eon et al. 2011;
             * tests/test_marschner.c); the sums of the local scattering diverge as
             * a_f + a_b reaches 1, so the excess is scaled away. */
            double total = 0.0;
            for (int p = 0; p < 3; p++) total += channel(fwd[p], c) + channel(back[p], c);
            const double keep = total > 1.0 ? 1.0 / total : 1.0;
            double af = 0.0, ab = 0.0, alpha_f = 0.0, alpha_b = 0.0, bf2 = 0.0, bb2 = 0.0;
            for (int p = 0; p < 3; p++) {
                const double f = keep * channel(fwd[p], c), b = keep * channel(back[p], c);
                set_channel(&en->lobe[p], c, f + b);
                af += f, ab += b;
                alpha_f += f * alpha[p], alpha_b += b * alpha[p];
                bf2 += f * beta[p] * beta[p], bb2 += b * beta[p] * beta[p];
            }
            /* Mean shifts and variances of the forward and backward lobes (§4.3, the
             * lobes weighted by what each scatters into the half-space). */
            alpha_f = af > 0.0 ? alpha_f / af : 0.0, bf2 = af > 0.0 ? bf2 / af : beta[1] * beta[1];
            alpha_b = ab > 0.0 ? alpha_b / ab : 0.0, bb2 = ab > 0.0 ? bb2 / ab : beta[0] * beta[0];
            set_channel(&en->a_f, c, af);
            set_channel(&en->a_b, c, ab);
            set_channel(&en->beta_f2, c, bf2);
            /* Local multiple scattering (Zinke eqs. 11-17): one and three backward
             * scatterings among any number of forward ones, their shift and spread. */
            const double f = fmin(af, 0.999), f2 = f * f, q = 1.0 - f2, b2 = ab * ab, b3 = b2 * ab;
            const double A1 = ab * f2 / q, A3 = b3 * f2 / (q * q * q);
            const double delta =
                alpha_b * (1.0 - 2.0 * b2 / (q * q)) + alpha_f * (2.0 * q * q + 4.0 * f2 * b2) / (q * q * q);
            const double bf = sqrt(bf2), bb = sqrt(bb2);
            const double den = ab + b3 * (2.0 * bf + 3.0 * bb);
            const double sigma = den > 0.0 ? (1.0 + HK_DUAL_DB * f2) *
                                                 (ab * sqrt(2.0 * bf2 + bb2) + b3 * sqrt(2.0 * bf2 + 3.0 * bb2)) / den
                                           : sqrt(bb2);
            set_channel(&en->A_b, c, A1 + A3);
            set_channel(&en->delta_b, c, delta);
            set_channel(&en->sigma_b2, c, sigma * sigma);
        }
    }
}

hk_DualEntry hk_dual_lookup(const hk_DualScattering *ds, double sin_i)
{
    const double ti = asin(fmax(-1.0, fmin(1.0, sin_i)));
    double x = (ti + 0.5 * HK_PI) / (HK_PI / HK_DUAL_THETA) - 0.5;
    x = fmax(0.0, fmin((double)(HK_DUAL_THETA - 1), x));
    int k = (int)x;
    if (k > HK_DUAL_THETA - 2) k = HK_DUAL_THETA - 2;
    const double w = x - k;
    /* The entry is doubles only: interpolate them as an array. */
    enum { N = sizeof(hk_DualEntry) / sizeof(double) };
    double a[N], b[N], r[N];
    memcpy(a, &ds->at[k], sizeof a);
    memcpy(b, &ds->at[k + 1], sizeof b);
    for (int i = 0; i < N; i++) r[i] = a[i] + w * (b[i] - a[i]);
    hk_DualEntry out;
    memcpy(&out, r, sizeof out);
    return out;
}

/* G of hk_dual_global_fraction, given direct = exp(-n) (the shaders have it already).
 * Comparisons, not fmin and fmax (calls into libm): the same values, NaN included
 * (a NaN a_f takes 1, a NaN difference 0, as with fmin and fmax). */
static hk_Vec3 global_fraction(const hk_DualEntry *en, double n, double direct)
{
    hk_Vec3 g;
    for (int c = 0; c < 3; c++) {
        const double af = channel(en->a_f, c), kept = exp(-n * (1.0 - (af < 1.0 ? af : 1.0))) - direct;
        set_channel(&g, c, HK_DUAL_DF * (kept > 0.0 ? kept : 0.0));
    }
    return g;
}

hk_Vec3 hk_dual_global_fraction(const hk_DualEntry *en, double n) { return global_fraction(en, n, exp(-n)); }

/* Angles of a pair of directions about the fibre. */
typedef struct Angles {
    double sin_i, cos_i, theta_h, inv_cos2_d;
} Angles;

static Angles angles(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e)
{
    Angles a;
    a.sin_i = fmax(-1.0, fmin(1.0, hk_v3_dot(t, l)));
    const double sin_o = fmax(-1.0, fmin(1.0, hk_v3_dot(t, e)));
    const double ti = asin(a.sin_i), to = asin(sin_o);
    a.cos_i = cos(ti);
    a.theta_h = 0.5 * (ti + to);
    const double cos_d = cos(0.5 * (to - ti));
    a.inv_cos2_d = 1.0 / fmax(cos_d * cos_d, 1e-6);
    return a;
}

/* The backscattering lobe A_b g(theta_h - delta_b, sigma_b^2 + extra) / (2 pi cos^2
 * theta_d) times cos(theta_i): its integral over the backward half-space is A_b. */
static hk_Vec3 backscatter(const hk_DualEntry *en, const Angles *a, hk_Vec3 extra)
{
    hk_Vec3 r;
    for (int c = 0; c < 3; c++) {
        const double v = channel(en->sigma_b2, c) + channel(extra, c);
        set_channel(&r, c,
                    channel(en->A_b, c) * 0.5 * gauss(v, a->theta_h - channel(en->delta_b, c)) / HK_PI * a->inv_cos2_d *
                        a->cos_i);
    }
    return r;
}

hk_Vec3 hk_dual_local(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e)
{
    const Angles a = angles(t, l, e);
    const hk_DualEntry en = hk_dual_lookup(ds, a.sin_i);
    return hk_v3_scale(backscatter(&en, &a, hk_v3_zero()), HK_DUAL_DB);
}

hk_Vec3 hk_shade_dual_marschner(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, double n)
{
    const Angles a = angles(t, l, e);
    const hk_DualEntry en = hk_dual_lookup(ds, a.sin_i);
    const double direct = exp(-n);
    const hk_Vec3 global = global_fraction(&en, n, direct);
    const hk_Vec3 spread = hk_v3_scale(en.beta_f2, n);
    /* Light arriving unscattered: the single lobes and the neighbours' backscattering. */
    hk_Vec3 out = hk_v3_scale(
        hk_v3_add(hk_shade_marschner(t, l, e, &ds->fibre), hk_v3_scale(backscatter(&en, &a, hk_v3_zero()), HK_DUAL_DB)),
        direct);
    /* Light forward-scattered through the fibres in front: the lobes widened by the
     * spread and averaged over the azimuth (lobe p scatters en.lobe[p] in all, over
     * 2 pi), and the backscattering of the light arriving from all around. */
    const hk_Vec3 back = backscatter(&en, &a, spread);
    for (int c = 0; c < 3; c++) {
        const double s2 = channel(spread, c);
        double sg = 0.0;
        for (int p = 0; p < 3; p++) {
            double alpha, beta;
            lobe_shape(&ds->fibre, p, &alpha, &beta);
            sg += channel(en.lobe[p], c) / (2.0 * HK_PI) * 0.5 * gauss(beta * beta + s2, a.theta_h - alpha);
        }
        sg *= a.inv_cos2_d * a.cos_i;
        set_channel(&out, c, channel(out, c) + channel(global, c) * (sg + HK_PI * HK_DUAL_DB * channel(back, c)));
    }
    return out;
}

hk_Vec3 hk_shade_dual_kajiya_kay(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, double n,
                                 const hk_Visuality *v)
{
    const double tl = hk_v3_dot(t, l), te = hk_v3_dot(t, e);
    const double cos2_tl = 1.0 - tl * tl, cos2_te = 1.0 - te * te; /* fmax(0, .) by comparisons */
    const double sin_tl = sqrt(cos2_tl > 0.0 ? cos2_tl : 0.0), sin_te = sqrt(cos2_te > 0.0 ? cos2_te : 0.0);
    const double cone = sin_tl * sin_te - tl * te; /* cos(theta_i + theta_o) */
    const double p = v->glossiness;
    const double spec = cone > 0.0 ? pow(cone, p) : 0.0;
    const double direct = exp(-n);
    hk_Vec3 out = hk_v3_scale(hk_v3_add(hk_v3_scale(v->diffuse, sin_tl), hk_v3_scale(v->specular, spec)), direct);
    if (!(n > 1e-6)) return out; /* nothing in front: nothing forward-scattered */
    /* Only a_f and beta_f2 of the entry are needed: interpolated alone (the whole
     * entry is 27 numbers). */
    const double ti = asin(clamp_to(tl, -1.0, 1.0));
    const double x = clamp_to((ti + 0.5 * HK_PI) / (HK_PI / HK_DUAL_THETA) - 0.5, 0.0, (double)(HK_DUAL_THETA - 1));
    const int k = x < HK_DUAL_THETA - 1 ? (int)x : HK_DUAL_THETA - 2;
    const double w = x - k;
    hk_DualEntry en;
    en.a_f = hk_v3_add(ds->at[k].a_f, hk_v3_scale(hk_v3_sub(ds->at[k + 1].a_f, ds->at[k].a_f), w));
    en.beta_f2 = hk_v3_add(ds->at[k].beta_f2, hk_v3_scale(hk_v3_sub(ds->at[k + 1].beta_f2, ds->at[k].beta_f2), w));
    const hk_Vec3 global = global_fraction(&en, n, direct);
    /* The specular cone cos^p(2 theta_h) is about a Gaussian of variance 1 / (4 p) in
     * theta_h; widened by the spread s2 it keeps its integral: the exponent becomes
     * p' = p v / (v + s2) and the peak sqrt(p' / p). The spread of the three channels
     * differs by a few per cent: their mean is taken (one power instead of three). */
    const double p_min = p > 1e-6 ? p : 1e-6; /* fmax(p, 1e-6), NaN included */
    const double var = 1.0 / (4.0 * p_min);
    const double s2 = n * (en.beta_f2.x + en.beta_f2.y + en.beta_f2.z) / 3.0, pw = p * var / (var + s2);
    const double spec_g = cone > 0.0 ? sqrt(pw / p_min) * pow(cone, pw) : 0.0;
    const hk_Vec3 kk = hk_v3_add(hk_v3_scale(v->diffuse, sin_tl), hk_v3_scale(v->specular, spec_g));
    return hk_v3(out.x + global.x * kk.x, out.y + global.y * kk.y, out.z + global.z * kk.z);
}
