/* The entire functions c_n(x) = sum_k (-x)^k / (2k+n)! behind the closed-form helix
 * (Bertails et al. 2006 Appendix A), evaluated without cancellation near theta = 0. */
#include "helix_local.h"

#include <math.h>

/* 1/n! for n = 0..40 (exact where n! is representable, else correctly rounded). */
static const double inv_fact[41] = {
    1.0 / 1.0,
    1.0 / 1.0,
    1.0 / 2.0,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
    1.0 / 40320.0,
    1.0 / 362880.0,
    1.0 / 3628800.0,
    1.0 / 39916800.0,
    1.0 / 479001600.0,
    1.0 / 6227020800.0,
    1.0 / 87178291200.0,
    1.0 / 1307674368000.0,
    1.0 / 20922789888000.0,
    1.0 / 355687428096000.0,
    1.0 / 6402373705728000.0,
    8.2206352466243295e-18,
    4.1103176233121648e-19,
    1.9572941063391263e-20,
    8.8967913924505741e-22,
    3.8681701706306835e-23,
    1.6117375710961184e-24,
    6.4469502843844736e-26,
    2.4795962632247972e-27,
    9.183689863795546e-29,
    3.2798892370698378e-30,
    1.1309962886447718e-31,
    3.7699876288159054e-33,
    1.2161250415535181e-34,
    3.8003907548547441e-36,
    1.1516335620771951e-37,
    3.3871575355211618e-39,
    9.6775929586318907e-41,
    2.688220266286636e-42,
    7.2654601791530714e-44,
    1.911963205040282e-45,
    4.9024697565135435e-47,
    1.225617439128386e-48,
};

/* Series sum_k (-x)^k / (2k+n)! by Horner's rule with a fixed number of terms chosen
 * from x; called only where the terms decrease from the first one (x < (n-1) n / 2
 * for the orders n >= 7 it serves, or x < 1), so it does not cancel. Truncation is
 * below 1e-16 of c_n in the whole range (x < 28, terms up to (-x)^15 / (30+n)!).
 * Each count of terms is its own call of horner, whose loop then unrolls completely
 * (the same operations). */
static inline double horner(double x, int n, int terms)
{
    double sum = inv_fact[2 * (terms - 1) + n];
#pragma GCC unroll 16
    for (int k = terms - 2; k >= 0; k--) sum = inv_fact[2 * k + n] - x * sum;
    return sum;
}

static double cn_series(double x, int n)
{
    if (x < 1.0) return horner(x, n, 8);
    return x < 8.0 ? horner(x, n, 12) : horner(x, n, 16);
}

void hk_helix_cn(double x, double c[HK_CN_COUNT])
{
    /* Orders below `first` come from cos, sin and the upward recurrence
     * c_n = (1/(n-2)! - c_{n-2}) / x, which loses about log2((n-1) n / x) bits: it is
     * used only where that is at most one bit. The others (all of them when x < 1)
     * start from the series for the two highest orders and go down with
     * c_n = 1/n! - x c_{n+2}, which in that range shrinks relative errors by
     * x / ((n+1)(n+2)) < 1/2 per step. */
    int first = 0;
    if (x >= 1.0) {
        const double theta = sqrt(x);
        c[0] = cos(theta);
        c[1] = sin(theta) / theta;
        first = 2;
        while (first < HK_CN_COUNT && x >= 0.5 * (double)((first - 1) * first)) {
            c[first] = (inv_fact[first - 2] - c[first - 2]) / x;
            first++;
        }
    }
    for (int n = HK_CN_COUNT - 1; n >= first && n + 2 >= HK_CN_COUNT; n--) c[n] = cn_series(x, n);
#pragma GCC unroll 7
    for (int n = HK_CN_COUNT - 3; n >= first; n--) c[n] = inv_fact[n] - x * c[n + 2];
}

void hk_helix_cn_x2(hk_Lanes x, hk_Lanes c[HK_CN_COUNT])
{
    if (!(x[0] < 1.0 && x[1] < 1.0)) { /* each lane its own branches */
        double c0[HK_CN_COUNT], c1[HK_CN_COUNT];
        hk_helix_cn(x[0], c0);
        hk_helix_cn(x[1], c1);
#pragma GCC unroll 9
        for (int n = 0; n < HK_CN_COUNT; n++) c[n] = (hk_Lanes){c0[n], c1[n]};
        return;
    }
    /* Both below 1: hk_helix_cn's series of 8 terms for the two highest orders and its
     * downward recurrence for the others, the same operations in both lanes. */
#pragma GCC unroll 9
    for (int n = HK_CN_COUNT - 1; n >= 0; n--) {
        if (n + 2 < HK_CN_COUNT) {
            c[n] = lanes(inv_fact[n]) - x * c[n + 2];
            continue;
        }
        hk_Lanes sum = lanes(inv_fact[2 * 7 + n]);
#pragma GCC unroll 7
        for (int k = 6; k >= 0; k--) sum = lanes(inv_fact[2 * k + n]) - x * sum;
        c[n] = sum;
    }
}
