/* The rotation of a rotation vector, R = exp([r]x), with the angular velocity and
 * acceleration of a moving r(t): what turns the interpolated keyframes of a motion
 * file (and the fixed-axis scripted rotations) into R, omega and alpha.
 *
 * With x = |r|^2 and the entire functions c_n(x) = sum_k (-x)^k / (2k+n)! (as in the
 * Super-Helix, docs/physics.md): R = I + c1 [r]x + c2 [r]x^2 (Rodrigues), and the left
 * Jacobian of the exponential map gives the world angular velocity
 *     omega = J(r) r',  J(r) = I + c2 [r]x + c3 [r]x^2,
 * whose time derivative is alpha (c_n' = dc_n/dx, x' = 2 r.r'):
 *     alpha = r'' + c2' x' (r x r') + c2 (r x r'') + c3' x' (r x (r x r'))
 *             + c3 (r' x (r x r') + r x (r x r'')).
 * Everything is an entire function of r, so there is no singularity anywhere (J is
 * singular at |r| = 2 pi k, which only means that some r' do not turn the head). */
#include <math.h>

#include "motion_internal.h"

/* c1, c2, c3 and dc2/dx, dc3/dx. */
typedef struct Coefs {
    double c1, c2, c3, d2, d3;
} Coefs;

/* Below x = 4 (|r| < 2 rad) the series: terms fall by at least x / 20 per step from
 * the first, so there is no cancellation, and 14 terms leave less than 1e-20. Above,
 * the closed forms, whose differences (like 1 - cos) have lost at most a few bits.
 * The derivatives use c_n' = (c_{n-1} - n c_n) / (2x), which follows from the series. */
static Coefs coefs(double x)
{
    Coefs k;
    if (x < 4.0) {
        /* sum_j (-x)^j / (2j+n)! and sum_j (-1)^(j+1) (j+1) x^j / (2j+n+2)! by Horner. */
        double f[32];
        f[0] = 1.0;
        for (int i = 1; i < 32; i++) f[i] = f[i - 1] / i;
        const int terms = 14;
        double s1 = 0, s2 = 0, s3 = 0, t2 = 0, t3 = 0;
        for (int j = terms - 1; j >= 0; j--) {
            const double sign = (j % 2) ? -1.0 : 1.0; /* (-1)^j */
            s1 = s1 * x + sign * f[2 * j + 1];
            s2 = s2 * x + sign * f[2 * j + 2];
            s3 = s3 * x + sign * f[2 * j + 3];
            t2 = t2 * x - sign * (j + 1) * f[2 * j + 4];
            t3 = t3 * x - sign * (j + 1) * f[2 * j + 5];
        }
        k.c1 = s1, k.c2 = s2, k.c3 = s3, k.d2 = t2, k.d3 = t3;
        return k;
    }
    const double theta = sqrt(x);
    k.c1 = sin(theta) / theta;
    k.c2 = (1.0 - cos(theta)) / x;
    k.c3 = (1.0 - k.c1) / x; /* c1 = 1 - x c3 */
    k.d2 = (k.c1 - 2.0 * k.c2) / (2.0 * x);
    k.d3 = (k.c2 - 3.0 * k.c3) / (2.0 * x);
    return k;
}

void hk_rotation_exp(hk_Vec3 r, hk_Vec3 dr, hk_Vec3 ddr, hk_Mat3 *rot, hk_Vec3 *omega, hk_Vec3 *alpha)
{
    const double x = hk_v3_dot(r, r);
    const Coefs k = coefs(x);

    /* [r]x^2 = r r^T - x I */
    hk_Mat3 skew = hk_m3_skew(r), sq = hk_m3_outer(r, r);
    for (int i = 0; i < 3; i++) sq.m[i][i] -= x;
    hk_Mat3 a = hk_m3_scale(&skew, k.c1), b = hk_m3_scale(&sq, k.c2), id = hk_m3_identity();
    hk_Mat3 ab = hk_m3_add(&a, &b);
    *rot = hk_m3_add(&id, &ab);

    const hk_Vec3 r_dr = hk_v3_cross(r, dr), r_r_dr = hk_v3_cross(r, r_dr);
    *omega = hk_v3_add(dr, hk_v3_add(hk_v3_scale(r_dr, k.c2), hk_v3_scale(r_r_dr, k.c3)));

    const double dx = 2.0 * hk_v3_dot(r, dr);
    const hk_Vec3 r_ddr = hk_v3_cross(r, ddr);
    hk_Vec3 al = ddr;
    al = hk_v3_madd(al, r_dr, k.d2 * dx);
    al = hk_v3_madd(al, r_ddr, k.c2);
    al = hk_v3_madd(al, r_r_dr, k.d3 * dx);
    al = hk_v3_madd(al, hk_v3_add(hk_v3_cross(dr, r_dr), hk_v3_cross(r, r_ddr)), k.c3);
    *alpha = al;
}
