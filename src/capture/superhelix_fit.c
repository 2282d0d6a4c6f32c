/* A Super-Helix fitted to a polyline (hairkit/capture.h; docs/capture.md, "Fitting").
 *
 * Unknowns: q = (tau, kappa1, kappa2) of each of N elements of equal length; the root
 * pose is fixed by the polyline. Residuals: e_j = r(s_j; q) - p_j for every point after
 * the root, at its arc length s_j along the polyline. The Jacobian is exact: over element
 * Q with start frame R_Q, a change dk of its curvatures moves its end by R_Q (dd/dk) dk
 * and turns everything beyond by the world rotation vector R_Q Lambda_Q dk (the
 * kinematics of Bertails et al. 2006 §3.1 as hairkit/rod.h writes them; d E E^T =
 * [Lambda dk]x), so for a point at r in a later element
 *     dr/dk_Q = R_Q dd_Q - [r - r_{Q+1}]x R_Q Lambda_Q = C_Q - [r]x B_Q,
 * with C_Q = R_Q dd_Q + [r_{Q+1}]x B_Q and B_Q = R_Q Lambda_Q computed once per element,
 * and dr/dk_P = R_P dd(u) in its own element P. A point depends on the elements up to
 * its own only (the Jacobian is block lower triangular), and J^T J is summed block by
 * block. The generic Levenberg-Marquardt of src/optimize takes at most 32 parameters
 * and differences its Jacobian; a strand has up to 3 x 256 here, so the damped
 * Gauss-Newton loop (Nielsen's update of the damping) is written
 * for this Jacobian (with Levenberg's damping, see least_squares()).
 *
 * Two starts, the better kept: element after element, each element's curvatures fitted
 * alone (a few Gauss-Newton steps on 3 unknowns) to the polyline over its own length and
 * the next one's, from the end pose of the previous one; and coarse to fine, from one
 * element to N by doubling. When N is chosen, it then doubles by splitting every element
 * in two with the same curvatures (the same curve) and fitting again. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "hairkit/capture.h"
#include "rod/helix_local.h"

#define FIT_MAX_ELEMENTS  256
#define COARSE_ITERATIONS 30   /* per coarse level: a start for the next, not an answer */
#define FIT_MIN_SEGMENT   1e-9 /* m: consecutive points closer than this are one point */

hk_SuperHelixFitDef hk_default_superhelix_fit_def(void)
{
    hk_SuperHelixFitDef d;
    d.elements = 0;
    d.element_length = 0.01;
    d.max_elements = 64;
    d.tolerance = 5e-5;
    d.max_iterations = 200;
    return d;
}

typedef struct Fit {
    int m;           /* points after the root */
    hk_Vec3 *target; /* [m] */
    double *s;       /* [m] arc length of each along the polyline */
    double *poly_s;  /* [m + 1] arc length of every polyline point, the root's 0 */
    hk_Vec3 *poly;   /* [m + 1] the polyline without repeated points */
    int *elem;       /* [m] element of each point for the current N */
    double *u;       /* [m] offset into it */
    hk_SuperHelix *sh;
    /* per element, for the current q */
    hk_Vec3 *node;                                         /* [N + 1] */
    hk_Mat3 *frame;                                        /* [N + 1] */
    hk_Mat3 *bq, *cq;                                      /* [N] B_Q and C_Q above */
    hk_Mat3 *jb;                                           /* [N] a point's Jacobian blocks */
    double *ata, *g, *factor, *diag, *step, *trial, *best; /* 3N x 3N, then 3N each */
} Fit;

static hk_Vec3 k_of(const double *q, int e) { return hk_v3(q[3 * e], q[3 * e + 1], q[3 * e + 2]); }

static hk_Mat3 cross_matrix(hk_Vec3 v)
{
    hk_Mat3 m = hk_m3_zero();
    m.m[0][1] = -v.z;
    m.m[0][2] = v.y;
    m.m[1][0] = v.z;
    m.m[1][2] = -v.x;
    m.m[2][0] = -v.y;
    m.m[2][1] = v.x;
    return m;
}

/* Poses at the element ends for q, and with derivs the blocks B_Q and C_Q. */
static void forward(Fit *f, const double *q, int derivs)
{
    const hk_SuperHelix *sh = f->sh;
    f->node[0] = sh->root;
    f->frame[0] = sh->root_frame;
    for (int e = 0; e < sh->n; e++) {
        hk_ElementLocal el;
        hk_element_local(k_of(q, e), sh->length[e], derivs ? 1 : 0, 0, &el);
        const hk_Mat3 *r = &f->frame[e];
        f->node[e + 1] = hk_v3_add(f->node[e], hk_m3_mul_v3(r, hk_m3_col(&el.lam, 0)));
        f->frame[e + 1] = hk_m3_mul(r, &el.rot);
        if (derivs) {
            f->bq[e] = hk_m3_mul(r, &el.lam);
            const hk_Mat3 a = hk_m3_mul(r, &el.dd), rx = cross_matrix(f->node[e + 1]);
            const hk_Mat3 rb = hk_m3_mul(&rx, &f->bq[e]);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) f->cq[e].m[i][j] = a.m[i][j] + rb.m[i][j];
        }
    }
}

/* The Super-Helix at point j's arc length, after forward(). dd: its own element's block. */
static hk_Vec3 point_at(const Fit *f, const double *q, int j, hk_Mat3 *dd)
{
    const int e = f->elem[j];
    hk_Mat3 local;
    const hk_Vec3 d = hk_element_offset(k_of(q, e), f->u[j], dd ? &local : NULL, NULL);
    if (dd) *dd = hk_m3_mul(&f->frame[e], &local);
    return hk_v3_add(f->node[e], hk_m3_mul_v3(&f->frame[e], d));
}

/* Half the sum of squared residuals at q; the mean and largest distance when asked. */
static double cost_at(Fit *f, const double *q, double *mean, double *max)
{
    forward(f, q, 0);
    double c = 0.0, sum = 0.0, top = 0.0;
    for (int j = 0; j < f->m; j++) {
        const double d = hk_v3_norm(hk_v3_sub(point_at(f, q, j, NULL), f->target[j]));
        c += 0.5 * d * d;
        sum += d;
        if (d > top) top = d;
    }
    if (mean) *mean = sum / f->m;
    if (max) *max = top;
    return c;
}

/* J^T J (lower and upper triangles) and J^T e at sh->q; returns the cost. */
static double normal_equations(Fit *f)
{
    const double *q = f->sh->q;
    const int n = f->sh->n, dim = 3 * n;
    forward(f, q, 1);
    memset(f->ata, 0, (size_t)dim * (size_t)dim * sizeof(double));
    memset(f->g, 0, (size_t)dim * sizeof(double));
    double c = 0.0;
    for (int j = 0; j < f->m; j++) {
        const int p = f->elem[j];
        hk_Mat3 own;
        const hk_Vec3 r = point_at(f, q, j, &own);
        const hk_Vec3 e = hk_v3_sub(r, f->target[j]);
        c += 0.5 * hk_v3_dot(e, e);
        const hk_Mat3 rx = cross_matrix(r);
        for (int b = 0; b < p; b++) {
            const hk_Mat3 t = hk_m3_mul(&rx, &f->bq[b]);
            for (int i = 0; i < 3; i++)
                for (int k = 0; k < 3; k++) f->jb[b].m[i][k] = f->cq[b].m[i][k] - t.m[i][k];
        }
        f->jb[p] = own;
        const double ev[3] = {e.x, e.y, e.z};
        for (int b = 0; b <= p; b++)
            for (int k = 0; k < 3; k++) {
                const int row = 3 * b + k;
                const double jk[3] = {f->jb[b].m[0][k], f->jb[b].m[1][k], f->jb[b].m[2][k]};
                f->g[row] += jk[0] * ev[0] + jk[1] * ev[1] + jk[2] * ev[2];
                double *arow = f->ata + (size_t)row * (size_t)dim;
                for (int b2 = 0; b2 <= b; b2++)
                    for (int k2 = 0; k2 < 3; k2++) {
                        const int col = 3 * b2 + k2;
                        if (col > row) break;
                        arow[col] +=
                            jk[0] * f->jb[b2].m[0][k2] + jk[1] * f->jb[b2].m[1][k2] + jk[2] * f->jb[b2].m[2][k2];
                    }
            }
    }
    for (int i = 0; i < dim; i++)
        for (int k = 0; k < i; k++)
            f->ata[(size_t)k * (size_t)dim + (size_t)i] = f->ata[(size_t)i * (size_t)dim + (size_t)k];
    return c;
}

/* Damped Gauss-Newton on sh->q until it stops improving; returns the iterations. */
static int least_squares(Fit *f, int max_iterations)
{
    const int dim = 3 * f->sh->n;
    double *q = f->sh->q;
    double mu = -1.0, nu = 2.0;
    int it = 0;
    while (it < max_iterations) {
        it++;
        const double cost = normal_equations(f);
        double top = 0.0;
        for (int i = 0; i < dim; i++) top = fmax(top, f->ata[(size_t)i * (size_t)dim + (size_t)i]);
        if (!(top > 0.0) || !(cost > 0.0)) break;
        /* Levenberg's damping, mu times the largest diagonal on every coordinate: they all
         * are curvatures (1/m). Marquardt's scaling by each diagonal lets the twist of
         * nearly straight elements (which the centreline hardly sees) take big steps into
         * the curved valley the twist and the next curvatures make, where the model is
         * poor: three times the iterations on the tests' strands. */
        for (int i = 0; i < dim; i++) f->diag[i] = top;
        if (mu < 0.0) mu = 1e-3;
        int accepted = 0;
        double gain = 0.0, biggest = 0.0;
        while (!accepted && mu < 1e20) {
            if (!hk_cholesky_factor(dim, f->ata, mu, f->diag, f->factor)) {
                mu *= nu;
                nu *= 2.0;
                continue;
            }
            for (int i = 0; i < dim; i++) f->step[i] = -f->g[i];
            hk_cholesky_solve(dim, f->factor, f->step);
            double predicted = 0.0;
            biggest = 0.0;
            for (int i = 0; i < dim; i++) {
                f->trial[i] = q[i] + f->step[i];
                predicted += 0.5 * f->step[i] * (mu * f->diag[i] * f->step[i] - f->g[i]);
                biggest = fmax(biggest, fabs(f->step[i]) / (1.0 + fabs(q[i])));
            }
            const double trial_cost = cost_at(f, f->trial, NULL, NULL);
            if (isfinite(trial_cost) && trial_cost < cost) {
                accepted = 1;
                gain = cost - trial_cost;
                const double rho = predicted > 0.0 ? gain / predicted : 0.0;
                const double t = 2.0 * rho - 1.0;
                mu *= fmax(1.0 / 3.0, 1.0 - t * t * t);
                nu = 2.0;
                memcpy(q, f->trial, (size_t)dim * sizeof(double));
            } else {
                mu *= nu;
                nu *= 2.0;
            }
        }
        if (!accepted || gain <= 1e-12 * cost || biggest <= 1e-12) break;
    }
    return it;
}

/* The polyline point at arc length s (linear between its points). */
static hk_Vec3 polyline_at(const Fit *f, double s)
{
    int lo = 0, hi = f->m; /* poly has m + 1 points */
    if (s <= 0.0) return f->poly[0];
    if (s >= f->poly_s[hi]) return f->poly[hi];
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (f->poly_s[mid] <= s)
            lo = mid;
        else
            hi = mid;
    }
    const double t = (s - f->poly_s[lo]) / (f->poly_s[hi] - f->poly_s[lo]);
    return hk_v3_add(f->poly[lo], hk_v3_scale(hk_v3_sub(f->poly[hi], f->poly[lo]), t));
}

/* Each point's element and offset for the current element lengths. */
static void place_points(Fit *f)
{
    const hk_SuperHelix *sh = f->sh;
    int e = 0;
    for (int j = 0; j < f->m; j++) {
        while (e < sh->n - 1 && f->s[j] >= sh->s_start[e + 1]) e++;
        f->elem[j] = e;
        f->u[j] = fmin(f->s[j] - sh->s_start[e], sh->length[e]);
    }
}

/* The start: each element's curvatures fitted alone to the polyline at the middle and
 * the end of its length and at its own points, from the end pose of the one before. */
static void initial_guess(Fit *f)
{
    hk_SuperHelix *sh = f->sh;
    hk_Mat3 r = sh->root_frame;
    hk_Vec3 p = sh->root;
    hk_Vec3 k = hk_v3_zero();
    int first = 0;
    for (int e = 0; e < sh->n; e++) {
        const double s0 = sh->s_start[e], l = sh->length[e];
        /* the points over this element and the next: a helix fitted over twice its
         * length leaves the element with a steadier tangent */
        const double reach = e + 1 < sh->n ? 2.0 * l : l;
        int last = first, own = first;
        while (last < f->m && f->s[last] <= s0 + reach) last++;
        while (own < f->m && f->s[own] <= s0 + l) own++;
        for (int iter = 0; iter < 8; iter++) {
            double ata[9] = {0}, g[3] = {0};
            for (int t = -2; t < last - first; t++) {
                const double u = t == -2 ? 0.5 * l : t == -1 ? reach : f->s[first + t] - s0;
                const hk_Vec3 want = t < 0 ? polyline_at(f, s0 + u) : f->target[first + t];
                hk_Mat3 dd;
                const hk_Vec3 d = hk_element_offset(k, fmin(fmax(u, 0.0), reach), &dd, NULL);
                const hk_Vec3 e3 = hk_v3_sub(hk_v3_add(p, hk_m3_mul_v3(&r, d)), want);
                const hk_Mat3 jac = hk_m3_mul(&r, &dd);
                const double ev[3] = {e3.x, e3.y, e3.z};
                for (int a = 0; a < 3; a++) {
                    for (int i = 0; i < 3; i++) g[a] += jac.m[i][a] * ev[i];
                    for (int b = 0; b < 3; b++)
                        for (int i = 0; i < 3; i++) ata[3 * a + b] += jac.m[i][a] * jac.m[i][b];
                }
            }
            const double damp = 1e-6 * (ata[0] + ata[4] + ata[8]) + 1e-300;
            double fac[9];
            if (!hk_cholesky_factor(3, ata, damp, NULL, fac)) break;
            double step[3] = {-g[0], -g[1], -g[2]};
            hk_cholesky_solve(3, fac, step);
            if (!(isfinite(step[0]) && isfinite(step[1]) && isfinite(step[2]))) break;
            k = hk_v3_add(k, hk_v3(step[0], step[1], step[2]));
        }
        sh->q[3 * e] = k.x;
        sh->q[3 * e + 1] = k.y;
        sh->q[3 * e + 2] = k.z;
        hk_ElementLocal el;
        hk_element_local(k, l, 0, 0, &el);
        p = hk_v3_add(p, hk_m3_mul_v3(&r, hk_m3_col(&el.lam, 0)));
        r = hk_m3_mul(&r, &el.rot);
        first = own;
    }
}

/* The polyline without repeated points, its arc lengths and the root tangent. */
static hk_Status read_polyline(Fit *f, const hk_Vec3 *points, int count, hk_Vec3 *tangent, hk_Error *err)
{
    int kept = 0;
    for (int i = 0; i < count; i++) {
        const hk_Vec3 x = points[i];
        if (!(isfinite(x.x) && isfinite(x.y) && isfinite(x.z)))
            return hk_error_set(err, HK_ERR_INVALID, "superhelix fit: point %d is not finite", i + 1);
        if (kept > 0 && hk_v3_norm(hk_v3_sub(x, f->poly[kept - 1])) < FIT_MIN_SEGMENT) continue;
        f->poly_s[kept] = kept ? f->poly_s[kept - 1] + hk_v3_norm(hk_v3_sub(x, f->poly[kept - 1])) : 0.0;
        f->poly[kept++] = x;
    }
    if (kept < 2) return hk_error_set(err, HK_ERR_INVALID, "superhelix fit: the %d points have no length", count);
    f->m = kept - 1;
    for (int j = 0; j < f->m; j++) {
        f->target[j] = f->poly[j + 1];
        f->s[j] = f->poly_s[j + 1];
    }
    /* Derivative at s = 0 of the parabola through the first three points (second order in
     * the segment length, where the first chord is first order). */
    hk_Vec3 t = hk_v3_sub(f->poly[1], f->poly[0]);
    if (kept >= 3) {
        const double s1 = f->poly_s[1], s2 = f->poly_s[2];
        t = hk_v3_add(
            hk_v3_add(hk_v3_scale(f->poly[0], -(s1 + s2) / (s1 * s2)), hk_v3_scale(f->poly[1], s2 / (s1 * (s2 - s1)))),
            hk_v3_scale(f->poly[2], -s1 / (s2 * (s2 - s1))));
        if (!(hk_v3_norm(t) > 0.0) || hk_v3_dot(t, hk_v3_sub(f->poly[1], f->poly[0])) <= 0.0)
            t = hk_v3_sub(f->poly[1], f->poly[0]);
    }
    *tangent = hk_v3_normalize(t);
    return HK_OK;
}

static void free_work(Fit *f)
{
    hk_free(f->target);
    hk_free(f->frame);
    hk_free(f->ata);
    memset(f, 0, sizeof *f);
}

/* Work memory for up to n elements (reused as N doubles). */
static hk_Status alloc_work(Fit *f, int points, int n, hk_Error *err)
{
    const size_t m = (size_t)points, dim = 3 * (size_t)n;
    /* one block of vectors, one of matrices, one of doubles */
    hk_Vec3 *vecs = hk_alloc_array(2 * m + 1, sizeof(hk_Vec3), err);
    hk_Mat3 *mats = hk_alloc_array(5 * (size_t)n + 2, sizeof(hk_Mat3), err);
    double *doubles = hk_alloc_array(2 * dim * dim + 5 * dim + 4 * m + 1, sizeof(double), err);
    if (!vecs || !mats || !doubles) {
        hk_free(vecs);
        hk_free(mats);
        hk_free(doubles);
        return err ? err->code : HK_ERR_NOMEM;
    }
    f->target = vecs;
    f->poly = vecs + m;
    f->ata = doubles;
    f->frame = mats;
    f->bq = mats + n + 1;
    f->cq = mats + 2 * n + 1;
    f->jb = mats + 3 * n + 1;
    f->node = (hk_Vec3 *)(mats + 4 * n + 2); /* n + 1 vectors fit in n matrices + 1 */
    f->factor = f->ata + dim * dim;
    f->g = f->factor + dim * dim;
    f->diag = f->g + dim;
    f->step = f->diag + dim;
    f->trial = f->step + dim;
    f->best = f->trial + dim;
    f->s = f->best + dim;
    f->poly_s = f->s + m;
    f->u = f->poly_s + m + 1;
    f->elem = (int *)(f->u + m); /* m ints in the m doubles left */
    return HK_OK;
}

/* The fit's Super-Helix replaced by one of n2 equal elements along the same length, each
 * with the curvatures of the old element holding its middle (the same curve when n2 is a
 * multiple of N). */
static hk_Status split(Fit *f, int n2, hk_Error *err)
{
    const hk_SuperHelix *old = f->sh;
    if (n2 < 1 || n2 > FIT_MAX_ELEMENTS)
        return hk_error_set(err, HK_ERR_INVALID, "superhelix fit: %d elements, expected 1..%d", n2, FIT_MAX_ELEMENTS);
    double lengths[FIT_MAX_ELEMENTS];
    for (int e = 0; e < n2; e++) lengths[e] = old->total_length / n2;
    hk_SuperHelix *finer = NULL;
    const hk_Status st = hk_superhelix_create(n2, lengths, &finer, err);
    if (st != HK_OK) return st;
    finer->material = old->material;
    finer->root = old->root;
    finer->root_frame = old->root_frame;
    for (int e = 0; e < n2; e++) {
        int from = (int)((e + 0.5) * old->n / n2);
        if (from >= old->n) from = old->n - 1;
        for (int i = 0; i < 3; i++) finer->q[3 * e + i] = old->q[3 * from + i];
    }
    hk_superhelix_destroy(f->sh);
    f->sh = finer;
    place_points(f);
    return HK_OK;
}

/* The element count a fit starts with: given, or from the element length; never more
 * than one element per segment when chosen. */
static int first_count(const hk_SuperHelixFitDef *d, double length, int segments)
{
    if (d->elements > 0) return d->elements;
    int n = (int)ceil(length / d->element_length - 1e-9);
    if (n > d->max_elements) n = d->max_elements;
    if (n > segments) n = segments;
    return n < 1 ? 1 : n;
}

hk_Status hk_superhelix_fit(const hk_Vec3 *points, int count, const hk_RodMaterial *material,
                            const hk_SuperHelixFitDef *def, hk_SuperHelix **out, hk_SuperHelixFitReport *report,
                            hk_Error *err)
{
    *out = NULL;
    const hk_SuperHelixFitDef d = def ? *def : hk_default_superhelix_fit_def();
    if (!points || count < 2 || count > HK_MAX_SAMPLES_PER_STRAND)
        return hk_error_set(err, HK_ERR_INVALID, "superhelix fit: %d points, expected 2 to %d", count,
                            HK_MAX_SAMPLES_PER_STRAND);
    if (d.elements < 0 || d.elements > FIT_MAX_ELEMENTS || d.max_elements < 1 || d.max_elements > FIT_MAX_ELEMENTS ||
        !(d.element_length > 0.0) || !(d.tolerance >= 0.0) || d.max_iterations < 1)
        return hk_error_set(err, HK_ERR_INVALID,
                            "superhelix fit: elements 0..%d, max_elements 1..%d, element_length > 0, "
                            "tolerance >= 0 and max_iterations >= 1 expected",
                            FIT_MAX_ELEMENTS, FIT_MAX_ELEMENTS);
    const int cap = d.elements > 0 ? d.elements : d.max_elements;
    Fit f = {0};
    hk_Status st = alloc_work(&f, count, cap, err);
    hk_Vec3 tangent = hk_v3_zero();
    if (st == HK_OK) st = read_polyline(&f, points, count, &tangent, err);
    if (st != HK_OK) {
        free_work(&f);
        return st;
    }
    const double length = f.poly_s[f.m];
    const int target = first_count(&d, length, f.m);
    /* one element carrying the pose and the material, then split() to N */
    st = hk_superhelix_create(1, &length, &f.sh, err);
    if (st == HK_OK) {
        if (material) f.sh->material = *material;
        f.sh->root = f.poly[0];
        f.sh->root_frame = hk_root_frame(tangent);
        st = split(&f, target, err);
    }
    if (st != HK_OK) {
        hk_superhelix_destroy(f.sh);
        free_work(&f);
        return st;
    }
    /* Two starts, the better kept (each alone leaves about 1 % of real or curly strands
     * in a local minimum several times worse than the polyline allows):
     * A: element after element at N (initial_guess), then the whole fit; */
    initial_guess(&f);
    int iterations = least_squares(&f, d.max_iterations);
    double mean = 0.0, max = 0.0;
    const double cost_a = cost_at(&f, f.sh->q, &mean, &max);
    /* B: coarse to fine, N doubling from 1 to the target, each fit starting from the one
     * before split finer (the same curve), a few iterations on each coarse level. */
    if (target > 1 && mean > d.tolerance) {
        memcpy(f.best, f.sh->q, (size_t)(3 * target) * sizeof(double));
        int level = 1;
        st = split(&f, 1, err);
        if (st == HK_OK) {
            initial_guess(&f);
            iterations += least_squares(&f, COARSE_ITERATIONS);
        }
        while (st == HK_OK && level < target) {
            level = 2 * level < target ? 2 * level : target;
            st = split(&f, level, err);
            if (st == HK_OK) iterations += least_squares(&f, level < target ? COARSE_ITERATIONS : d.max_iterations);
        }
        if (st == HK_OK && !(cost_at(&f, f.sh->q, &mean, &max) < cost_a)) {
            memcpy(f.sh->q, f.best, (size_t)(3 * target) * sizeof(double));
            cost_at(&f, f.sh->q, &mean, &max);
        }
    }
    int n = target;
    /* Chosen N: split every element in two while the error is too big. */
    while (st == HK_OK && d.elements == 0 && mean > d.tolerance && n < d.max_elements && n < f.m) {
        n = 2 * n;
        if (n > d.max_elements) n = d.max_elements;
        if (n > f.m) n = f.m;
        st = split(&f, n, err);
        if (st != HK_OK) break;
        iterations += least_squares(&f, d.max_iterations);
        cost_at(&f, f.sh->q, &mean, &max);
    }
    if (st == HK_OK && !(isfinite(mean) && isfinite(max)))
        st = hk_error_set(err, HK_ERR_NUMERIC, "superhelix fit: the fit did not converge (not finite)");
    if (st != HK_OK) {
        hk_superhelix_destroy(f.sh);
        free_work(&f);
        return st;
    }
    memcpy(f.sh->q_rest, f.sh->q, (size_t)(3 * n) * sizeof(double));
    if (report) {
        report->mean_error = mean;
        report->max_error = max;
        report->length = length;
        report->elements = n;
        report->iterations = iterations;
    }
    *out = f.sh;
    free_work(&f);
    return HK_OK;
}
