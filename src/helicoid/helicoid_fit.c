/* p-helicoid fitting (Piuze et al. 2011 §5): the helicoid piece as the model of the generic
 * piecewise fitter (curvefit.h: Fréchet coupling, Nelder-Mead with the regularisation of
 * eq. 5, recursive splitting of §5.3). */
#include <math.h>
#include <string.h>

#include "hairkit/helicoid_fit.h"
#include "helicoid_internal.h"
#include "rk4_field.h"

/* Least |w| a fitted piece may reach (1 at its origin): it stays at least a tenth of its
 * origin's distance away from the singular axis, where it turns at most ten times faster
 * than there. */
#define MIN_AXIS_W 0.1
/* Most the field may turn between two samples at a fitted piece's origin (rad). */
#define MAX_TURN_PER_SAMPLE 1.0

/* The search's tracer (issue 17: 85 % of a fit is RK4 tracing). The search for the
 * pieces traces with RK4 steps that turn the field by up to SEARCH_TURN instead of the
 * standard tracer's MAX_TURN_PER_STEP (0.25 rad, within 0.5 um of the exact curve), and
 * where the samples are dense (a strand resampled 4 times finer turns by a few
 * hundredths of a radian a sample) one step spans up to SEARCH_SPAN samples, the ones
 * inside it interpolated (hk_helicoid_piece_rk4_local): search_model below. The pieces
 * found are then fitted again with the standard tracer (options.final_model, one
 * Levenberg-Marquardt run each from the search's parameters), which also gives the
 * reported errors: the parameters describe the curve the standard tracer draws, not the
 * search's discretisation of it (docs/helicoid-fitting.md §7). */
#define SEARCH_TURN 0.5
#define SEARCH_SPAN 4

struct hk_HelicoidFitter {
    int capacity;    /* points a model call may trace */
    hk_Mat3 *frames; /* their frames, for the end pose */
    hk_CurveFitWorkspace *ws;
    /* root_roll's last alpha (bits) and the cosine and sine of its roll; rolled: 1 when set */
    double roll_alpha, roll_c, roll_s;
    int rolled;
};

hk_CurveFitDef hk_default_helicoid_fit_def(void)
{
    hk_CurveFitDef o = hk_default_curve_fit_def();
    o.arc_length = 1; /* the pieces are traced by RK4 or closed forms at arc-length spacing */
    /* Jacobians from one differentiated trace: 2 to 3 times fewer traced points than forward
     * differences for the same fits (docs/helicoid-fitting.md). */
    o.model_derivative = hk_helicoid_piece_derivative;
    /* The cap that scales with the strand's length is the minimal fragment's (at most one
     * piece per 5 mm); 64 only bounds strands over 32 cm. A piece's tangents all lie on one
     * spiral phi = alpha theta of the sphere (eq. 1-2), so eq. 4's helical waves, whose
     * tangents circle, take about 9 pieces a turn: examples/helicoid/wisp.txt (27 cm, 5
     * turns) needs 45, and with curvefit's cap of 16 its strands came out 2.4 mm off, now
     * 0.08 mm. No fit of Sintel, Bangs or Curly changes (none spends 16 pieces).
     * docs/helicoid-fitting.md, "Waves". */
    o.max_pieces = HK_HELICOID_MAX_PIECES;
    return o;
}

void hk_helicoid_fit_seed(double length, double seed[4], double scale[4])
{
    /* Straight to start; a first simplex step of a quarter turn over the strand for
     * the curvatures and of 0.5 for alpha (a dimensionless pitch). */
    const double turn = (HK_PI / 2.0) / (length > 0.0 ? length : 1.0);
    for (int i = 0; i < 4; i++) seed[i] = 0.0;
    scale[0] = scale[1] = scale[2] = turn;
    scale[3] = 0.5;
}

hk_HelicoidFitter *hk_helicoid_fitter_create(int max_samples, hk_Error *err)
{
    if (max_samples < 2 || max_samples > HK_CURVEFIT_MAX_SAMPLES) {
        hk_error_set(err, HK_ERR_INVALID, "fitter for %d samples: 2 to %d", max_samples, HK_CURVEFIT_MAX_SAMPLES);
        return NULL;
    }
    hk_HelicoidFitter *f = hk_calloc_array(1, sizeof *f, err);
    if (!f) return NULL;
    f->capacity = max_samples;
    f->frames = hk_alloc_array((size_t)max_samples, sizeof(hk_Mat3), err);
    f->ws = f->frames ? hk_curve_fit_workspace_create(max_samples, err) : NULL;
    if (!f->frames || !f->ws) {
        hk_helicoid_fitter_destroy(f);
        return NULL;
    }
    return f;
}

void hk_helicoid_fitter_destroy(hk_HelicoidFitter *f)
{
    if (!f) return;
    hk_free(f->frames);
    hk_curve_fit_workspace_destroy(f->ws);
    hk_free(f);
}

/* The piece of one model call as a p-helicoid; 0 when its parameters are usable at this
 * spacing (the rules below), with *step the output spacing. */
static int model_piece(const hk_HelicoidFitter *f, const double *params, const hk_CurveStart *start, double length,
                       int count, hk_PHelicoid *h, double *step)
{
    if (count < 2 || count > f->capacity || !(length > 0.0)) return 1;
    /* One piece: only its entries are set (and read by the tracers and the checks); a
     * whole hk_PHelicoid cleared was 1 % of a fit's instructions. */
    h->root = start->pos;
    h->frame = start->frame;
    h->piece_count = 1;
    h->k[0] = (hk_Helicoid){params[0], params[1], params[2], params[3]};
    h->length[0] = length;
    /* count points at spacing length / (count - 1): the trace's own step rule gives
     * exactly that many when the step divides the length. */
    *step = length / (count - 1);
    /* The field may not turn faster than MAX_TURN_PER_SAMPLE between two samples at the
     * piece's origin (|w| = 1): a bend the samples cannot resolve is not something they
     * can be fitted with, and its trace would need many substeps. */
    double per_w, constant;
    hk_helicoid_turn_bound(&h->k[0], &per_w, &constant);
    if (!((per_w + constant) * *step <= MAX_TURN_PER_SAMPLE)) return 1;
    return hk_phelicoid_point_count(h, *step) != count;
}

/* 1 when the point l (in the piece's local frame, origin at its root) is near the
 * field's singular axis w = 0. A piece that passes there turns at |k_N + i k_T| / |w|,
 * and its phi = alpha theta depends on how often the trace winds round the axis:
 * parameters that lead there describe no definite curve (a finer trace of them differs
 * by centimetres), so the fit may not use them. */
static int near_axis_at(const hk_Helicoid *k, hk_Vec3 l)
{
    const double wr = 1.0 + k->kn * l.x - k->kt * l.y, wi = k->kt * l.x + k->kn * l.y;
    return wr * wr + wi * wi < MIN_AXIS_W * MIN_AXIS_W;
}

/* 1 when a point of the trace (world points) comes near the singular axis. */
static int near_axis(const hk_PHelicoid *h, const hk_Vec3 *points, int count)
{
    for (int i = 1; i < count; i++)
        if (near_axis_at(&h->k[0], hk_m3_tmul_v3(&h->frame, hk_v3_sub(points[i], h->root)))) return 1;
    return 0;
}

/* Carries a piece's local trace to the world and sets its end pose; 0 when finite and
 * clear of the singular axis (checked on the local points, before they are carried: the
 * same test without taking them back from the world). */
static int to_world(const hk_PHelicoid *h, const hk_HelicoidAngles *a, hk_Vec3 *points, int count, hk_CurveStart *end)
{
    const hk_Mat3 *q = &h->frame;
    for (int i = 1; i < count; i++)
        if (near_axis_at(&h->k[0], points[i])) return 1;
    for (int i = 0; i < count; i++) points[i] = hk_v3_add(h->root, hk_m3_mul_v3(q, points[i]));
    for (int i = 0; i < count; i++)
        if (!hk_v3_isfinite(points[i])) return 1;
    const hk_Mat3 frame = hk_helicoid_frame_of(a);
    end->pos = points[count - 1];
    end->frame = hk_m3_mul(q, &frame);
    return 0;
}

int hk_helicoid_piece_model(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                            hk_Vec3 *out_points, hk_CurveStart *end)
{
    hk_HelicoidFitter *f = user;
    hk_PHelicoid h;
    double step;
    if (model_piece(f, params, start, length, count, &h, &step) != 0) return 1;
    if (hk_phelicoid_trace(&h, step, NULL, NULL, out_points, f->frames, NULL) != HK_OK) return 1;
    if (near_axis(&h, out_points, count)) return 1;
    end->pos = out_points[count - 1];
    end->frame = f->frames[count - 1];
    return 0;
}

/* The derivative model: the standard tracer's steps differentiated, or (search) the
 * search's phased trace (SEARCH_TURN, SEARCH_SPAN). */
static int derivative_with(hk_HelicoidFitter *f, int search, const double *params, const hk_CurveStart *start,
                           double length, int count, hk_Vec3 *out_points, hk_CurveStart *end, hk_Vec3 *d_points,
                           hk_Vec3 *d_end_tangent)
{
    hk_PHelicoid h;
    double step;
    if (model_piece(f, params, start, length, count, &h, &step) != 0) return 1;
    /* Traced in the piece's local frame from its origin, then carried to the world. */
    hk_HelicoidAngles a;
    if (search)
        hk_helicoid_piece_rk4_tangent_local(&h.k[0], length, count - 1, SEARCH_TURN, SEARCH_SPAN, out_points, d_points,
                                            &a, d_end_tangent);
    else
        hk_helicoid_piece_rk4_tangent(&h.k[0], length, count - 1, out_points, d_points, &a, d_end_tangent);
    const hk_Mat3 *q = &h.frame;
    for (int i = 0; i < 4 * count; i++) d_points[i] = hk_m3_mul_v3(q, d_points[i]);
    for (int j = 0; j < 4; j++) d_end_tangent[j] = hk_m3_mul_v3(q, d_end_tangent[j]);
    return to_world(&h, &a, out_points, count, end);
}

int hk_helicoid_piece_derivative(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                                 hk_Vec3 *out_points, hk_CurveStart *end, hk_Vec3 *d_points, hk_Vec3 *d_end_tangent)
{
    return derivative_with(user, 0, params, start, length, count, out_points, end, d_points, d_end_tangent);
}

/* The search's model (SEARCH_TURN, SEARCH_SPAN; RK4 also where alpha = 0, which has a
 * closed form), the phases carried instead of taken by sincos (rk4_field.h): the same
 * trace as search_derivative's, whose Jacobian is then this trace's. */
static int search_model(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                        hk_Vec3 *out_points, hk_CurveStart *end)
{
    hk_HelicoidFitter *f = user;
    hk_PHelicoid h;
    double step;
    if (model_piece(f, params, start, length, count, &h, &step) != 0) return 1;
    hk_HelicoidAngles a;
    hk_helicoid_piece_rk4_local(&h.k[0], length, count - 1, SEARCH_TURN, SEARCH_SPAN, out_points, &a);
    return to_world(&h, &a, out_points, count, end);
}

static int search_derivative(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                             hk_Vec3 *out_points, hk_CurveStart *end, hk_Vec3 *d_points, hk_Vec3 *d_end_tangent)
{
    return derivative_with(user, 1, params, start, length, count, out_points, end, d_points, d_end_tangent);
}

/* The helicoid's frame at the root from the estimated Frenet frame: its initial
 * curvature vector is k_T (E_N + alpha E_B) (eq. 1-2 differentiated at the origin, where
 * d theta/ds = k_T and d phi/ds = alpha k_T), so its Frenet normal is E_N rolled about
 * E_T by atan(alpha): roll the estimate back by that much. With this rule the root frame
 * follows alpha, and a fit started in the Frenet frame can reach every helicoid. */
static void root_roll(void *user, const double *params, hk_CurveStart *start)
{
    /* The fitter asks for the same alpha again and again (the pose's rates in the other
     * parameters, the residuals of a step that keeps it): its roll's arctangent, cosine
     * and sine are remembered, the same bits. */
    hk_HelicoidFitter *f = user;
    if (!f->rolled || memcmp(&f->roll_alpha, &params[3], sizeof(double)) != 0) {
        const double roll = -atan(params[3]);
        f->roll_alpha = params[3], f->roll_c = cos(roll), f->roll_s = sin(roll), f->rolled = 1;
    }
    const double c = f->roll_c, sn = f->roll_s;
    const hk_Vec3 t = hk_m3_col(&start->frame, 0), n = hk_m3_col(&start->frame, 1), b = hk_m3_col(&start->frame, 2);
    const hk_Vec3 n2 = hk_v3_add(hk_v3_scale(n, c), hk_v3_scale(b, sn));
    start->frame = hk_m3_from_cols(t, n2, hk_v3_cross(t, n2));
}

/* A starting point from the fragment's discrete curvature vector kappa = (p0 - 2 p1 +
 * p2) / h^2 in the start frame: k_T = kappa . N and alpha = (kappa . B) / (kappa . N)
 * (the initial curvature vector above); k_N = k_B = 0. At the root the frame is the
 * Frenet one, so kappa . B is about 0 and root_roll supplies the roll. */
static void fragment_seed(void *user, const hk_Vec3 *p, int count, const hk_CurveStart *start, double *params)
{
    (void)user;
    (void)count;
    const double h = hk_v3_dist(p[1], p[0]);
    for (int i = 0; i < 4; i++) params[i] = 0.0;
    if (!(h > 0.0)) return;
    const hk_Vec3 kappa = hk_v3_scale(hk_v3_add(hk_v3_sub(p[0], hk_v3_scale(p[1], 2.0)), p[2]), 1.0 / (h * h));
    const double kn = hk_v3_dot(kappa, hk_m3_col(&start->frame, 1)), kb = hk_v3_dot(kappa, hk_m3_col(&start->frame, 2));
    if (!isfinite(kn) || !isfinite(kb)) return;
    params[0] = kn;
    /* |alpha| <= 1: beyond it the curve climbs more than it turns, better found by the
     * minimiser than guessed from one corner. */
    if (fabs(kn) > 1e-9 * fabs(kb)) params[3] = fmax(-1.0, fmin(1.0, kb / kn));
}

/* One fit with the options as they are (the body of hk_helicoid_fit). */
static hk_Status fit_once(hk_HelicoidFitter *f, const hk_Vec3 *points, int count, const hk_CurveFitDef *options,
                          hk_PHelicoid *out, hk_CurveFit *fit, hk_Error *err)
{
    const hk_CurveFitDef opt = *options;
    double length = 0.0;
    for (int i = 1; i < count; i++) length += hk_v3_dist(points[i], points[i - 1]);
    double seed[4], scale[4];
    hk_helicoid_fit_seed(length, seed, scale);

    hk_CurveFitDef first = opt;
    first.fragment_seed = fragment_seed;
    /* alpha is a pitch ratio, not a curvature: weigh it as a curvature of one radian per
     * sample spacing, so that the regularisation prefers a bend in the frame's normal
     * plane (k_T, alpha near 0) to the same bend made with k_T near 0 and alpha huge (the
     * root roll rule makes them equal at the root, and both are planar when alpha -> inf):
     * fits of neighbouring strands then agree on their parameters and can be blended
     * (§5.4). An |alpha| of 1 costs what k = 1/h does, lambda / h (50 um at 2 mm). */
    if (!(first.penalty_weight[3] > 0.0) && count >= 2 && length > 0.0)
        first.penalty_weight[3] = (double)(count - 1) / length;
    if (!opt.use_start) first.root_frame = root_roll;
    if (!opt.use_start && count >= 3 && hk_curve_estimate_start(points, count, &first.start, NULL) == HK_OK) {
        /* curvefit's estimate takes the first segment as the tangent, exact for the
         * paper's forward-Euler traces but off by half a segment's turn for a smooth
         * strand (0.05 rad at k = 30 / m and 3.4 mm spacing: millimetres at the tip).
         * The derivative of the parabola through the first three points (Lagrange, on
         * the chord lengths) is second order. */
        const double h1 = hk_v3_dist(points[1], points[0]), h2 = hk_v3_dist(points[2], points[1]);
        if (h1 > 0.0 && h2 > 0.0) {
            const double c0 = -(2.0 * h1 + h2) / (h1 * (h1 + h2)), c1 = (h1 + h2) / (h1 * h2),
                         c2 = -h1 / (h2 * (h1 + h2));
            hk_Vec3 t = hk_v3_add(hk_v3_add(hk_v3_scale(points[0], c0), hk_v3_scale(points[1], c1)),
                                  hk_v3_scale(points[2], c2));
            const hk_Vec3 t0 = hk_m3_col(&first.start.frame, 0);
            if (hk_v3_norm(t) > 0.5 && hk_v3_dot(t, t0) > 0.5 * hk_v3_norm(t)) {
                t = hk_v3_normalize(t);
                hk_Vec3 n = hk_m3_col(&first.start.frame, 1);
                n = hk_v3_normalize(hk_v3_madd(n, t, -hk_v3_dot(n, t)));
                first.start.frame = hk_m3_from_cols(t, n, hk_v3_cross(t, n));
                first.use_start = 1;
            }
        }
    }
    /* The search with the search's tracer, finished with the standard one (see above). */
    first.final_model = hk_helicoid_piece_model;
    first.final_derivative = opt.model_derivative;
    /* The finishing's Jacobians from the search's cheaper differentiated trace too: they
     * only steer its steps, whose residuals and kept errors are the standard tracer's, and
     * the two tracers' columns differ by microns (Curly's fits moved by 0.08 um at most;
     * docs/helicoid-fitting.md §7). */
    if (opt.model_derivative == hk_helicoid_piece_derivative)
        first.model_derivative = first.final_derivative = search_derivative;
    else if (opt.model_derivative)
        first.final_model = NULL; /* someone else's derivative: no search tracer */
    hk_Status st =
        hk_curve_fit_piecewise_ws(f->ws, points, count, first.final_model ? search_model : hk_helicoid_piece_model, f,
                                  4, seed, scale, &first, fit, err);
    if (st != HK_OK) return st;
    if (fit->piece_count > HK_HELICOID_MAX_PIECES)
        return hk_error_set(err, HK_ERR_INVALID, "fit of %d pieces: at most %d", fit->piece_count,
                            HK_HELICOID_MAX_PIECES);
    memset(out, 0, sizeof *out);
    out->root = fit->start.pos;
    out->frame = fit->start.frame;
    out->piece_count = fit->piece_count;
    for (int p = 0; p < fit->piece_count; p++) {
        out->k[p] = (hk_Helicoid){fit->params[p][0], fit->params[p][1], fit->params[p][2], fit->params[p][3]};
        out->length[p] = fit->length[p];
    }
    return HK_OK;
}

/* A coarse polyline (fewer than this many points) whose fit misses the tolerance is fitted
 * again on RESAMPLE times as many samples, and the better fit is kept. */
#define COARSE_POINTS 64
#define RESAMPLE      4

hk_Status hk_helicoid_fit(hk_HelicoidFitter *f, const hk_Vec3 *points, int count, const hk_CurveFitDef *options,
                          hk_PHelicoid *out, hk_CurveFit *fit, hk_Error *err)
{
    hk_CurveFit local;
    if (!fit) fit = &local;
    const hk_CurveFitDef opt = options ? *options : hk_default_helicoid_fit_def();
    hk_Status st = fit_once(f, points, count, &opt, out, fit, err);
    /* A piece needs param_count + 2 samples, so a strand of 16 points (TressFX) is never
     * cut into more than 2 pieces, and most real strands then miss the tolerance (0.74 mm
     * mean on the Sintel groom, a strand 85 mm off). Resampled 4 times finer (the points
     * kept, straight between them) it can be cut where it bends: on every 38th Sintel
     * strand the mean error goes from 0.64 to 0.18 mm and the worst from 18 to 0.86 mm;
     * Bangs 0.50 to 0.15 mm, Curly 0.49 to 0.17 mm (docs/helicoid-fitting.md). The
     * errors compared are both mean leashes against the same polyline. */
    const int finer = RESAMPLE * (count - 1) + 1;
    if (st == HK_OK && opt.samples == 0 && opt.fixed_pieces == 0 && !(opt.piece_length > 0.0) &&
        count < COARSE_POINTS && fit->error > opt.tolerance && finer <= f->capacity) {
        hk_CurveFitDef retry = opt;
        retry.samples = finer;
        /* the strand in one piece missed at its own points: no need to try it again */
        retry.known_to_split = 1;
        hk_PHelicoid other;
        hk_CurveFit other_fit = {0};
        hk_Error ignored;
        if (fit_once(f, points, count, &retry, &other, &other_fit, &ignored) == HK_OK && other_fit.error < fit->error) {
            other_fit.evaluations += fit->evaluations;
            *out = other;
            *fit = other_fit;
        } else {
            fit->evaluations += other_fit.evaluations;
        }
    }
    return st;
}
