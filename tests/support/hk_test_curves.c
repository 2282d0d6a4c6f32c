/* Distances between polylines for the fitting tests (hk_test_curves.h). */
#include "hk_test_curves.h"

#include <math.h>

static double mean_distance_to_polyline(const hk_Vec3 *a, int na, const hk_Vec3 *b, int nb)
{
    double sum = 0.0;
    for (int i = 0; i < na; i++) {
        double best = INFINITY;
        for (int j = 0; j + 1 < nb; j++) {
            const hk_Vec3 d = hk_v3_sub(b[j + 1], b[j]);
            const double dd = hk_v3_dot(d, d);
            const double t = dd > 0.0 ? fmax(0.0, fmin(1.0, hk_v3_dot(hk_v3_sub(a[i], b[j]), d) / dd)) : 0.0;
            best = fmin(best, hk_v3_dist(a[i], hk_v3_madd(b[j], d, t)));
        }
        sum += best;
    }
    return sum / na;
}

double hk_test_polyline_distance(const hk_Vec3 *a, int na, const hk_Vec3 *b, int nb)
{
    return fmax(mean_distance_to_polyline(a, na, b, nb), mean_distance_to_polyline(b, nb, a, na));
}
