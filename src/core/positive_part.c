/* The positive part of a symmetric matrix (issue 12: the geometric stiffness G+ of every
 * guide, every step, src/dynamics/strand_dynamics.c).
 * A+ = V max(L, 0) V^T without the whole eigen-decomposition: the Householder reduction
 * A = Q T Q^T with the reflectors kept (LAPACK dsytd2, Golub & Van Loan 8.3.1), the
 * fewer side's eigenvalues of T alone by Sturm counts in lanes, bisection then Newton's
 * steps (fewer_side_by_counts), or where those cannot be trusted all of T's by the
 * square-root-free QL iteration of Pal, Walker and Kahan (EISPACK tqlrat, its
 * recurrences recast so that no division waits on another; tql2 waits on a square root
 * and a division per rotation), both in tridiagonal_eigenvalues.h, T's eigenvectors for
 * the fewer side only, by inverse iteration all at once (LAPACK dstein, the eigenvectors side by side so
 * that their independent chains overlap), Q applied to them, and A+ = A - sum over the
 * negative modes of w v v^T (or the sum over the positive ones, when fewer). Compiled
 * twice, for AVX and for SSE2, the same bits either way (hk_symmetric_positive_part at
 * the end). */

#include "core/linalg.h"
#include "core/simd_lanes.h"
#include "core/tridiagonal_eigenvalues.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* y -= f x (x NULL: y as it is), then sum z[i] y[i], i < n, of the new y, in one pass
 * (z may be y): two pairs of partial sums (their chains overlap) in a fixed order, the
 * same bytes on every machine and thread count. wide (a constant where inlined: the
 * other branch is compiled out): the two pairs as one Quad, the same operations. */
static inline __attribute__((always_inline)) double sub_then_dot(double *y, double f, const double *x, const double *z,
                                                                 int n, int wide)
{
    const Pair fp = splat(f);
    Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
    int i = 0;
    if (wide) {
        const Quad fq = splat4(f);
        Quad s = {0.0, 0.0, 0.0, 0.0};
        for (; i + 4 <= n; i += 4) {
            Quad y4 = load_quad(y + i);
            if (x) {
                y4 -= fq * load_quad(x + i);
                STORE_QUAD(y + i, y4);
            }
            s += load_quad(z + i) * y4;
        }
        s0 = LOW_PAIR(s);
        s1 = HIGH_PAIR(s);
    } else
        for (; i + 4 <= n; i += 4) {
            Pair y0 = load_pair(y + i), y1 = load_pair(y + i + 2);
            if (x) {
                y0 -= fp * load_pair(x + i);
                y1 -= fp * load_pair(x + i + 2);
                store_pair(y + i, y0);
                store_pair(y + i + 2, y1);
            }
            s0 += load_pair(z + i) * y0;
            s1 += load_pair(z + i + 2) * y1;
        }
    if (i + 2 <= n) {
        Pair y0 = load_pair(y + i);
        if (x) {
            y0 -= fp * load_pair(x + i);
            store_pair(y + i, y0);
        }
        s0 += load_pair(z + i) * y0;
        i += 2;
    }
    s0 += s1;
    double r = s0[0] + s0[1];
    if (i < n) {
        if (x) y[i] -= f * x[i];
        r += z[i] * y[i];
    }
    return r;
}

/* block_pass's two rows b0, b1 (i, i + 1): the splats of their elements of v, w and u,
 * and the pairs of partial sums of their products with u. */
typedef struct {
    double *b0, *b1;
    Pair v0, v1, w0, w1, u0, u1, dot0, dot1;
} RowPair;

/* block_pass on the columns j, j + 1 of the rows r. */
static inline __attribute__((always_inline)) void row_pair_step(RowPair *r, int j, const double *v, const double *w,
                                                                const double *u, double *y)
{
    Pair x0 = load_pair(r->b0 + j), x1 = load_pair(r->b1 + j);
    if (v) {
        const Pair vj = load_pair(v + j), wj = load_pair(w + j);
        x0 -= r->v0 * wj + r->w0 * vj;
        x1 -= r->v1 * wj + r->w1 * vj;
        store_pair(r->b0 + j, x0);
        store_pair(r->b1 + j, x1);
    }
    if (u) {
        const Pair uj = load_pair(u + j);
        r->dot0 += x0 * uj;
        r->dot1 += x1 * uj;
        store_pair(y + j, load_pair(y + j) + (r->u0 * x0 + r->u1 * x1));
    }
}

/* One pass over the symmetric m x m block B of which the upper triangle is kept (row
 * stride sn), two rows at a time: B -= v w^T + w v^T if v (LAPACK dsyr2), then y = B u
 * with the rows as updated if u (dsymv's upper-triangle loop: each row's part right of
 * the diagonal block gives its product with u, y's row element, and its multiple of u's
 * row element, y's column elements by symmetry). The reduction's next product runs on
 * the rows its step has just updated (tridiagonalise): a pass over S a step instead of
 * two. The rows pair up from the first, so that the columns right of a pair start at
 * the same parity in every pair: y's pairs are always loaded where they were stored
 * whole (a load across two stores would wait for both); wide, four columns at a time
 * from a multiple of 4 on, for the same reason, each row's products summed by pairs in
 * order. */
static inline __attribute__((always_inline)) void block_pass(int m, double *b, size_t sn, const double *v,
                                                             const double *w, const double *u, double *y, int wide)
{
    if (u)
        for (int j = 0; j < m; j++) y[j] = 0.0;
    int i = 0;
    for (; i + 1 < m; i += 2) {
        double *b0 = b + (size_t)i * sn, *b1 = b0 + sn;
        const double v0 = v ? v[i] : 0.0, v1 = v ? v[i + 1] : 0.0, w0 = v ? w[i] : 0.0, w1 = v ? w[i + 1] : 0.0;
        const double u0 = u ? u[i] : 0.0, u1 = u ? u[i + 1] : 0.0;
        RowPair r = {b0, b1, splat(v0), splat(v1), splat(w0), splat(w1), splat(u0), splat(u1), {0.0, 0.0}, {0.0, 0.0}};
        if (v) {
            b0[i] -= v0 * w0 + w0 * v0;
            b0[i + 1] -= v0 * w[i + 1] + w0 * v[i + 1];
            b1[i + 1] -= v1 * w1 + w1 * v1;
        }
        /* the columns right of the diagonal block by pairs, or wide four at a time
         * from the first multiple of 4 (j is even), q0 .. q1 */
        int j = i + 2;
        const int end = j + ((m - j) & ~1);
        int q0 = j, q1 = j;
        if (wide) {
            q0 = j + (j & 2) < end ? j + (j & 2) : end;
            q1 = q0 + ((end - q0) & ~3);
        }
        for (; j < q0; j += 2) row_pair_step(&r, j, v, w, u, y);
        if (q0 < q1) {
            const Quad qv0 = splat4(v0), qv1 = splat4(v1), qw0 = splat4(w0), qw1 = splat4(w1);
            const Quad qu0 = splat4(u0), qu1 = splat4(u1);
            for (; j < q1; j += 4) { /* the pairs' sums in the same order */
                Quad x0 = load_quad(b0 + j), x1 = load_quad(b1 + j);
                if (v) {
                    const Quad vj = load_quad(v + j), wj = load_quad(w + j);
                    x0 -= qv0 * wj + qw0 * vj;
                    x1 -= qv1 * wj + qw1 * vj;
                    STORE_QUAD(b0 + j, x0);
                    STORE_QUAD(b1 + j, x1);
                }
                if (u) {
                    const Quad uj = load_quad(u + j), p0 = x0 * uj, p1 = x1 * uj;
                    r.dot0 += LOW_PAIR(p0);
                    r.dot0 += HIGH_PAIR(p0);
                    r.dot1 += LOW_PAIR(p1);
                    r.dot1 += HIGH_PAIR(p1);
                    STORE_QUAD(y + j, load_quad(y + j) + (qu0 * x0 + qu1 * x1));
                }
            }
            /* the splats past the loop from the Quads' low halves: the pairs' own,
             * kept alive through it beside the Quads, were spilled around it (about 30
             * instructions a pair of rows) */
            r.v0 = LOW_PAIR(qv0), r.v1 = LOW_PAIR(qv1), r.w0 = LOW_PAIR(qw0), r.w1 = LOW_PAIR(qw1);
            r.u0 = LOW_PAIR(qu0), r.u1 = LOW_PAIR(qu1);
        }
        for (; j < end; j += 2) row_pair_step(&r, j, v, w, u, y);
        if (v && j < m) { /* m odd: the last column */
            b0[j] -= r.v0[0] * w[j] + r.w0[0] * v[j];
            b1[j] -= r.v1[0] * w[j] + r.w1[0] * v[j];
        }
        if (u) {
            const double u0s = r.u0[0], u1s = r.u1[0];
            double r0 = r.dot0[0] + r.dot0[1], r1 = r.dot1[0] + r.dot1[1];
            if (j < m) {
                r0 += b0[j] * u[j];
                r1 += b1[j] * u[j];
                y[j] += u0s * b0[j] + u1s * b1[j];
            }
            y[i] += (b0[i] * u0s + b0[i + 1] * u1s) + r0;
            y[i + 1] += (b0[i + 1] * u0s + b1[i + 1] * u1s) + r1;
        }
    }
    if (i < m) {
        double *bi = b + (size_t)i * sn + (size_t)i;
        if (v) *bi -= v[i] * w[i] + w[i] * v[i];
        if (u) y[i] += *bi * u[i];
    }
}

/* hk_dot(a, b, n) to the bit: wide, inline, its partial sums s0..s3 (the indices mod 4)
 * as one Quad, the remainder into s0, then (s0 + s1) + (s2 + s3). */
static inline __attribute__((always_inline)) double dot(const double *a, const double *b, int n, int wide)
{
    if (!wide) return hk_dot(a, b, n);
    Quad s = {0.0, 0.0, 0.0, 0.0};
    int k = 0;
    for (; k + 4 <= n; k += 4) s += load_quad(a + k) * load_quad(b + k);
    double s0 = s[0];
    for (; k < n; k++) s0 += a[k] * b[k];
    return (s0 + s[1]) + (s[2] + s[3]);
}

/* The short loops over a row below (rows of 30 and less): wide four at a time, else
 * two, the last one alone, each element's operations as written (GCC's loops for "omp
 * simd" peel and check more than the arithmetic on such rows). x[i] *= f: */
static inline __attribute__((always_inline)) void scale_by(double *x, double f, int n, int wide)
{
    int i = 0;
    if (wide)
        for (const Quad fq = splat4(f); i + 4 <= n; i += 4) STORE_QUAD(x + i, load_quad(x + i) * fq);
    for (const Pair fp = splat(f); i + 2 <= n; i += 2) store_pair(x + i, load_pair(x + i) * fp);
    if (i < n) x[i] *= f;
}

/* s[i] -= a p[i] + b x[i] (a row of dsyr2's update) */
static inline __attribute__((always_inline)) void sub_rank2_row(double *s, double a, const double *p, double b,
                                                                const double *x, int n, int wide)
{
    int i = 0;
    if (wide)
        for (const Quad aq = splat4(a), bq = splat4(b); i + 4 <= n; i += 4)
            STORE_QUAD(s + i, load_quad(s + i) - (aq * load_quad(p + i) + bq * load_quad(x + i)));
    for (const Pair ap = splat(a), bp = splat(b); i + 2 <= n; i += 2)
        store_pair(s + i, load_pair(s + i) - (ap * load_pair(p + i) + bp * load_pair(x + i)));
    if (i < n) s[i] -= a * p[i] + b * x[i];
}

/* The Householder reflector H = I - tau v v^T with H x = (beta, 0, ..., 0) for the m
 * elements x (LAPACK dlarfg): v into x (its first element 1), beta into *e. Returns 0
 * if x is already reduced (H = I, tau 0). */
static inline __attribute__((always_inline)) int make_reflector(double *x, int m, double *e, double *tau, int wide)
{
    const double alpha = x[0], xx = dot(x + 1, x + 1, m - 1, wide);
    x[0] = 1.0;
    if (xx == 0.0) {
        *e = alpha;
        *tau = 0.0;
        return 0;
    }
    const double beta = alpha >= 0.0 ? -sqrt(alpha * alpha + xx) : sqrt(alpha * alpha + xx);
    const double scale = 1.0 / (alpha - beta);
    *e = beta;
    *tau = (beta - alpha) / beta;
    scale_by(x + 1, scale, m - 1, wide);
    return 1;
}

/* Householder reduction of the symmetric a (full storage, row-major, overwritten) to
 * tridiagonal form: diagonal d, off-diagonal e (e[k] couples k and k + 1). Row k keeps
 * the k-th reflector's vector right of its diagonal (its first element 1), tau[k] its
 * factor: H_k = I - tau v v^T acts on k + 1 .. n - 1 and Q = H_0 H_1 ... H_{n-3}. Only
 * the upper triangle is read and updated, along rows; p holds 2n doubles. */
static inline __attribute__((always_inline)) void tridiagonalise(int n, double *a, double *d, double *e, double *tau,
                                                                 double *p, int wide)
{
    const size_t sn = (size_t)n;
    double *q = p + n;
    int have = n > 2 && make_reflector(a + 1, n - 1, &e[0], &tau[0], wide), ready = 0;
    for (int k = 0; k + 2 < n; k++) {
        double *row = a + (size_t)k * sn, *x = row + k + 1, *s = x + sn; /* S: the trailing block */
        const int m = n - k - 1, next = k + 3 < n;                       /* next: another reflector follows */
        d[k] = row[k];
        if (!have) { /* H = I: S stays */
            if (next) have = make_reflector(s + 1, m - 1, &e[k + 1], &tau[k + 1], wide);
            ready = 0;
            continue;
        }
        /* p = tau S v, then w = p - (tau/2)(p . v) v and S -= v w^T + w v^T (dsytd2's
         * steps; S v is ready when the last step's pass took it) */
        if (!ready) block_pass(m, s, sn, NULL, NULL, x, p, wide);
        const double t = tau[k];
        scale_by(p, t, m, wide);
        const double half = -0.5 * t * dot(p, x, m, wide);
        add_multiple(p, half, x, m, wide);
        if (!next) {
            block_pass(m, s, sn, x, p, NULL, NULL, wide);
            continue;
        }
        /* S's first row first: it gives the next reflector, which the pass over the
         * rest of S takes its product with */
        const double x0 = x[0], p0 = p[0];
        sub_rank2_row(s, x0, p, p0, x, m, wide);
        have = make_reflector(s + 1, m - 1, &e[k + 1], &tau[k + 1], wide);
        if (have)
            block_pass(m - 1, s + sn + 1, sn, x + 1, p + 1, s + 1, q, wide);
        else
            block_pass(m - 1, s + sn + 1, sn, x + 1, p + 1, NULL, NULL, wide);
        ready = have;
        double *swap = p;
        p = q;
        q = swap;
    }
    if (n >= 2) {
        d[n - 2] = a[(sn - 2) * sn + sn - 2];
        e[n - 2] = a[(sn - 2) * sn + sn - 1];
        tau[n - 2] = 0.0;
    }
    if (n >= 1) d[n - 1] = a[sn * sn - 1];
    if (n >= 1) e[n - 1] = 0.0;
}


/* Lanes of the inverse iteration: k eigenvectors of the tridiagonal matrix (d, e) side
 * by side, row i of an n x w block holding their i-th elements, two lanes to a pair (w:
 * k rounded up to even; an odd k's last pair holds a spare lane, started at zero). */
typedef struct {
    int n, k, w;
    double *shift;             /* w: the eigenvalues, kept apart within a cluster */
    double *mult, *swap, *inv; /* n x w: the factors of T - shift I, by rows (swap: a
                                * row interchange, as all bits set, else 0) */
    double *up1, *up2;         /* n x w: U's first and second superdiagonals */
    double *carry0, *carry1;   /* w: the row being eliminated (then carry0: the lanes'
                                * products in lanes_orthonormalise) */
    int *cluster;              /* k: the first lane of the lane's cluster */
} Lanes;

static inline Pair abs_pair(Pair p) { return (Pair)((Bits)p & (Bits){LLONG_MAX, LLONG_MAX}); }

/* m ? a : b for each element (m's elements all bits set or none, as comparisons give). */
static inline Pair pick(Bits m, Pair a, Pair b) { return (Pair)(((Bits)a & m) | ((Bits)b & ~m)); }

/* T - shift I = P L U for every lane at once, Gaussian elimination with partial pivoting
 * (LAPACK dlagtf); a pivot smaller than tol is taken as +-tol (dlagts), as T - lambda I
 * is singular to working precision by design. The lanes' chains are independent: the
 * loop over them fills the latency of each one's division, two divisions to an
 * instruction. */
static inline __attribute__((always_inline)) void lanes_factor(const Lanes *ln, const double *d, const double *e,
                                                               double tol)
{
    const int n = ln->n, w = ln->w;
    const Pair ptol = splat(tol), zero = {0.0, 0.0}, one = {1.0, 1.0};
    double *c0 = ln->carry0, *c1 = ln->carry1;
    for (int j = 0; j < w; j++) {
        c0[j] = d[0] - ln->shift[j];
        c1[j] = n > 1 ? e[0] : 0.0;
    }
    for (int i = 0; i < n; i++) {
        const Pair b = splat(i + 1 < n ? e[i] : 0.0), b1 = splat(i + 2 < n ? e[i + 1] : 0.0);
        const Pair di = splat(i + 1 < n ? d[i + 1] : 0.0);
        const size_t o = (size_t)i * (size_t)w;
        for (int j = 0; j < w; j += 2) {
            const Pair c0j = load_pair(c0 + j), c1j = load_pair(c1 + j), a1 = di - load_pair(ln->shift + j);
            const Bits sw = abs_pair(b) > abs_pair(c0j);
            Pair p = pick(sw, b, c0j);
            p = pick(abs_pair(p) < ptol, pick(p >= zero, ptol, -ptol), p);
            const Pair inv = one / p, m = pick(sw, c0j, b) * inv;
            const Pair u1 = pick(sw, a1, c1j), u2 = pick(sw, b1, zero);
            store_pair(c0 + j, pick(sw, c1j, a1) - m * u1);
            store_pair(c1 + j, pick(sw, zero, b1) - m * u2);
            store_pair(ln->mult + o + j, m);
            store_pair(ln->swap + o + j, (Pair)sw);
            store_pair(ln->inv + o + j, inv);
            store_pair(ln->up1 + o + j, i + 1 < n ? u1 : zero);
            store_pair(ln->up2 + o + j, i + 2 < n ? u2 : zero);
        }
    }
}

/* x = (T - shift I)^-1 x for every lane (x: n + 2 rows of w, the last two zero). */
static inline __attribute__((always_inline)) void lanes_solve(const Lanes *ln, double *x)
{
    const int n = ln->n, w = ln->w;
    const size_t sw = (size_t)w;
    for (int i = 0; i + 1 < n; i++) { /* the interchanges and L */
        double *xi = x + (size_t)i * sw, *xn = xi + sw;
        const double *m = ln->mult + (size_t)i * sw, *swap = ln->swap + (size_t)i * sw;
        for (int j = 0; j < w; j += 2) {
            const Bits swj = (Bits)load_pair(swap + j);
            const Pair x0 = load_pair(xi + j), x1 = load_pair(xn + j), top = pick(swj, x1, x0);
            store_pair(xi + j, top);
            store_pair(xn + j, pick(swj, x0, x1) - load_pair(m + j) * top);
        }
    }
    for (int i = n - 1; i >= 0; i--) { /* U */
        double *xi = x + (size_t)i * sw;
        const double *x1 = xi + sw, *x2 = x1 + sw;
        const size_t o = (size_t)i * sw;
        const double *u1 = ln->up1 + o, *u2 = ln->up2 + o, *inv = ln->inv + o;
        for (int j = 0; j < w; j += 2)
            store_pair(xi + j, (load_pair(xi + j) - load_pair(u1 + j) * load_pair(x1 + j) -
                                load_pair(u2 + j) * load_pair(x2 + j)) *
                                   load_pair(inv + j));
    }
}

/* dst[c][r] = src[r][c] for the rows x cols block src (row strides ss, ds): 2 x 2
 * blocks, two rows' pairs loaded and interleaved into two columns' pairs (element by
 * element, each a scattered store, the copies took a tenth of G+'s time). */
static inline __attribute__((always_inline)) void transpose(const double *src, size_t ss, size_t rows, size_t cols,
                                                            double *dst, size_t ds)
{
    size_t r = 0;
    for (; r + 2 <= rows; r += 2) {
        const double *s0 = src + r * ss, *s1 = s0 + ss;
        size_t c = 0;
        for (; c + 2 <= cols; c += 2) {
            const Pair a = load_pair(s0 + c), b = load_pair(s1 + c);
            store_pair(dst + c * ds + r, (Pair){a[0], b[0]});
            store_pair(dst + (c + 1) * ds + r, (Pair){a[1], b[1]});
        }
        if (c < cols) {
            dst[c * ds + r] = s0[c];
            dst[c * ds + r + 1] = s1[c];
        }
    }
    if (r < rows)
        for (size_t c = 0; c < cols; c++) dst[c * ds + r] = src[r * ss + c];
}

/* v scaled to unit length, f its squared length. */
static inline __attribute__((always_inline)) void unit_length(double *v, double f, int n, int wide)
{
    scale_by(v, 1.0 / sqrt(f), n, wide);
}

/* Lane j of x scaled to unit length after made orthogonal to the earlier lanes of its
 * cluster (modified Gram-Schmidt, dstein's way to keep close eigenvalues' vectors
 * apart). The lanes are copied out to rows of t (k x n) for it, so that the products
 * run along memory, and back to x (for the next solve or the reflectors). f: k doubles.
 * Each lane's operations are those of MGS lane by lane (each pass takes off one earlier
 * vector's part and finds the next one's product, the last pass the length), taken
 * right-looking: as soon as vector q + 1 is final, the later lanes of the cluster take
 * off vector q's part and find q + 1's. Their passes are independent of one another, so
 * that their chains overlap, where lane by lane each pass waited on the last (the same
 * bits). */
static inline __attribute__((always_inline)) void lanes_orthonormalise(const Lanes *ln, double *x, double *t, double *f,
                                                                       int wide)
{
    const int n = ln->n, k = ln->k;
    const size_t sk = (size_t)k, sn = (size_t)n, sw = (size_t)ln->w;
    transpose(x, sw, sn, sk, t, sn);
    for (int a = 0, b; a < k; a = b) { /* the cluster a .. b - 1 */
        for (b = a + 1; b < k && ln->cluster[b] == a;) b++;
        double *ta = t + (size_t)a * sn;
        unit_length(ta, sub_then_dot(ta, 0.0, NULL, ta, n, wide), n, wide);
        for (int j = a + 1; j < b; j++) f[j] = sub_then_dot(t + (size_t)j * sn, 0.0, NULL, ta, n, wide);
        for (int q = a; q + 1 < b; q++) {
            const double *tq = t + (size_t)q * sn;
            double *next = t + (size_t)(q + 1) * sn;
            unit_length(next, sub_then_dot(next, f[q + 1], tq, next, n, wide), n, wide);
            for (int j = q + 2; j < b; j++) f[j] = sub_then_dot(t + (size_t)j * sn, f[j], tq, next, n, wide);
        }
    }
    transpose(t, sn, sk, sn, x, sw);
}

/* The inverse iteration's start: a fixed pseudo-random sequence (a linear congruential
 * generator, its top 24 bits scaled to -0.5 .. 0.5), drawn row by row into the k lanes.
 * Its first START_DRAWS draws are made once, when the library is loaded: drawn at every
 * call, the generator's chain of integer products cost about 3.8 thousand instructions
 * on a head's G (n = 30, k = 10), copied 0.5. Longer starts are drawn as before, the
 * same numbers either way. */
#define START_DRAWS 2048
#define START_SEED  12345u

static double start_draws[START_DRAWS];
static int start_drawn; /* set once they are: a call from another constructor run
                         * before this one (their order is unspecified) draws its own */

static inline unsigned next_draw(unsigned state) { return state * 1664525u + 1013904223u; }

static inline double draw_value(unsigned state) { return (double)(state >> 8) / 16777216.0 - 0.5; }

__attribute__((constructor)) static void make_start_draws(void)
{
    unsigned state = START_SEED;
    for (int i = 0; i < START_DRAWS; i++) {
        state = next_draw(state);
        start_draws[i] = draw_value(state);
    }
    start_drawn = 1;
}

/* The eigenvectors of T (d, e) for the k eigenvalues lambda (ascending) into the lanes
 * of x (n + 2 rows of w; t: k x n, Gram-Schmidt's rows) by inverse iteration: two
 * solves from a fixed pseudo-random start, which leave of the other eigenvalues'
 * components (eps tnorm / gap)^2, 4e-20 or less past a cluster's gap, gaps within a
 * cluster (closer than 1e-3 tnorm, dstein's bound) handled by the Gram-Schmidt step
 * (whose mixing of two vectors within a cluster, (eps tnorm / gap)^2, moves A+ by that
 * times the gap, below eps tnorm). dstein's third solve changed A+ by 5.2e-16 of ||G||
 * at most on the head's G and took a twentieth of the call. */
static inline __attribute__((always_inline)) void lanes_eigenvectors(Lanes *ln, const double *d, const double *e,
                                                                     const double *lambda, double tnorm, double *x,
                                                                     double *t, int wide)
{
    const int n = ln->n, k = ln->k;
    const double apart = 10.0 * DBL_EPSILON * tnorm, close = 1e-3 * tnorm;
    for (int j = 0; j < k; j++) {
        double s = lambda[j];
        if (j > 0 && s - ln->shift[j - 1] < apart) s = ln->shift[j - 1] + apart;
        ln->shift[j] = s;
        ln->cluster[j] = j > 0 && lambda[j] - lambda[j - 1] <= close ? ln->cluster[j - 1] : j;
    }
    if (ln->w > k) ln->shift[k] = ln->shift[k - 1]; /* the spare lane: finite factors */
    lanes_factor(ln, d, e, DBL_EPSILON * tnorm);
    const size_t sw = (size_t)ln->w;
    const size_t sk = (size_t)k;
    if (start_drawn && (size_t)n * sk <= START_DRAWS)
        for (size_t i = 0; i < (size_t)n; i++) {
            double *xi = x + i * sw;
            for (size_t j = 0; j < sk; j++) xi[j] = start_draws[i * sk + j];
            for (size_t j = sk; j < sw; j++) xi[j] = 0.0;
        }
    else {
        unsigned state = START_SEED;
        for (size_t i = 0; i < (size_t)n; i++) {
            double *xi = x + i * sw;
            for (size_t j = 0; j < sk; j++) {
                state = next_draw(state);
                xi[j] = draw_value(state);
            }
            for (size_t j = sk; j < sw; j++) xi[j] = 0.0;
        }
    }
    for (size_t i = (size_t)n * sw; i < (size_t)(n + 2) * sw; i++) x[i] = 0.0;
    for (int pass = 0; pass < 2; pass++) {
        lanes_solve(ln, x);
        lanes_orthonormalise(ln, x, t, ln->carry0, wide);
    }
}

/* reflect_lanes on eight lanes from yj (two Quads, v's elements splat once), or ten
 * (k = 9, 10: nearly every head's G): the last two ride along as a Pair on the same
 * splats and pass over the rows (a pass of their own cost 1.8 thousand instructions a
 * call more). */
static inline __attribute__((always_inline)) void reflect_eight_lanes(const double *v, int m, int i0, int last,
                                                                      double tau, double *yj, size_t sw, int ten)
{
    Quad s0 = splat4(0.0), s1 = s0, t0 = s0, t1 = s0;
    Pair p0 = {0.0, 0.0}, p1 = p0;
    for (int i = i0; i < last; i += 2) {
        const Quad v0 = splat4(v[i]), v1 = splat4(v[i + 1]);
        double *y0 = yj + (size_t)i * sw, *y1 = y0 + sw;
        s0 += v0 * load_quad(y0);
        t0 += v0 * load_quad(y0 + 4);
        s1 += v1 * load_quad(y1);
        t1 += v1 * load_quad(y1 + 4);
        if (ten) {
            p0 += LOW_PAIR(v0) * load_pair(y0 + 8);
            p1 += LOW_PAIR(v1) * load_pair(y1 + 8);
        }
    }
    Quad f = s0 + s1, g = t0 + t1;
    Pair h = p0 + p1;
    if (i0) {
        const Quad v0 = splat4(v[0]);
        f += v0 * load_quad(yj);
        g += v0 * load_quad(yj + 4);
        if (ten) h += LOW_PAIR(v0) * load_pair(yj + 8);
    }
    if (last < m) {
        const Quad vl = splat4(v[last]);
        f += vl * load_quad(yj + (size_t)last * sw);
        g += vl * load_quad(yj + (size_t)last * sw + 4);
        if (ten) h += LOW_PAIR(vl) * load_pair(yj + (size_t)last * sw + 8);
    }
    f *= splat4(tau);
    g *= splat4(tau);
    h *= splat(tau);
    for (int i = 0; i < m; i++) {
        double *yi = yj + (size_t)i * sw;
        const Quad vi = splat4(v[i]);
        STORE_QUAD(yi, load_quad(yi) - f * vi);
        STORE_QUAD(yi + 4, load_quad(yi + 4) - g * vi);
        if (ten) store_pair(yi + 8, load_pair(yi + 8) - h * LOW_PAIR(vi));
    }
}

/* x = Q x for the eigenvectors in the lanes of x (n rows of w), Q = H_0 ... H_{n-3}
 * from tridiagonalise: the reflectors from the last (LAPACK dormtr), each on every lane
 * at once, y -= tau (v . y) v (dlarf). In the lanes a reflector's product with v runs
 * down the rows, each row's lanes one vector operation (wide, eight lanes to two Quads
 * that share a splat of v's element, the rest by pairs), without the bookkeeping of
 * the eigenvectors as rows (their pairs aligned to even indices, a prologue and an
 * epilogue for every four vectors and reflector: the stage took 27 thousand
 * instructions a call for a head's G, now 20 with the lanes' copy to rows). Each lane's
 * sums are those of the rows' kernel it replaced, to the bit: two partial sums, of the
 * elements at even and at odd indices from the first even one, in order, their sum,
 * then the first element where its index is odd, the last where one is left over. */
static inline __attribute__((always_inline)) void reflect_lanes(const double *v, int m, int first, double tau,
                                                                double *y, size_t sw, int w, int wide)
{
    const int i0 = first & 1, last = i0 + ((m - i0) & ~1);
    int j = 0;
    for (; wide && j + 8 <= w; j += 8)
        if (w - j == 10) {
            reflect_eight_lanes(v, m, i0, last, tau, y + j, sw, 1);
            j += 2;
        } else
            reflect_eight_lanes(v, m, i0, last, tau, y + j, sw, 0);
    for (; j < w; j += 2) { /* a Pair of lanes (the rest, or all of them on SSE2) */
        double *yj = y + j;
        Pair s0 = {0.0, 0.0}, s1 = {0.0, 0.0};
        for (int i = i0; i < last; i += 2) {
            s0 += splat(v[i]) * load_pair(yj + (size_t)i * sw);
            s1 += splat(v[i + 1]) * load_pair(yj + (size_t)(i + 1) * sw);
        }
        Pair f = s0 + s1;
        if (i0) f += splat(v[0]) * load_pair(yj);
        if (last < m) f += splat(v[last]) * load_pair(yj + (size_t)last * sw);
        f *= splat(tau);
        for (int i = 0; i < m; i++) store_pair(yj + (size_t)i * sw, load_pair(yj + (size_t)i * sw) - f * splat(v[i]));
    }
}

static inline __attribute__((always_inline)) void apply_reflectors(int n, const double *a, const double *tau, int w,
                                                                   double *x, int wide)
{
    const size_t sn = (size_t)n, sw = (size_t)w;
    for (int r = n - 3; r >= 0; r--)
        if (tau[r] != 0.0)
            reflect_lanes(a + (size_t)r * sn + (size_t)r + 1, n - r - 1, r + 1, tau[r], x + (size_t)(r + 1) * sw, sw, w,
                          wide);
}

/* The lower triangle of out (and the diagonal) = base + sum_q c[q] x_q x_q^T (base: a,
 * or zero if a is NULL; x_q the k rows of x, n long), then mirrored to the upper
 * triangle (symmetric to the bit) in 2 x 2 blocks. Two rows of out at a time, four
 * columns at a time (two pairs, or wide one Quad; row i's may reach past its diagonal,
 * which the mirroring writes over), each entry's sum taken in registers over q in
 * order; b holds 4k doubles (the rows' factors c[q] x_q[i], paired). */
static inline __attribute__((always_inline)) void add_rank_k(int n, const double *a, int k, const double *c,
                                                             const double *x, double *out, double *b, int wide)
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
        const double *a0 = a ? a + (size_t)i * sn : NULL, *a1 = a ? a + (size_t)i1 * sn : NULL;
        const Pair zero = {0.0, 0.0};
        const Quad zero4 = {0.0, 0.0, 0.0, 0.0};
        int j = 0;
        for (; wide && j + 3 <= i1 && j + 3 < n; j += 4) {
            Quad s0 = a ? load_quad(a0 + j) : zero4, s1 = a ? load_quad(a1 + j) : zero4;
            for (int q = 0; q < k; q++) {
                const Quad xj = load_quad(x + (size_t)q * sn + (size_t)j);
                s0 += splat4(b[4 * q]) * xj;
                s1 += splat4(b[4 * q + 2]) * xj;
            }
            STORE_QUAD(r1 + j, s1);
            STORE_QUAD(r0 + j, s0);
        }
        for (; j + 3 <= i1 && j + 3 < n; j += 4) { /* four columns: x's loads shared */
            Pair s00 = a ? load_pair(a0 + j) : zero, s01 = a ? load_pair(a0 + j + 2) : zero;
            Pair s10 = a ? load_pair(a1 + j) : zero, s11 = a ? load_pair(a1 + j + 2) : zero;
            for (int q = 0; q < k; q++) {
                const double *xq = x + (size_t)q * sn + (size_t)j;
                const Pair xa = load_pair(xq), xb = load_pair(xq + 2), b0 = load_pair(b + 4 * q),
                           b1 = load_pair(b + 4 * q + 2);
                s00 += b0 * xa;
                s01 += b0 * xb;
                s10 += b1 * xa;
                s11 += b1 * xb;
            }
            store_pair(r1 + j, s10);
            store_pair(r1 + j + 2, s11);
            store_pair(r0 + j, s00);
            store_pair(r0 + j + 2, s01);
        }
        for (; j + 1 <= i1 && j + 1 < n; j += 2) {
            Pair s0 = a ? load_pair(a0 + j) : zero, s1 = a ? load_pair(a1 + j) : zero;
            for (int q = 0; q < k; q++) {
                const Pair xj = load_pair(x + (size_t)q * sn + (size_t)j);
                s0 += load_pair(b + 4 * q) * xj;
                s1 += load_pair(b + 4 * q + 2) * xj;
            }
            store_pair(r1 + j, s1);
            store_pair(r0 + j, s0);
        }
        if (j <= i1) { /* n odd: the last column */
            double s0 = a ? a0[j] : 0.0, s1 = a ? a1[j] : 0.0;
            for (int q = 0; q < k; q++) {
                const double xj = x[(size_t)q * sn + (size_t)j];
                s0 += b[4 * q] * xj;
                s1 += b[4 * q + 2] * xj;
            }
            r1[j] = s1;
            if (j <= i) r0[j] = s0;
        }
    }
    for (size_t i = 0; i < sn; i += 2) { /* rows i, i + 1 left of the diagonal to columns i, i + 1 */
        transpose(out + i * sn, sn, i + 1 < sn ? 2 : 1, i, out + i, sn);
        if (i + 1 < sn) out[i * sn + i + 1] = out[(i + 1) * sn + i];
    }
}

/* hk_symmetric_positive_part, compiled twice below (every function it calls above is
 * always inlined into it): for AVX and for the baseline (SSE2). */
static inline __attribute__((always_inline)) int positive_part(int n, const double *a, double *out, double *work,
                                                               int *negative, int wide)
{
    const size_t sn = (size_t)n, lanes = sn / 2 + 1;
    double *t = work, *d = t + sn * sn, *e = d + sn, *e2 = e + sn, *w = e2 + sn, *tau = w + sn;
    double *scratch = tau + sn;
    for (size_t i = 0; i < sn; i++) /* the upper triangle, all the reduction reads */
        memcpy(t + i * sn + i, a + i * sn + i, (sn - i) * sizeof *t);
    tridiagonalise(n, t, d, e, tau, scratch, wide);
    double tnorm = 0.0, sum = 0.0;
    for (int i = 0; i < n; i++) {
        tnorm = fmax(tnorm, fabs(d[i]) + fabs(e[i]) + (i > 0 ? fabs(e[i - 1]) : 0.0));
        sum += fabs(d[i]) + fabs(e[i]);
    }
    /* not a number anywhere (fmax passes over one): no convergence, as tql2 would say */
    if (!isfinite(sum)) return 0;
    /* the fewer side's eigenvalues ascending into lambda (e2's place) by the counts, or
     * from all of them by the QL */
    double *lambda = e2;
    int neg = 0, subtract = 0, k = 0;
    if (!fewer_side_by_counts(n, d, e, tnorm, lambda, &neg, &subtract, &k, scratch)) {
        /* QL deflates at the top and converges fastest on a matrix graded with its
         * large entries at the bottom (LAPACK dsterf chooses between QL and QR so); G
         * is largest at the root, and so is T: the eigenvalues are those of T upside
         * down. */
        const int flip = n > 0 && fabs(d[n - 1]) < fabs(d[0]);
        neg = 0;
        for (int i = 0; i < n; i++) {
            w[flip ? n - 1 - i : i] = d[i];
            if (i + 1 < n) e2[flip ? n - 2 - i : i] = e[i] * e[i];
        }
        if (!tridiagonal_eigenvalues(n, w, e2, tnorm, wide)) return 0;
        int pos = 0;
        for (int i = 0; i < n; i++) {
            neg += w[i] < 0.0;
            pos += w[i] > 0.0;
        }
        /* A+ = A - sum of the negative modes when they are fewer, else the positive sum */
        subtract = 2 * neg < n, k = subtract ? neg : pos;
        for (int i = 0, c = 0; i < n; i++) {
            if (!(subtract ? w[i] < 0.0 : w[i] > 0.0)) continue;
            int j = c++;
            for (; j > 0 && w[i] < lambda[j - 1]; j--) lambda[j] = lambda[j - 1];
            lambda[j] = w[i];
        }
    }
    *negative = neg;
    double *x = scratch, *xt = x + (sn + 2) * lanes;
    if (k > 0) {
        Lanes ln = {.n = n, .k = k, .w = (k + 1) & ~1, .shift = xt + sn * lanes};
        ln.mult = ln.shift + lanes;
        ln.swap = ln.mult + sn * lanes;
        ln.inv = ln.swap + sn * lanes;
        ln.up1 = ln.inv + sn * lanes;
        ln.up2 = ln.up1 + sn * lanes;
        ln.carry0 = ln.up2 + sn * lanes;
        ln.carry1 = ln.carry0 + lanes;
        ln.cluster = (int *)(ln.carry1 + lanes);
        lanes_eigenvectors(&ln, d, e, lambda, tnorm, x, xt, wide);
        apply_reflectors(n, t, tau, ln.w, x, wide);
        transpose(x, (size_t)ln.w, sn, (size_t)k, xt, sn); /* the vectors to rows for add_rank_k */
    }
    if (subtract)
        for (int q = 0; q < k; q++) lambda[q] = -lambda[q];
    add_rank_k(n, subtract ? a : NULL, k, lambda, xt, out, x, wide);
    return 1;
}

/* The AVX path: a Quad's arithmetic in one register (the kernels along rows and lanes
 * with a fifth to a third fewer instructions, 186 against 230 thousand a call for a
 * head's G, 30 x 30); no FMA (target "avx" only), so that the bits are the baseline's.
 * Chosen at run time: the build stays portable (no -march). */
__attribute__((target("avx"))) static int positive_part_avx(int n, const double *a, double *out, double *work,
                                                            int *negative)
{
    return positive_part(n, a, out, work, negative, 1);
}

static int positive_part_sse2(int n, const double *a, double *out, double *work, int *negative)
{
    return positive_part(n, a, out, work, negative, 0);
}

int hk_symmetric_positive_part(int n, const double *a, double *out, double *work, int *negative)
{
    if (hk_avx_path()) return positive_part_avx(n, a, out, work, negative);
    return positive_part_sse2(n, a, out, work, negative);
}
