/* Small dense linear algebra for the solvers (row-major n x n matrices). Internal to
 * hairkit (not installed, not exported): included as "core/linalg.h". */
#ifndef HK_CORE_LINALG_H
#define HK_CORE_LINALG_H

#include <stddef.h>

/* sum a[k] b[k], k < n, with four partial sums in a fixed order (the same bytes on
 * every machine and thread count). */
double hk_dot(const double *a, const double *b, int n);

/* *ab = hk_dot(a, b, n) and *ac = hk_dot(a, c, n), the same bits, in one pass over a. */
void hk_dot2(const double *a, const double *b, const double *c, int n, double *ab, double *ac);

/* out[j] = x[0] yt[j] + x[1] yt[stride + j] + ... + x[5] yt[5 stride + j] for j < count,
 * summed left to right as a plain 6-term dot product of x with column j of the 6 x count
 * matrix yt (row stride `stride`): the same bits as that dot product, for several j at
 * once (the loop over j vectorises). One row of X^T Y with Y stored transposed. */
void hk_dot6_columns(const double x[6], const double *yt, size_t stride, int count, double *out);

/* The AVX paths of the loops that GCC vectorises two doubles wide in the baseline build
 * (-O2, no -march) and four wide with target("avx"): hk_dot6_columns, the dense solve's
 * factorisation (hk_upper_cholesky), the contact points' Jacobian rows, G+
 * (hk_symmetric_positive_part, its kernels' four-wide Quads). Each element's
 * operations are the same and in the same order (no FMA: target "avx" only), so either
 * path gives the same bits; taken at run time where the CPU has AVX, unless a test
 * turned them off (hk_avx_paths_allow(0)) to compare the baseline's. */
extern int hk_avx_paths_allowed;
static inline int hk_avx_path(void) { return hk_avx_paths_allowed && __builtin_cpu_supports("avx"); }
/* Sets whether the paths above may be taken; returns whether the CPU has AVX. Not
 * thread-safe: for the tests that compare the two paths bit for bit. */
int hk_avx_paths_allow(int allow);

/* Cholesky factor of the symmetric matrix a + shift * diag(d) (d may be NULL: identity)
 * into the lower triangle of l (n x n; the strict upper triangle is left alone). Only
 * the lower triangle of a is read, each entry before l's is written there: l may be a
 * (factored in place).
 * Returns 1 on success, 0 if the matrix is not numerically positive definite. */
int hk_cholesky_factor(int n, const double *a, double shift, const double *d, double *l);

/* Solves L L^T x = b in place (x holds b on entry) with the factor from above. */
void hk_cholesky_solve(int n, const double *l, double *x);

/* Eigen-decomposition of the symmetric matrix a (n x n, row-major): eigenvalues w (n,
 * unordered) and eigenvectors as the columns of v (n x n); e is n doubles of work.
 * Householder tridiagonalisation and implicit QL (tred2/tql2). Returns 0 if the
 * iteration did not converge. */
int hk_symmetric_eigen(int n, const double *a, double *w, double *v, double *e);

/* The positive part A+ = V max(L, 0) V^T of the symmetric a (n x n, row-major) into out
 * (n x n, symmetric to the bit), *negative the number of negative eigenvalues. The same
 * matrix as from hk_symmetric_eigen's decomposition to round-off, at about half the cost:
 * eigenvectors only for the fewer of the negative and positive eigenvalues. work holds
 * HK_POSITIVE_PART_WORK(n) doubles. Returns 0 if the eigenvalue iteration did not
 * converge (out is then not written). */
#define HK_POSITIVE_PART_WORK(n)                                                                                       \
    ((size_t)(n) * (size_t)(n) + 5 * (size_t)(n) + ((size_t)(n) / 2 + 1) * (7 * (size_t)(n) + 6))
int hk_symmetric_positive_part(int n, const double *a, double *out, double *work, int *negative);

#endif /* HK_CORE_LINALG_H */
