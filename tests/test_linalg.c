/* Symmetric eigen-decomposition against its definition: A v_j = w_j v_j and V^T V = I,
 * on random matrices of every size up to 40, diagonal and rank-deficient ones, and a
 * matrix with known eigenvalues (Q diag(d) Q^T with Q from a random orthogonalisation).
 * The positive part A+ (hk_symmetric_positive_part) against V max(L, 0) V^T from the
 * decomposition and against what defines it: A+ positive semidefinite, A+ (A+ - A) = 0
 * (the two parts' products vanish), on random, repeated, clustered and graded spectra;
 * its AVX path against its SSE2 path, bit for bit, and its bits against main's (a hash);
 * the Cholesky test that skips it where G is positive definite (strand_dynamics.c)
 * against it on semidefinite and barely indefinite matrices.
 * Cholesky factors (also in place, bit for bit) and solves against the residual A x - b. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"

static void check(int n, const double *a, const double *w, const double *v)
{
    double norm = 0.0;
    for (int i = 0; i < n * n; i++) norm = fmax(norm, fabs(a[i]));
    for (int j = 0; j < n; j++) {
        for (int i = 0; i < n; i++) {
            double av = 0.0;
            for (int k = 0; k < n; k++) av += a[i * n + k] * v[k * n + j];
            hk_assert_near(av, w[j] * v[i * n + j], 1e-12 * (norm + 1e-300) * n);
        }
        for (int k = 0; k < n; k++) {
            double d = 0.0;
            for (int i = 0; i < n; i++) d += v[i * n + j] * v[i * n + k];
            hk_assert_near(d, j == k ? 1.0 : 0.0, 1e-12 * n);
        }
    }
}

static void test_random_symmetric(void **state)
{
    (void)state;
    for (int n = 1; n <= 40; n++) {
        double *a = malloc(sizeof(double) * n * n), *v = malloc(sizeof(double) * n * n);
        double *w = malloc(sizeof(double) * n), *e = malloc(sizeof(double) * n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j <= i; j++) a[i * n + j] = a[j * n + i] = 2.0 * hk_test_uniform() - 1.0;
        assert_int_equal(hk_symmetric_eigen(n, a, w, v, e), 1);
        check(n, a, w, v);
        /* trace = sum of eigenvalues */
        double tr = 0.0, sw = 0.0;
        for (int i = 0; i < n; i++) tr += a[i * n + i], sw += w[i];
        hk_assert_near(sw, tr, 1e-12 * n);
        free(a), free(v), free(w), free(e);
    }
}

/* Q diag(d) Q^T, Q orthogonal from Gram-Schmidt of random columns (q: n x n work) */
static void known_spectrum(int n, const double *d, double *q, double *a)
{
    for (int i = 0; i < n * n; i++) q[i] = 2.0 * hk_test_uniform() - 1.0;
    for (int j = 0; j < n; j++) {
        for (int k = 0; k < j; k++) {
            double dot = 0.0;
            for (int i = 0; i < n; i++) dot += q[i * n + j] * q[i * n + k];
            for (int i = 0; i < n; i++) q[i * n + j] -= dot * q[i * n + k];
        }
        double s = 0.0;
        for (int i = 0; i < n; i++) s += q[i * n + j] * q[i * n + j];
        for (int i = 0; i < n; i++) q[i * n + j] /= sqrt(s);
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) s += q[i * n + k] * d[k] * q[j * n + k];
            a[i * n + j] = a[j * n + i] = s;
        }
}

static void test_known_spectrum(void **state)
{
    (void)state;
    enum { N = 12 };
    double q[N * N], a[N * N], v[N * N], w[N], e[N];
    /* eigenvalues with a repeated one, a zero and negatives */
    const double d[N] = {-3, -1e-9, 0, 0, 1e-6, 1, 1, 1, 2.5, 7, 1e3, -1e3};
    known_spectrum(N, d, q, a);
    assert_int_equal(hk_symmetric_eigen(N, a, w, v, e), 1);
    check(N, a, w, v);
    /* same multiset of eigenvalues */
    double sorted[N], want[N];
    memcpy(sorted, w, sizeof sorted);
    memcpy(want, d, sizeof want);
    for (int i = 0; i < N; i++)
        for (int j = i + 1; j < N; j++) {
            if (sorted[j] < sorted[i]) {
                double t = sorted[i];
                sorted[i] = sorted[j];
                sorted[j] = t;
            }
            if (want[j] < want[i]) {
                double t = want[i];
                want[i] = want[j];
                want[j] = t;
            }
        }
    for (int i = 0; i < N; i++) hk_assert_near(sorted[i], want[i], 1e-12 * 1e3);
}

static void test_diagonal_and_zero(void **state)
{
    (void)state;
    double a[9] = {3, 0, 0, 0, -2, 0, 0, 0, 0}, v[9], w[3], e[3];
    assert_int_equal(hk_symmetric_eigen(3, a, w, v, e), 1);
    check(3, a, w, v);
    double z[16] = {0}, vz[16], wz[4], ez[4];
    assert_int_equal(hk_symmetric_eigen(4, z, wz, vz, ez), 1);
    check(4, z, wz, vz);
    for (int i = 0; i < 4; i++) assert_true(wz[i] == 0.0);
}


/* A+ of a against the decomposition's V max(L, 0) V^T and its definition; returns the
 * number of negative eigenvalues reported. */
static int check_positive_part(int n, const double *a)
{
    const size_t nn = (size_t)n * (size_t)n;
    double *pos = malloc(sizeof(double) * nn), *ref = malloc(sizeof(double) * nn);
    double *v = malloc(sizeof(double) * nn), *w = malloc(sizeof(double) * (size_t)n);
    double *e = malloc(sizeof(double) * (size_t)n), *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(n));
    int negative = -1;
    assert_int_equal(hk_symmetric_positive_part(n, a, pos, work, &negative), 1);
    assert_int_equal(hk_symmetric_eigen(n, a, w, v, e), 1);
    double norm = 0.0, smallest = INFINITY;
    int below = 0;
    for (size_t i = 0; i < nn; i++) norm = fmax(norm, fabs(a[i]));
    for (int k = 0; k < n; k++) below += w[k] < 0.0, smallest = fmin(smallest, fabs(w[k]));
    /* the count is the decomposition's wherever no eigenvalue is within round-off of 0 */
    if (smallest > 1e-10 * norm) assert_int_equal(negative, below);
    const double tol = 1e-12 * (norm + 1e-300);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) s += w[k] > 0.0 ? v[i * n + k] * w[k] * v[j * n + k] : 0.0;
            ref[i * n + j] = s;
            assert_memory_equal(&pos[i * n + j], &pos[j * n + i], sizeof(double));
            hk_assert_near(pos[i * n + j], s, tol);
        }
    for (int i = 0; i < n; i++) /* A+ (A+ - A) = 0 */
        for (int j = 0; j < n; j++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) s += pos[i * n + k] * (pos[k * n + j] - a[k * n + j]);
            hk_assert_near(s, 0.0, 1e-12 * n * (norm * norm + 1e-300));
        }
    assert_int_equal(hk_symmetric_eigen(n, pos, w, v, e), 1); /* A+ >= 0 */
    for (int k = 0; k < n; k++) assert_true(w[k] >= -tol);
    free(pos), free(ref), free(v), free(w), free(e), free(work);
    return negative;
}

static void test_positive_part_random(void **state)
{
    (void)state;
    for (int n = 1; n <= 40; n++) {
        double *a = malloc(sizeof(double) * (size_t)(n * n));
        for (int i = 0; i < n; i++)
            for (int j = 0; j <= i; j++) a[i * n + j] = a[j * n + i] = 2.0 * hk_test_uniform() - 1.0;
        check_positive_part(n, a);
        /* shifted: mostly negative (A+ summed from the positive modes), then mostly
         * positive */
        for (int i = 0; i < n; i++) a[i * n + i] -= 0.6 * sqrt(n);
        check_positive_part(n, a);
        for (int i = 0; i < n; i++) a[i * n + i] += 1.2 * sqrt(n);
        check_positive_part(n, a);
        free(a);
    }
}

static void test_positive_part_spectra(void **state)
{
    (void)state;
    enum { N = 30 };
    double d[N], q[N * N], a[N * N];
    /* graded as the geometric stiffness of a guide (one eigenvalue of 1, the others
     * 1e-2 to 1e-7 of it, 10 of them negative) */
    for (int k = 0; k < N; k++) d[k] = (k % 3 == 1 ? -1.0 : 1.0) * pow(10.0, -2.0 - 5.0 * k / (N - 1.0));
    d[0] = 1.0;
    known_spectrum(N, d, q, a);
    assert_int_equal(check_positive_part(N, a), 10);
    /* repeated negative eigenvalues, zeros, a cluster 1e-12 apart */
    for (int k = 0; k < N; k++) d[k] = 1.0 + k;
    d[3] = d[4] = d[5] = -2.0;
    d[6] = d[7] = 0.0;
    d[8] = -0.5, d[9] = -0.5 * (1.0 + 1e-12), d[10] = -0.5 * (1.0 + 2e-12);
    d[11] = -1e-9, d[12] = -1e-9 * (1.0 + 1e-6), d[13] = 1e-9;
    known_spectrum(N, d, q, a);
    check_positive_part(N, a);
    /* more negative than positive: the positive sum, with repeated positives */
    for (int k = 0; k < N; k++) d[k] = -1.0 - k;
    d[0] = d[1] = d[2] = 3.0;
    d[3] = 3.0 * (1.0 + 1e-13);
    known_spectrum(N, d, q, a);
    assert_int_equal(check_positive_part(N, a), N - 4);
    /* diagonal (already tridiagonal, with zero off-diagonals) and zero */
    memset(a, 0, sizeof a);
    check_positive_part(N, a);
    for (int k = 0; k < N; k++) a[k * N + k] = k % 4 == 0 ? -1.0 : (k % 4 == 1 ? 1.0 : 0.25 * k);
    check_positive_part(N, a);
    /* tridiagonal with a split in the middle and equal blocks */
    memset(a, 0, sizeof a);
    for (int k = 0; k + 1 < N; k++) {
        a[k * N + k + 1] = a[(k + 1) * N + k] = k == N / 2 - 1 ? 0.0 : 1.0;
        a[k * N + k] = (k % (N / 2)) * 0.1 - 1.0;
    }
    a[N * N - 1] = (N / 2 - 1) * 0.1 - 1.0;
    check_positive_part(N, a);
    /* not a number: reported, as the decomposition reports no convergence */
    a[3 * N + 5] = a[5 * N + 3] = NAN;
    double out[N * N], work[HK_POSITIVE_PART_WORK(N)];
    int negative = 0;
    assert_int_equal(hk_symmetric_positive_part(N, a, out, work, &negative), 0);
}

static void test_cholesky_solves(void **state)
{
    (void)state;
    srand(7);
    for (int n = 1; n <= 40; n += 3) {
        const int count = 1 + n % 7 * 5;
        double *a = malloc(sizeof(double) * (size_t)(n * n)), *l = calloc((size_t)(n * n), sizeof(double));
        double *b = malloc(sizeof(double) * (size_t)(n * count)), *x = malloc(sizeof(double) * (size_t)(n * count));
        /* A = B B^T + n I: symmetric positive definite */
        double *m = malloc(sizeof(double) * (size_t)(n * n));
        for (int i = 0; i < n * n; i++) m[i] = rand() / (double)RAND_MAX - 0.5;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double v = i == j ? n : 0.0;
                for (int k = 0; k < n; k++) v += m[i * n + k] * m[j * n + k];
                a[i * n + j] = v;
            }
        assert_true(hk_cholesky_factor(n, a, 0.0, NULL, l));
        /* in place (the contacts' solve factors so): the same lower triangle, bit for bit */
        double *in_place = malloc(sizeof(double) * (size_t)(n * n));
        memcpy(in_place, a, sizeof(double) * (size_t)(n * n));
        assert_true(hk_cholesky_factor(n, in_place, 0.0, NULL, in_place));
        for (int i = 0; i < n; i++)
            for (int j = 0; j <= i; j++) assert_memory_equal(&in_place[i * n + j], &l[i * n + j], sizeof(double));
        free(in_place);
        for (int i = 0; i < n * count; i++) b[i] = x[i] = rand() / (double)RAND_MAX - 0.5;
        for (int r = 0; r < count; r++) hk_cholesky_solve(n, l, x + (size_t)r * (size_t)n);
        for (int r = 0; r < count; r++)
            for (int i = 0; i < n; i++) {
                double ax = 0.0;
                for (int k = 0; k < n; k++) ax += a[i * n + k] * x[r * n + k];
                hk_assert_near(ax, b[r * n + i], 1e-12 * n * n);
            }
        free(a), free(l), free(b), free(x), free(m);
    }
}

/* hk_symmetric_positive_part's AVX path against its SSE2 path, the same bytes: the
 * AVX kernels do each element's operations in the SSE2 kernels' order (no FMA), so
 * any difference is a bug, not round-off. Returns 0 where the machine has no AVX
 * (nothing to compare). */
static int paths_agree(int n, const double *a)
{
    if (!hk_avx_paths_allow(1)) return 0;
    const size_t nn = (size_t)n * (size_t)n;
    double *avx = malloc(sizeof(double) * nn), *sse2 = malloc(sizeof(double) * nn);
    double *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(n));
    int neg_avx = -1, neg_sse2 = -2;
    assert_int_equal(hk_symmetric_positive_part(n, a, avx, work, &neg_avx), 1);
    hk_avx_paths_allow(0);
    assert_int_equal(hk_symmetric_positive_part(n, a, sse2, work, &neg_sse2), 1);
    hk_avx_paths_allow(1);
    assert_int_equal(neg_avx, neg_sse2);
    assert_memory_equal(avx, sse2, sizeof(double) * nn);
    free(avx), free(sse2), free(work);
    return 1;
}

/* Every size to 40 (odd and even, every alignment of the kernels' four-wide steps),
 * either side the fewer, and spectra graded as a guide's G at the sizes of N = 10,
 * 20 and 40. */
static void test_positive_part_paths_same_bits(void **state)
{
    (void)state;
    if (!hk_avx_paths_allow(1)) {
        print_message("no AVX on this machine: the SSE2 path alone (the other tests)\n");
        return;
    }
    for (int n = 1; n <= 40; n++) {
        double *a = malloc(sizeof(double) * (size_t)(n * n));
        for (int i = 0; i < n; i++)
            for (int j = 0; j <= i; j++) a[i * n + j] = a[j * n + i] = 2.0 * hk_test_uniform() - 1.0;
        for (int shift = 0; shift < 3; shift++) {
            for (int i = 0; i < n; i++) a[i * n + i] += (shift == 1 ? -0.6 : shift == 2 ? 1.2 : 0.0) * sqrt(n);
            assert_true(paths_agree(n, a));
        }
        free(a);
    }
    const int sizes[3] = {30, 60, 120};
    for (int s = 0; s < 3; s++) {
        const int n = sizes[s];
        double *d = malloc(sizeof(double) * (size_t)n), *q = malloc(sizeof(double) * (size_t)(n * n));
        double *a = malloc(sizeof(double) * (size_t)(n * n));
        for (int k = 0; k < n; k++) d[k] = (k % 3 == 1 ? -1.0 : 1.0) * pow(10.0, -2.0 - 5.0 * k / (n - 1.0));
        d[0] = 1.0;
        known_spectrum(n, d, q, a);
        assert_true(paths_agree(n, a));
        free(d), free(q), free(a);
    }
}

/* A fixed symmetric n x n matrix from a generator of its own (so that it does not
 * depend on the other tests, nor on libm): kind 0 uniform in [-1, 1], 1 and 2 shifted
 * as above (either side the fewer), 3 graded as a guide's G (entries falling by 0.75 a
 * row and a column, 1.8e-10 at the last of 40, a third of the diagonal negative). */
static void bits_matrix(int n, int kind, unsigned *state, double *a)
{
    double grade[160]; /* n up to 80 */
    grade[0] = 1.0;
    for (int k = 1; k < 2 * n; k++) grade[k] = grade[k - 1] * 0.75;
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            *state = *state * 1664525u + 1013904223u;
            double x = (double)(*state >> 8) / 16777216.0 * 2.0 - 1.0;
            if (kind == 3) x *= grade[i + j] * (i != j ? 1.0 : i % 3 == 1 ? -4.0 : 4.0);
            a[i * n + j] = a[j * n + i] = x;
        }
    if (kind == 1 || kind == 2)
        for (int i = 0; i < n; i++) a[i * n + i] += (kind == 1 ? -0.6 : 1.2) * sqrt(n);
}

/* FNV-1a over A+'s bytes and the negative count of each matrix above, sizes 1 to 40. */
static unsigned long long positive_part_bits(void)
{
    unsigned long long h = 1469598103934665603ULL;
    unsigned state = 2026u;
    double *a = malloc(sizeof(double) * 40 * 40), *out = malloc(sizeof(double) * 40 * 40);
    double *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(40));
    for (int n = 1; n <= 40; n++)
        for (int kind = 0; kind < 4; kind++) {
            int negative = -1;
            bits_matrix(n, kind, &state, a);
            assert_int_equal(hk_symmetric_positive_part(n, a, out, work, &negative), 1);
            const unsigned char *b = (const unsigned char *)out;
            for (size_t k = 0; k < sizeof(double) * (size_t)(n * n); k++) h = (h ^ b[k]) * 1099511628211ULL;
            h = (h ^ (unsigned)negative) * 1099511628211ULL;
        }
    free(a), free(out), free(work);
    return h;
}

/* A+'s bits as main's kernels gave them (gplus16, 7 December 2026: the fewer side's
 * eigenvalues by Sturm counts and Newton's steps instead of the QL, and two inverse
 * iteration solves instead of three, within 1.2e-15 of ||G|| of main's on the head's G;
 * 0x0d13eb6682c9f03c before, 0x1a90cb436a45a6c5 with the counts alone), on either path: the
 * kernels rewritten for speed alone must keep every operation and its order. A change
 * that means to change the bits (another summation order, fewer solves) updates the
 * hash with its reasons. */
static void test_positive_part_bits_kept(void **state)
{
    (void)state;
    const int avx = hk_avx_paths_allow(1);
    for (int path = avx ? 0 : 1; path < 2; path++) {
        hk_avx_paths_allow(path == 0);
        assert_true(positive_part_bits() == 0xd398923620514e46ULL);
    }
    hk_avx_paths_allow(1);
}

/* A+ = V max(L, 0) V^T by cyclic Jacobi rotations in long double (64-bit significands:
 * a reference 2^11 times finer than double, and an algorithm that shares nothing with
 * hk_symmetric_positive_part's reduction, Sturm counts and inverse iteration). */
static void jacobi_positive_part(int n, const double *a, double *out)
{
    const size_t nn = (size_t)n * (size_t)n;
    long double *m = malloc(sizeof(long double) * nn), *v = malloc(sizeof(long double) * nn);
    for (size_t i = 0; i < nn; i++) m[i] = a[i], v[i] = i % (size_t)(n + 1) == 0 ? 1.0L : 0.0L;
    for (int sweep = 0; sweep < 60; sweep++) {
        long double off = 0.0L, all = 0.0L;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                all += m[i * n + j] * m[i * n + j];
                if (i != j) off += m[i * n + j] * m[i * n + j];
            }
        if (off <= 1e-40L * all) break;
        for (int p = 0; p < n; p++)
            for (int q = p + 1; q < n; q++) {
                const long double apq = m[p * n + q];
                if (apq == 0.0L) continue;
                const long double theta = (m[q * n + q] - m[p * n + p]) / (2.0L * apq);
                const long double t = (theta >= 0.0L ? 1.0L : -1.0L) / (fabsl(theta) + sqrtl(theta * theta + 1.0L));
                const long double c = 1.0L / sqrtl(t * t + 1.0L), s = t * c;
                for (int k = 0; k < n; k++) { /* columns p, q, then rows p, q */
                    const long double mkp = m[k * n + p], mkq = m[k * n + q];
                    m[k * n + p] = c * mkp - s * mkq;
                    m[k * n + q] = s * mkp + c * mkq;
                    const long double vkp = v[k * n + p], vkq = v[k * n + q];
                    v[k * n + p] = c * vkp - s * vkq;
                    v[k * n + q] = s * vkp + c * vkq;
                }
                for (int k = 0; k < n; k++) {
                    const long double mpk = m[p * n + k], mqk = m[q * n + k];
                    m[p * n + k] = c * mpk - s * mqk;
                    m[q * n + k] = s * mpk + c * mqk;
                }
            }
    }
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            long double s = 0.0L;
            for (int k = 0; k < n; k++)
                if (m[k * n + k] > 0.0L) s += v[i * n + k] * m[k * n + k] * v[j * n + k];
            out[i * n + j] = (double)s;
        }
    free(m), free(v);
}

/* A+ against the long double reference to 2e-14 of ||A||_F (a bound the positive part's
 * Lipschitz constant of 1 in the Frobenius norm carries over from the reduction's and the
 * counts' backward errors, a few n eps ||A||_F; 4.3e-15 measured at most) on the matrices
 * of the bits' hash, sizes 1 to 40: uniform, shifted either way, graded as a guide's G
 * (the eigenvalues from the Sturm counts and Newton's steps, or the QL where the counts
 * cannot be trusted); returns the largest error found, in units of ||A||_F. */
static double positive_part_against_jacobi(int n, int kind, unsigned *state)
{
    const size_t nn = (size_t)n * (size_t)n;
    double *a = malloc(sizeof(double) * nn), *pos = malloc(sizeof(double) * nn), *ref = malloc(sizeof(double) * nn);
    double *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(n));
    int negative = -1;
    bits_matrix(n, kind, state, a);
    assert_int_equal(hk_symmetric_positive_part(n, a, pos, work, &negative), 1);
    jacobi_positive_part(n, a, ref);
    double norm = 0.0, worst = 0.0;
    for (size_t i = 0; i < nn; i++) norm += a[i] * a[i];
    norm = sqrt(norm);
    for (size_t i = 0; i < nn; i++) worst = fmax(worst, fabs(pos[i] - ref[i]));
    free(a), free(pos), free(ref), free(work);
    return worst / norm;
}

static void test_positive_part_against_long_double(void **state)
{
    (void)state;
    unsigned seed = 2028u;
    double worst = 0.0;
    for (int n = 1; n <= 40; n++)
        for (int kind = 0; kind < 4; kind++) {
            const double error = positive_part_against_jacobi(n, kind, &seed);
            assert_true(error <= 2e-14);
            worst = fmax(worst, error);
        }
    print_message("A+ against Jacobi in long double: at most %.2g of ||A||_F\n", worst);
}

/* The inverse iteration's start is copied from draws made once (2,048 of them) where
 * its n x k numbers fit, and drawn at the call beyond: both sides of that bound, and
 * sizes past 40, give main's bits (gplus16's, eigenvalues from Sturm counts and two
 * solves; 0xb889d50175d10193 with the QL's and three, e3cdd56, before the draws were made once),
 * on either path. FNV-1a as above; n = 45 .. 80, uniform and shifted either way (k from
 * about 20 to 40: 900 to 3,200 draws). */
static void test_positive_part_long_starts_bits_kept(void **state)
{
    (void)state;
    const int sizes[4] = {45, 64, 65, 80};
    double *a = malloc(sizeof(double) * 80 * 80), *out = malloc(sizeof(double) * 80 * 80);
    double *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(80));
    const int avx = hk_avx_paths_allow(1);
    int fit = 0, drawn = 0; /* starts within and beyond the draws made once */
    for (int path = avx ? 0 : 1; path < 2; path++) {
        hk_avx_paths_allow(path == 0);
        unsigned long long h = 1469598103934665603ULL;
        unsigned seed = 2027u;
        for (int s = 0; s < 4; s++)
            for (int kind = 0; kind < 3; kind++) {
                const int n = sizes[s];
                int negative = -1;
                bits_matrix(n, kind, &seed, a);
                assert_int_equal(hk_symmetric_positive_part(n, a, out, work, &negative), 1);
                const int k = 2 * negative < n ? negative : n - negative; /* no zero eigenvalue here */
                if (n * k <= 2048)
                    fit++;
                else
                    drawn++;
                const unsigned char *b = (const unsigned char *)out;
                for (size_t i = 0; i < sizeof(double) * (size_t)(n * n); i++) h = (h ^ b[i]) * 1099511628211ULL;
                h = (h ^ (unsigned)negative) * 1099511628211ULL;
            }
        assert_true(h == 0xc1669fd56e757d68ULL);
    }
    assert_true(fit > 0 && drawn > 0);
    hk_avx_paths_allow(1);
    free(a), free(out), free(work);
}

/* strand_dynamics.c skips the decomposition where a Cholesky factorisation of G
 * succeeds (hk_cholesky_factor, a pivot above 1e-13 of its diagonal entry) and takes
 * G for G+. Against the full path: positive definite, the full path finds no negative
 * eigenvalue and returns G bit for bit (A minus no mode); singular positive
 * semidefinite and barely indefinite (the eigenvalue nearest zero at -1e-14 and -1e-10
 * of the largest), where the factorisation may pass only if G+ is G to that order (the
 * shortcut's error is the eigenvalue it misses, within the factorisation's bound) and
 * must fail at -1e-10 (an indefinite matrix beyond round-off has a negative pivot). */
static void test_positive_part_cholesky_shortcut(void **state)
{
    (void)state;
    enum { N = 30 };
    double d[N], q[N * N], a[N * N], out[N * N], l[N * N], work[HK_POSITIVE_PART_WORK(N)];
    const double nearest[5] = {1e-3, 1e-8, 0.0, -1e-14, -1e-10};
    for (int c = 0; c < 5; c++) {
        /* graded as a guide's G, all positive, the smallest replaced */
        for (int k = 0; k < N; k++) d[k] = pow(10.0, -5.0 * k / (N - 1.0));
        d[N - 1] = nearest[c];
        known_spectrum(N, d, q, a);
        int negative = -1;
        assert_int_equal(hk_symmetric_positive_part(N, a, out, work, &negative), 1);
        const int passes = hk_cholesky_factor(N, a, 0.0, NULL, l);
        double diff = 0.0;
        for (int i = 0; i < N * N; i++) diff = fmax(diff, fabs(out[i] - a[i]));
        if (nearest[c] > 0.0) { /* positive definite: both ways G itself */
            assert_true(passes);
            assert_int_equal(negative, 0);
            assert_memory_equal(out, a, sizeof a);
        }
        if (nearest[c] <= 0.0) /* G+ is G to the eigenvalue left out (and round-off) */
            assert_true(diff <= fabs(nearest[c]) + 1e-14);
        if (nearest[c] == -1e-10) {
            assert_false(passes);
            assert_true(negative == 1 && diff >= 0.5e-10 / N);
        }
    }
}

/* hk_dot6_columns is, to the bit, the plain dot product x . column j summed left to right,
 * on either path (AVX's four columns a vector, the baseline's two, and each one's scalar
 * remainder): every count from 0 to 33 and two strides. */
static void test_dot6_columns_same_bits(void **state)
{
    (void)state;
    enum { MAX = 33, STRIDE = 40 };
    double yt[6 * STRIDE], x[6], out[MAX + 1];
    for (int k = 0; k < 6 * STRIDE; k++) yt[k] = 2.0 * hk_test_uniform() - 1.0;
    for (int k = 0; k < 6; k++) x[k] = 2.0 * hk_test_uniform() - 1.0;
    const int avx = hk_avx_paths_allow(1);
    for (int path = avx ? 0 : 1; path < 2; path++) {
        hk_avx_paths_allow(path == 0);
        for (size_t stride = MAX; stride <= STRIDE; stride += STRIDE - MAX)
            for (int count = 0; count <= MAX; count++) {
                out[count] = 7.0; /* not written */
                hk_dot6_columns(x, yt, stride, count, out);
                for (int j = 0; j < count; j++) {
                    double want = x[0] * yt[j];
                    for (size_t r = 1; r < 6; r++) want += x[r] * yt[r * stride + (size_t)j];
                    assert_memory_equal(&out[j], &want, sizeof want);
                }
                assert_true(out[count] == 7.0);
            }
    }
    hk_avx_paths_allow(1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_symmetric),
        cmocka_unit_test(test_cholesky_solves),
        cmocka_unit_test(test_known_spectrum),
        cmocka_unit_test(test_diagonal_and_zero),
        cmocka_unit_test(test_positive_part_random),
        cmocka_unit_test(test_positive_part_spectra),
        cmocka_unit_test(test_positive_part_paths_same_bits),
        cmocka_unit_test(test_positive_part_bits_kept),
        cmocka_unit_test(test_positive_part_long_starts_bits_kept),
        cmocka_unit_test(test_positive_part_against_long_double),
        cmocka_unit_test(test_positive_part_cholesky_shortcut),
        cmocka_unit_test(test_dot6_columns_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
