/* Gauss-Legendre quadrature rules for the integrals over an element (paper 000 §3.3
 * integrates symbolically; a Gauss rule with enough points for the element's helix
 * phase is exact to rounding for these smooth integrands). */
#include <math.h>

#include "dynamics_internal.h"

void hk_gauss_table_init(hk_GaussTable *table)
{
    const double pi = HK_PI;
    for (int n = 1; n <= HK_GAUSS_MAX; n++) {
        for (int i = 0; i < n; i++) {
            /* Root i of P_n by Newton from the Chebyshev-like guess cos(pi (i + 3/4) /
             * (n + 1/2)); P_n and P_n' from the three-term recurrence. */
            double x = cos(pi * (i + 0.75) / (n + 0.5)), dp = 1.0;
            for (int it = 0; it < 100; it++) {
                double p0 = 1.0, p1 = x;
                for (int k = 2; k <= n; k++) {
                    const double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                dp = n * (x * p1 - p0) / (x * x - 1.0);
                const double dx = p1 / dp;
                x -= dx;
                if (fabs(dx) < 1e-16) break;
            }
            /* Map [-1, 1] to [0, 1]. */
            table->node[n - 1][i] = 0.5 * (1.0 - x);
            table->weight[n - 1][i] = 1.0 / ((1.0 - x * x) * dp * dp);
        }
    }
}
