/* The linear system of a dynamics step, (M + diag(extra)) x = rhs, solved two ways
 * (docs/dynamics.md):
 *
 * Dense: M_ab = xi_a . Y_b for a in an earlier element than b, where Y_b, the momentum
 * of the motion field of coordinate b, is its own element's coupling plus the inertia
 * of everything beyond acting on xi_b; within one element M_ab = mass_ab + xi_a . S xi_b.
 * Then Cholesky: O(N^2) to assemble, O(N^3) to factor (paper 000 §3.4 uses conjugate
 * gradients on the same dense matrix), as A = U U^T with U upper triangular (the
 * unknowns in reverse order): the factor the contacts' solve needs (a point's rows of
 * U^-1 J^T stop at its element), so that with the contacts a strand's matrix is factored
 * once a step instead of twice (L L^T for the step, U U^T for the contacts: 7.6 % of a
 * frame's instructions on examples/guides200 shaking).
 *
 * Linear: the strand is a chain whose element P moves with the screw A_P of its start
 * frame and its own coordinates x_P. Eliminating from the tip, the rows of everything
 * beyond node P+1 leave its momentum affine in the node's screw, h = IA A + z (an
 * articulated-body inertia, Featherstone 1983). Element P's rows are then
 *     K_P x_P = rhs_P - xi_P^T z - C_P A_P,
 *     K_P = mass_P + diag(extra_P) + xi_P^T IA xi_P,   C_P = coupling_P + xi_P^T IA,
 * and IA <- inertia_P + IA - C_P^T K_P^-1 C_P, z <- z + C_P^T K_P^-1 (rhs_P - xi_P^T z).
 * A forward sweep from the clamped root (A_0 = 0) recovers x_P and A_{P+1} = A_P +
 * xi_P x_P. 3x3 solves and 6x6 products per element: O(N). */
#include <math.h>
#include <string.h>

#include "dynamics_internal.h"
#include "core/linalg.h"
#include "core/simd_lanes.h" /* Quad, Pair (four doubles on the paths taken with wide), add_multiple */

static double dot6(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
}

static void mul66(double m[6][6], const double *x, double *out)
{
    for (int i = 0; i < 6; i++) out[i] = dot6(m[i], x);
}

/* mul66 with m given by its columns (mt[j][i] = m[i][j]), and c + that product into sum:
 * the six rows side by side, each entry's products and sums in dot6's order (the same
 * bits), four and two lanes on the AVX path (wide), three pairs else. */
static inline __attribute__((always_inline)) void mul66_columns(double mt[6][6], const double *x, double *out,
                                                                const double *c, double *sum, int wide)
{
    if (wide) {
        Quad lo, q;
        Pair hi, d;
        memcpy(&lo, mt[0], sizeof lo), memcpy(&hi, mt[0] + 4, sizeof hi);
        lo *= x[0], hi *= x[0];
#pragma GCC unroll 5
        for (int j = 1; j < 6; j++) {
            memcpy(&q, mt[j], sizeof q), memcpy(&d, mt[j] + 4, sizeof d);
            lo += q * x[j], hi += d * x[j];
        }
        memcpy(out, &lo, sizeof lo), memcpy(out + 4, &hi, sizeof hi);
        memcpy(&q, c, sizeof q), memcpy(&d, c + 4, sizeof d);
        q += lo, d += hi;
        memcpy(sum, &q, sizeof q), memcpy(sum + 4, &d, sizeof d);
        return;
    }
    Pair r[3], e;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) memcpy(&r[i], mt[0] + 2 * i, sizeof r[i]), r[i] *= x[0];
#pragma GCC unroll 5
    for (int j = 1; j < 6; j++)
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++) memcpy(&e, mt[j] + 2 * i, sizeof e), r[i] += e * x[j];
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
        memcpy(out + 2 * i, &r[i], sizeof r[i]);
        memcpy(&e, c + 2 * i, sizeof e), e += r[i];
        memcpy(sum + 2 * i, &e, sizeof e);
    }
}

/* The lower triangle and diagonal of the effective mass matrix, by rows: the
 * factorisation reads no more (hk_upper_cholesky). Mirroring each row into its column,
 * strided stores over the whole matrix, was a sixth of the assembly's instructions
 * (examples/guides200 shaking). */
static inline __attribute__((always_inline)) void assemble_lower(int n, const hk_ElementTerms *terms, double *mass,
                                                                 double *scratch, int wide)
{
    const size_t dim = (size_t)3 * (size_t)n;
    /* The screws xi_a transposed (6 rows of 3n), so that row b's products xi_a . Y_b
     * are taken for every earlier a at once (hk_dot6_columns: the same bits as dot6). */
    double *xt = scratch;
    for (int p = 0; p < n; p++)
#pragma GCC unroll 3
        for (int b = 0; b < 3; b++)
#pragma GCC unroll 6
            for (int r = 0; r < 6; r++) xt[(size_t)r * dim + (size_t)(3 * p + b)] = terms[p].xi[b][r];
    /* the inertia of everything beyond, by columns (beyond_t[j][i] = beyond[i][j]) for
     * mul66_columns */
    double beyond_t[6][6];
    memset(beyond_t, 0, sizeof beyond_t);
    for (int p = n - 1; p >= 0; p--) {
        const hk_ElementTerms *t = &terms[p];
        for (int b = 0; b < 3; b++) {
            const size_t ib = (size_t)(3 * p + b);
            double sxi[6], y[6];
            mul66_columns(beyond_t, t->xi[b], sxi, t->coupling[b], y, wide);
            double *row = mass + ib * dim;
            hk_dot6_columns(y, xt, dim, 3 * p, row);
            for (int a = 0; a <= b; a++) row[3 * p + a] = t->mass[a][b] + dot6(t->xi[a], sxi);
        }
        for (int j = 0; j < 6; j++)
            for (int i = 0; i < 6; i++) beyond_t[j][i] += t->inertia[i][j];
    }
}

void hk_terms_assemble(int n, const hk_ElementTerms *terms, double *mass, double *scratch)
{
    const size_t dim = (size_t)3 * (size_t)n;
    assemble_lower(n, terms, mass, scratch, 0);
    for (size_t i = 0; i < dim; i++) /* mirrored: exactly symmetric */
        for (size_t j = 0; j < i; j++) mass[j * dim + i] = mass[i * dim + j];
}

/* sum over k < n of a[-k] b[-k]: hk_cholesky_factor's dot product (core/linalg.c:
 * four partial sums s0..s3, s_r taking the terms k = r mod 4, the remainder in s0, then
 * (s0 + s1) + (s2 + s3)) read from the ends of two rows backwards, so that
 * hk_upper_cholesky takes the same operations in the same order as the factorisation of
 * the reversed matrix. The terms of s1 and s0 lie side by side in memory, s1's first:
 * one vector (s1, s0) takes them without a shuffle, as (s3, s2) those of s3 and s2. */
static inline __attribute__((always_inline)) double dot4_down(const double *a, const double *b, int n)
{
    Pair s10 = {0.0, 0.0}, s32 = s10;
    int k = 0;
    for (; k + 4 <= n; k += 4) {
        Pair a10, b10, a32, b32;
        memcpy(&a10, a - k - 1, sizeof a10), memcpy(&b10, b - k - 1, sizeof b10);
        memcpy(&a32, a - k - 3, sizeof a32), memcpy(&b32, b - k - 3, sizeof b32);
        s10 += a10 * b10;
        s32 += a32 * b32;
    }
    double s0 = s10[1];
    const int rest = n - k; /* at most three terms, written out (see dot4_down_pair) */
    if (rest > 0) s0 += a[-k] * b[-k];
    if (rest > 1) s0 += a[-k - 1] * b[-k - 1];
    if (rest > 2) s0 += a[-k - 2] * b[-k - 2];
    return (s0 + s10[0]) + (s32[1] + s32[0]);
}

/* dot4_down(a, b, n) and dot4_down(c, b, n) at once, b's loads shared: each product
 * takes the same operations in the same order as alone (the same bits). Four terms
 * a[-k-3..-k] lie in memory as the partial sums s3, s2, s1, s0 take them: with wide (the
 * AVX path) one vector of four holds (s3, s2, s1, s0), else two of two (GCC lowers a
 * vector of four to worse than two pairs on SSE2: 45.6 against 37.2 million
 * instructions). The remainder, at most three terms, is written out: as a loop its
 * counter and branch cost as much as its products (hk_upper_cholesky's rows of 3N = 30
 * leave a remainder in three of four rows). */
static inline __attribute__((always_inline)) void dot4_down_pair(const double *a, const double *c, const double *b,
                                                                 int n, double *ab, double *cb, int wide)
{
    double s[4] = {0.0, 0.0, 0.0, 0.0}, t[4] = {0.0, 0.0, 0.0, 0.0}; /* (s3, s2, s1, s0) */
    int k = 0;
    if (wide) {
        Quad s4 = {0.0, 0.0, 0.0, 0.0}, t4 = s4;
        for (; k + 4 <= n; k += 4) {
            Quad a4, c4, b4;
            memcpy(&b4, b - k - 3, sizeof b4);
            memcpy(&a4, a - k - 3, sizeof a4), memcpy(&c4, c - k - 3, sizeof c4);
            s4 += a4 * b4;
            t4 += c4 * b4;
        }
        memcpy(s, &s4, sizeof s), memcpy(t, &t4, sizeof t);
    } else {
        Pair s10 = {0.0, 0.0}, s32 = s10, t10 = s10, t32 = s10;
        for (; k + 4 <= n; k += 4) {
            Pair a10, c10, b10, a32, c32, b32;
            memcpy(&b10, b - k - 1, sizeof b10), memcpy(&b32, b - k - 3, sizeof b32);
            memcpy(&a10, a - k - 1, sizeof a10), memcpy(&a32, a - k - 3, sizeof a32);
            memcpy(&c10, c - k - 1, sizeof c10), memcpy(&c32, c - k - 3, sizeof c32);
            s10 += a10 * b10, s32 += a32 * b32;
            t10 += c10 * b10, t32 += c32 * b32;
        }
        memcpy(s, &s32, sizeof s32), memcpy(s + 2, &s10, sizeof s10);
        memcpy(t, &t32, sizeof t32), memcpy(t + 2, &t10, sizeof t10);
    }
    double s0 = s[3], t0 = t[3];
    const int rest = n - k;
    if (rest > 0) s0 += a[-k] * b[-k], t0 += c[-k] * b[-k];
    if (rest > 1) s0 += a[-k - 1] * b[-k - 1], t0 += c[-k - 1] * b[-k - 1];
    if (rest > 2) s0 += a[-k - 2] * b[-k - 2], t0 += c[-k - 2] * b[-k - 2];
    *ab = (s0 + s[2]) + (s[1] + s[0]);
    *cb = (t0 + t[2]) + (t[1] + t[0]);
}

static inline __attribute__((always_inline)) int upper_cholesky(int n, const double *a, const double *extra, double *u,
                                                                int wide)
{
    const size_t sn = (size_t)n;
    /* Row j of U from column j on is row n - 1 - j of the reversed matrix's L read
     * backwards: its dot products run from the rows' ends. a's lower triangle is read,
     * along row j (a[j][i] = a[i][j]). U^T goes to u's strict lower part as well (row j
     * there is column j of U, written along the row as column j is found): the contacts'
     * solve takes U by columns (hk_dynamics_reversed_factor), and the factorisation reads
     * only U's upper part. The reciprocals of U's diagonal follow the n x n block
     * (hk_upper_cholesky). */
    double *inverse = u + sn * sn;
    for (int j = n - 1; j >= 0; j--) {
        const size_t jj = (size_t)j * sn + (size_t)j;
        const double *uj = u + (size_t)j * sn + (sn - 1), *aj = a + (size_t)j * sn;
        const int len = n - 1 - j;
        const double diag = a[jj] + extra[j] - dot4_down(uj, uj, len);
        /* as hk_cholesky_factor: a pivot this small against the diagonal means the
         * matrix is indefinite or singular to working precision */
        const double ref = fabs(a[jj]) + fabs(extra[j]);
        if (!(diag > 1e-13 * ref) || !isfinite(diag)) return 0;
        const double ujj = sqrt(diag);
        u[jj] = ujj;
        inverse[j] = 1.0 / ujj;
        int i = j - 1;
        for (; i >= 1; i -= 2) { /* rows i and i - 1 share uj's loads */
            const double *ui = u + (size_t)i * sn + (sn - 1);
            double di, dk;
            dot4_down_pair(ui, ui - sn, uj, len, &di, &dk, wide);
            /* both entries' subtraction and division in two lanes: one division
             * instruction for two, each lane's the same IEEE operation */
            Pair num;
            memcpy(&num, aj + i - 1, sizeof num);
            num -= (Pair){dk, di};
            const Pair q = num / ujj;
            u[(size_t)i * sn + (size_t)j] = q[1];
            u[(size_t)(i - 1) * sn + (size_t)j] = q[0];
            memcpy(u + (size_t)j * sn + (size_t)(i - 1), &q, sizeof q); /* U^T, after aj's read */
        }
        if (i == 0) u[j] = u[(size_t)j * sn] = (aj[0] - dot4_down(u + (sn - 1), uj, len)) / ujj;
    }
    return 1;
}

/* The AVX path: dot4_down_pair's vector of four in one register (hk_upper_cholesky
 * 37.2 -> 29.9 million instructions in the head driver's 8 frames); no FMA (target
 * "avx" only), so the bits are the baseline's. Chosen at run time (core/linalg.h,
 * hk_avx_path): the build stays portable (no -march). */
__attribute__((target("avx"))) static int upper_cholesky_avx(int n, const double *a, const double *extra, double *u)
{
    return upper_cholesky(n, a, extra, u, 1);
}

static int upper_cholesky_sse2(int n, const double *a, const double *extra, double *u)
{
    return upper_cholesky(n, a, extra, u, 0);
}

int hk_upper_cholesky(int n, const double *a, const double *extra, double *u)
{
    if (hk_avx_path()) return upper_cholesky_avx(n, a, extra, u);
    return upper_cholesky_sse2(n, a, extra, u);
}

/* U^T x = y in place by the rows of U: once x_i is known it leaves the rows below, all
 * of them side by side, each x_k taking its terms in the order of i as a sum along U's
 * column k would (less U_ik x_i as plus U_ik (-x_i): the same bits, negation is exact).
 * Each unknown waits for the last: x_i times 1 / U_ii (the factor's reciprocals) puts a
 * multiplication (4 cycles) on that chain where a division took 13 and more; the
 * product differs from the quotient by rounding. Two unknowns a pass (add_multiple2,
 * the same bits as a pass each): a pass's vector loads of x read what the last pass's
 * stores wrote at other offsets, which the CPU cannot forward, so each pass waited for
 * the last one's stores (3N = 30, a solve timed alone: 365 -> 260 ns with the
 * reciprocals, 180 ns paired; docs/dynamics.md, "Speed", 7 December 2026, evening). */
static inline __attribute__((always_inline)) void upper_transpose_solve(int n, const double *u, double *x, int wide)
{
    const size_t sn = (size_t)n;
    const double *inverse = u + sn * sn;
    int i = 0;
    for (; i + 1 < n; i += 2) { /* x_i, then x_i+1 less its term of x_i */
        const double *row = u + (size_t)i * sn, *next = row + sn;
        const double xi = x[i] * inverse[i];
        const double xj = (x[i + 1] + -xi * row[i + 1]) * inverse[i + 1];
        x[i] = xi, x[i + 1] = xj;
        add_multiple2(x + i + 2, -xi, row + i + 2, -xj, next + i + 2, n - 2 - i, wide);
    }
    if (i < n) x[i] *= inverse[i];
}

/* U U^T x = b: U y = b from the last unknown, then U^T x = y. The first half by U's
 * columns (U^T's rows, below the diagonal), two unknowns a pass, as upper_transpose_solve
 * and the contacts' back substitution (contact_rows.c): once x_i is known, U_ki x_i
 * leaves every x_k above it side by side. By rows, a dot product along each row (its
 * sums in another order: other bits), each unknown waited for the last one's division
 * and its store: 3N = 30 timed alone, the whole solve 740 -> 545 ns with the
 * reciprocals, 365 ns by columns. */
static inline __attribute__((always_inline)) void upper_solve(int n, const double *u, double *x, int wide)
{
    const size_t sn = (size_t)n;
    const double *inverse = u + sn * sn;
    int i = n - 1;
    for (; i >= 1; i -= 2) {                                  /* x_i, then x_i-1 less its term of x_i */
        const double *ci = u + (size_t)i * sn, *cj = ci - sn; /* ci[k] = U_ki for k < i */
        const double xi = x[i] * inverse[i];
        const double xj = (x[i - 1] + -xi * ci[i - 1]) * inverse[i - 1];
        x[i] = xi, x[i - 1] = xj;
        add_multiple2(x, -xi, ci, -xj, cj, i - 1, wide);
    }
    if (i == 0) x[0] *= inverse[0];
    upper_transpose_solve(n, u, x, wide);
}

void hk_upper_solve(int n, const double *u, double *x) { upper_solve(n, u, x, 0); }

/* Four entries a vector where the CPU has AVX (the same bits: core/linalg.h). */
__attribute__((target("avx"))) static void upper_transpose_solve_avx(int n, const double *u, double *x)
{
    upper_transpose_solve(n, u, x, 1);
}

static void upper_transpose_solve_sse2(int n, const double *u, double *x) { upper_transpose_solve(n, u, x, 0); }

void hk_upper_transpose_solve(int n, const double *u, double *x)
{
    if (hk_avx_path())
        upper_transpose_solve_avx(n, u, x);
    else
        upper_transpose_solve_sse2(n, u, x);
}

static inline __attribute__((always_inline)) int terms_solve_dense(int n, const hk_ElementTerms *terms,
                                                                   const double *extra, const double *geo, double scale,
                                                                   const double *rhs, double *x, double *work, int wide)
{
    const int dim = 3 * n;
    const size_t count = (size_t)dim * (size_t)dim;
    double *mass = work, *factor = work + count; /* U, then its diagonal's reciprocals */
    assemble_lower(n, terms, mass, work + 2 * count + (size_t)dim, wide);
    if (geo) /* the lower triangle, which the factorisation reads */
        for (int i = 0; i < dim; i++)
            add_multiple(mass + (size_t)i * (size_t)dim, scale, geo + (size_t)i * (size_t)dim, i + 1, wide);
    if (!upper_cholesky(dim, mass, extra, factor, wide)) return 0;
    memcpy(x, rhs, (size_t)dim * sizeof(double));
    upper_solve(dim, factor, x, wide);
    return 1;
}

/* The whole dense solve on AVX where the CPU has it (its vectorised loops four wide,
 * the same bits: core/linalg.h, hk_avx_path). */
__attribute__((target("avx"))) static int terms_solve_dense_avx(int n, const hk_ElementTerms *terms,
                                                                const double *extra, const double *geo, double scale,
                                                                const double *rhs, double *x, double *work)
{
    return terms_solve_dense(n, terms, extra, geo, scale, rhs, x, work, 1);
}

static int terms_solve_dense_sse2(int n, const hk_ElementTerms *terms, const double *extra, const double *geo,
                                  double scale, const double *rhs, double *x, double *work)
{
    return terms_solve_dense(n, terms, extra, geo, scale, rhs, x, work, 0);
}

int hk_terms_solve_dense(int n, const hk_ElementTerms *terms, const double *extra, const double *geo, double scale,
                         const double *rhs, double *x, double *work)
{
    if (hk_avx_path()) return terms_solve_dense_avx(n, terms, extra, geo, scale, rhs, x, work);
    return terms_solve_dense_sse2(n, terms, extra, geo, scale, rhs, x, work);
}

/* Cholesky of a symmetric 3x3 matrix in place (lower triangle); 0 if not SPD. */
static int chol3(double k[3][3])
{
    const double ref = fabs(k[0][0]) + fabs(k[1][1]) + fabs(k[2][2]);
    for (int j = 0; j < 3; j++) {
        double d = k[j][j];
        for (int c = 0; c < j; c++) d -= k[j][c] * k[j][c];
        if (!(d > 1e-15 * ref) || !isfinite(d)) return 0;
        k[j][j] = sqrt(d);
        for (int i = j + 1; i < 3; i++) {
            double v = k[i][j];
            for (int c = 0; c < j; c++) v -= k[i][c] * k[j][c];
            k[i][j] = v / k[j][j];
        }
    }
    return 1;
}

static void chol3_solve(double l[3][3], double *x)
{
    for (int i = 0; i < 3; i++) {
        double v = x[i];
        for (int c = 0; c < i; c++) v -= l[i][c] * x[c];
        x[i] = v / l[i][i];
    }
    for (int i = 2; i >= 0; i--) {
        double v = x[i];
        for (int c = i + 1; c < 3; c++) v -= l[c][i] * x[c];
        x[i] = v / l[i][i];
    }
}

static int solve_recursive(int n, const hk_ElementTerms *terms, const double *extra, const double *rhs, double *x,
                           double *work)
{
    /* work per element: u (3) then G = K^-1 C (3 x 6). */
    double ia[6][6], z[6];
    memset(ia, 0, sizeof ia);
    memset(z, 0, sizeof z);
    for (int p = n - 1; p >= 0; p--) {
        const hk_ElementTerms *t = &terms[p];
        double *u = work + (size_t)21 * (size_t)p, *g = u + 3;
        double iaxi[3][6], k[3][3], c[3][6];
        for (int b = 0; b < 3; b++) mul66(ia, t->xi[b], iaxi[b]);
        for (int a = 0; a < 3; a++) {
            for (int b = 0; b < 3; b++) k[a][b] = t->mass[a][b] + dot6(t->xi[a], iaxi[b]);
            k[a][a] += extra[3 * p + a];
            for (int i = 0; i < 6; i++) c[a][i] = t->coupling[a][i] + iaxi[a][i];
            u[a] = rhs[3 * p + a] - dot6(t->xi[a], z);
        }
        if (!chol3(k)) return 0;
        chol3_solve(k, u);
        for (int i = 0; i < 6; i++) {
            double col[3] = {c[0][i], c[1][i], c[2][i]};
            chol3_solve(k, col);
            for (int a = 0; a < 3; a++) g[6 * a + i] = col[a];
        }
        for (int i = 0; i < 6; i++) {
            for (int j = 0; j < 6; j++) {
                double s = 0.0;
                for (int a = 0; a < 3; a++) s += c[a][i] * g[6 * a + j];
                ia[i][j] += t->inertia[i][j] - s;
            }
            for (int a = 0; a < 3; a++) z[i] += c[a][i] * u[a];
        }
    }
    double screw[6] = {0, 0, 0, 0, 0, 0};
    for (int p = 0; p < n; p++) {
        const hk_ElementTerms *t = &terms[p];
        const double *u = work + (size_t)21 * (size_t)p, *g = u + 3;
        for (int a = 0; a < 3; a++) x[3 * p + a] = u[a] - dot6(g + 6 * a, screw);
        for (int i = 0; i < 6; i++)
            screw[i] += t->xi[0][i] * x[3 * p] + t->xi[1][i] * x[3 * p + 1] + t->xi[2][i] * x[3 * p + 2];
    }
    return 1;
}

void hk_terms_multiply(int n, const hk_ElementTerms *terms, const double *extra, const double *x, double *out,
                       double *screws)
{
    /* Row a of element P: its own points, mass_P x_P + coupling_P . A_P with A_P the
     * screw of the element's start frame, plus xi_a . h_{P+1}, the momentum of
     * everything beyond: sum over later elements Q of inertia_Q A_Q + coupling_Q^T x_Q. */
    double screw[6] = {0, 0, 0, 0, 0, 0};
    for (int p = 0; p < n; p++) {
        const hk_ElementTerms *t = &terms[p];
        const double *xp = x + 3 * p;
        memcpy(screws + 6 * p, screw, sizeof screw);
        for (int a = 0; a < 3; a++)
            out[3 * p + a] = t->mass[a][0] * xp[0] + t->mass[a][1] * xp[1] + t->mass[a][2] * xp[2] +
                             dot6(t->coupling[a], screw) + extra[3 * p + a] * xp[a];
        for (int i = 0; i < 6; i++) screw[i] += t->xi[0][i] * xp[0] + t->xi[1][i] * xp[1] + t->xi[2][i] * xp[2];
    }
    double h[6] = {0, 0, 0, 0, 0, 0};
    for (int p = n - 1; p >= 0; p--) {
        const hk_ElementTerms *t = &terms[p];
        const double *xp = x + 3 * p, *a = screws + 6 * p;
        for (int b = 0; b < 3; b++) out[3 * p + b] += dot6(t->xi[b], h);
        for (int i = 0; i < 6; i++)
            h[i] += dot6(t->inertia[i], a) + t->coupling[0][i] * xp[0] + t->coupling[1][i] * xp[1] +
                    t->coupling[2][i] * xp[2];
    }
}

int hk_terms_solve_linear(int n, const hk_ElementTerms *terms, const double *extra, const double *rhs, double *x,
                          double *work)
{
    return solve_recursive(n, terms, extra, rhs, x, work);
}
