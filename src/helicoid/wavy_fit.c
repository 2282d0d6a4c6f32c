/* A p-helicoid with the waviness of eq. 4 on top (Piuze, Kry and Siddiqi 2011, §3.2) fitted to
 * a polyline (hk_helicoid_fit_wavy, include/hairkit/helicoid_fit.h). The waves are a helical
 * offset a (cos(b s + c) E_B + sin(b s + c) E_N) in the frame of the base p-helicoid, s its arc
 * length: no p-helicoid follows them (a piece's tangents lie on one spiral phi = alpha theta of
 * the sphere, the waves' tangents circle), so the plain fitter spends about 9 pieces a turn.
 * Here the base and the waves are estimated in turns, then polished together:
 *  1. b and a from the strand's median curvature kappa and torsion tau, those of a helix of
 *     radius a and pitch 2 pi / b round a straight base: b = (kappa^2 + tau^2) / tau,
 *     a = kappa / (kappa^2 + tau^2);
 *  2. the base first taken as the strand averaged over one wave length (2 pi / b);
 *  3. rounds: the base fitted with pieces of equal length (§5.4's fixed layout), the residual
 *     of the strand against it read in the base's frames as z = r.E_B + i r.E_N = a e^{i(b s +
 *     c)}, b at the peak of |sum z e^{-i b s}| (a periodogram), a e^{ic} the mean of z e^{-i b s};
 *     the waves so found taken off the strand for the next base;
 *  4. Levenberg-Marquardt on every parameter at once (the pieces, the waves, the root frame's
 *     turn and position, and the base's length, shorter than the strand's by the waves' coils).
 * docs/helicoid-fitting.md, "Waves". */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/helicoid_fit.h"
#include "helicoid_internal.h"
#include "optimize/curvefit_internal.h"

/* The polish's parameters: 4 per piece, then a, b, c, the root frame's turn (3), the root's
 * move (3) and the log of the base's length scale. */
enum { EXTRA = 10, MAX_BASE = (HK_LEAST_SQUARES_MAX_PARAMS - EXTRA) / 4, FINE = 8 };

hk_WavyFitDef hk_default_wavy_fit_def(void)
{
    hk_WavyFitDef o;
    memset(&o, 0, sizeof o);
    o.base = hk_default_helicoid_fit_def();
    o.base_piece_length = 0.07;
    o.rounds = 4;
    o.polish_evaluations = 3000;
    return o;
}

typedef struct Work {
    const hk_Vec3 *target;
    int n;
    double *s;         /* the target's arc length (chords) */
    hk_Vec3 *base;     /* the base's target: the strand with the waves taken off */
    hk_Vec3 *at;       /* the base fit at the target's places, and its frames */
    hk_Mat3 *frame_at; /* (also the polish's trace) */
    hk_Vec3 *fine;     /* the base fit traced FINE times finer, and its frames */
    hk_Mat3 *fine_frame;
    double *fine_arc;
    int fine_capacity;
    double *scratch;               /* n doubles (medians, the polish's residual checks) */
    const hk_PHelicoid *reference; /* the polish's parameters are relative to it */
} Work;

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Median of v[0..n) (sorted in place). */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The first index whose arc length is at least x. */
static int first_at(const double *s, int n, double x)
{
    int lo = 0, hi = n;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (s[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Step 2: each point the mean of the points within half a wave length along the strand (the
 * window shrunk at the ends so that it stays centred). */
static void moving_average(const Work *w, double window, hk_Vec3 *out)
{
    const double length = w->s[w->n - 1];
    for (int i = 0; i < w->n; i++) {
        const double half = fmin(0.5 * window, fmin(w->s[i], length - w->s[i]));
        const int lo = first_at(w->s, w->n, w->s[i] - half), hi = first_at(w->s, w->n, w->s[i] + half + 1e-12 * length);
        hk_Vec3 sum = hk_v3_zero();
        for (int j = lo; j < hi; j++) sum = hk_v3_add(sum, w->target[j]);
        out[i] = hi > lo ? hk_v3_scale(sum, 1.0 / (hi - lo)) : w->target[i];
    }
}

/* The base h and its frames at arc length base_arc(i) = s_i times its length over the
 * strand's (the base is shorter than the waved strand): traced FINE times finer than the
 * strand's spacing and interpolated. */
static hk_Status sample_base(Work *w, const hk_PHelicoid *h, hk_Error *err)
{
    const double length = hk_phelicoid_length(h), step = length / (FINE * (w->n - 1.0));
    const int m = hk_phelicoid_point_count(h, step);
    if (m < 2 || m > w->fine_capacity) return hk_error_set(err, HK_ERR_NUMERIC, "wavy fit: base of %d points", m);
    const hk_Status st = hk_phelicoid_trace(h, step, NULL, NULL, w->fine, w->fine_frame, err);
    if (st != HK_OK) return st;
    int j = 0;
    double start = 0.0;
    w->fine_arc[0] = 0.0;
    for (int p = 0; p < h->piece_count; p++) {
        const int steps = hk_helicoid_piece_steps(h->length[p], step);
        for (int k = 1; k <= steps && j + 1 < m; k++) w->fine_arc[++j] = start + h->length[p] * k / steps;
        start += h->length[p];
    }
    int k = 0;
    for (int i = 0; i < w->n; i++) {
        const double a = w->s[i] * length / w->s[w->n - 1];
        while (k < m - 2 && w->fine_arc[k + 1] < a) k++;
        const double t = fmax(0.0, fmin(1.0, (a - w->fine_arc[k]) / (w->fine_arc[k + 1] - w->fine_arc[k])));
        w->at[i] = hk_v3_madd(w->fine[k], hk_v3_sub(w->fine[k + 1], w->fine[k]), t);
        double *f = &w->frame_at[i].m[0][0];
        const double *f0 = &w->fine_frame[k].m[0][0], *f1 = &w->fine_frame[k + 1].m[0][0];
        for (int c = 0; c < 9; c++) f[c] = f0[c] + (f1[c] - f0[c]) * t;
    }
    return HK_OK;
}

/* sum z_i e^{-i b s_i} over the strand, z the residual in the base's frames. */
static void wave_sum(const Work *w, double b, double base_scale, double *re, double *im)
{
    *re = *im = 0.0;
    for (int i = 0; i < w->n; i++) {
        const hk_Vec3 r = hk_v3_sub(w->target[i], w->at[i]);
        const double zb = hk_v3_dot(r, hk_m3_col(&w->frame_at[i], 2)), zn = hk_v3_dot(r, hk_m3_col(&w->frame_at[i], 1));
        const double phase = b * w->s[i] * base_scale, cs = cos(phase), sn = sin(phase);
        *re += zb * cs + zn * sn;
        *im += zn * cs - zb * sn;
    }
}

/* Step 3's waves from the residual: b at the periodogram's peak within 15 % of the guess (a
 * grid of 0.2 %, then of 0.01 % round the best), then a and c. */
static void estimate_wave(const Work *w, double base_scale, double guess, hk_Waviness *wave)
{
    double best = -1.0, b = guess;
    for (int pass = 0; pass < 2; pass++) {
        const double centre = b, span = pass ? 0.002 * guess : 0.15 * guess, grid = pass ? 1e-4 * guess : 2e-3 * guess;
        for (double x = centre - span; x <= centre + span + 0.5 * grid; x += grid) {
            double re, im;
            wave_sum(w, x, base_scale, &re, &im);
            if (re * re + im * im > best) best = re * re + im * im, b = x;
        }
    }
    double re, im;
    wave_sum(w, b, base_scale, &re, &im);
    wave->amplitude = sqrt(re * re + im * im) / w->n;
    wave->frequency = b;
    wave->phase = atan2(im, re);
}

/* The strand with the waves taken off, in the frames of the base just sampled. */
static void take_off_wave(Work *w, double base_scale, const hk_Waviness *wave)
{
    for (int i = 0; i < w->n; i++) {
        const double phase = wave->frequency * w->s[i] * base_scale + wave->phase;
        const hk_Vec3 offset = hk_v3_add(hk_v3_scale(hk_m3_col(&w->frame_at[i], 2), wave->amplitude * cos(phase)),
                                         hk_v3_scale(hk_m3_col(&w->frame_at[i], 1), wave->amplitude * sin(phase)));
        w->base[i] = hk_v3_sub(w->target[i], offset);
    }
}

static void unpack(const Work *w, const double *x, hk_PHelicoid *h, hk_Waviness *wave)
{
    *h = *w->reference;
    int q = 0;
    for (int p = 0; p < h->piece_count; p++, q += 4) h->k[p] = (hk_Helicoid){x[q], x[q + 1], x[q + 2], x[q + 3]};
    *wave = (hk_Waviness){x[q], x[q + 1], x[q + 2]};
    const hk_Vec3 turn = hk_v3(x[q + 3], x[q + 4], x[q + 5]);
    const double angle = hk_v3_norm(turn);
    if (angle > 0.0) {
        const hk_Mat3 r = hk_helicoid_axis_angle(hk_v3_scale(turn, 1.0 / angle), angle);
        h->frame = hk_m3_mul(&r, &w->reference->frame);
    }
    h->root = hk_v3_add(w->reference->root, hk_v3(x[q + 6], x[q + 7], x[q + 8]));
    const double scale = exp(x[q + 9]);
    for (int p = 0; p < h->piece_count; p++) h->length[p] = w->reference->length[p] * scale;
}

/* Step 4's residuals: the waved base traced at the strand's count against the strand, point
 * by point. Undefined when the trace fails or does not give the strand's count. */
static int polish_residuals(void *user, const double *x, double *r)
{
    Work *w = user;
    hk_PHelicoid h;
    hk_Waviness wave;
    unpack(w, x, &h, &wave);
    const double step = hk_phelicoid_length(&h) / (w->n - 1);
    if (!(wave.amplitude >= 0.0) || hk_phelicoid_point_count(&h, step) != w->n) return 1;
    if (hk_phelicoid_trace(&h, step, &wave, NULL, w->at, NULL, NULL) != HK_OK) return 1;
    for (int i = 0; i < w->n; i++) {
        const hk_Vec3 d = hk_v3_sub(w->at[i], w->target[i]);
        r[3 * i] = d.x, r[3 * i + 1] = d.y, r[3 * i + 2] = d.z;
    }
    return 0;
}

hk_Status hk_helicoid_traced_measures(const hk_PHelicoid *h, const hk_Waviness *wave, const hk_Vec3 *points, int n,
                                      hk_Vec3 *work, hk_FrechetMeasures *m, hk_Error *err)
{
    const double step = hk_phelicoid_length(h) / (n - 1);
    if (hk_phelicoid_point_count(h, step) != n)
        return hk_error_set(err, HK_ERR_NUMERIC, "the fit does not trace at the strand's spacing");
    hk_Status st = hk_phelicoid_trace(h, step, wave, NULL, work, NULL, err);
    if (st == HK_OK) st = hk_frechet_measures(points, n, work, n, m, err);
    return st;
}

/* Normalised coupling of the waved base traced at the strand's count against the strand. */
static hk_Status waved_error(Work *w, const hk_PHelicoid *h, const hk_Waviness *wave, double *error, hk_Error *err)
{
    hk_FrechetMeasures m;
    const hk_Status st = hk_helicoid_traced_measures(h, wave, w->target, w->n, w->at, &m, err);
    if (st == HK_OK) *error = m.normalized;
    return st;
}

static hk_Status fit_wavy(hk_HelicoidFitter *f, Work *w, const hk_WavyFitDef *o, hk_PHelicoid *out, hk_Waviness *wave,
                          double *error, hk_Error *err)
{
    const int n = w->n;
    const double length = w->s[n - 1], spacing = length / (n - 1);
    int c = 0;
    for (int i = 1; i < n - 2; i++) {
        double turn, twist;
        hk_polyline_bend(w->target, i, &turn, &twist);
        w->scratch[c++] = turn / spacing;
    }
    const double kappa = c ? median(w->scratch, c) : 0.0;
    c = 0;
    for (int i = 1; i < n - 2; i++) {
        double turn, twist;
        hk_polyline_bend(w->target, i, &turn, &twist);
        w->scratch[c++] = fabs(twist) / spacing;
    }
    const double tau = c ? median(w->scratch, c) : 0.0;
    hk_CurveFitDef base = o->base;
    base.fixed_pieces = (int)fmin(MAX_BASE, fmax(1.0, round(length / o->base_piece_length)));
    base.piece_length = 0.0;
    if (!(kappa > 0.0 && tau > 0.0)) { /* planar or straight: no waves (the plain fit follows) */
        *error = INFINITY;
        return HK_OK;
    }
    double guess = (kappa * kappa + tau * tau) / tau;
    moving_average(w, 2.0 * HK_PI / guess, w->base);
    hk_PHelicoid h;
    hk_Status st = HK_OK;
    for (int round = 0; st == HK_OK && round < o->rounds; round++) {
        st = hk_helicoid_fit(f, w->base, n, &base, &h, NULL, err);
        if (st == HK_OK) st = sample_base(w, &h, err);
        if (st != HK_OK) break;
        /* the waves' phase runs along the base: b per metre of base, not of strand */
        const double base_scale = hk_phelicoid_length(&h) / length;
        estimate_wave(w, base_scale, round == 0 ? guess / base_scale : wave->frequency, wave);
        take_off_wave(w, base_scale, wave);
    }
    if (st != HK_OK) return st;
    /* Step 4, from the last round's base and waves; kept only when it is better. */
    w->reference = &h;
    double x[HK_LEAST_SQUARES_MAX_PARAMS], scale[HK_LEAST_SQUARES_MAX_PARAMS];
    int q = 0;
    for (int p = 0; p < h.piece_count; p++) {
        const double k[4] = {h.k[p].kt, h.k[p].kn, h.k[p].kb, h.k[p].alpha};
        for (int j = 0; j < 4; j++) x[q] = k[j], scale[q++] = j == 3 ? 0.1 : 1.0;
    }
    const double start[EXTRA] = {wave->amplitude, wave->frequency, wave->phase};
    const double steps[EXTRA] = {1e-4, 1.0, 0.1, 0.01, 0.01, 0.01, 1e-4, 1e-4, 1e-4, 0.01};
    for (int j = 0; j < EXTRA; j++) x[q] = start[j], scale[q++] = steps[j];
    double before;
    st = waved_error(w, &h, wave, &before, err);
    if (st != HK_OK) return st;
    hk_LeastSquaresDef lo = hk_default_least_squares_def();
    lo.max_evaluations = o->polish_evaluations;
    lo.f_tolerance = 1e-9;
    double *work = hk_alloc_array(HK_LEAST_SQUARES_WORK(q, 3 * n), sizeof(double), err);
    if (!work) return HK_ERR_NOMEM;
    hk_MinimizeResult result;
    hk_Error ignored; /* a polish that cannot start leaves the rounds' fit */
    hk_PHelicoid polished;
    hk_Waviness polished_wave;
    double after = INFINITY;
    if (o->polish_evaluations > 0 &&
        hk_least_squares_minimize(q, 3 * n, x, scale, polish_residuals, w, &lo, work, &result, &ignored) == HK_OK) {
        unpack(w, x, &polished, &polished_wave);
        if (waved_error(w, &polished, &polished_wave, &after, &ignored) != HK_OK) after = INFINITY;
    }
    hk_free(work);
    if (after < before) {
        *out = polished, *wave = polished_wave, *error = after;
    } else {
        *out = h, *error = before;
    }
    return HK_OK;
}

hk_Status hk_helicoid_fit_wavy(hk_HelicoidFitter *f, const hk_Vec3 *points, int count, const hk_WavyFitDef *options,
                               hk_PHelicoid *out, hk_Waviness *wave, double *error, hk_Error *err)
{
    const hk_WavyFitDef defaults = hk_default_wavy_fit_def();
    const hk_WavyFitDef *o = options ? options : &defaults;
    if (!f || !points || !out || !wave || !error) return hk_error_set(err, HK_ERR_INVALID, "wavy fit: NULL argument");
    if (count < 8 || count > HK_CURVEFIT_MAX_SAMPLES)
        return hk_error_set(err, HK_ERR_INVALID, "wavy fit: %d points (8 to %d)", count, HK_CURVEFIT_MAX_SAMPLES);
    if (!(o->base_piece_length > 0.0) || !isfinite(o->base_piece_length) || o->rounds < 1 || o->polish_evaluations < 0)
        return hk_error_set(err, HK_ERR_INVALID, "wavy fit: base piece length %g, %d rounds, %d evaluations",
                            o->base_piece_length, o->rounds, o->polish_evaluations);
    for (int i = 0; i < count; i++)
        if (!(isfinite(points[i].x) && isfinite(points[i].y) && isfinite(points[i].z)))
            return hk_error_set(err, HK_ERR_INVALID, "wavy fit: point %d is not finite", i);
    Work w;
    memset(&w, 0, sizeof w);
    w.target = points, w.n = count;
    w.fine_capacity = FINE * (count - 1) + 1 + HK_HELICOID_MAX_PIECES;
    w.s = hk_alloc_array((size_t)count, sizeof *w.s, err);
    w.scratch = w.s ? hk_alloc_array((size_t)count, sizeof *w.scratch, err) : NULL;
    w.base = w.scratch ? hk_alloc_array((size_t)count, sizeof *w.base, err) : NULL;
    w.at = w.base ? hk_alloc_array((size_t)count, sizeof *w.at, err) : NULL;
    w.frame_at = w.at ? hk_alloc_array((size_t)count, sizeof *w.frame_at, err) : NULL;
    w.fine = w.frame_at ? hk_alloc_array((size_t)w.fine_capacity, sizeof *w.fine, err) : NULL;
    w.fine_frame = w.fine ? hk_alloc_array((size_t)w.fine_capacity, sizeof *w.fine_frame, err) : NULL;
    w.fine_arc = w.fine_frame ? hk_alloc_array((size_t)w.fine_capacity, sizeof *w.fine_arc, err) : NULL;
    hk_Status st = w.fine_arc ? HK_OK : HK_ERR_NOMEM;
    if (st == HK_OK) {
        w.s[0] = 0.0;
        for (int i = 1; i < count; i++) w.s[i] = w.s[i - 1] + hk_v3_dist(points[i], points[i - 1]);
        if (!(w.s[count - 1] > 0.0)) st = hk_error_set(err, HK_ERR_INVALID, "wavy fit: a strand of no length");
    }
    if (st == HK_OK) st = fit_wavy(f, &w, o, out, wave, error, err);
    /* Never worse than the plain fit (a strand without waves, or a short one, has nothing
     * for the waves to take): both errors are mean leashes against the strand. */
    hk_PHelicoid plain;
    hk_CurveFit report;
    if (st == HK_OK) st = hk_helicoid_fit(f, points, count, &o->base, &plain, &report, err);
    if (st == HK_OK && report.error <= *error) {
        *out = plain, *error = report.error;
        *wave = (hk_Waviness){0.0, 0.0, 0.0};
    }
    hk_free(w.s), hk_free(w.scratch), hk_free(w.base), hk_free(w.at), hk_free(w.frame_at);
    hk_free(w.fine), hk_free(w.fine_frame), hk_free(w.fine_arc);
    return st;
}
