/* Symmetric eigen-decomposition against its definition: A v_j = w_j v_j and V^T V = I,
 * on random matrices of every size up to 40, diagonal and rank-deficient ones, and a
 * matrix with known eigenvalues (Q diag(d) Q^T with Q from a random orthogonalisation).
 * Cholesky solves of many right-hand sides at once against the residual A x - b. */
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

static void test_known_spectrum(void **state)
{
    (void)state;
    enum { N = 12 };
    double q[N * N], a[N * N], v[N * N], w[N], e[N];
    /* Gram-Schmidt of random columns */
    for (int i = 0; i < N * N; i++) q[i] = 2.0 * hk_test_uniform() - 1.0;
    for (int j = 0; j < N; j++) {
        for (int k = 0; k < j; k++) {
            double d = 0.0;
            for (int i = 0; i < N; i++) d += q[i * N + j] * q[i * N + k];
            for (int i = 0; i < N; i++) q[i * N + j] -= d * q[i * N + k];
        }
        double s = 0.0;
        for (int i = 0; i < N; i++) s += q[i * N + j] * q[i * N + j];
        for (int i = 0; i < N; i++) q[i * N + j] /= sqrt(s);
    }
    /* eigenvalues with a repeated one, a zero and negatives */
    const double d[N] = {-3, -1e-9, 0, 0, 1e-6, 1, 1, 1, 2.5, 7, 1e3, -1e3};
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double s = 0.0;
            for (int k = 0; k < N; k++) s += q[i * N + k] * d[k] * q[j * N + k];
            a[i * N + j] = s;
        }
    for (int i = 0; i < N; i++)
        for (int j = 0; j < i; j++) a[i * N + j] = a[j * N + i]; /* exactly symmetric */
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


static void test_cholesky_columns(void **state)
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
        hk_cholesky_solve_columns(n, l, x, count);
        for (int r = 0; r < count; r++)
            for (int i = 0; i < n; i++) {
                double ax = 0.0;
                for (int k = 0; k < n; k++) ax += a[i * n + k] * x[k * count + r];
                hk_assert_near(ax, b[i * count + r], 1e-12 * n * n);
            }
        free(a), free(l), free(b), free(x), free(m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_symmetric),
        cmocka_unit_test(test_cholesky_columns),
        cmocka_unit_test(test_known_spectrum),
        cmocka_unit_test(test_diagonal_and_zero),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
