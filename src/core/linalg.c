/* Dense Cholesky factorisation for the Newton solvers (n up to a few hundred). */
#include "core/linalg.h"

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

/* Dot product with four partial sums: the compiler may not reorder floating-point
 * sums on its own, and a fixed order keeps results identical on every machine. Inline
 * in the factorisation and the solve below: their dot products are short (rows of
 * 3N = 30 on a head; callgrind on examples/guides200: 10 instructions a call of hk_dot
 * from the factorisation, which takes 8 % fewer instructions with them inline). */
static inline double dot4(const double *a, const double *b, int n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        s0 += a[k] * b[k];
        s1 += a[k + 1] * b[k + 1];
        s2 += a[k + 2] * b[k + 2];
        s3 += a[k + 3] * b[k + 3];
    }
    for (; k < n; k++) s0 += a[k] * b[k];
    return (s0 + s1) + (s2 + s3);
}

double hk_dot(const double *a, const double *b, int n) { return dot4(a, b, n); }

/* hk_dot twice with a's loads shared (a Jacobian's normal equations take a column's
 * product with every other): its partial sums s0..s3, two to a vector register, the
 * remainder added to s0, then (s0 + s1) + (s2 + s3), exactly as hk_dot's. */
void hk_dot2(const double *a, const double *b, const double *c, int n, double *ab, double *ac)
{
    typedef double Pair __attribute__((vector_size(16)));
    Pair b01 = {0.0, 0.0}, b23 = b01, c01 = b01, c23 = b01;
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        const Pair a01 = {a[k], a[k + 1]}, a23 = {a[k + 2], a[k + 3]};
        b01 += a01 * (Pair){b[k], b[k + 1]};
        b23 += a23 * (Pair){b[k + 2], b[k + 3]};
        c01 += a01 * (Pair){c[k], c[k + 1]};
        c23 += a23 * (Pair){c[k + 2], c[k + 3]};
    }
    double sb = b01[0], sc = c01[0];
    for (; k < n; k++) sb += a[k] * b[k], sc += a[k] * c[k];
    *ab = (sb + b01[1]) + (b23[0] + b23[1]);
    *ac = (sc + c01[1]) + (c23[0] + c23[1]);
}

/* out[j] = x . (column j of the six rows yt), for j < count: each sum in hk_dot6's order
 * ((x0 y0 + x1 y1) + x2 y2) + ..., the columns side by side, four a vector on the AVX
 * path (wide), then two, then one. By hand rather than an `omp simd` loop, whose
 * peeling and remainder checks cost more than the arithmetic on rows of 3N = 30 and
 * less (the assembly's and the potential's Hessian rows, count = 3p). */
static inline __attribute__((always_inline)) void dot6_columns(const double x[6], const double *yt, size_t stride,
                                                               int count, double *out, int wide)
{
    typedef double Quad __attribute__((vector_size(32)));
    typedef double Pair __attribute__((vector_size(16)));
    const double *restrict y0 = yt, *restrict y1 = y0 + stride, *restrict y2 = y1 + stride;
    const double *restrict y3 = y2 + stride, *restrict y4 = y3 + stride, *restrict y5 = y4 + stride;
    double *restrict o = out;
    const double x0 = x[0], x1 = x[1], x2 = x[2], x3 = x[3], x4 = x[4], x5 = x[5];
    int j = 0;
    /* columns j to j + width - 1 in a vector V */
#define HK_DOT6_COLUMNS(V)                                                                                             \
    do {                                                                                                               \
        V a, s;                                                                                                        \
        memcpy(&a, y0 + j, sizeof a), s = x0 * a;                                                                      \
        memcpy(&a, y1 + j, sizeof a), s += x1 * a;                                                                     \
        memcpy(&a, y2 + j, sizeof a), s += x2 * a;                                                                     \
        memcpy(&a, y3 + j, sizeof a), s += x3 * a;                                                                     \
        memcpy(&a, y4 + j, sizeof a), s += x4 * a;                                                                     \
        memcpy(&a, y5 + j, sizeof a), s += x5 * a;                                                                     \
        memcpy(o + j, &s, sizeof s);                                                                                   \
    } while (0)
    if (wide)
        for (; j + 4 <= count; j += 4) HK_DOT6_COLUMNS(Quad);
    for (; j + 2 <= count; j += 2) HK_DOT6_COLUMNS(Pair);
#undef HK_DOT6_COLUMNS
    if (j < count) o[j] = x0 * y0[j] + x1 * y1[j] + x2 * y2[j] + x3 * y3[j] + x4 * y4[j] + x5 * y5[j];
}

/* On AVX four columns a vector instead of two: each column's sum is its own lane's, in
 * the same order (no FMA: target "avx" only), so the bits are the baseline's (linalg.h,
 * hk_avx_path). */
__attribute__((target("avx"))) static void dot6_columns_avx(const double x[6], const double *yt, size_t stride,
                                                            int count, double *out)
{
    dot6_columns(x, yt, stride, count, out, 1);
}

static void dot6_columns_sse2(const double x[6], const double *yt, size_t stride, int count, double *out)
{
    dot6_columns(x, yt, stride, count, out, 0);
}

int hk_avx_paths_allowed = 1;

int hk_avx_paths_allow(int allow)
{
    hk_avx_paths_allowed = allow;
    return __builtin_cpu_supports("avx");
}

void hk_dot6_columns(const double x[6], const double *yt, size_t stride, int count, double *out)
{
    if (hk_avx_path())
        dot6_columns_avx(x, yt, stride, count, out);
    else
        dot6_columns_sse2(x, yt, stride, count, out);
}

int hk_cholesky_factor(int n, const double *a, double shift, const double *d, double *l)
{
    const size_t sn = (size_t)n;
    for (int j = 0; j < n; j++) {
        const double *lj = l + (size_t)j * sn;
        double diag = a[(size_t)j * sn + (size_t)j] + shift * (d ? d[j] : 1.0) - dot4(lj, lj, j);
        /* A pivot this small relative to the original diagonal means the matrix is
         * indefinite or singular to working precision. */
        const double ref = fabs(a[(size_t)j * sn + (size_t)j]) + fabs(shift * (d ? d[j] : 1.0));
        if (!(diag > 1e-13 * ref) || !isfinite(diag)) return 0;
        const double ljj = sqrt(diag);
        l[(size_t)j * sn + (size_t)j] = ljj;
        for (int i = j + 1; i < n; i++) {
            double *li = l + (size_t)i * sn;
            li[j] = (a[(size_t)i * sn + (size_t)j] - dot4(li, lj, j)) / ljj;
        }
    }
    return 1;
}

void hk_cholesky_solve(int n, const double *l, double *x)
{
    const size_t sn = (size_t)n;
    for (int i = 0; i < n; i++) {
        x[i] = (x[i] - dot4(l + (size_t)i * sn, x, i)) / l[(size_t)i * sn + (size_t)i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double v = x[i];
        for (int k = i + 1; k < n; k++) v -= l[(size_t)k * sn + (size_t)i] * x[k];
        x[i] = v / l[(size_t)i * sn + (size_t)i];
    }
}

/* ---- symmetric eigen-decomposition ------------------------------------------------
 * Householder reduction to tridiagonal form, then the implicit QL iteration with
 * Wilkinson-like shifts (Wilkinson & Reinsch, Handbook for Automatic Computation II,
 * procedures tred2 and tql2), accumulating the transformations into the eigenvectors. */

/* sqrt(a^2 + b^2) without libm's hypot, several times slower and not needed: the
 * matrices here hold physical values far from overflow. */
static double hypot2(double a, double b) { return sqrt(a * a + b * b); }

static void transpose_square(double *m, size_t n)
{
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            const double t = m[i * n + j];
            m[i * n + j] = m[j * n + i];
            m[j * n + i] = t;
        }
}

int hk_symmetric_eigen(int n, const double *a, double *w, double *v, double *e)
{
    const size_t sn = (size_t)n;
#define V(i, j) v[(size_t)(i)*sn + (size_t)(j)]
    for (size_t k = 0; k < sn * sn; k++) v[k] = a[k];
    /* tred2: V becomes the orthogonal transformation, w the diagonal, e the
     * subdiagonal (e[i] couples i - 1 and i). */
    for (int i = n - 1; i > 0; i--) {
        const int l = i - 1;
        double h = 0.0, scale = 0.0;
        if (l > 0) {
            for (int k = 0; k <= l; k++) scale += fabs(V(i, k));
            if (scale == 0.0) {
                e[i] = V(i, l);
            } else {
                for (int k = 0; k <= l; k++) {
                    V(i, k) /= scale;
                    h += V(i, k) * V(i, k);
                }
                double f = V(i, l);
                double g = f >= 0.0 ? -sqrt(h) : sqrt(h);
                e[i] = scale * g;
                h -= f * g;
                V(i, l) = f - g;
                f = 0.0;
                for (int j = 0; j <= l; j++) {
                    V(j, i) = V(i, j) / h;
                    g = 0.0;
                    for (int k = 0; k <= j; k++) g += V(j, k) * V(i, k);
                    for (int k = j + 1; k <= l; k++) g += V(k, j) * V(i, k);
                    e[j] = g / h;
                    f += e[j] * V(i, j);
                }
                const double hh = f / (h + h);
                for (int j = 0; j <= l; j++) {
                    f = V(i, j);
                    e[j] = g = e[j] - hh * f;
                    for (int k = 0; k <= j; k++) V(j, k) -= f * e[k] + g * V(i, k);
                }
            }
        } else {
            e[i] = V(i, l);
        }
        w[i] = h;
    }
    w[0] = 0.0;
    e[0] = 0.0;
    double gbuf[256];
    for (int i = 0; i < n; i++) {
        const int l = i - 1;
        if (w[i] != 0.0 && n <= 256) {
            /* As below, row by row: no g depends on another column's update (row i is
             * not updated), and each g sums in the same order, so the bits are the
             * same; the rows vectorise. */
            for (int j = 0; j <= l; j++) gbuf[j] = 0.0;
            for (int k = 0; k <= l; k++) {
                const double x = V(i, k), *row = v + (size_t)k * sn;
#pragma omp simd
                for (int j = 0; j <= l; j++) gbuf[j] += x * row[j];
            }
            for (int k = 0; k <= l; k++) {
                const double y = V(k, i);
                double *row = v + (size_t)k * sn;
#pragma omp simd
                for (int j = 0; j <= l; j++) row[j] -= gbuf[j] * y;
            }
        } else if (w[i] != 0.0) {
            for (int j = 0; j <= l; j++) {
                double g = 0.0;
                for (int k = 0; k <= l; k++) g += V(i, k) * V(k, j);
                for (int k = 0; k <= l; k++) V(k, j) -= g * V(k, i);
            }
        }
        w[i] = V(i, i);
        V(i, i) = 1.0;
        for (int j = 0; j <= l; j++) V(j, i) = V(i, j) = 0.0;
    }
    /* tql2 (QL with implicit shifts) on the tridiagonal matrix; columns of V are
     * rotated, so that in the end column j of V is the eigenvector of w[j]. V is held
     * transposed meanwhile: a rotation then runs along two rows in memory, which
     * vectorises (each element computed as before: the same bits). */
    transpose_square(v, sn);
    for (int i = 1; i < n; i++) e[i - 1] = e[i];
    if (n > 0) e[n - 1] = 0.0;
    for (int l = 0; l < n; l++) {
        int iter = 0, m;
        do {
            for (m = l; m < n - 1; m++) {
                const double dd = fabs(w[m]) + fabs(w[m + 1]);
                if (fabs(e[m]) <= 1e-15 * dd) break;
            }
            if (m != l) {
                if (iter++ == 60) { /* no convergence */
                    transpose_square(v, sn);
                    return 0;
                }
                double g = (w[l + 1] - w[l]) / (2.0 * e[l]);
                double r = hypot2(g, 1.0);
                g = w[m] - w[l] + e[l] / (g + (g >= 0.0 ? fabs(r) : -fabs(r)));
                double s = 1.0, c = 1.0, p = 0.0;
                int i;
                for (i = m - 1; i >= l; i--) {
                    double f = s * e[i];
                    const double b = c * e[i];
                    e[i + 1] = (r = hypot2(f, g));
                    if (r == 0.0) {
                        w[i + 1] -= p;
                        e[m] = 0.0;
                        break;
                    }
                    s = f / r;
                    c = g / r;
                    g = w[i + 1] - p;
                    r = (w[i] - g) * s + 2.0 * c * b;
                    w[i + 1] = g + (p = s * r);
                    g = c * r - b;
                    double *vi = v + (size_t)i * sn, *vn = vi + sn; /* columns i, i + 1 */
#pragma omp simd
                    for (int k = 0; k < n; k++) {
                        const double x = vi[k], y = vn[k];
                        vn[k] = s * x + c * y;
                        vi[k] = c * x - s * y;
                    }
                }
                if (r == 0.0 && i >= l) continue;
                w[l] -= p;
                e[l] = g;
                e[m] = 0.0;
            }
        } while (m != l);
    }
    transpose_square(v, sn);
#undef V
    return 1;
}
