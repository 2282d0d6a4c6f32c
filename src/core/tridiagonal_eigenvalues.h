/* The eigenvalues of a symmetric tridiagonal matrix for G+ (src/core/positive_part.c,
 * issue 12): all of them by the square-root-free QL iteration (tridiagonal_eigenvalues),
 * or the fewer side's alone by Sturm counts in lanes (fewer_side_by_counts). Internal:
 * static inline, included by positive_part.c only, which is compiled twice (AVX and
 * SSE2) with the same bits either way. */
#ifndef HK_CORE_TRIDIAGONAL_EIGENVALUES_H
#define HK_CORE_TRIDIAGONAL_EIGENVALUES_H

#include <float.h>
#include <math.h>

#include "core/simd_lanes.h"

/* The state of a QL sweep (tridiagonal_eigenvalues, below) between its steps. */
typedef struct {
    double g, h, s, u, n1, n2;
    int negligible; /* the lowest off-diagonal at or below the tolerance so far */
} QlSweep;

/* One step of the sweep, at row i (tridiagonal_eigenvalues tells the recurrences). */
static inline __attribute__((always_inline)) void ql_step(QlSweep *q, double *d, double *e2, int i, double b, double c)
{
    const double p = q->g * q->h, r = p + e2[i], ginv = q->n2 / q->n1, tu = e2[i] * ginv * ginv * q->u;
    q->u = 1.0 + tu;
    const double cu = 1.0 / q->u;
    e2[i + 1] = q->s * r;
    if (!(e2[i + 1] > c)) q->negligible = i + 1;
    q->s = tu * cu;
    d[i + 1] = q->h + q->s * (q->h + d[i]);
    double n0 = d[i] * q->n1 - e2[i] * q->n2, n1 = q->n1;
    /* zero lies below the range: its test leaves the common path */
    if (fabs(n0) < 0x1p-600 || fabs(n0) > 0x1p600) {
        if (n0 == 0.0) n0 = b * n1; /* g = 0: tqlrat's g = b */
        if (fabs(n0) < 0x1p-600) {
            n0 *= 0x1p600;
            n1 *= 0x1p600;
        } else if (fabs(n0) > 0x1p600) {
            n0 *= 0x1p-600;
            n1 *= 0x1p-600;
        }
    }
    q->n2 = n1;
    q->n1 = n0;
    q->g = n0 / n1;
    q->h = q->g * cu;
}

/* The eigenvalues of the symmetric tridiagonal matrix with diagonal d and squared
 * off-diagonal e2 (e2[i] couples i and i + 1; both overwritten, d with the eigenvalues,
 * unordered) by the rational QL iteration of Pal, Walker and Kahan (EISPACK tqlrat;
 * Parlett, The Symmetric Eigenvalue Problem, 8.15), no square root in the inner loop.
 * Off-diagonals below (eps tnorm)^2 count as zero: an absolute tolerance, all that A+
 * needs (its error is of that order anyway). Returns 0 if an eigenvalue took more than
 * 60 iterations.
 *
 * The sweep's chains are recast so that no division waits on the last one (tqlrat's own
 * form waits on a division for g and on one for h at every step, and the sweeps, 760
 * steps for a guide's G of N = 10, were 40 % of G+'s time):
 * - tqlrat's g_i = d_i - e2_i / g_{i+1} (the pivots of T - shift from the bottom) is the
 *   ratio n_i / n_{i+1} of the three-term recurrence n_i = d_i n_{i+1} - e2_i n_{i+2}
 *   (Sturm's sequence, Wilkinson, The Algebraic Eigenvalue Problem, 5.37): its chain
 *   is a product and a difference; g is a division beside it. n is kept within
 *   2^-600 .. 2^600 by powers of two, which leave its ratios as they are, and T is
 *   scaled by a power of two to tnorm about 1 (the same bits as unscaled), so that
 *   d n and e2 n never leave the normal range.
 * - tqlrat's h' = g' p / r with p = g h, r = p + e2: u = r / p obeys
 *   u_i = 1 + (e2_i / g^2) u_{i-1} (h = g / u_{i-1}), a product and a sum on its
 *   chain; 1 / u gives h and s = e2 / r = (u - 1) / u (taken as the product
 *   (e2 / g^2) u_{i-1} over u, without the cancellation of u - 1).
 * Three divisions a step, none on a chain: the eigenvalues of the head's guides' G
 * (N = 10) in 0.65 of tqlrat's time, within 2e-15 tnorm of tqlrat's. */
static inline __attribute__((always_inline)) int tridiagonal_eigenvalues(int n, double *d, double *e2, double tnorm,
                                                                         int wide)
{
    if (n == 0) return 1;
    /* T scaled by 2^-ex: tnorm in [1, 2) (ex bounded so that 2^-2ex is a double) */
    const int ex = tnorm > 0.0 && isfinite(tnorm) ? (int)fmax(-500.0, fmin(500.0, (double)ilogb(tnorm))) : 0;
    const double scale = ldexp(1.0, -ex), scale2 = scale * scale;
    for (int i = 0; i < n; i++) {
        d[i] *= scale;
        e2[i] *= scale2;
    }
    const double b = DBL_EPSILON * tnorm * scale, c = b * b;
    double f = 0.0;
    e2[n - 1] = 0.0;
    int known = 0; /* past l: the first negligible off-diagonal from l, noted by l - 1's last sweep */
    for (int l = 0; l < n; l++) {
        int iter = 0, m = l;
        if (known > l)
            m = known;
        else
            while (e2[m] > c) m++; /* e2[n - 1] is zero: the search stops there */
        known = 0;
        /* after a sweep the first negligible off-diagonal from l is known without the
         * search: the sweep rewrites e2[l .. m] (e2[m] to zero) and notes the lowest
         * one at or below c as it goes (the search took 5.6 of the 36 thousand
         * instructions of the eigenvalues on a head's G, with a mispredicted exit); the
         * last sweep of an eigenvalue notes it for the next (its own search took most
         * of what was left of that) */
        while (m != l) {
            if (iter++ == 60) return 0;
            /* Wilkinson-like shift from the leading 2 x 2 block, as tql2's, in the form
             * e2 / (delta + sign(delta) sqrt(delta^2 + e2)): one square root and one
             * division in a row instead of two of each */
            const double g0 = d[l], half = 0.5 * (d[l + 1] - g0), r0 = sqrt(half * half + e2[l]);
            d[l] = e2[l] / (half + (half >= 0.0 ? r0 : -r0));
            const double shift = g0 - d[l];
            sub_constant(d + l + 1, shift, n - l - 1, wide);
            f += shift;
            const double g = d[m] != 0.0 ? d[m] : b;
            QlSweep q = {.g = g, .h = g, .s = 0.0, .u = 1.0, .n1 = g, .n2 = 1.0, .negligible = m};
            int i = m - 1;
            for (; i > l; i -= 2) { /* two steps a turn: n1 and n2 trade registers, no copies */
                ql_step(&q, d, e2, i, b, c);
                ql_step(&q, d, e2, i - 1, b, c);
            }
            if (i == l) ql_step(&q, d, e2, i, b, c);
            const double h = q.h;
            e2[l] = q.s * q.g * h;
            d[l] = h;
            known = q.negligible;
            if (h == 0.0) break;
            m = !(e2[l] > c) ? l : q.negligible;
        }
        d[l] += f;
    }
    const double unscale = ldexp(1.0, ex);
    for (int i = 0; i < n; i++) d[i] *= unscale;
    return 1;
}

/* The fewer side's eigenvalues alone, by Sturm counts in lanes (issue 12: G+ needs only
 * the 8 to 11 negative eigenvalues of a head's G, of 30, and the QL iteration above finds
 * all 30 on a chain of dependent divisions). Each lane seeks one eigenvalue, the j-th
 * from the bottom: its count of eigenvalues below a shift s says on which side s lies
 * (bisection, LAPACK dstebz), and the lanes' chains are independent, twelve side by side
 * (three Quads). The count is the number of sign changes of Sturm's sequence (Wilkinson,
 * The Algebraic Eigenvalue Problem, 5.37), n_i = (d_i - s) n_{i-1} - e_{i-1}^2 n_{i-2},
 * n_{-1} = 1, n_{-2} = 0: a product and a difference on the chain, no division (the
 * pivots' form, d_i - s - e^2 / q_{i-1}, waits on a division a step). A zero n_i takes
 * the sign of its sign bit: the change across it is counted once either way, as n_{i+1}
 * = -e_i^2 n_{i-1} has the sign opposite to n_{i-1}. Every step adds +1 where n_i and
 * n_{i-1} have the same sign bit and -1 where they differ (three bitwise operations and
 * an add), so that c = n - 2 count.
 * The head's negative eigenvalues are graded (from about 0.2 of ||G|| down to 1e-10 of
 * it): the first steps take the bracket's geometric mean while its ends are more than a
 * factor 2 apart, then Newton's method on det(T - s I) = n_{n-1} (its derivative by the
 * same recurrence differentiated), safeguarded by the bracket (Newton's step when it
 * falls inside, else the bracket's middle) and accepted once the step is below the
 * tolerance and the bracket holds this eigenvalue alone. About 10 + 7 counts a call in
 * place of the QL's 760 steps, within 1.2e-15 of ||G|| of the QL's on the head's G.
 * T is scaled by a power of two to ||T|| in [1, 2), so that n never overflows (|n_i|
 * grows at most 9 times a step); it may underflow where the e^2 are small, as (n_i,
 * n_{i-1}) shrinks by at most e_{i-1}^2 / 16 a step: the pair is rescaled by 2^400 at the
 * ends of segments chosen so that it cannot fall below 2^-950 within one. */
typedef long long QuadBits __attribute__((vector_size(32)));

/* m ? a : b for each element of Quads (m's elements all bits set or none) */
#define PICK_QUAD(m, a, b) ((Quad)(((QuadBits)(a) & (m)) | ((QuadBits)(b) & ~(m))))
#define SQRT_QUAD(q)       ((Quad){sqrt((q)[0]), sqrt((q)[1]), sqrt((q)[2]), sqrt((q)[3])})

#define STURM_LANES 12 /* three Quads */

/* The scaled T for the counts: d and e^2 splat to Quads (dq[4 i..], eq[4 i..] with
 * e_{i-1}^2, eq's first zero), and the ends of the segments between rescalings. */
typedef struct {
    int n, segments;
    const double *dq, *eq;
    const int *seg_end;
} SturmMatrix;

/* One step of the recurrence on a Quad of lanes: x = n_{i-2} becomes n_i, p = n_{i-1};
 * with newton, dx = n'_{i-2} becomes n'_i (dp = n'_{i-1}), n' = dn/ds. c: the count. */
#define STURM_STEP(x, p, dx, dp, i, s, c)                                                                              \
    do {                                                                                                               \
        const Quad a_ = load_quad(m->dq + 4 * (i)) - (s), e_ = load_quad(m->eq + 4 * (i));                             \
        if (newton) (dx) = a_ * (dp) - (p)-e_ * (dx);                                                                  \
        (x) = a_ * (p)-e_ * (x);                                                                                       \
        (c) += (Quad)((((QuadBits)(x) ^ (QuadBits)(p)) & sign) | one_bits);                                            \
    } while (0)

/* (a, b) and with newton (da, db) times 2^400 in the lanes where |a| + |b| < 2^-400 */
#define STURM_RESCALE(a, b, da, db)                                                                                    \
    do {                                                                                                               \
        const Quad size_ = (Quad)((QuadBits)(a) & ~sign) + (Quad)((QuadBits)(b) & ~sign);                              \
        const Quad f_ = PICK_QUAD(size_ < splat4(0x1p-400), splat4(0x1p400), one);                                     \
        (a) *= f_;                                                                                                     \
        (b) *= f_;                                                                                                     \
        if (newton) {                                                                                                  \
            (da) *= f_;                                                                                                \
            (db) *= f_;                                                                                                \
        }                                                                                                              \
    } while (0)

/* The counts c (n - 2 count, see above) of the 12 lanes at the shifts s; with newton
 * (a constant where inlined) also det = n_{n-1} and its derivative, both scaled alike. */
static inline __attribute__((always_inline)) void sturm_lanes(const SturmMatrix *m, const double *s, double *c,
                                                              double *det, double *slope, int newton)
{
    const Quad one = splat4(1.0), zero = splat4(0.0), s0 = load_quad(s), s1 = load_quad(s + 4), s2 = load_quad(s + 8);
    const QuadBits one_bits = (QuadBits)one, sign = (QuadBits)splat4(-0.0);
    Quad a0 = one, a1 = one, a2 = one, b0 = zero, b1 = zero, b2 = zero, c0 = zero, c1 = zero, c2 = zero;
    Quad da0 = zero, da1 = zero, da2 = zero, db0 = zero, db1 = zero, db2 = zero;
    for (int g = 0, i = 0; g < m->segments; g++) {
        const int end = m->seg_end[g];
        for (; i + 2 <= end; i += 2) { /* two steps a turn: a and b trade roles, no copies */
            STURM_STEP(b0, a0, db0, da0, i, s0, c0);
            STURM_STEP(b1, a1, db1, da1, i, s1, c1);
            STURM_STEP(b2, a2, db2, da2, i, s2, c2);
            STURM_STEP(a0, b0, da0, db0, i + 1, s0, c0);
            STURM_STEP(a1, b1, da1, db1, i + 1, s1, c1);
            STURM_STEP(a2, b2, da2, db2, i + 1, s2, c2);
        }
        if (i < end) {
            STURM_STEP(b0, a0, db0, da0, i, s0, c0);
            STURM_STEP(b1, a1, db1, da1, i, s1, c1);
            STURM_STEP(b2, a2, db2, da2, i, s2, c2);
            i++;
            Quad t = a0;
            a0 = b0, b0 = t, t = a1, a1 = b1, b1 = t, t = a2, a2 = b2, b2 = t;
            t = da0, da0 = db0, db0 = t, t = da1, da1 = db1, db1 = t, t = da2, da2 = db2, db2 = t;
        }
        if (g + 1 < m->segments) {
            STURM_RESCALE(a0, b0, da0, db0);
            STURM_RESCALE(a1, b1, da1, db1);
            STURM_RESCALE(a2, b2, da2, db2);
        }
    }
    STORE_QUAD(c, c0);
    STORE_QUAD(c + 4, c1);
    STORE_QUAD(c + 8, c2);
    if (newton) {
        STORE_QUAD(det, a0);
        STORE_QUAD(det + 4, a1);
        STORE_QUAD(det + 8, a2);
        STORE_QUAD(slope, da0);
        STORE_QUAD(slope + 4, da1);
        STORE_QUAD(slope + 8, da2);
    }
}

/* A lane's bracket: lo < its eigenvalue <= hi (by the counts), the counts' c there. */
typedef struct {
    double lo[STURM_LANES], hi[STURM_LANES], c_lo[STURM_LANES], c_hi[STURM_LANES];
    double want[STURM_LANES]; /* n - 2 j: c below it at s means more than j eigenvalues below s */
} Brackets;

#define BISECTION_STEPS 10 /* before Newton's (8 to 12 took about as long on the head's G) */
#define NEWTON_LIMIT    60 /* counts, then the QL (never reached on the head's G) */

/* The bisection's steps, all lanes at once: the geometric mean of a bracket's ends
 * while they are more than a factor 2 apart (both are negative), else their middle. */
static inline __attribute__((always_inline)) void bisect_lanes(const SturmMatrix *m, Brackets *b)
{
    double s[STURM_LANES], c[STURM_LANES];
    for (int step = 0; step < BISECTION_STEPS; step++) {
        for (int q = 0; q < STURM_LANES; q += 4) {
            const Quad lo = load_quad(b->lo + q), hi = load_quad(b->hi + q), p = lo * hi;
            STORE_QUAD(s + q, PICK_QUAD(lo < splat4(2.0) * hi, -SQRT_QUAD(p), (lo + hi) * splat4(0.5)));
        }
        sturm_lanes(m, s, c, NULL, NULL, 0);
        for (int q = 0; q < STURM_LANES; q += 4) {
            const Quad sq = load_quad(s + q), cq = load_quad(c + q);
            const QuadBits above = cq < load_quad(b->want + q); /* s above the eigenvalue */
            STORE_QUAD(b->hi + q, PICK_QUAD(above, sq, load_quad(b->hi + q)));
            STORE_QUAD(b->c_hi + q, PICK_QUAD(above, cq, load_quad(b->c_hi + q)));
            STORE_QUAD(b->lo + q, PICK_QUAD(above, load_quad(b->lo + q), sq));
            STORE_QUAD(b->c_lo + q, PICK_QUAD(above, load_quad(b->c_lo + q), cq));
        }
    }
}

/* Newton's steps from the brackets' middles until every lane's eigenvalue is found to
 * tol (the bracket narrower than tol, or Newton's step below tol from inside a bracket
 * that holds this eigenvalue alone), into x; returns 0 if some lane took NEWTON_LIMIT
 * counts. A step that falls within tol outside the bracket is taken just inside it once
 * (the eigenvalue may lie there), else the bracket's middle. */
static inline __attribute__((always_inline)) int newton_lanes(const SturmMatrix *m, Brackets *b, double tol, double *x)
{
    double s[STURM_LANES], c[STURM_LANES], det[STURM_LANES], slope[STURM_LANES];
    int nudged[STURM_LANES] = {0};
    for (int q = 0; q < STURM_LANES; q++) s[q] = 0.5 * (b->lo[q] + b->hi[q]);
    for (int count = 0; count < NEWTON_LIMIT; count++) {
        sturm_lanes(m, s, c, det, slope, 1);
        int going = 0;
        for (int q = 0; q < STURM_LANES; q++) {
            if (c[q] < b->want[q])
                b->hi[q] = s[q], b->c_hi[q] = c[q];
            else
                b->lo[q] = s[q], b->c_lo[q] = c[q];
            const double lo = b->lo[q], hi = b->hi[q], step = det[q] / slope[q], next = s[q] - step;
            const int alone = b->c_lo[q] - b->c_hi[q] == 2.0;
            if (hi - lo <= tol) {
                x[q] = s[q] = 0.5 * (lo + hi);
                continue;
            }
            if (fabs(step) <= tol && next > lo && next < hi && alone) {
                x[q] = s[q] = next;
                continue;
            }
            going = 1;
            double t = next;
            const double in = 0.25 * tol;
            if (!nudged[q] && t <= lo + in && t > lo - tol)
                t = lo + in;
            else if (!nudged[q] && t >= hi - in && t < hi + tol)
                t = hi - in;
            nudged[q] = t != next;
            if (!(t > lo && t < hi)) t = lo < 2.0 * hi ? -sqrt(lo * hi) : 0.5 * (lo + hi);
            s[q] = t;
        }
        if (!going) return 1;
    }
    return 0;
}

/* The fewer side's eigenvalues of T (d, e; tnorm its norm) ascending into lambda, as the
 * QL's path below gives them: *negative the count below zero, *subtract whether the
 * negative side is the fewer (then *k of them), else the *k positive ones. work holds
 * 9 n doubles. Returns 0 where the counts cannot be trusted (n < 4 or > 200,
 * an off-diagonal below 2^-250 of ||T||, a lane that did not converge): the QL then. */
static inline __attribute__((always_inline)) int fewer_side_by_counts(int n, const double *d, const double *e,
                                                                      double tnorm, double *lambda, int *negative,
                                                                      int *subtract, int *k, double *work)
{
    if (n < 4 || n > 200 || !(tnorm > 0.0) || !isfinite(tnorm)) return 0;
    const int ex = ilogb(tnorm);
    if (ex < -500 || ex > 500) return 0;
    const double scale = ldexp(1.0, -ex), unscale = ldexp(1.0, ex);
    double *dq = work, *eq = dq + 4 * n;
    int *seg_end = (int *)(eq + 4 * n), segments = 0;
    for (int i = 0, loss = 0; i < n; i++) {
        double e2 = 0.0;
        if (i > 0) {
            const double es = e[i - 1] * scale;
            e2 = es * es;
            /* log2 of the pair's largest shrink this step, 16 / e2 */
            unsigned long long bits; /* e2's exponent: ilogb without the call */
            memcpy(&bits, &e2, sizeof bits);
            const int step_loss = e2 > 0x1p-500 ? 4 - ((int)(bits >> 52) - 1023) : 1000;
            if (step_loss > 500) return 0;
            if (loss + step_loss > 550) {
                seg_end[segments++] = i;
                loss = 0;
            }
            loss += step_loss;
        }
        STORE_QUAD(dq + 4 * i, splat4(d[i] * scale));
        STORE_QUAD(eq + 4 * i, splat4(e2));
    }
    seg_end[segments++] = n;
    const SturmMatrix m = {n, segments, dq, eq, seg_end};
    double zero[STURM_LANES] = {0.0}, c[STURM_LANES];
    sturm_lanes(&m, zero, c, NULL, NULL, 0);
    *negative = (n - (int)c[0]) / 2;
    *subtract = 2 * *negative < n;
    if (!*subtract) { /* the positive eigenvalues: the negative ones of -T */
        for (int i = 0; i < 4 * n; i++) dq[i] = -dq[i];
        sturm_lanes(&m, zero, c, NULL, NULL, 0);
    }
    *k = (n - (int)c[0]) / 2;
    /* eigenvalues above -2^-60 ||T|| (they change A+ by less than that) are taken there */
    const double bottom = -(tnorm * scale * (1.0 + 1e-12) + 0x1p-900), top = -0x1p-60, tol = 4.0 * DBL_EPSILON;
    for (int first = 0; first < *k; first += STURM_LANES) {
        Brackets b;
        for (int q = 0; q < STURM_LANES; q++) {
            const int j = first + q < *k ? first + q : *k - 1; /* spare lanes repeat the last */
            b.lo[q] = bottom, b.hi[q] = top;
            b.c_lo[q] = n, b.c_hi[q] = -n; /* no eigenvalue below the bottom; at the top unknown */
            b.want[q] = n - 2 * j;
        }
        bisect_lanes(&m, &b);
        double x[STURM_LANES];
        if (!newton_lanes(&m, &b, tol, x)) return 0;
        for (int q = 0; q < STURM_LANES && first + q < *k; q++) {
            const int j = first + q;
            if (*subtract)
                lambda[j] = x[q] * unscale;
            else
                lambda[*k - 1 - j] = -x[q] * unscale;
        }
    }
    return 1;
}

#endif
