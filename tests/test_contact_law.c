/* The contact law of one guide-guide pair (src/dynamics/hair_contact_law.h), as a
 * Gauss-Seidel visit solves it, against a reference in long double that shares none of
 * its shortcuts: the sticking system by Cramer's rule, the friction disc's
 * trust-region problem by its own eigen-decomposition and 200 bisections on the
 * multiplier. Random well-conditioned blocks span the law's cases (sticking, sliding
 * on the disc's edge, inside it, no push, viscous), with the disc's multiplier
 * entering cold (0), warm (the last visit's, inputs moved a little) or far off. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics/hair_contact_law.h"

#define CASES 200000

/* A small deterministic generator (the test's own, the same on every platform). */
static double uniform(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / 9007199254740992.0;
}

static double around(unsigned long long *st, double scale) { return scale * (2.0 * uniform(st) - 1.0); }

/* min over |t| <= s of 1/2 t^T a t + g . t, a symmetric positive definite 2 x 2. */
static void reference_disc(const long double a[2][2], const long double g[2], long double s, long double t[2])
{
    const long double m = 0.5L * (a[0][0] + a[1][1]), dd = 0.5L * (a[0][0] - a[1][1]);
    const long double rad = sqrtl(dd * dd + a[0][1] * a[0][1]);
    const long double e[2] = {m + rad, m - rad};
    long double v0[2] = {1.0L, 0.0L};
    if (rad > 0.0L) {
        const long double ang = 0.5L * atan2l(a[0][1], dd);
        v0[0] = cosl(ang), v0[1] = sinl(ang);
    }
    const long double v1[2] = {-v0[1], v0[0]};
    const long double b[2] = {-(v0[0] * g[0] + v0[1] * g[1]), -(v1[0] * g[0] + v1[1] * g[1])};
    long double nu = 0.0L;
    if (hypotl(b[0] / e[0], b[1] / e[1]) > s) {
        long double lo = 0.0L, hi = 1.0L;
        while (hypotl(b[0] / (e[0] + hi), b[1] / (e[1] + hi)) > s) hi *= 2.0L;
        for (int k = 0; k < 200; k++) {
            const long double mid = 0.5L * (lo + hi);
            *(hypotl(b[0] / (e[0] + mid), b[1] / (e[1] + mid)) > s ? &lo : &hi) = mid;
        }
        nu = 0.5L * (lo + hi);
    }
    const long double c0 = b[0] / (e[0] + nu), c1 = b[1] / (e[1] + nu);
    t[0] = c0 * v0[0] + c1 * v1[0], t[1] = c0 * v0[1] + c1 * v1[1];
}

static long double det3(long double m[3][3])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

/* The law of contact_law's comment, in long double; *margin: how far (relatively) the
 * sticking test's two inequalities are from their thresholds (the verdict may differ
 * within rounding when it is tiny). Returns the verdict as contact_law does. */
static int reference_law(double w[3][3], const double u0[3], double beta, double gamma, double mu, double viscous,
                         double bound, long double lam[3], long double *margin)
{
    const long double free_push = (long double)beta - (long double)gamma * u0[0];
    const long double den = 1.0L + (long double)gamma * w[0][0];
    *margin = INFINITY;
    const long double f = mu > 0.0 ? 1.0L : viscous, e = mu > 0.0 ? 0.0L : 1.0L;
    long double a[3][3] = {{den, (long double)gamma * w[0][1], (long double)gamma * w[0][2]},
                           {f * w[1][0], e + f * w[1][1], f * w[1][2]},
                           {f * w[2][0], f * w[2][1], e + f * w[2][2]}};
    const long double rhs[3] = {free_push, -f * u0[1], -f * u0[2]}, d = det3(a);
    long double x[3];
    for (int c = 0; c < 3; c++) {
        long double m[3][3];
        memcpy(m, a, sizeof m);
        for (int r = 0; r < 3; r++) m[r][c] = rhs[r];
        x[c] = det3(m) / d;
    }
    const long double tangential = x[1] * x[1] + x[2] * x[2], cone = (long double)mu * mu * x[0] * x[0];
    const long double size = sqrtl(x[0] * x[0] + tangential);
    *margin = fabsl(x[0]) / size;
    if (mu > 0.0) *margin = fminl(*margin, fabsl(tangential - cone) / (tangential + cone));
    if (x[0] > 0.0L && (mu == 0.0 || tangential <= cone)) {
        memcpy(lam, x, sizeof x);
        return mu > 0.0 ? 2 : 1;
    }
    const long double n0 = free_push / den;
    lam[0] = lam[1] = lam[2] = 0.0L;
    if (!(mu > 0.0) || !(bound > 0.0)) {
        if (!(n0 > 0.0L)) return 0;
        lam[0] = n0;
        return 1;
    }
    const long double r[2] = {(long double)gamma * w[0][1] / den, (long double)gamma * w[0][2] / den};
    const long double schur[2][2] = {{w[1][1] - w[1][0] * r[0], w[1][2] - w[1][0] * r[1]},
                                     {w[2][1] - w[2][0] * r[0], w[2][2] - w[2][0] * r[1]}};
    const long double g[2] = {u0[1] + w[1][0] * n0, u0[2] + w[2][0] * n0};
    long double t[2];
    reference_disc(schur, g, bound, t);
    const long double n = n0 - r[0] * t[0] - r[1] * t[1];
    *margin = fminl(*margin, fabsl(n) / fabsl(n0));
    if (!(n > 0.0L)) return 0;
    lam[0] = n, lam[1] = t[0], lam[2] = t[1];
    return 1;
}

/* A Delassus-like block: B B^T + floor I, B's entries of either sign, scaled by a
 * random power of ten (the pairs' blocks span several). */
static void random_block(unsigned long long *st, double w[3][3])
{
    double b[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) b[r][c] = around(st, 1.0);
    const double scale = pow(10.0, around(st, 2.0));
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            double sum = r == c ? 0.05 : 0.0;
            for (int k = 0; k < 3; k++) sum += b[r][k] * b[c][k];
            w[r][c] = scale * sum;
        }
}

static void test_law_against_reference(void **state)
{
    (void)state;
    unsigned long long st = 18;
    long cases[3] = {0}, edge = 0, warm = 0, near_threshold = 0;
    double worst = 0.0;
    for (int k = 0; k < CASES; k++) {
        double w[3][3];
        random_block(&st, w);
        const double gamma = pow(10.0, around(&st, 1.5)) / w[0][0], mu = k % 50 == 0 ? 0.0 : 0.05 + uniform(&st);
        const double viscous = mu > 0.0 ? 0.0 : uniform(&st), vel = around(&st, 1.0);
        double u0[3] = {vel + around(&st, 0.3), around(&st, 1.0), around(&st, 1.0)};
        const double beta = gamma * around(&st, 2.0), bound = k % 7 == 0 ? 0.0 : mu * uniform(&st) * fabs(beta);
        double nu = k % 3 == 0 ? 0.0 : pow(10.0, around(&st, 3.0)) * w[1][1];
        LawParts lp;
        double a[3][3];
        memcpy(a, w, sizeof a);
        law_parts(a, gamma, mu, viscous, &lp);
        /* Twice: the second visit starts from the first's multiplier, its inputs moved by
         * up to 1 % (a pair's next sweep). */
        for (int pass = 0; pass < 2; pass++) {
            if (pass == 1)
                for (int r = 0; r < 3; r++) u0[r] *= 1.0 + around(&st, 0.01);
            double lam[3];
            long double ref[3], margin;
            const int verdict = contact_law(w, &lp, u0, beta, gamma, mu, viscous, bound, lam, &nu);
            const int expected = reference_law(w, u0, beta, gamma, mu, viscous, bound, ref, &margin);
            if (margin < 1e-9) {
                near_threshold++;
                continue;
            }
            assert_int_equal(verdict, expected);
            /* (the disc's solve leaves its multiplier in nu, 0 inside the disc) */
            const int on_edge = verdict == 1 && mu > 0.0 && bound > 0.0 && nu > 0.0;
            cases[verdict]++;
            edge += on_edge;
            warm += pass == 1 && on_edge;
            const long double size = sqrtl(ref[0] * ref[0] + ref[1] * ref[1] + ref[2] * ref[2]);
            long double off = 0.0L;
            for (int r = 0; r < 3; r++) off += (lam[r] - ref[r]) * (lam[r] - ref[r]);
            const double err = size > 0.0L ? (double)(sqrtl(off) / size) : (double)sqrtl(off);
            if (err > worst) worst = err;
            /* The blocks' conditions reach about 1e4 (B's floor 0.05 against entries up to
             * 3, and gamma up to 30 / w00), and the disc's Newton iteration stops at 1e-12
             * of its radius: the largest error here is 5.1e-11 of |lambda|, the same with
             * the law before law18 (its divisions, its check of every Newton step). */
            assert_true(err <= 1e-10);
            if (on_edge) hk_assert_rel(hypot(lam[1], lam[2]), bound, 1e-12, 0.0);
        }
    }
    print_message("no push %ld, pushing %ld (on the disc's edge %ld, warm %ld), sticking %ld; %ld near a threshold "
                  "skipped; largest error %.2g of |lambda|\n",
                  cases[0], cases[1], edge, warm, cases[2], near_threshold, worst);
    assert_true(cases[0] > CASES / 50 && cases[2] > CASES / 50 && edge > CASES / 5 && warm > CASES / 10);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_law_against_reference),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
