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

/* sqrt(a^2 + b^2) as linalg.c's QL takes it, without libm's hypot (several times slower,
 * and not needed: the matrices here hold physical values far from overflow). */
static double hypot2(double a, double b) { return sqrt(a * a + b * b); }


/* Householder reduction of the symmetric a (full storage, row-major, overwritten) to
 * tridiagonal form: diagonal d, off-diagonal e (e[k] couples k and k + 1). Row k keeps
 * the k-th reflector's vector right of its diagonal (its first element 1), tau[k] its
 * factor: H_k = I - tau v v^T acts on k + 1 .. n - 1 and Q = H_0 H_1 ... H_{n-3}. Only
 * the upper triangle is read and updated, along rows (the loops vectorise); p holds 2n
 * doubles. */
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
         * trailing block, of which the upper triangle is kept: each of its rows gives
         * its part right of the diagonal to p as a product along the row and as a
         * multiple of the row). */
        double *s = a + (size_t)(k + 1) * sn + (size_t)(k + 1);
        /* the products along the rows go apart from p (q), and into it afterwards: a
         * vector load of p[i] just after a scalar store there waits for the store (the
         * reduction took 9.2 instead of 6.3 us at n = 30) */
        double *q = p + n;
        for (int j = 0; j < m; j++) p[j] = 0.0;
        for (int i = 0; i < m; i++) {
            const double *si = s + (size_t)i * sn;
            const double vi = t * x[i];
            q[i] = t * hk_dot(si + i + 1, x + i + 1, m - i - 1);
#pragma omp simd
            for (int j = i; j < m; j++) p[j] += vi * si[j];
        }
#pragma omp simd
        for (int j = 0; j < m; j++) p[j] += q[j];
        const double half = -0.5 * t * hk_dot(p, x, m);
#pragma omp simd
        for (int j = 0; j < m; j++) p[j] += half * x[j];
        for (int i = 0; i < m; i++) {
            const double vi = x[i], wi = p[i];
            double *si = s + (size_t)i * sn;
#pragma omp simd
            for (int j = i; j < m; j++) si[j] -= vi * p[j] + wi * x[j];
        }
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
    double *mult, *swap, *inv; /* n x k: the factors of T - shift I, by rows */
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
    double *c0 = ln->carry0, *c1 = ln->carry1;
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
            ln->swap[o + (size_t)j] = sw;
            ln->inv[o + (size_t)j] = inv;
            ln->up1[o + (size_t)j] = i + 1 < n ? u1 : 0.0;
            ln->up2[o + (size_t)j] = i + 2 < n ? u2 : 0.0;
            c0[j] = n0;
            c1[j] = n1;
        }
    }
}

/* x = (T - shift I)^-1 x for every lane (x: n + 2 rows of k, the last two zero). */
static void lanes_solve(const Lanes *ln, double *x)
{
    const int n = ln->n, k = ln->k;
    const size_t sk = (size_t)k;
    for (int i = 0; i + 1 < n; i++) {
        double *xi = x + (size_t)i * sk, *xn = xi + sk;
        const double *m = ln->mult + (size_t)i * sk, *sw = ln->swap + (size_t)i * sk;
        for (int j = 0; j < k; j++) {
            const double top = sw[j] != 0.0 ? xn[j] : xi[j], bottom = sw[j] != 0.0 ? xi[j] : xn[j];
            xi[j] = top;
            xn[j] = bottom - m[j] * top;
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        double *xi = x + (size_t)i * sk;
        const double *x1 = xi + sk, *x2 = x1 + sk;
        const double *u1 = ln->up1 + (size_t)i * sk, *u2 = ln->up2 + (size_t)i * sk, *inv = ln->inv + (size_t)i * sk;
        for (int j = 0; j < k; j++) xi[j] = (xi[j] - u1[j] * x1[j] - u2[j] * x2[j]) * inv[j];
    }
}

/* Lane j of x scaled to unit length after made orthogonal to the earlier lanes of its
 * cluster (modified Gram-Schmidt, dstein's way to keep close eigenvalues' vectors
 * apart). The lanes are copied out to rows of t (k x n) for it, so that the products
 * run along memory. */
static void lanes_orthonormalise(const Lanes *ln, double *x, double *t)
{
    const int n = ln->n, k = ln->k;
    const size_t sk = (size_t)k, sn = (size_t)n;
    for (size_t i = 0; i < sn; i++)
        for (size_t j = 0; j < sk; j++) t[j * sn + i] = x[i * sk + j];
    for (int j = 0; j < k; j++) {
        double *tj = t + (size_t)j * sn;
        for (int q = ln->cluster[j]; q < j; q++) {
            const double *tq = t + (size_t)q * sn, f = hk_dot(tq, tj, n);
#pragma omp simd
            for (int i = 0; i < n; i++) tj[i] -= f * tq[i];
        }
        const double scale = 1.0 / sqrt(hk_dot(tj, tj, n));
#pragma omp simd
        for (int i = 0; i < n; i++) tj[i] *= scale;
    }
    for (size_t i = 0; i < sn; i++)
        for (size_t j = 0; j < sk; j++) x[i * sk + j] = t[j * sn + i];
}

/* The eigenvectors of T (d, e) for the k eigenvalues lambda (ascending) into x (n + 2
 * rows of k) by inverse iteration: three solves from a fixed pseudo-random start, which
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
        lanes_orthonormalise(ln, x, t);
    }
}

/* y = Q x for the k lanes of x, Q = H_0 ... H_{n-3} from tridiagonalise. */
static void apply_reflectors(int n, const double *a, const double *tau, int k, double *x, double *s)
{
    const size_t sn = (size_t)n, sk = (size_t)k;
    for (int r = n - 3; r >= 0; r--) {
        if (tau[r] == 0.0) continue;
        const double *v = a + (size_t)r * sn + (size_t)r + 1;
        const int m = n - r - 1;
        double *xr = x + (size_t)(r + 1) * sk;
        for (size_t j = 0; j < sk; j++) s[j] = 0.0;
        for (int i = 0; i < m; i++) {
            const double vi = v[i], *xi = xr + (size_t)i * sk;
#pragma omp simd
            for (size_t j = 0; j < sk; j++) s[j] += vi * xi[j];
        }
        for (size_t j = 0; j < sk; j++) s[j] *= tau[r];
        for (int i = 0; i < m; i++) {
            const double vi = v[i];
            double *xi = xr + (size_t)i * sk;
#pragma omp simd
            for (size_t j = 0; j < sk; j++) xi[j] -= vi * s[j];
        }
    }
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
        apply_reflectors(n, t, tau, k, x, ln.carry0);
        for (int j = 0; j < k; j++) /* transposed, so that the sums below run along rows */
            for (size_t i = 0; i < sn; i++) xt[(size_t)j * sn + i] = x[i * (size_t)k + (size_t)j];
    }
    for (size_t i = 0; i < sn; i++) {
        double *row = out + i * sn;
        for (size_t j = 0; j <= i; j++) row[j] = subtract ? a[i * sn + j] : 0.0;
        for (int q = 0; q < k; q++) {
            const double *vq = xt + (size_t)q * sn;
            const double p = subtract ? -lambda[q] * vq[i] : lambda[q] * vq[i];
#pragma omp simd
            for (size_t j = 0; j <= i; j++) row[j] += p * vq[j];
        }
        for (size_t j = 0; j < i; j++) out[j * sn + i] = row[j];
    }
    return 1;
}
