/* Discrete Fréchet measures between polylines (Piuze et al. 2011 §5.1, after Eiter &
 * Mannila, "Computing discrete Fréchet distance", TU Wien CD-TR 94/64, 1994).
 *
 * Both measures minimise over monotone couplings (the dog and its handler both walk
 * forward, each pair of points is joined by a leash, leashes never cross):
 *   coupling  C[i][j] = d(a_i, b_j) + min(C[i-1][j], C[i][j-1], C[i-1][j-1])   (sum)
 *   distance  D[i][j] = max(d(a_i, b_j), min(D[i-1][j], D[i][j-1], D[i-1][j-1]))
 * The paper fits with the first ("the minimum total length of leashes ... such that
 * leashes do not cross"); the second is the classic discrete Fréchet distance, the
 * worst deviation, reported alongside.
 *
 * Memory: one row over the shorter curve, updated in place; the cell above-left is
 * carried in a scalar. Time: p*q square roots and min-chains, no allocation. When p == q
 * the transposed programme performs the very same operations (min is exact and
 * (x - y)^2 == (y - x)^2), so the measures are exactly symmetric; when p != q the
 * longer curve is always the outer loop, whatever the argument order. */
#include <math.h>

#include "optimize/curvefit_internal.h"

static inline double leash(hk_Vec3 a, hk_Vec3 b)
{
    const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    return sqrt(dx * dx + dy * dy + dz * dz);
}

static inline double min2(double a, double b) { return a < b ? a : b; }

/* Coupling with a (p points) outer and b (q points) inner; row has q cells. prefix (may
 * be NULL, only meaningful when p == q) gets the diagonal C[i][i].
 * Speed: min(up, diag) does not depend on the cell to the left, so the loop-carried
 * path is one min and one add; the square roots overlap with it (measured: about 1.4 us
 * for 30 x 30 points, bound by the square roots' throughput; sweeping two rows at once
 * or packed square roots gained under 10%, not worth the code). */
static double coupling_rows(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *row, double *prefix)
{
    double acc = 0.0;
    for (int j = 0; j < q; j++) {
        acc += leash(a[0], b[j]);
        row[j] = acc;
    }
    if (prefix) prefix[0] = row[0];
    for (int i = 1; i < p; i++) {
        const hk_Vec3 ai = a[i];
        double diag = row[0];
        double left = row[0] + leash(ai, b[0]);
        row[0] = left;
        for (int j = 1; j < q; j++) {
            const double up = row[j];
            left = leash(ai, b[j]) + min2(left, min2(up, diag));
            diag = up;
            row[j] = left;
        }
        if (prefix) prefix[i] = row[i];
    }
    return row[q - 1];
}

static double distance_rows(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *row)
{
    double acc = 0.0;
    for (int j = 0; j < q; j++) {
        const double d = leash(a[0], b[j]);
        acc = d > acc ? d : acc;
        row[j] = acc;
    }
    for (int i = 1; i < p; i++) {
        const hk_Vec3 ai = a[i];
        double diag = row[0];
        const double d0 = leash(ai, b[0]);
        double left = d0 > row[0] ? d0 : row[0];
        row[0] = left;
        for (int j = 1; j < q; j++) {
            const double up = row[j];
            const double m = min2(left, min2(up, diag));
            const double d = leash(ai, b[j]);
            left = d > m ? d : m;
            diag = up;
            row[j] = left;
        }
    }
    return row[q - 1];
}

static void both_rows(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *rs, double *rm, double *coupling,
                      double *distance)
{
    double sum = 0.0, mx = 0.0;
    for (int j = 0; j < q; j++) {
        const double d = leash(a[0], b[j]);
        sum += d;
        mx = d > mx ? d : mx;
        rs[j] = sum;
        rm[j] = mx;
    }
    for (int i = 1; i < p; i++) {
        const hk_Vec3 ai = a[i];
        double ds = rs[0], dm = rm[0];
        const double d0 = leash(ai, b[0]);
        double ls = rs[0] + d0, lm = d0 > rm[0] ? d0 : rm[0];
        rs[0] = ls;
        rm[0] = lm;
        for (int j = 1; j < q; j++) {
            const double d = leash(ai, b[j]);
            const double us = rs[j], um = rm[j];
            ls = d + min2(ls, min2(us, ds));
            const double m = min2(lm, min2(um, dm));
            lm = d > m ? d : m;
            ds = us;
            dm = um;
            rs[j] = ls;
            rm[j] = lm;
        }
    }
    *coupling = rs[q - 1];
    *distance = rm[q - 1];
}

static int args_ok(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, const double *work)
{
    return a && b && work && p >= 1 && q >= 1;
}

double hk_frechet_coupling(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work)
{
    if (!args_ok(a, p, b, q, work)) return NAN;
    return p >= q ? coupling_rows(a, p, b, q, work, NULL) : coupling_rows(b, q, a, p, work, NULL);
}

double hk_frechet_coupling_normalized(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work)
{
    return hk_frechet_coupling(a, p, b, q, work) / (double)(p > q ? p : q);
}

double hk_frechet_distance(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work)
{
    if (!args_ok(a, p, b, q, work)) return NAN;
    return p >= q ? distance_rows(a, p, b, q, work) : distance_rows(b, q, a, p, work);
}

double hk_frechet_coupling_prefix(const hk_Vec3 *a, const hk_Vec3 *b, int n, double *row, double *prefix)
{
    if (!a || !b || !row || n < 1) return NAN;
    return coupling_rows(a, n, b, n, row, prefix);
}

void hk_frechet_both(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work, double *coupling, double *distance)
{
    if (!args_ok(a, p, b, q, work)) {
        *coupling = *distance = NAN;
        return;
    }
    const int m = p < q ? p : q;
    if (p >= q)
        both_rows(a, p, b, q, work, work + m, coupling, distance);
    else
        both_rows(b, q, a, p, work, work + m, coupling, distance);
}

/* Cells beyond which the checked entry point refuses (seconds of work, not a hang). */
#define MAX_CELLS 1e9

hk_Status hk_frechet_measures(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, hk_FrechetMeasures *out, hk_Error *err)
{
    if (!a || !b || !out) return hk_error_set(err, HK_ERR_INVALID, "frechet: NULL argument");
    if (p < 1 || q < 1)
        return hk_error_set(err, HK_ERR_INVALID, "frechet: curves need at least one point (got %d and %d)", p, q);
    if ((double)p * (double)q > MAX_CELLS)
        return hk_error_set(err, HK_ERR_INVALID,
                            "frechet: %d x %d points is too many for the O(pq) measures; resample first", p, q);
    for (int i = 0; i < p; i++)
        if (!hk_v3_isfinite(a[i]))
            return hk_error_set(err, HK_ERR_INVALID, "frechet: point %d of the first curve is not finite", i);
    for (int j = 0; j < q; j++)
        if (!hk_v3_isfinite(b[j]))
            return hk_error_set(err, HK_ERR_INVALID, "frechet: point %d of the second curve is not finite", j);
    const int m = p < q ? p : q;
    double *work = hk_alloc_array(2 * (size_t)m, sizeof(double), err);
    if (!work) return err ? err->code : HK_ERR_NOMEM;
    hk_frechet_both(a, p, b, q, work, &out->coupling, &out->distance);
    out->normalized = out->coupling / (double)(p > q ? p : q);
    hk_free(work);
    return HK_OK;
}
