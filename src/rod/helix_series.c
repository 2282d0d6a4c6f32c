/* The entire functions c_n(x) = sum_k (-x)^k / (2k+n)! behind the closed-form helix
 * (paper 000 Appendix A), evaluated without cancellation near theta = 0. */
#include "helix_local.h"

#include <math.h>

static const double inv_factorial[HK_CN_COUNT] = {
    1.0, 1.0, 1.0 / 2.0, 1.0 / 6.0, 1.0 / 24.0, 1.0 / 120.0, 1.0 / 720.0, 1.0 / 5040.0,
    1.0 / 40320.0,
};

/* Series sum_k (-x)^k / (2k+n)!; called only where its terms decrease from the first
 * one (x < (n+1)(n+2) / 2 for n >= 2, x < 1 for n < 2), so it does not cancel. */
static double cn_series(double x, int n)
{
    double term = inv_factorial[n], sum = term;
    for (int k = 0; k < 40; k++) {
        term *= -x / ((double)(2 * k + n + 1) * (double)(2 * k + n + 2));
        sum += term;
        if (fabs(term) <= 1e-18 * fabs(sum)) break;
    }
    return sum;
}

void hk_helix_cn(double x, int count, double c[HK_CN_COUNT])
{
    if (x < 1.0) {
        for (int n = 0; n < count; n++) c[n] = cn_series(x, n);
        return;
    }
    double theta = sqrt(x);
    c[0] = cos(theta);
    c[1] = sin(theta) / theta;
    for (int n = 2; n < count; n++) {
        /* c_n = (1/(n-2)! - c_{n-2}) / x loses about log2((n-1) n / x) bits to
         * cancellation: use it only where that is at most one bit. */
        if (x >= 0.5 * (double)((n - 1) * n))
            c[n] = (inv_factorial[n - 2] - c[n - 2]) / x;
        else
            c[n] = cn_series(x, n);
    }
}
