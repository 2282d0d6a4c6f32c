/* Dense Cholesky factorisation for the Newton solvers (n up to a few hundred). */
#include "hairkit/linalg.h"

#include <math.h>
#include <stddef.h>

/* Dot product with four partial sums: the compiler may not reorder floating-point
 * sums on its own, and a fixed order keeps results identical on every machine. */
static double dot(const double *a, const double *b, int n)
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

int hk_cholesky_factor(int n, const double *a, double shift, const double *d, double *l)
{
    const size_t sn = (size_t)n;
    for (int j = 0; j < n; j++) {
        const double *lj = l + (size_t)j * sn;
        double diag = a[(size_t)j * sn + (size_t)j] + shift * (d ? d[j] : 1.0) - dot(lj, lj, j);
        /* A pivot this small relative to the original diagonal means the matrix is
         * indefinite or singular to working precision. */
        const double ref = fabs(a[(size_t)j * sn + (size_t)j]) + fabs(shift * (d ? d[j] : 1.0));
        if (!(diag > 1e-13 * ref) || !isfinite(diag)) return 0;
        const double ljj = sqrt(diag);
        l[(size_t)j * sn + (size_t)j] = ljj;
        for (int i = j + 1; i < n; i++) {
            double *li = l + (size_t)i * sn;
            li[j] = (a[(size_t)i * sn + (size_t)j] - dot(li, lj, j)) / ljj;
        }
    }
    return 1;
}

void hk_cholesky_solve(int n, const double *l, double *x)
{
    const size_t sn = (size_t)n;
    for (int i = 0; i < n; i++) {
        x[i] = (x[i] - dot(l + (size_t)i * sn, x, i)) / l[(size_t)i * sn + (size_t)i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double v = x[i];
        for (int k = i + 1; k < n; k++) v -= l[(size_t)k * sn + (size_t)i] * x[k];
        x[i] = v / l[(size_t)i * sn + (size_t)i];
    }
}
