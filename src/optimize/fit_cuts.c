/* Where to cut a range that one piece cannot fit (Piuze et al. 2011 §5.3), and the
 * recursion over ranges.
 *
 * The paper's cut (with Nelder-Mead):
 *  - upper limit (Fréchet threshold): grow a fragment from the start of the range while
 *    the coupling of the fragment against the same stretch of the fit stays within
 *    split_threshold (60% in the paper) of the whole fit's coupling; at 100% the whole
 *    range is one fragment, as the paper says. Fit that fragment; while its fit is
 *    still within tolerance, grow it by half and fit again, so that the limit lies past
 *    the change the split is looking for;
 *  - backtracking (curvature): compare the bend of the target and of the fragment's fit
 *    vertex by vertex (turning and twisting angles, which do not depend on where the
 *    fit has drifted to) and cut where the target stops agreeing with the fit: the
 *    minimum of the cumulative sum of (difference - its mean) over the fragment (a CUSUM
 *    change point), no closer to the start than the minimal fragment.
 * Ours (with least squares): the longest acceptable prefix, searched from the short end
 * (fragments twice as long while they fit, then bisection), settled up to SETTLE_BACK
 * samples back by a look-ahead fit. */
#include <math.h>
#include <string.h>

#include "optimize/piecewise_internal.h"

/* Upper limit of the first fragment: the last sample k such that the fragment i0..k
 * couples with the same stretch of the fit (in ws->best) within `threshold` of the
 * whole range's coupling. */
static int frechet_upper_limit(Fit *F, int i0, int i1)
{
    const int m = i1 - i0 + 1;
    const double total = hk_frechet_coupling_prefix(F->ws->target + i0, F->ws->best, m, F->ws->row, F->ws->prefix);
    const double limit = F->opt->split_threshold * total;
    for (int k = 1; k < m; k++)
        if (F->ws->prefix[k] > limit) return i0 + k - 1;
    return i1;
}

/* Backtracking from the upper limit k_max: the cut k in [k_lo, k_max] where the target's
 * bend stops agreeing with the fit of fragment i0..k_max (see above). Vertex j's
 * bend (its turning angle and the twist that follows) belongs to the piece that owns the
 * step from segment j-1 to segment j, so a cut at k keeps vertices up to k. The fit is
 * traced two samples past k_max (k_max <= i1 - 2) so that those bends exist. */
static hk_Status curvature_cut(Fit *F, int i0, int k_lo, int k_max, const Piece *frag, int *cut)
{
    const int m = k_max - i0 + 3;
    hk_CurveStart end;
    /* A model may refuse to go on past its fragment (a helicoid nearing its singular
     * axis): then the last two vertices' bends are not compared (they count as the mean
     * difference, neutral in the cumulative sum below). */
    int last = k_max;
    if (hk_cf_trace(F, frag->params, &frag->start, m, F->ws->best, &end) != 0) {
        last = k_max - 2;
        if (last <= i0 || hk_cf_trace(F, frag->params, &frag->start, m - 2, F->ws->best, &end) != 0)
            return hk_error_set(F->err, HK_ERR_NUMERIC,
                                "curve fit: the model failed at its own best fit (samples %d..%d)", i0, k_max);
    }
    double *d = F->ws->diff;
    double mean = 0.0;
    for (int j = i0 + 1; j <= last; j++) {
        double turn_t, twist_t, turn_f, twist_f;
        hk_polyline_bend(F->ws->target, j, &turn_t, &twist_t);
        hk_polyline_bend(F->ws->best, j - i0, &turn_f, &twist_f);
        d[j] = fabs(turn_t - turn_f) + fabs(twist_t - twist_f);
        mean += d[j];
    }
    mean /= (double)(last - i0);
    for (int j = last + 1; j <= k_max; j++) d[j] = mean;
    double s = 0.0, best_s = INFINITY;
    int best_k = k_max;
    for (int k = i0 + 1; k <= k_max; k++) {
        s += d[k] - mean;
        /* <=: among equal sums the longest fragment, the first met when backtracking
         * from the upper limit as the paper does. */
        if (k >= k_lo && s <= best_s) {
            best_s = s;
            best_k = k;
        }
    }
    *cut = best_k;
    return HK_OK;
}

/* The paper's cut (§5.3, see above): an upper limit from the Fréchet threshold,
 * grown while the fragment still fits, then backtracking by bends. frag gets a fit
 * usable as the first part's hint; *reuse says whether it is the fit of exactly i0..cut. */
static hk_Status paper_cut(Fit *F, int i0, int i1, int k_lo, int k_hi, const hk_CurveStart *start, const Piece *whole,
                           Piece *frag, int *cut, int *reuse)
{
    hk_Status st;
    /* The whole fit's trace for the Fréchet threshold (a `known` fit left none behind). */
    hk_CurveStart tmp;
    if (hk_cf_trace(F, whole->params, &whole->start, i1 - i0 + 1, F->ws->best, &tmp) != 0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed at its own best fit (samples %d..%d)",
                            i0, i1);
    int k_max = frechet_upper_limit(F, i0, i1);
    k_max = k_max < k_lo ? k_lo : (k_max > k_hi ? k_hi : k_max);
    *frag = *whole;
    *reuse = 0;
    *cut = k_lo;
    if (k_max <= k_lo) return HK_OK;
    /* Fits that only locate the cut stay in the estimated root frame: no refinement
     * for each, and on clean data that frame is the exact one. */
    if ((st = hk_cf_fit_piece(F, i0, k_max, start, 0, whole, NULL, frag)) != HK_OK) return st;
    /* The threshold is only a first guess: while the fragment still fits within the
     * tolerance, grow it by half, so that the backtracking starts past the change. */
    while (frag->error <= F->opt->tolerance && k_max < k_hi) {
        const int step = (k_max - i0) / 2 > F->min_points - 1 ? (k_max - i0) / 2 : F->min_points - 1;
        const int next = k_max + step < k_hi ? k_max + step : k_hi;
        Piece longer;
        if ((st = hk_cf_fit_piece(F, i0, next, start, 0, frag, NULL, &longer)) != HK_OK) return st;
        k_max = next;
        *frag = longer;
    }
    if ((st = curvature_cut(F, i0, k_lo, k_max, frag, cut)) != HK_OK) return st;
    /* The fragment's fit is the first part's when the cut is at its end (at the root
     * with refine_start, the first part gets its own chance to refine the frame). */
    *reuse = *cut == k_max && (i0 > 0 || !F->opt->refine_start);
    return HK_OK;
}

/* Samples the longest acceptable prefix may overshoot a join by (its last points lean
 * a little off the piece it belongs to, within the tolerance) and the cuts tried there;
 * on a resampled coarse target one sample back only (see settle_cut). */
#define SETTLE_BACK           3
#define SETTLE_BACK_RESAMPLED 1
#define SETTLE_GAIN           0.01

/* A prefix that runs a sample or two past a join still fits within the tolerance, but
 * it ends in a pose the next piece cannot start from. Try the cut at the longest
 * acceptable prefix and up to SETTLE_BACK samples before it, and (on a target fitted at
 * its own points) further back while each cut still improves on the last: each with its
 * first part fitted and a look-ahead piece (as long as half that part, at least a
 * minimal fragment) fitted from its end pose; keep the cut whose two fits have the least
 * mean error (the later cut on ties). A bent prefix can stay within the tolerance well
 * past a join (examples/helicoid/curly.txt traced at 0.5 mm: pieces of 60 samples fit up
 * to 66, their errors falling steadily back to the join at 60; stopping at 63 left a
 * first piece in a wrong minimum, and 16 pieces 3.1 mm off where 8 recover the strand to
 * 5 um). frag holds the first part's fit of *cut on entry and on return. (The kept cut's
 * look-ahead as the rest's first fragment, or its seed, saved 1-8% of the model calls
 * on Sintel, Bangs and Curly but took examples/helicoid/wisp.txt from 0.068 to 0.109 mm:
 * a piece of a wave is a poor start for the next one, docs/helicoid-fitting.md §7.) */
static hk_Status settle_cut(Fit *F, int i0, int k_lo, int i1, Piece *frag, int *cut)
{
    const int good = *cut;
    /* On a resampled coarse target the added samples lie on straight chords, and the
     * mean error of a cut wanders with where their corners fall: past the window it
     * walked a CT2Hair Bangs strand back from sample 13 to 8 (0.43 mm instead of
     * 0.16 mm); four cuts instead of two cost 17% more traced points for mean errors
     * within 0.01 mm on Sintel, Bangs and Curly (docs/helicoid-fitting.md §7). */
    const int window = F->opt->samples != 0 ? SETTLE_BACK_RESAMPLED : SETTLE_BACK;
    double best = INFINITY;
    Piece first = *frag, look;
    int looked = 0;
    for (int c = good; c >= k_lo; c--) {
        const int beyond = c < good - window; /* go on only while it improves */
        if (beyond && F->opt->samples != 0) break;
        hk_Status st;
        if (c != good && (st = hk_cf_fit_piece(F, i0, c, &frag->base, 0, frag, NULL, &first)) != HK_OK) return st;
        if (!hk_cf_acceptable(F, &first)) {
            if (beyond) break;
            continue;
        }
        const int half = (c - i0) / 2 > F->min_points - 1 ? (c - i0) / 2 : F->min_points - 1;
        const int end = c + half < i1 ? c + half : i1;
        if (end <= c + 1) return HK_OK; /* no room to look ahead: keep the longest */
        /* seeded by the last look-ahead, one sample further on */
        if ((st = hk_cf_fit_piece(F, c, end, &first.end, 0, looked ? &look : NULL, NULL, &look)) != HK_OK) return st;
        looked = 1;
        const double mean = (first.error * (c - i0 + 1) + look.error * (end - c + 1)) / (double)(end - i0 + 2);
        /* Beyond the first SETTLE_BACK cuts a cut must gain a hundredth of the tolerance:
         * on a target the model makes exactly every error is rounding, and those
         * "gains" would walk the cut back to the shortest fragment. */
        if (mean < best - (beyond ? SETTLE_GAIN * F->opt->tolerance : 0.0)) {
            best = mean;
            *cut = c;
            if (c != good) *frag = first;
        } else if (beyond) {
            break;
        }
    }
    return HK_OK;
}

/* Fits samples i0..k from frag's root frame with one Levenberg-Marquardt run from frag
 * (the last fragment that fitted, usually a few steps from the longer one's minimum):
 * *fits = 1 when it is acceptable (then in *frag). A probe that misses is expected at
 * the end of the search: three starts for each cost 39% more traced points for Sintel's
 * mean error 0.193 mm instead of 0.202 mm, Bangs' and Curly's the same
 * (docs/helicoid-fitting.md §7). */
static hk_Status probe(Fit *F, int i0, int k, const Piece *hint, Piece *frag, int *fits)
{
    Piece trial;
    F->single_start = 1;
    const hk_Status st = hk_cf_fit_piece(F, i0, k, &frag->base, 0, frag, hint, &trial);
    F->single_start = 0;
    if (st != HK_OK) return st;
    *fits = hk_cf_acceptable(F, &trial);
    if (*fits) *frag = trial;
    return HK_OK;
}

/* Our cut for the least-squares fitter: the longest first fragment i0..k (k_lo <= k <=
 * k_hi) whose own fit is within the tolerance, the whole range i1 counting as the
 * longest of all (no cut; *cut = i1 and *whole its fit). A longer fragment can only fit
 * worse, give or take the normalisation, so it is searched for from the short end: the
 * shortest fragment, then fragments twice as long until one misses, then bisection
 * between the two, each probe started from the last fragment that fitted.
 * Cutting greedily at the longest acceptable prefix gives the fewest pieces when
 * acceptability is monotone, and on a target made of pieces it lands on a join (the
 * prefix stops fitting exactly where the next piece begins). Searched from the long end
 * (the whole range first, then bisection over the rest of it), most probes were long
 * fragments that miss, each fitted from three starts: on Sintel three quarters of the
 * traced points. When even the shortest fragment misses, the cut is there (a longer
 * fragment would miss too; the undo below compares the whole range when the strand
 * misses). whole_misses: the whole range is known to miss. frag gets the fit of
 * i0..cut. */
static hk_Status longest_prefix_cut(Fit *F, int i0, int i1, int k_lo, int k_hi, const hk_CurveStart *start,
                                    const Piece *hint, int whole_misses, Piece *whole, Piece *frag, int *cut)
{
    hk_Status st;
    /* The probes stay in the root frame the shortest one settled (refining the frame for
     * each would be costly and, on a range that needs two pieces, would turn the frame to
     * fit the wrong shape); the shortest one may refine it, which noisy first points
     * need. */
    if ((st = hk_cf_fit_piece(F, i0, k_lo, start, 1, hint, NULL, frag)) != HK_OK) return st;
    *cut = k_lo;
    if (!hk_cf_acceptable(F, frag)) return HK_OK; /* a longer fragment would miss too */
    int good = k_lo;
    int bad = whole_misses ? k_hi + 1 : i1 + 1; /* the shortest fragment known to miss (i1 + 1: none) */
    while (good < bad - 1 && good < i1) {
        int next = bad > i1 ? i0 + 2 * (good - i0) : good + (bad - good) / 2;
        /* cuts lie in k_lo..k_hi; past k_hi only the whole range (no cut) is left */
        if (next >= i1)
            next = i1;
        else if (next > k_hi)
            next = good < k_hi ? k_hi : i1;
        if (next == i1 && bad <= i1) break;
        int fits;
        if (next == i1) {
            if ((st = hk_cf_fit_piece(F, i0, i1, start, i0 == 0, frag, hint, whole)) != HK_OK) return st;
            if (hk_cf_acceptable(F, whole)) {
                *cut = i1;
                return HK_OK;
            }
            bad = k_hi + 1;
            continue;
        }
        if ((st = probe(F, i0, next, hint, frag, &fits)) != HK_OK) return st;
        if (fits)
            good = next;
        else
            bad = next;
    }
    *cut = good;
    if ((st = settle_cut(F, i0, k_lo, i1, frag, cut)) != HK_OK) return st;
    /* The first piece at the root, now that its extent is known, may refine the frame it
     * starts from (the probes kept the estimated one): every later piece inherits it. */
    if (i0 == 0 && F->opt->refine_start) {
        Piece trial;
        if ((st = hk_cf_fit_piece(F, i0, *cut, start, 1, frag, NULL, &trial)) != HK_OK) return st;
        if (hk_cf_acceptable(F, &trial) && trial.error + trial.join_error < frag->error + frag->join_error)
            *frag = trial;
    }
    return HK_OK;
}

/* The normalised coupling of the output's pieces from `mark` on, chained from their
 * first start, against samples i0..i1 (traced into ws->chain); -1 when the model failed. */
static double chained_error(Fit *F, int mark, int i0, int i1)
{
    if (hk_cf_trace_chain(F->model, F->user, F->out, mark, F->out->piece_count, i1, F->h, &F->starts[mark],
                          F->ws->chain, &F->evaluations) != 0)
        return -1.0;
    const int m = i1 - i0 + 1;
    return hk_frechet_coupling_prefix(F->ws->target + i0, F->ws->chain + i0, m, F->ws->row, NULL) / (double)m;
}

/* The least-squares recursion on samples i0..i1 from `start` (see hk_cf_fit_range):
 * the longest acceptable prefix is emitted, and the rest fitted from its end pose.
 * `known` (may be NULL) is a fit of this very range; hint (may be NULL) an extra seed. */
static hk_Status fit_range_lsq(Fit *F, int i0, int i1, const hk_CurveStart *start, int budget, const Piece *known,
                               const Piece *hint, hk_CurveStart *end)
{
    hk_Status st;
    Piece whole;
    /* A first fragment that also turns the root frame has ROT more unknowns to pin down. */
    const int first_points = F->min_points + (F->opt->refine_start && i0 == 0 ? ROT : 0);
    const int k_lo = i0 + first_points - 1, k_hi = i1 - (F->min_points - 1);
    if (budget < 2 || k_lo > k_hi) {
        if (known)
            whole = *known;
        else if ((st = hk_cf_fit_piece(F, i0, i1, start, 1, hint, NULL, &whole)) != HK_OK)
            return st;
        hk_cf_emit(F, &whole, i0, i1);
        *end = whole.end;
        return HK_OK;
    }
    /* The strand in one piece first, unless the caller knows it misses. Fragments of it
     * are fitted with the join term, whose target tangent comes from the points near the
     * cut: on noisy points (0.1 mm on 3.4 mm spacing turns it by 0.05 rad, a millimetre
     * over 4 cm) no fragment is acceptable, and a strand that fits in one piece was cut
     * into eight (test_fit_noise). */
    Piece strand;
    const int strand_fitted = i0 == 0 && !F->opt->known_to_split;
    if (strand_fitted) {
        if ((st = hk_cf_fit_piece(F, i0, i1, start, 1, known ? known : hint, known ? hint : NULL, &strand)) != HK_OK)
            return st;
        if (hk_cf_acceptable(F, &strand)) {
            hk_cf_emit(F, &strand, i0, i1);
            *end = strand.end;
            return HK_OK;
        }
        /* a seed for the fragments: on a strand that lifts off its root (test_lift_off_
         * layouts), warm starts from the shortest fragment alone led every longer one
         * astray (ten minimal pieces, 0.21 mm; three and 0.089 mm with this seed) */
        if (!hint) hint = &strand;
    }
    Piece frag;
    int cut;
    if ((st = longest_prefix_cut(F, i0, i1, k_lo, k_hi, start, hint, strand_fitted, &whole, &frag, &cut)) != HK_OK)
        return st;
    if (cut == i1) {
        hk_cf_emit(F, &whole, i0, i1);
        *end = whole.end;
        return HK_OK;
    }
    const int mark = F->out->piece_count;
    hk_cf_emit(F, &frag, i0, cut);
    st = fit_range_lsq(F, cut, i1, &frag.end, budget - 1, NULL, &frag, end);
    if (st != HK_OK || i0 > 0) return st;

    /* Undo a split that made the strand worse (a cut can misjudge): the chain against
     * the strand in one piece (when the caller knew it to miss, fitted now by one run
     * from the first piece, in the frame that piece settled, and only if the chain misses
     * the tolerance too). At the root only: at every level, with the rest's one-piece
     * fit, it cost 21% more traced points for mean errors of 0.195 mm instead of 0.201
     * mm on Sintel, 0.157 instead of 0.161 mm on Bangs, Curly's the same
     * (docs/helicoid-fitting.md §7). */
    const double split_error = chained_error(F, mark, i0, i1);
    if (split_error < 0.0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
    if (!strand_fitted) {
        if (split_error <= F->opt->tolerance) return HK_OK;
        F->single_start = 1;
        st = hk_cf_fit_piece(F, i0, i1, &frag.base, 0, &frag, hint, &strand);
        F->single_start = 0;
        if (st != HK_OK) return st;
    }
    if (!(split_error < strand.error)) {
        F->out->piece_count = mark;
        hk_cf_emit(F, &strand, i0, i1);
        *end = strand.end;
    }
    return HK_OK;
}

/* Fits samples i0..i1 from `start` with at most `budget` pieces, appending them to
 * F->out; *end gets the end pose of the last one. `known` (may be NULL) is a fit of this
 * very range already computed; hint (may be NULL) an extra seed. */
hk_Status hk_cf_fit_range(Fit *F, int i0, int i1, const hk_CurveStart *start, int budget, const Piece *known,
                          const Piece *hint, hk_CurveStart *end)
{
    if (F->opt->method == HK_CURVEFIT_LEAST_SQUARES) return fit_range_lsq(F, i0, i1, start, budget, known, hint, end);
    Piece whole;
    hk_Status st;
    if (known)
        whole = *known;
    else if ((st = hk_cf_fit_piece(F, i0, i1, start, 1, hint, NULL, &whole)) != HK_OK)
        return st;
    /* A first fragment that also turns the root frame has ROT more unknowns to pin down. */
    const int first_points = F->min_points + (F->opt->refine_start && i0 == 0 ? ROT : 0);
    const int k_lo = i0 + first_points - 1, k_hi = i1 - (F->min_points - 1);
    if (hk_cf_acceptable(F, &whole) || budget < 2 || k_lo > k_hi) {
        hk_cf_emit(F, &whole, i0, i1);
        *end = whole.end;
        return HK_OK;
    }

    /* frag fits samples i0..cut when the heuristic says so; otherwise it is only a hint
     * for the first part's own fit. */
    Piece frag;
    int cut = k_lo, reuse = 1;
    if ((st = paper_cut(F, i0, i1, k_lo, k_hi, start, &whole, &frag, &cut, &reuse)) != HK_OK) return st;
    const int mark = F->out->piece_count;
    hk_CurveStart mid;
    st = hk_cf_fit_range(F, i0, cut, start, budget - 1, reuse ? &frag : NULL, &frag, &mid);
    if (st != HK_OK) return st;
    const int used = F->out->piece_count - mark;
    st = hk_cf_fit_range(F, cut, i1, &mid, budget - used, NULL, &whole, end);
    if (st != HK_OK) return st;

    /* Undo a split that made the range worse (the heuristics can misjudge a cut). */
    const double split_error = chained_error(F, mark, i0, i1);
    if (split_error < 0.0)
        return hk_error_set(F->err, HK_ERR_NUMERIC, "curve fit: the model failed re-tracing its own pieces");
    if (!(split_error < whole.error)) {
        F->out->piece_count = mark;
        hk_cf_emit(F, &whole, i0, i1);
        *end = whole.end;
    }
    return HK_OK;
}
