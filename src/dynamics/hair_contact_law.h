/* The contact law of one guide-guide pair in its basis, solved at every Gauss-Seidel
 * visit of the pair (hair_contact_solve.c; docs/dynamics.md, "Contacts solved together"),
 * and the parts of it that depend on the pair's Delassus block alone (LawParts, once per
 * pair and step). A header of static inline functions: the law is inlined into the
 * sweeps' visit (always: sweep_group has an AVX twin, from which gcc left them calls),
 * and tests/test_contact_law.c checks it against references. */
#ifndef HK_HAIR_CONTACT_LAW_H
#define HK_HAIR_CONTACT_LAW_H

#include <math.h>
#include <string.h>

/* The parts of a pair's contact law that depend on its Delassus block w (and gamma, mu,
 * the viscous coefficient) alone, the same for every visit of a solve: the
 * elimination of the sticking (or viscous) system, the normal block's Schur complement
 * and its eigen-decomposition. Computed once per pair and step instead of at every
 * visit. The pivots and 1 + gamma w00 are kept as reciprocals: a visit multiplies
 * where it divided, three divisions fewer on its chain (law18). */
typedef struct LawParts {
    double upper[6];  /* the sticking system's matrix as the elimination leaves it: its
                         upper triangle by rows (upper_at), the diagonal (the pivots)
                         as reciprocals */
    double factor[3]; /* the multiples of row c taken from row r > c (factor_at) */
    double den_inv;   /* 1 / (1 + gamma w00) */
    double r[2];      /* gamma (w01, w02) / (1 + gamma w00) */
    double e[2];      /* the eigenvalues of the tangential block's Schur complement */
    double v0[2];     /* and the first eigenvector (the second is (-v0[1], v0[0])) */
    char pivot[3];    /* the row swapped with row c at column c */
    char regular;     /* 0: the system is singular (solve3 fails) */
} LawParts;

/* Where LawParts keeps entry (r, k), k >= r, of the eliminated matrix, and the factor
 * of row r > c at column c. */
static inline int upper_at(int r, int k) { return 3 * r - r * (r - 1) / 2 + k - r; }
static inline int factor_at(int r, int c) { return r + c - 1; }

/* Gaussian elimination with partial pivoting of the 3 x 3 matrix a into lp (upper,
 * factor, pivot, regular): the part of solving a x = b that does not depend on b. */
static inline void eliminate3(double a[3][3], LawParts *lp)
{
    lp->regular = 0;
    memset(lp->factor, 0, sizeof lp->factor);
    for (int c = 0; c < 3; c++) {
        int piv = c;
        for (int r = c + 1; r < 3; r++)
            if (fabs(a[r][c]) > fabs(a[piv][c])) piv = r;
        lp->pivot[c] = (char)piv;
        if (!(fabs(a[piv][c]) > 0.0)) return;
        if (piv != c)
            for (int k = 0; k < 3; k++) {
                const double t = a[c][k];
                a[c][k] = a[piv][k], a[piv][k] = t;
            }
        for (int r = c + 1; r < 3; r++) {
            const double f = a[r][c] / a[c][c];
            lp->factor[factor_at(r, c)] = f;
            for (int k = c; k < 3; k++) a[r][k] -= f * a[c][k];
        }
    }
    for (int r = 0; r < 3; r++)
        for (int k = r; k < 3; k++) lp->upper[upper_at(r, k)] = k == r ? 1.0 / a[r][k] : a[r][k];
    lp->regular = 1;
}

/* Solves a x = b with a eliminated by eliminate3 (b is overwritten): the operations on
 * b of the whole elimination, in its order, the back substitution by the pivots'
 * reciprocals; 0 when singular or not finite. */
static inline __attribute__((always_inline)) int solve_eliminated3(const LawParts *lp, double b[3], double x[3])
{
    if (!lp->regular) return 0;
    /* Written out with the packed places (upper_at, factor_at) as constants: as loops the
     * places were computed at every visit (22 million more instructions in the sweeps of
     * the head driver's settling and 8 frames, callgrind). Column 2 has no swap nor row
     * below it. */
    const double *f = lp->factor, *u = lp->upper;
    for (int c = 0; c < 2; c++) {
        const int piv = lp->pivot[c];
        if (piv != c) {
            const double t = b[c];
            b[c] = b[piv], b[piv] = t;
        }
        if (c == 0)
            b[1] -= f[0] * b[0], b[2] -= f[1] * b[0];
        else
            b[2] -= f[2] * b[1];
    }
    x[2] = b[2] * u[5];
    x[1] = (b[1] - u[4] * x[2]) * u[3];
    x[0] = (b[0] - u[1] * x[1] - u[2] * x[2]) * u[0];
    /* One test on the sum: not finite when any is (inf - inf is NaN); it rejects a finite
     * solution only when the sum overflows, impulses beyond 1e307, no answer either. */
    return isfinite(x[0] + x[1] + x[2]);
}

/* The eigen-decomposition of the symmetric 2 x 2 a = sum e_i v_i v_i^T into lp. */
static inline void eigen2(const double a[2][2], LawParts *lp)
{
    const double m = 0.5 * (a[0][0] + a[1][1]), dd = 0.5 * (a[0][0] - a[1][1]);
    const double rad = sqrt(dd * dd + a[0][1] * a[0][1]);
    lp->e[0] = m + rad, lp->e[1] = m - rad;
    if (rad > 0.0) {
        const double c = dd / rad, sn = a[0][1] / rad; /* cos 2t, sin 2t */
        const double ct = sqrt(0.5 * (1.0 + c)), st = sqrt(0.5 * (1.0 - c));
        lp->v0[0] = ct, lp->v0[1] = sn >= 0.0 ? st : -st;
    } else {
        lp->v0[0] = 1.0, lp->v0[1] = 0.0;
    }
}

/* The relative error |y| / s - 1 below which disc_qp's Newton iteration stops, and
 * the bound on the error it predicts after a step below which it takes that step
 * without checking it: a hundredth of the first, for the curvature's change between the
 * iterate and the root. */
#define HK_DISC_TOLERANCE 1e-12
#define HK_DISC_PREDICTED 1e-14

/* min over |y| <= s of 1/2 y^T a y + g . y for the symmetric 2 x 2 a decomposed in lp
 * (eigen2), positive definite: the unconstrained minimiser when it lies in the disc,
 * else the boundary point where (a + nu I) y = -g with nu > 0 (the trust-region
 * problem, Moré and Sorensen 1983), nu found by Newton's iteration on
 * f(nu) - 1/s, f = 1/|y(nu)|, which is concave and increasing in nu: from the left of
 * its root the iteration climbs to it without overshooting, from the right its first
 * step lands left of it (clamped at 0). *nu enters as the start (the pair's nu of its
 * last visit: the bound and g change little from one sweep to the next; on
 * examples/guides200 the loop then runs 3.5 times a solve on the edge instead of 4.5
 * from 0) and leaves as the root (0 inside the disc). y = 0 when a is not positive
 * definite.
 * The iteration is one chain of divisions and square roots, which the sweeps wait on
 * (law18): 1/s is taken once, a step's division by q runs beside the square root, and
 * the check of the last step is skipped when Newton's error bound already predicts
 * it converged. With W = |y|^2 = sum w_i, w_i = c_i^2, P = sum w_i / (e_i + nu) (q
 * below), Q = sum w_i / (e_i + nu)^2, the relative error of |y| after a step from
 * one of relative error d is K d^2 with K = f'' f / (2 f'^2) = 3/2 (Q W / P^2 - 1)
 * (f' = P W^-3/2, f'' = -3 (Q W - P^2) W^-5/2), K taken at the iterate. On the
 * head driver's settling and 8 frames the passes with a square root fell from 3.57 to
 * 2.78 a solve on the edge, the visits' law from 121-142 to 96-115 ns (its latency,
 * docs/dynamics.md, "The contact law's divisions off the visit's chain"). */
static inline __attribute__((always_inline)) void disc_qp(const LawParts *lp, const double g[2], double s, double y[2],
                                                          double *nu_io)
{
    y[0] = y[1] = 0.0;
    const double start = *nu_io > 0.0 ? *nu_io : 0.0;
    *nu_io = 0.0;
    if (!(s > 0.0)) return;
    const double *e = lp->e, *v0 = lp->v0, v1[2] = {-v0[1], v0[0]};
    if (!(e[1] > 0.0)) return;
    const double b[2] = {-(v0[0] * g[0] + v0[1] * g[1]), -(v1[0] * g[0] + v1[1] * g[1])};
    /* Inside the disc when |(b0 / e0, b1 / e1)| <= s, tested multiplied out by
     * (e0 e1)^2 > 0: no division nor square root before the iteration starts. */
    const double reach = s * (1.0 + HK_DISC_TOLERANCE), e01 = e[0] * e[1];
    const double b0e1 = b[0] * e[1], b1e0 = b[1] * e[0];
    double c0, c1, nu = 0.0;
    if (b0e1 * b0e1 + b1e0 * b1e0 <= reach * reach * (e01 * e01)) {
        c0 = b[0] / e[0], c1 = b[1] / e[1];
    } else { /* outside the disc: on its edge */
        const double s_inv = 1.0 / s;
        nu = start;
        for (int it = 0;; it++) {
            const double i0 = 1.0 / (e[0] + nu), i1 = 1.0 / (e[1] + nu);
            c0 = b[0] * i0, c1 = b[1] * i1;
            if (it == 30) break;
            const double w0 = c0 * c0, w1 = c1 * c1, norm2 = w0 + w1;
            /* Newton's step (f - 1/s) / f' = (1 - |y|/s) W / P: W / P beside the root. */
            const double p0 = w0 * i0, p1 = w1 * i1, q = p0 + p1, ratio = norm2 / q;
            const double d = 1.0 - sqrt(norm2) * s_inv;
            if (fabs(d) <= HK_DISC_TOLERANCE) break;
            if (!(q > 0.0)) break;
            const double stepped = nu - ratio * d, qq = p0 * i0 + p1 * i1; /* Q */
            nu = stepped >= 0.0 ? stepped : 0.0;
            if (stepped >= 0.0 && 1.5 * (qq * norm2 - q * q) * (d * d) <= HK_DISC_PREDICTED * (q * q)) {
                c0 = b[0] / (e[0] + nu), c1 = b[1] / (e[1] + nu);
                break;
            }
        }
    }
    *nu_io = nu;
    y[0] = c0 * v0[0] + c1 * v1[0];
    y[1] = c0 * v0[1] + c1 * v1[1];
    const double norm = sqrt(y[0] * y[0] + y[1] * y[1]);
    if (norm > s) y[0] *= s / norm, y[1] *= s / norm; /* rounding */
}

/* The parts of a pair's contact law that depend on w alone (LawParts). */
static inline void law_parts(double w[3][3], double gamma, double mu, double viscous, LawParts *lp)
{
    const double e = mu > 0.0 ? 0.0 : 1.0, f = mu > 0.0 ? 1.0 : viscous;
    double a[3][3] = {{1.0 + gamma * w[0][0], gamma * w[0][1], gamma * w[0][2]},
                      {f * w[1][0], e + f * w[1][1], f * w[1][2]},
                      {f * w[2][0], f * w[2][1], e + f * w[2][2]}};
    eliminate3(a, lp);
    const double den = 1.0 + gamma * w[0][0];
    lp->den_inv = 1.0 / den;
    lp->r[0] = gamma * w[0][1] / den, lp->r[1] = gamma * w[0][2] / den;
    const double *r = lp->r;
    const double schur[2][2] = {{w[1][1] - w[1][0] * r[0], w[1][2] - w[1][0] * r[1]},
                                {w[2][1] - w[2][0] * r[0], w[2][2] - w[2][0] * r[1]}};
    eigen2(schur, lp);
}

/* The contact law of one pair in its basis (0: normal, 1 and 2: tangents): the impulse
 * lam given u0, the relative velocity at the step's end without this pair's impulse,
 * and w, the pair's Delassus block (u = u0 + w lam; lp its parts, law_parts). Normal
 * law: lam_0 = max(0, beta - gamma u_0), i.e. lam minimises 1/2 lam^T (w + diag(1/gamma,
 * 0, 0)) lam + (u0 - beta/gamma e_0) . lam over lam_0 >= 0. Tangentially, mu > 0:
 * Coulomb with the bound s = mu lam_0 of the pair's last iterate (a Tresca problem per
 * sweep, convex, whose bound follows the normal impulse from sweep to sweep): the
 * contact sticks (u_1 = u_2 = 0) when that needs at most s, else the friction is on the
 * disc's edge, both found exactly (the edge by one trust-region problem on the normal
 * block's Schur complement). mu = 0: the viscous lam_t = -viscous u_t.
 * Returns 2 when it sticks, 1 when it pushes otherwise, 0 when it does not push. */
static inline __attribute__((always_inline)) int contact_law(double w[3][3], const LawParts *lp, const double u0[3],
                                                             double beta, double gamma, double mu, double viscous,
                                                             double bound, double lam[3], double *nu)
{
    const double free_push = beta - gamma * u0[0];
    if (mu > 0.0 || viscous > 0.0) {
        /* Sticking (mu > 0) or viscous, with the normal law, as one linear system. */
        const double f = mu > 0.0 ? 1.0 : viscous;
        double b[3] = {free_push, -f * u0[1], -f * u0[2]}, x[3];
        if (solve_eliminated3(lp, b, x) && x[0] > 0.0 &&
            (mu == 0.0 || x[1] * x[1] + x[2] * x[2] <= mu * mu * x[0] * x[0])) {
            memcpy(lam, x, sizeof x);
            return mu > 0.0 ? 2 : 1;
        }
    }
    const double n0 = free_push * lp->den_inv;
    if (!(mu > 0.0) || !(bound > 0.0)) {
        lam[0] = n0;
        lam[1] = lam[2] = 0.0;
        if (!(lam[0] > 0.0)) return lam[0] = 0.0, 0;
        return 1;
    }
    /* Friction on the disc's edge (or no push). With n eliminated through its own
     * equation, n = n0 - r . t, the tangential impulse minimises the Schur complement's
     * quadratic over the disc; when that n is positive the pair is the minimiser of the
     * whole convex problem (it is over n of any sign), else the minimiser has n = 0:
     * no push, no friction. */
    const double *r = lp->r;
    const double g[2] = {u0[1] + w[1][0] * n0, u0[2] + w[2][0] * n0};
    double t[2];
    disc_qp(lp, g, bound, t, nu);
    const double n = n0 - r[0] * t[0] - r[1] * t[1];
    if (!(n > 0.0)) {
        lam[0] = lam[1] = lam[2] = 0.0;
        return 0;
    }
    lam[0] = n, lam[1] = t[0], lam[2] = t[1];
    return 1;
}

#endif
