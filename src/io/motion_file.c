/* Head motion files (docs/file-formats.md, "Head motion file"): keyframes of the head's
 * pose read with the project's `Key value...` reader, and their C2 interpolation in time.
 *
 * Each keyframe gives a translation p and a rotation vector r = angle * unit(axis) (the
 * rotation is about the pivot). Both are interpolated channel by channel, in R^6:
 *   - a cubic spline clamped to zero velocity at the first and last keys (the head holds
 *     still outside them), whose first and last pieces are lifted to quintics so that
 *     the acceleration also reaches zero there. Each piece is the quintic Hermite
 *     interpolant of (value, velocity, acceleration) at its two keys; on the inner
 *     pieces those are the cubic spline's own, so they are the spline itself. Values,
 *     velocities and accelerations are then continuous everywhere (C2), also where the
 *     motion starts and stops, and the keys are reproduced exactly.
 *   - the rotation as a rotation vector rather than a quaternion: R = exp([r]x) is an
 *     entire function of r, so R, omega and alpha are smooth for any r(t), whereas
 *     spline-interpolated quaternion components must be renormalised and break down
 *     where they pass near zero (keys far apart), and cannot say "turn by 270 degrees"
 *     between two keys. Angles are taken as written (no wrapping to +-180), so a file
 *     can script whole turns; for a head, rotations stay well below a half turn, where
 *     the interpolation is close to the shortest path. */
#include <math.h>
#include <string.h>

#include "hairkit/io.h"
#include "io/keyfile.h"
#include "dynamics/motion_internal.h"


/* Sanity limits: beyond them the values are typing errors, and within them the spline
 * arithmetic stays far from overflow (velocities < 1e10, accelerations < 1e17). */
#define HK_MOTION_MAX_TIME    1e6    /* |t| in seconds (11 days) */
#define HK_MOTION_MIN_GAP     1e-6   /* seconds between keys (mocap runs at 1e-3) */
#define HK_MOTION_MAX_METRES  1000.0 /* |translation|, |pivot| components */
#define HK_MOTION_MAX_DEGREES 1e5    /* |angle|: some 280 turns */

#define KEY_NUMBERS 8 /* t tx ty tz ax ay az angle */

/* ---- Reading ------------------------------------------------------------------------ */

static int is_pivot(const hk_KeyLine *kl) { return hk_key_equal(kl->key, "Pivot"); }

/* A keyframe line starts with its time: a digit, a sign or a decimal point. */
static int starts_like_number(const char *s) { return (*s >= '0' && *s <= '9') || *s == '+' || *s == '-' || *s == '.'; }

/* Unit vector along v, scaled first so that tiny or huge components neither underflow
 * nor overflow; zero stays zero. */
static hk_Vec3 unit_axis(hk_Vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!(m > 0.0)) return hk_v3_zero();
    return hk_v3_normalize(hk_v3_scale(v, 1.0 / m));
}

static hk_Status read_pivot(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Vec3 *pivot, hk_Error *err)
{
    double v[3];
    hk_Status st = hk_keyline_doubles(kf, kl, 3, v, err);
    if (st != HK_OK) return st;
    for (int i = 0; i < 3; i++)
        if (!(fabs(v[i]) <= HK_MOTION_MAX_METRES))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                    "Pivot coordinates must be within +-%g m, got %s", HK_MOTION_MAX_METRES,
                                    kl->values[i]);
    *pivot = hk_v3(v[0], v[1], v[2]);
    return HK_OK;
}

/* One keyframe into time and channels (translation, rotation vector). */
static hk_Status read_key(const hk_KeyFile *kf, const hk_KeyLine *kl, double *t, double ch[6], hk_Error *err)
{
    if (!starts_like_number(kl->key))
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "unknown key '%s' in a head motion file (a keyframe line is "
                                "t tx ty tz ax ay az angle)",
                                kl->key);
    if (kl->count + 1 != KEY_NUMBERS)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "expected %d numbers on a keyframe line (t tx ty tz ax ay az "
                                "angle), got %d",
                                KEY_NUMBERS, kl->count + 1);
    /* The time is the line's first token, which the reader calls its key: hand the
     * whole line to the number parser, so that its rules (no nan, inf, hex, any
     * locale) and messages are the same as everywhere else. */
    const char *tokens[KEY_NUMBERS];
    tokens[0] = kl->key;
    for (int i = 1; i < KEY_NUMBERS; i++) tokens[i] = kl->values[i - 1];
    const hk_KeyLine whole = {kl->line, "keyframe", KEY_NUMBERS, tokens};
    double v[KEY_NUMBERS];
    hk_Status st = hk_keyline_doubles(kf, &whole, KEY_NUMBERS, v, err);
    if (st != HK_OK) return st;

    if (!(fabs(v[0]) <= HK_MOTION_MAX_TIME))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "time must be within +-%g s, got %s",
                                HK_MOTION_MAX_TIME, tokens[0]);
    for (int i = 1; i <= 3; i++)
        if (!(fabs(v[i]) <= HK_MOTION_MAX_METRES))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "translation must be within +-%g m, got %s",
                                    HK_MOTION_MAX_METRES, tokens[i]);
    if (!(fabs(v[7]) <= HK_MOTION_MAX_DEGREES))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "angle must be within +-%g degrees, got %s",
                                HK_MOTION_MAX_DEGREES, tokens[7]);
    const hk_Vec3 axis = unit_axis(hk_v3(v[4], v[5], v[6]));
    if (hk_v3_norm2(axis) == 0.0 && v[7] != 0.0)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                "the rotation axis is zero but the angle is %s degrees (a zero "
                                "axis goes only with angle 0)",
                                tokens[7]);
    const hk_Vec3 r = hk_v3_scale(axis, v[7] * (HK_PI / 180.0));
    *t = v[0];
    ch[0] = v[1], ch[1] = v[2], ch[2] = v[3];
    ch[3] = r.x, ch[4] = r.y, ch[5] = r.z;
    return HK_OK;
}

/* ---- Interpolation ------------------------------------------------------------------ */

static double *knot(const hk_HeadMotion *m, int key, int channel)
{
    return m->knots + ((size_t)key * HK_MOTION_CHANNELS + (size_t)channel) * 3;
}

/* Clamped cubic spline (zero end velocities) through every channel: the tridiagonal
 * system for the second derivatives M_i at the keys,
 *   h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1} = 6 (d_i - d_{i-1}),
 *   2 h_0 M_0 + h_0 M_1 = 6 d_0,   h_{n-2} M_{n-2} + 2 h_{n-2} M_{n-1} = -6 d_{n-2},
 * with d_i = (y_{i+1} - y_i) / h_i, is strictly diagonally dominant, so the Thomas
 * algorithm needs no pivoting. Its matrix depends on the times only: factored once
 * (cp, den in scratch[2n]), solved per channel. Then v_i = d_i - h_i (2 M_i + M_{i+1}) / 6,
 * and the end velocities and accelerations are set to zero (the quintic end pieces). */
static void build_spline(hk_HeadMotion *m, double *scratch)
{
    const int n = m->key_count;
    const double *t = m->times;
    double *cp = scratch, *den = scratch + n;
    if (n >= 2) {
        for (int i = 0; i < n; i++) {
            const double hl = i > 0 ? t[i] - t[i - 1] : 0.0, hr = i < n - 1 ? t[i + 1] - t[i] : 0.0;
            den[i] = 2.0 * (hl + hr) - (i > 0 ? hl * cp[i - 1] : 0.0);
            cp[i] = hr / den[i];
        }
    }
    for (int c = 0; c < HK_MOTION_CHANNELS; c++) {
        if (n >= 2) {
            double prev_d = 0.0; /* d_{i-1}; the clamped end velocity at i = 0 */
            for (int i = 0; i < n; i++) {
                const double d = i < n - 1 ? (knot(m, i + 1, c)[0] - knot(m, i, c)[0]) / (t[i + 1] - t[i])
                                           : 0.0; /* the clamped end velocity */
                const double hl = i > 0 ? t[i] - t[i - 1] : 0.0;
                const double below = i > 0 ? knot(m, i - 1, c)[2] : 0.0;
                knot(m, i, c)[2] = (6.0 * (d - prev_d) - hl * below) / den[i];
                prev_d = d;
            }
            for (int i = n - 2; i >= 0; i--) knot(m, i, c)[2] -= cp[i] * knot(m, i + 1, c)[2];
            for (int i = 0; i < n - 1; i++) {
                const double h = t[i + 1] - t[i];
                const double *a = knot(m, i, c), *b = knot(m, i + 1, c);
                knot(m, i, c)[1] = (b[0] - a[0]) / h - h * (2.0 * a[2] + b[2]) / 6.0;
            }
        }
        knot(m, 0, c)[1] = knot(m, 0, c)[2] = 0.0;
        knot(m, n - 1, c)[1] = knot(m, n - 1, c)[2] = 0.0;
    }
}

void hk_motion_keys_eval(const hk_HeadMotion *m, double t, hk_RigidState *out)
{
    const int n = m->key_count;
    double p[HK_MOTION_CHANNELS], dp[HK_MOTION_CHANNELS], ddp[HK_MOTION_CHANNELS];
    int hold = -1;
    if (n == 1 || !(t > m->times[0]))
        hold = 0;
    else if (t >= m->times[n - 1])
        hold = n - 1;
    if (hold >= 0) {
        for (int c = 0; c < HK_MOTION_CHANNELS; c++) {
            p[c] = knot(m, hold, c)[0];
            dp[c] = ddp[c] = 0.0;
        }
    } else {
        int lo = 0, hi = n - 1; /* times[lo] <= t < times[hi] */
        while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            if (m->times[mid] <= t)
                lo = mid;
            else
                hi = mid;
        }
        const double h = m->times[hi] - m->times[lo], u = (t - m->times[lo]) / h;
        for (int c = 0; c < HK_MOTION_CHANNELS; c++) {
            /* Quintic Hermite in u in [0, 1]: y(u) = sum_k e_k u^k, with e0..e2 from the
             * left key and e3..e5 so that value, velocity and acceleration match at the
             * right key (the solution of that 3x3 system). */
            const double *a = knot(m, lo, c), *b = knot(m, hi, c);
            const double e0 = a[0], e1 = a[1] * h, e2 = 0.5 * a[2] * h * h;
            const double dy = b[0] - (e0 + e1 + e2), dv = b[1] * h - (e1 + 2.0 * e2), da = b[2] * h * h - 2.0 * e2;
            const double e3 = 10.0 * dy - 4.0 * dv + 0.5 * da;
            const double e4 = -15.0 * dy + 7.0 * dv - da;
            const double e5 = 6.0 * dy - 3.0 * dv + 0.5 * da;
            p[c] = e0 + u * (e1 + u * (e2 + u * (e3 + u * (e4 + u * e5))));
            dp[c] = (e1 + u * (2.0 * e2 + u * (3.0 * e3 + u * (4.0 * e4 + u * 5.0 * e5)))) / h;
            ddp[c] = (2.0 * e2 + u * (6.0 * e3 + u * (12.0 * e4 + u * 20.0 * e5))) / (h * h);
        }
    }
    hk_rotation_exp(hk_v3(p[3], p[4], p[5]), hk_v3(dp[3], dp[4], dp[5]), hk_v3(ddp[3], ddp[4], ddp[5]), &out->rot,
                    &out->omega, &out->alpha);
    hk_motion_about_pivot(out, m->pivot, hk_v3(p[0], p[1], p[2]), hk_v3(dp[0], dp[1], dp[2]),
                          hk_v3(ddp[0], ddp[1], ddp[2]));
}

/* ---- Loading ------------------------------------------------------------------------ */

/* Reads every line into m (times, knot values, pivot); the keys are counted already. */
static hk_Status read_lines(const hk_KeyFile *kf, hk_HeadMotion *m, hk_Error *err)
{
    int pivot_line = 0, keys = 0, prev_line = 0, first_key_line = 0;
    const char *prev_time = NULL; /* the previous key's time as written */
    for (int i = 0; i < kf->line_count; i++) {
        const hk_KeyLine *kl = &kf->lines[i];
        hk_Status st;
        if (is_pivot(kl)) {
            if (pivot_line)
                return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                        "duplicate key 'Pivot' (first given at line %d)", pivot_line);
            if (keys)
                return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                        "Pivot must come before the first keyframe (line %d)", first_key_line);
            st = read_pivot(kf, kl, &m->pivot, err);
            if (st != HK_OK) return st;
            pivot_line = kl->line;
            continue;
        }
        double t = 0.0, ch[HK_MOTION_CHANNELS];
        st = read_key(kf, kl, &t, ch, err);
        if (st != HK_OK) return st;
        if (keys > 0) {
            const double before = m->times[keys - 1];
            if (!(t > before))
                return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                        "time %s is not after the previous keyframe's %s (line "
                                        "%d): times must increase strictly",
                                        kl->key, prev_time, prev_line);
            if (t - before < HK_MOTION_MIN_GAP)
                return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                        "time %s is less than %g s after the previous keyframe's "
                                        "%s (line %d)",
                                        kl->key, HK_MOTION_MIN_GAP, prev_time, prev_line);
        }
        m->times[keys] = t;
        for (int c = 0; c < HK_MOTION_CHANNELS; c++) knot(m, keys, c)[0] = ch[c];
        if (keys++ == 0) first_key_line = kl->line;
        prev_line = kl->line;
        prev_time = kl->key;
    }
    return HK_OK;
}

hk_Status hk_head_motion_load(const char *path, hk_HeadMotion **out, hk_Error *err)
{
    *out = NULL;
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;

    /* Count the keyframes before allocating anything. */
    int keys = 0;
    for (int i = 0; i < kf.line_count; i++) {
        if (is_pivot(&kf.lines[i])) continue;
        if (++keys > HK_MAX_MOTION_KEYS) {
            st = hk_keyfile_error(&kf, kf.lines[i].line, HK_ERR_INVALID, err, "more than %d keyframes",
                                  HK_MAX_MOTION_KEYS);
            hk_keyfile_free(&kf);
            return st;
        }
    }
    if (keys == 0) {
        st = hk_keyfile_error(&kf, 0, HK_ERR_PARSE, err, "no keyframe (expected lines 't tx ty tz ax ay az angle')");
        hk_keyfile_free(&kf);
        return st;
    }

    hk_HeadMotion *m = hk_calloc_array(1, sizeof *m, err);
    double *scratch = NULL;
    if (m) {
        m->kind = HK_MOTION_KEYS;
        m->pivot = hk_default_head_pivot();
        m->key_count = keys;
        m->path = hk_alloc_array(strlen(path) + 1, 1, err);
        if (m->path) memcpy(m->path, path, strlen(path) + 1);
        m->times = m->path ? hk_alloc_array((size_t)keys, sizeof *m->times, err) : NULL;
        m->knots = m->times ? hk_calloc_array((size_t)keys * HK_MOTION_CHANNELS * 3, sizeof *m->knots, err) : NULL;
        scratch = m->knots ? hk_alloc_array(2 * (size_t)keys, sizeof *scratch, err) : NULL;
    }
    if (!scratch) st = HK_ERR_NOMEM;
    if (st == HK_OK) st = read_lines(&kf, m, err);
    if (st == HK_OK) {
        build_spline(m, scratch);
        const size_t count = (size_t)keys * HK_MOTION_CHANNELS * 3;
        for (size_t i = 0; i < count && st == HK_OK; i++)
            if (!isfinite(m->knots[i]))
                st = hk_keyfile_error(&kf, 0, HK_ERR_NUMERIC, err, "the interpolation of the keyframes overflowed");
    }
    hk_free(scratch);
    hk_keyfile_free(&kf);
    if (st != HK_OK) {
        hk_head_motion_destroy(m);
        return st;
    }
    *out = m;
    return HK_OK;
}
