/* Dense solve of the thin-plate interpolation system of Turk & O'Brien (2002, §3):
 * [A P; P' 0][w; p] = [h; 0] with A_ij = |c_i - c_j|^3 and a linear polynomial.
 *
 * The system is symmetric but indefinite. Rather than a pivoted LU or LDL', we use
 * that r^3 is conditionally positive definite of order 2 (Micchelli 1986; Wendland,
 * Scattered Data Approximation, Thm 8.16): w' A w > 0 for every w != 0 with P' w = 0.
 * With P = Q [R; 0] (Householder QR) and Q = [Q1 Q2], the constraint P' w = 0 is
 * w = Q2 z, and z solves the symmetric positive definite system
 *   (Q2' A Q2) z = Q2' h,
 * of size n - 4, by Cholesky: half the work of LU, no pivoting, and a failed pivot
 * means the constraints really are (numerically) degenerate. Then R p = Q1'(h - A w).
 * This is the null-space method for saddle-point systems (Benzi, Golub & Liesen,
 * Acta Numerica 2005, §6). Every parallel loop gives each entry to one thread with a
 * fixed order of operations, so the bytes do not depend on the thread count. */
#include <math.h>
#include <string.h>

#include "follicle_internal.h"
#include "core/linalg.h"

typedef struct Reflector {
    double *v; /* n entries, zero before the reflector's index */
    double tau;
} Reflector;

/* x <- (I - tau v v') x */
static void reflect(const Reflector *r, int n, double *x)
{
    const double s = r->tau * hk_dot(r->v, x, n);
    for (int i = 0; i < n; i++) x[i] -= s * r->v[i];
}

/* Householder QR of P = [1 x y z] (n x 4, here as 4 columns of n): fills the
 * reflectors and R (upper triangular 4 x 4). Returns 0 when a column is (nearly)
 * dependent on the others: all centres in one plane, on one line or at one point. */
static int householder_qr(int n, double *cols[4], Reflector h[4], double r[4][4])
{
    for (int k = 0; k < 4; k++) {
        double *x = cols[k];
        const double col_norm = sqrt(hk_dot(x, x, n)); /* before this step's reflection */
        double norm = sqrt(hk_dot(x + k, x + k, n - k));
        if (!(norm > 1e-9 * (col_norm + 1e-300)) || !(norm > 1e-12 * sqrt((double)n))) return 0;
        const double alpha = x[k] > 0.0 ? -norm : norm;
        memset(h[k].v, 0, sizeof(double) * (size_t)n);
        for (int i = k; i < n; i++) h[k].v[i] = x[i];
        h[k].v[k] -= alpha;
        const double vv = hk_dot(h[k].v, h[k].v, n);
        h[k].tau = vv > 0.0 ? 2.0 / vv : 0.0;
        for (int j = k; j < 4; j++) reflect(&h[k], n, cols[j]);
        for (int j = 0; j < 4; j++) r[k][j] = j >= k ? cols[j][k] : 0.0;
    }
    return 1;
}

/* a <- H a H for the symmetric n x n matrix a and H = I - tau v v':
 * H a H = a - v q' - q v' with u = a v, q = tau u - (tau^2 v'u / 2) v. */
static void reflect_both_sides(const Reflector *h, int n, double *a, double *u, int threads)
{
    const size_t sn = (size_t)n;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int i = 0; i < n; i++) u[i] = hk_dot(a + (size_t)i * sn, h->v, n);
    const double k = 0.5 * h->tau * h->tau * hk_dot(h->v, u, n);
    for (int i = 0; i < n; i++) u[i] = h->tau * u[i] - k * h->v[i]; /* u becomes q */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int i = 0; i < n; i++) {
        double *row = a + (size_t)i * sn;
        const double vi = h->v[i], qi = u[i];
        for (int j = 0; j < n; j++) row[j] -= vi * u[j] + qi * h->v[j];
    }
}

/* In-place Cholesky of the m x m row-major matrix a (lower triangle read and
 * overwritten by L). Left-looking in panels of PANEL columns: a row below the panel is
 * read from memory once per panel instead of once per column, and the rows are shared
 * among threads. Returns the column that failed, or -1 on success. */
enum { PANEL = 32 };

static int cholesky_in_place(int m, double *a, int threads)
{
    const size_t sm = (size_t)m;
    for (int jb = 0; jb < m; jb += PANEL) {
        const int je = jb + PANEL < m ? jb + PANEL : m;
        /* the panel's diagonal block, column by column */
        for (int j = jb; j < je; j++) {
            double *lj = a + (size_t)j * sm;
            const double d = lj[j] - hk_dot(lj, lj, j);
            /* a pivot this small against the original diagonal: the constraints are
             * degenerate to working precision */
            if (!(d > 1e-14 * fabs(lj[j])) || !isfinite(d)) return j;
            lj[j] = sqrt(d);
            for (int i = j + 1; i < je; i++) {
                double *li = a + (size_t)i * sm;
                li[j] = (li[j] - hk_dot(li, lj, j)) / lj[j];
            }
        }
        /* the rows below the panel */
        const long work = (long)(m - je) * (long)je;
#pragma omp parallel for schedule(static) num_threads(threads) if (work > 20000)
        for (int i = je; i < m; i++) {
            double *li = a + (size_t)i * sm;
            double s[PANEL];
            for (int c = 0; c < je - jb; c++) s[c] = li[jb + c] - hk_dot(li, a + (size_t)(jb + c) * sm, jb);
            for (int c = 0; c < je - jb; c++) {
                const double *lc = a + (size_t)(jb + c) * sm;
                double v = s[c];
                for (int k = 0; k < c; k++) v -= li[jb + k] * lc[jb + k];
                li[jb + c] = v / lc[jb + c];
            }
        }
    }
    return -1;
}

/* L L' x = b in place. */
static void cholesky_solve(int m, const double *l, double *x)
{
    const size_t sm = (size_t)m;
    for (int i = 0; i < m; i++) x[i] = (x[i] - hk_dot(l + (size_t)i * sm, x, i)) / l[(size_t)i * sm + (size_t)i];
    for (int i = m - 1; i >= 0; i--) {
        double v = x[i];
        for (int k = i + 1; k < m; k++) v -= l[(size_t)k * sm + (size_t)i] * x[k];
        x[i] = v / l[(size_t)i * sm + (size_t)i];
    }
}

hk_Status hk_rbf_solve(int n, const hk_Vec3 *c, const double *h, int threads, double *w, double p[4], hk_Error *err)
{
    if (n < 5) return hk_error_set(err, HK_ERR_INVALID, "the implicit surface needs at least 5 constraints, got %d", n);
    if (threads <= 0) threads = 1;
    const size_t sn = (size_t)n;
    const int m = n - 4;
    /* the matrix and 4 columns + 4 reflectors + 3 vectors of work */
    if (sn > HK_MAX_ALLOCATION / sizeof(double) / sn)
        return hk_error_set(err, HK_ERR_NOMEM, "interpolation system of %d constraints is too large", n);
    double *a = hk_alloc_array(sn * sn, sizeof(double), err);
    double *work = hk_alloc_array(11 * sn, sizeof(double), err);
    double *top = hk_alloc_array(4 * sn, sizeof(double), err);
    if (!a || !work || !top) {
        hk_free(a), hk_free(work), hk_free(top);
        return HK_ERR_NOMEM;
    }
    double *cols[4] = {work, work + sn, work + 2 * sn, work + 3 * sn};
    Reflector refl[4] = {{work + 4 * sn, 0}, {work + 5 * sn, 0}, {work + 6 * sn, 0}, {work + 7 * sn, 0}};
    double *u = work + 8 * sn, *rhs = work + 9 * sn, *z = work + 10 * sn;
    hk_Status st = HK_OK;

    for (int i = 0; i < n; i++) {
        cols[0][i] = 1.0;
        cols[1][i] = c[i].x;
        cols[2][i] = c[i].y;
        cols[3][i] = c[i].z;
    }
    double r[4][4];
    if (!householder_qr(n, cols, refl, r)) {
        st = hk_error_set(err, HK_ERR_INVALID,
                          "the implicit surface's constraints lie in one plane (or on a line): a linear "
                          "polynomial is not determined");
        goto done;
    }

#pragma omp parallel for schedule(static) num_threads(threads)
    for (int i = 0; i < n; i++) {
        double *row = a + (size_t)i * sn;
        for (int j = 0; j < n; j++) {
            const double r2 = hk_v3_norm2(hk_v3_sub(c[i], c[j]));
            row[j] = r2 * sqrt(r2);
        }
    }
    for (int k = 0; k < 4; k++) reflect_both_sides(&refl[k], n, a, u, threads);
    memcpy(rhs, h, sizeof(double) * sn);
    for (int k = 0; k < 4; k++) reflect(&refl[k], n, rhs);

    /* Keep the first 4 rows (they give p), then pack the trailing block Q2' A Q2 at
     * the start of the buffer with stride m. Forward copies never overwrite a row
     * that is still to be read: i m <= (i + 4) n + 4. */
    memcpy(top, a, sizeof(double) * 4 * sn);
    for (int i = 0; i < m; i++)
        memmove(a + (size_t)i * (size_t)m, a + (size_t)(i + 4) * sn + 4, sizeof(double) * (size_t)m);
    const int failed = cholesky_in_place(m, a, threads);
    if (failed >= 0) {
        st = hk_error_set(err, HK_ERR_NUMERIC,
                          "the implicit surface's interpolation system is singular to working precision "
                          "(pivot %d of %d): constraints too close together, or a normal offset reaching "
                          "another part of the surface",
                          failed + 1, m);
        goto done;
    }
    memcpy(z, rhs + 4, sizeof(double) * (size_t)m);
    cholesky_solve(m, a, z);

    /* w = Q [0; z] */
    for (int i = 0; i < 4; i++) w[i] = 0.0;
    memcpy(w + 4, z, sizeof(double) * (size_t)m);
    for (int k = 3; k >= 0; k--) reflect(&refl[k], n, w);
    /* R p = (Q' h)[0:4] - (Q' A Q)[0:4, 4:] z */
    double b[4];
    for (int k = 0; k < 4; k++) b[k] = rhs[k] - hk_dot(top + (size_t)k * sn + 4, z, m);
    for (int k = 3; k >= 0; k--) {
        double v = b[k];
        for (int j = k + 1; j < 4; j++) v -= r[k][j] * p[j];
        p[k] = v / r[k][k];
    }
    for (int i = 0; i < n; i++)
        if (!isfinite(w[i])) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "the implicit surface's weights are not finite");
            goto done;
        }
    for (int k = 0; k < 4; k++)
        if (!isfinite(p[k])) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "the implicit surface's polynomial is not finite");
            goto done;
        }
done:
    hk_free(a), hk_free(work), hk_free(top);
    return st;
}
