/* The positive part of a symmetric matrix (issue 12: the geometric stiffness G+ of every
 * guide, every step, src/dynamics/strand_dynamics.c).
 * A+ = V max(L, 0) V^T without the whole eigen-decomposition: the Householder reduction
 * A = Q T Q^T with the reflectors kept (LAPACK dsytd2, Golub & Van Loan 8.3.1), T's
 * eigenvalues by the square-root-free QL iteration of Pal, Walker and Kahan (EISPACK
 * tqlrat: its chain of dependent operations is about half of tql2's, which waits on a
 * square root and a division per rotation), T's eigenvectors for the fewer side only,
 * by inverse iteration all at once (LAPACK dstein, the eigenvectors side by side so
 * that their independent chains overlap), Q applied to them, and A+ = A - sum over the
 * negative modes of w v v^T (or the sum over the positive ones, when fewer). */

#include "core/linalg.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* sqrt(a^2 + b^2) as linalg.c's QL takes it, without libm's hypot (several times slower,
 * and not needed: the matrices here hold physical values far from overflow). */
static double hypot2(double a, double b) { return sqrt(a * a + b * b); }


/* Two doubles in one SSE2 register (GCC's vector extension, as in
 * src/helicoid/piece_rk4_tangent.c): the kernels below pair a row's elements by hand,
 * which -O2 does not do by itself for loops of unknown length and alignment (and
 * hk_dot's out-of-line call per row cost as much as the row's arithmetic). Loads and
 * stores through memcpy: unaligned, as the rows of a triangle start anywhere. */
typedef double Pair __attribute__((vector_size(16)));
typedef long long Bits __attribute__((vector_size(16))); /* a Pair's bits, for masks */

static inline Pair load_pair(const double *p)
{
    Pair r;
    memcpy(&r, p, sizeof r);
    return r;
}

static inline void store_pair(double *p, Pair v) { memcpy(p, &v, sizeof v); }

static inline Pair splat(double a) { return (Pair){a, a}; }

/* sum a[i] b[i], i < n, two pairs of partial sums (their chains overlap), in a fixed
 * order: the same bytes on every machine and thread count, as hk_dot's. */
static inline double dot_pairs(const double *a, const double *b, int n)
{
    Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
    int i = 0;
    for (; i + 4 <= n; i += 4) {
        s0 += load_pair(a + i) * load_pair(b + i);
        s1 += load_pair(a + i + 2) * load_pair(b + i + 2);
    }
    if (i + 2 <= n) {
        s0 += load_pair(a + i) * load_pair(b + i);
        i += 2;
    }
    s0 += s1;
    double r = s0[0] + s0[1];
    if (i < n) r += a[i] * b[i];
    return r;
}

/* y -= f x for n elements. */
static inline void sub_multiple(double *y, double f, const double *x, int n)
{
    const Pair fp = splat(f);
    int i = 0;
    for (; i + 2 <= n; i += 2) store_pair(y + i, load_pair(y + i) - fp * load_pair(x + i));
    if (i < n) y[i] -= f * x[i];
}

/* y = S v for the symmetric m x m block S of which the upper triangle is kept (row
 * stride sn), two rows at a time: each row's part right of the diagonal block gives its
 * product with v (y's row element) and its multiple of v's row element (y's column
 * elements, by symmetry) in one pass (LAPACK dsymv's upper-triangle loop), the two rows
 * sharing the loads of v and y. Rows pair up from the first, so that the columns right
 * of a pair start at the same parity in every pair: y's pairs are always loaded where
 * they were stored whole (a load across two stores would wait for both). */
static void upper_symv(int m, const double *s, size_t sn, const double *v, double *y)
{
    for (int j = 0; j < m; j++) y[j] = 0.0;
    int i = 0;
    for (; i + 1 < m; i += 2) {
        const double *s0 = s + (size_t)i * sn, *s1 = s0 + sn;
        const double v0 = v[i], v1 = v[i + 1];
        const Pair a0 = splat(v0), a1 = splat(v1);
        Pair dot0 = {0.0, 0.0}, dot1 = {0.0, 0.0};
        int j = i + 2;
        for (; j + 1 < m; j += 2) {
            const Pair x0 = load_pair(s0 + j), x1 = load_pair(s1 + j), vj = load_pair(v + j);
            dot0 += x0 * vj;
            dot1 += x1 * vj;
            store_pair(y + j, load_pair(y + j) + (a0 * x0 + a1 * x1));
        }
        double r0 = dot0[0] + dot0[1], r1 = dot1[0] + dot1[1];
        if (j < m) { /* m odd: the last column */
            r0 += s0[j] * v[j];
            r1 += s1[j] * v[j];
            y[j] += v0 * s0[j] + v1 * s1[j];
        }
        y[i] += (s0[i] * v0 + s0[i + 1] * v1) + r0;
        y[i + 1] += (s0[i + 1] * v0 + s1[i + 1] * v1) + r1;
    }
    if (i < m) y[i] += s[(size_t)i * sn + (size_t)i] * v[i];
}

/* S -= v w^T + w v^T on the upper triangle of the m x m block S (row stride sn), two
 * rows at a time as upper_symv pairs them (LAPACK dsyr2). */
static void upper_syr2(int m, double *s, size_t sn, const double *v, const double *w)
{
    int i = 0;
    for (; i + 1 < m; i += 2) {
        double *s0 = s + (size_t)i * sn, *s1 = s0 + sn;
        const double v0 = v[i], v1 = v[i + 1], w0 = w[i], w1 = w[i + 1];
        const Pair av0 = splat(v0), av1 = splat(v1), aw0 = splat(w0), aw1 = splat(w1);
        s0[i] -= v0 * w0 + w0 * v0;
        s0[i + 1] -= v0 * w[i + 1] + w0 * v[i + 1];
        s1[i + 1] -= v1 * w1 + w1 * v1;
        int j = i + 2;
        for (; j + 1 < m; j += 2) {
            const Pair vj = load_pair(v + j), wj = load_pair(w + j);
            store_pair(s0 + j, load_pair(s0 + j) - (av0 * wj + aw0 * vj));
            store_pair(s1 + j, load_pair(s1 + j) - (av1 * wj + aw1 * vj));
        }
        if (j < m) {
            s0[j] -= v0 * w[j] + w0 * v[j];
            s1[j] -= v1 * w[j] + w1 * v[j];
        }
    }
    if (i < m) s[(size_t)i * sn + (size_t)i] -= v[i] * w[i] + w[i] * v[i];
}

/* Householder reduction of the symmetric a (full storage, row-major, overwritten) to
 * tridiagonal form: diagonal d, off-diagonal e (e[k] couples k and k + 1). Row k keeps
 * the k-th reflector's vector right of its diagonal (its first element 1), tau[k] its
 * factor: H_k = I - tau v v^T acts on k + 1 .. n - 1 and Q = H_0 H_1 ... H_{n-3}. Only
 * the upper triangle is read and updated, along rows; p holds n doubles. */
static void tridiagonalise(int n, double *a, double *d, double *e, double *tau, double *p)
{
    const size_t sn = (size_t)n;
    for (int k = 0; k + 2 < n; k++) {
        double *row = a + (size_t)k * sn, *x = row + k + 1;
        const int m = n - k - 1;
        const double alpha = x[0], xx = hk_dot(x + 1, x + 1, m - 1);
        d[k] = row[k];
        if (xx == 0.0) { /* already reduced: H = I */
            e[k] = alpha;
            tau[k] = 0.0;
            x[0] = 1.0;
            continue;
        }
        const double beta = alpha >= 0.0 ? -sqrt(alpha * alpha + xx) : sqrt(alpha * alpha + xx);
        const double t = (beta - alpha) / beta, scale = 1.0 / (alpha - beta);
        e[k] = beta;
        tau[k] = t;
        x[0] = 1.0;
        for (int i = 1; i < m; i++) x[i] *= scale;
        /* p = tau S v, then w = p - (tau/2)(p . v) v and S -= v w^T + w v^T (S the
         * trailing block; dsytd2's steps) */
        double *s = a + (size_t)(k + 1) * sn + (size_t)(k + 1);
        upper_symv(m, s, sn, x, p);
#pragma omp simd
        for (int j = 0; j < m; j++) p[j] *= t;
        const double half = -0.5 * t * hk_dot(p, x, m);
#pragma omp simd
        for (int j = 0; j < m; j++) p[j] += half * x[j];
        upper_syr2(m, s, sn, x, p);
    }
    if (n >= 2) {
        d[n - 2] = a[(sn - 2) * sn + sn - 2];
        e[n - 2] = a[(sn - 2) * sn + sn - 1];
        tau[n - 2] = 0.0;
    }
    if (n >= 1) d[n - 1] = a[sn * sn - 1];
    if (n >= 1) e[n - 1] = 0.0;
}

/* The eigenvalues of the symmetric tridiagonal matrix with diagonal d and squared
 * off-diagonal e2 (e2[i] couples i and i + 1; both overwritten, d with the eigenvalues,
 * unordered) by the rational QL iteration of Pal, Walker and Kahan (EISPACK tqlrat;
 * Parlett, The Symmetric Eigenvalue Problem, 8.15): no square root in the inner loop,
 * whose chain waits on one division where tql2's waits on a square root and a division.
 * Off-diagonals below (eps tnorm)^2 count as zero: an absolute tolerance, all that A+
 * needs (its error is of that order anyway). Returns 0 if an eigenvalue took more than
 * 60 iterations. */
static int tridiagonal_eigenvalues(int n, double *d, double *e2, double tnorm)
{
    const double b = DBL_EPSILON * tnorm, c = b * b;
    double f = 0.0;
    if (n > 0) e2[n - 1] = 0.0;
    for (int l = 0; l < n; l++) {
        int iter = 0;
        for (;;) {
            int m = l;
            while (e2[m] > c) m++; /* e2[n - 1] is zero: the search stops there */
            if (m == l) break;
            if (iter++ == 60) return 0;
            /* Wilkinson-like shift from the leading 2 x 2 block, as tql2's */
            const double s0 = sqrt(e2[l]), g0 = d[l], p0 = (d[l + 1] - g0) / (2.0 * s0);
            const double r0 = hypot2(p0, 1.0);
            d[l] = s0 / (p0 + (p0 >= 0.0 ? r0 : -r0));
            const double shift = g0 - d[l];
            for (int i = l + 1; i < n; i++) d[i] -= shift;
            f += shift;
            double g = d[m] != 0.0 ? d[m] : b, h = g, s = 0.0;
            for (int i = m - 1; i >= l; i--) {
                /* 1 / r once for s and h: two divisions a step instead of three */
                const double p = g * h, r = p + e2[i], rinv = 1.0 / r;
                e2[i + 1] = s * r;
                s = e2[i] * rinv;
                d[i + 1] = h + s * (h + d[i]);
                g = d[i] - e2[i] / g;
                if (g == 0.0) g = b;
                h = g * p * rinv;
            }
            e2[l] = s * g * h;
            d[l] = h;
            if (h == 0.0) break;
        }
        d[l] += f;
    }
    return 1;
}

/* Lanes of the inverse iteration: k eigenvectors of the tridiagonal matrix (d, e) side
 * by side, row i of an n x k block holding their i-th elements. */
typedef struct {
    int n, k;
    double *shift;             /* k: the eigenvalues, kept apart within a cluster */
    double *mult, *swap, *inv; /* n x k: the factors of T - shift I, by rows (swap: a
                                * row interchange, as all bits set, else 0) */
    double *up1, *up2;         /* n x k: U's first and second superdiagonals */
    double *carry0, *carry1;   /* k: the row being eliminated */
    int *cluster;              /* k: the first lane of the lane's cluster */
} Lanes;

/* T - shift I = P L U for every lane at once, Gaussian elimination with partial pivoting
 * (LAPACK dlagtf); a pivot smaller than tol is taken as +-tol (dlagts), as T - lambda I
 * is singular to working precision by design. The lanes' chains are independent: the
 * loop over them fills the latency of each one's division. */
static void lanes_factor(const Lanes *ln, const double *d, const double *e, double tol)
{
    const int n = ln->n, k = ln->k;
    double *c0 = ln->carry0, *c1 = ln->carry1, all_bits;
    memset(&all_bits, 0xff, sizeof all_bits);
    for (int j = 0; j < k; j++) {
        c0[j] = d[0] - ln->shift[j];
        c1[j] = n > 1 ? e[0] : 0.0;
    }
    for (int i = 0; i < n; i++) {
        const double b = i + 1 < n ? e[i] : 0.0, b1 = i + 2 < n ? e[i + 1] : 0.0;
        const double di = i + 1 < n ? d[i + 1] : 0.0;
        const size_t o = (size_t)i * (size_t)k;
        for (int j = 0; j < k; j++) {
            const double a1 = di - ln->shift[j];
            const int sw = fabs(b) > fabs(c0[j]);
            double p = sw ? b : c0[j];
            if (fabs(p) < tol) p = p >= 0.0 ? tol : -tol;
            const double inv = 1.0 / p, m = (sw ? c0[j] : b) * inv;
            const double u1 = sw ? a1 : c1[j], u2 = sw ? b1 : 0.0;
            const double n0 = (sw ? c1[j] : a1) - m * u1, n1 = (sw ? 0.0 : b1) - m * u2;
            ln->mult[o + (size_t)j] = m;
            ln->swap[o + (size_t)j] = sw ? all_bits : 0.0;
            ln->inv[o + (size_t)j] = inv;
            ln->up1[o + (size_t)j] = i + 1 < n ? u1 : 0.0;
            ln->up2[o + (size_t)j] = i + 2 < n ? u2 : 0.0;
            c0[j] = n0;
            c1[j] = n1;
        }
    }
}

/* The lanes' elimination step on rows xi and xn (k long): the interchange where swap's
 * bits are set, then xn -= mult xi. */
static void eliminate_row(int k, const double *mult, const double *swap, double *xi, double *xn)
{
    int j = 0;
    for (; j + 2 <= k; j += 2) {
        Bits sw, a, b;
        const Pair ms = load_pair(swap + j), x0 = load_pair(xi + j), x1 = load_pair(xn + j);
        memcpy(&sw, &ms, sizeof sw);
        memcpy(&a, &x0, sizeof a);
        memcpy(&b, &x1, sizeof b);
        const Bits topb = (b & sw) | (a & ~sw), bottomb = (a & sw) | (b & ~sw);
        Pair top, bottom;
        memcpy(&top, &topb, sizeof top);
        memcpy(&bottom, &bottomb, sizeof bottom);
        store_pair(xi + j, top);
        store_pair(xn + j, bottom - load_pair(mult + j) * top);
    }
    if (j < k) {
        const double top = swap[j] != 0.0 ? xn[j] : xi[j], bottom = swap[j] != 0.0 ? xi[j] : xn[j];
        xi[j] = top;
        xn[j] = bottom - mult[j] * top;
    }
}

/* x = (T - shift I)^-1 x for every lane (x: n + 2 rows of k, the last two zero), the
 * lanes two to a pair. */
static void lanes_solve(const Lanes *ln, double *x)
{
    const int n = ln->n, k = ln->k;
    const size_t sk = (size_t)k;
    for (int i = 0; i + 1 < n; i++) {
        double *xi = x + (size_t)i * sk;
        eliminate_row(k, ln->mult + (size_t)i * sk, ln->swap + (size_t)i * sk, xi, xi + sk);
    }
    for (int i = n - 1; i >= 0; i--) {
        double *xi = x + (size_t)i * sk;
        const double *x1 = xi + sk, *x2 = x1 + sk;
        const double *u1 = ln->up1 + (size_t)i * sk, *u2 = ln->up2 + (size_t)i * sk, *inv = ln->inv + (size_t)i * sk;
        int j = 0;
        for (; j + 2 <= k; j += 2)
            store_pair(xi + j, (load_pair(xi + j) - load_pair(u1 + j) * load_pair(x1 + j) -
                                load_pair(u2 + j) * load_pair(x2 + j)) *
                                   load_pair(inv + j));
        if (j < k) xi[j] = (xi[j] - u1[j] * x1[j] - u2[j] * x2[j]) * inv[j];
    }
}

/* Lane j of x scaled to unit length after made orthogonal to the earlier lanes of its
 * cluster (modified Gram-Schmidt, dstein's way to keep close eigenvalues' vectors
 * apart). The lanes are copied out to rows of t (k x n) for it, so that the products
 * run along memory, and back to x when another solve follows (back). */
static void lanes_orthonormalise(const Lanes *ln, double *x, double *t, int back)
{
    const int n = ln->n, k = ln->k;
    const size_t sk = (size_t)k, sn = (size_t)n;
    for (size_t i = 0; i < sn; i++)
        for (size_t j = 0; j < sk; j++) t[j * sn + i] = x[i * sk + j];
    for (int j = 0; j < k; j++) {
        double *tj = t + (size_t)j * sn;
        for (int q = ln->cluster[j]; q < j; q++) {
            const double *tq = t + (size_t)q * sn;
            sub_multiple(tj, dot_pairs(tq, tj, n), tq, n);
        }
        const double scale = 1.0 / sqrt(dot_pairs(tj, tj, n));
#pragma omp simd
        for (int i = 0; i < n; i++) tj[i] *= scale;
    }
    if (back)
        for (size_t i = 0; i < sn; i++)
            for (size_t j = 0; j < sk; j++) x[i * sk + j] = t[j * sn + i];
}

/* The eigenvectors of T (d, e) for the k eigenvalues lambda (ascending) into the rows of
 * t (k x n; x: n + 2 rows of k, the lanes' work) by inverse iteration: three solves from a fixed pseudo-random start, which
 * leave of the other eigenvalues' components (eps tnorm / gap)^3, gaps within a cluster
 * (closer than 1e-3 tnorm, dstein's bound) handled by the Gram-Schmidt step. */
static void lanes_eigenvectors(Lanes *ln, const double *d, const double *e, const double *lambda, double tnorm,
                               double *x, double *t)
{
    const int n = ln->n, k = ln->k;
    const double apart = 10.0 * DBL_EPSILON * tnorm, close = 1e-3 * tnorm;
    for (int j = 0; j < k; j++) {
        double s = lambda[j];
        if (j > 0 && s - ln->shift[j - 1] < apart) s = ln->shift[j - 1] + apart;
        ln->shift[j] = s;
        ln->cluster[j] = j > 0 && lambda[j] - lambda[j - 1] <= close ? ln->cluster[j - 1] : j;
    }
    lanes_factor(ln, d, e, DBL_EPSILON * tnorm);
    unsigned state = 12345u;
    for (size_t i = 0; i < (size_t)n * (size_t)k; i++) {
        state = state * 1664525u + 1013904223u;
        x[i] = (double)(state >> 8) / 16777216.0 - 0.5;
    }
    for (size_t i = (size_t)n * (size_t)k; i < (size_t)(n + 2) * (size_t)k; i++) x[i] = 0.0;
    for (int pass = 0; pass < 3; pass++) {
        lanes_solve(ln, x);
        lanes_orthonormalise(ln, x, t, pass < 2);
    }
}

/* y -= tau (v . y) v for one or two rows y (y1 NULL: one), v and the rows m long: the
 * product along v and the multiple of it (LAPACK's dlarf), the two rows sharing the
 * loads of v. first: the rows' index of y[0]; the pairs start at an even index, so that
 * each is loaded where the last reflector stored it whole (a load across two stores
 * waits for both: the loop took twice as long so). */
static inline __attribute__((always_inline)) void reflect_rows(const double *v, int m, double tau, int first,
                                                               double *y0, double *y1)
{
    const int i0 = first & 1; /* an odd first element alone */
    Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
    for (int i = i0; i + 2 <= m; i += 2) {
        const Pair vi = load_pair(v + i);
        s0 += vi * load_pair(y0 + i);
        if (y1) s1 += vi * load_pair(y1 + i);
    }
    double f0 = s0[0] + s0[1], f1 = s1[0] + s1[1];
    const int last = i0 + ((m - i0) & ~1); /* the element left after the pairs, if any */
    if (i0) {
        f0 += v[0] * y0[0];
        if (y1) f1 += v[0] * y1[0];
    }
    if (last < m) {
        f0 += v[last] * y0[last];
        if (y1) f1 += v[last] * y1[last];
    }
    f0 *= tau;
    f1 *= tau;
    const Pair g0 = splat(f0), g1 = splat(f1);
    for (int i = i0; i + 2 <= m; i += 2) {
        const Pair vi = load_pair(v + i);
        store_pair(y0 + i, load_pair(y0 + i) - g0 * vi);
        if (y1) store_pair(y1 + i, load_pair(y1 + i) - g1 * vi);
    }
    if (i0) {
        y0[0] -= f0 * v[0];
        if (y1) y1[0] -= f1 * v[0];
    }
    if (last < m) {
        y0[last] -= f0 * v[last];
        if (y1) y1[last] -= f1 * v[last];
    }
}

/* x = Q x for the k rows of x (k x n), Q = H_0 ... H_{n-3} from tridiagonalise: the
 * reflectors from the last (LAPACK dormtr), two rows at a time. */
static void apply_reflectors(int n, const double *a, const double *tau, int k, double *x)
{
    const size_t sn = (size_t)n;
    for (int j = 0; j < k; j += 2) {
        double *x0 = x + (size_t)j * sn, *x1 = j + 1 < k ? x0 + sn : NULL;
        for (int r = n - 3; r >= 0; r--) {
            if (tau[r] == 0.0) continue;
            const double *v = a + (size_t)r * sn + (size_t)r + 1;
            if (x1)
                reflect_rows(v, n - r - 1, tau[r], r + 1, x0 + r + 1, x1 + r + 1);
            else
                reflect_rows(v, n - r - 1, tau[r], r + 1, x0 + r + 1, NULL);
        }
    }
}

/* The lower triangle of out (and the diagonal) = base + sum_q c[q] x_q x_q^T (base: a,
 * or zero if a is NULL; x_q the k rows of x, n long), then mirrored to the upper
 * triangle (symmetric to the bit). Two rows of out at a time, two columns to a pair,
 * each entry's sum taken in registers over q in order; b holds 4k doubles (the rows'
 * factors c[q] x_q[i], paired). */
static void add_rank_k(int n, const double *a, int k, const double *c, const double *x, double *out, double *b)
{
    const size_t sn = (size_t)n;
    for (int i = 0; i < n; i += 2) {
        const int i1 = i + 1 < n ? i + 1 : i; /* n odd: the last row twice */
        for (int q = 0; q < k; q++) {
            const double *xq = x + (size_t)q * sn;
            store_pair(b + 4 * q, splat(c[q] * xq[i]));
            store_pair(b + 4 * q + 2, splat(c[q] * xq[i1]));
        }
        double *r0 = out + (size_t)i * sn, *r1 = out + (size_t)i1 * sn;
        int j = 0;
        for (; j + 1 <= i1 && j + 1 < n; j += 2) {
            Pair s0 = a ? load_pair(a + (size_t)i * sn + (size_t)j) : (Pair){0.0, 0.0};
            Pair s1 = a ? load_pair(a + (size_t)i1 * sn + (size_t)j) : (Pair){0.0, 0.0};
            for (int q = 0; q < k; q++) {
                const Pair xj = load_pair(x + (size_t)q * sn + (size_t)j);
                s0 += load_pair(b + 4 * q) * xj;
                s1 += load_pair(b + 4 * q + 2) * xj;
            }
            store_pair(r1 + j, s1); /* row i's pair may reach past its diagonal: */
            store_pair(r0 + j, s0); /* the mirroring below writes it over */
        }
        if (j <= i1) { /* n odd: the last column */
            double s0 = a ? a[(size_t)i * sn + (size_t)j] : 0.0, s1 = a ? a[(size_t)i1 * sn + (size_t)j] : 0.0;
            for (int q = 0; q < k; q++) {
                const double xj = x[(size_t)q * sn + (size_t)j];
                s0 += b[4 * q] * xj;
                s1 += b[4 * q + 2] * xj;
            }
            r1[j] = s1;
            if (j <= i) r0[j] = s0;
        }
    }
    for (size_t i = 0; i < sn; i++)
        for (size_t j = 0; j < i; j++) out[j * sn + i] = out[i * sn + j];
}

int hk_symmetric_positive_part(int n, const double *a, double *out, double *work, int *negative)
{
    const size_t sn = (size_t)n, lanes = sn / 2 + 1;
    double *t = work, *d = t + sn * sn, *e = d + sn, *e2 = e + sn, *w = e2 + sn, *tau = w + sn;
    double *scratch = tau + sn;
    for (size_t i = 0; i < sn; i++) /* the upper triangle, all the reduction reads */
        for (size_t j = i; j < sn; j++) t[i * sn + j] = a[i * sn + j];
    tridiagonalise(n, t, d, e, tau, scratch);
    double tnorm = 0.0;
    /* QL deflates at the top and converges fastest on a matrix graded with its large
     * entries at the bottom (LAPACK dsterf chooses between QL and QR so); G is largest
     * at the root, and so is T: the eigenvalues are those of T upside down. */
    const int flip = n > 0 && fabs(d[n - 1]) < fabs(d[0]);
    for (int i = 0; i < n; i++) {
        tnorm = fmax(tnorm, fabs(d[i]) + fabs(e[i]) + (i > 0 ? fabs(e[i - 1]) : 0.0));
        w[flip ? n - 1 - i : i] = d[i];
        if (i + 1 < n) e2[flip ? n - 2 - i : i] = e[i] * e[i];
    }
    /* not a number anywhere (fmax passes over one): no convergence, as tql2 would say */
    double sum = 0.0;
    for (int i = 0; i < n; i++) sum += fabs(d[i]) + fabs(e[i]);
    if (!isfinite(sum) || !tridiagonal_eigenvalues(n, w, e2, tnorm)) return 0;
    int neg = 0, pos = 0;
    for (int i = 0; i < n; i++) {
        neg += w[i] < 0.0;
        pos += w[i] > 0.0;
    }
    *negative = neg;
    /* A+ = A - sum of the negative modes when they are fewer, else the positive sum:
     * the fewer side's eigenvalues ascending into lambda (e2's place, free now) */
    const int subtract = 2 * neg < n, k = subtract ? neg : pos;
    double *lambda = e2;
    for (int i = 0, c = 0; i < n; i++) {
        if (!(subtract ? w[i] < 0.0 : w[i] > 0.0)) continue;
        int j = c++;
        for (; j > 0 && w[i] < lambda[j - 1]; j--) lambda[j] = lambda[j - 1];
        lambda[j] = w[i];
    }
    double *x = scratch, *xt = x + (sn + 2) * lanes;
    if (k > 0) {
        Lanes ln = {.n = n, .k = k, .shift = xt + sn * lanes};
        ln.mult = ln.shift + lanes;
        ln.swap = ln.mult + sn * lanes;
        ln.inv = ln.swap + sn * lanes;
        ln.up1 = ln.inv + sn * lanes;
        ln.up2 = ln.up1 + sn * lanes;
        ln.carry0 = ln.up2 + sn * lanes;
        ln.carry1 = ln.carry0 + lanes;
        ln.cluster = (int *)(ln.carry1 + lanes);
        lanes_eigenvectors(&ln, d, e, lambda, tnorm, x, xt);
        apply_reflectors(n, t, tau, k, xt);
    }
    if (subtract)
        for (int q = 0; q < k; q++) lambda[q] = -lambda[q];
    add_rank_k(n, subtract ? a : NULL, k, lambda, xt, out, x);
    return 1;
}
