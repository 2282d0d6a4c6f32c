/* Wisps (Piuze et al. 2011 §3.3): more streamlines of a guide's own field, started from random points
 * around its root, optionally tilted at random to fan the wisp out. */
#include "hairkit/rng.h"
#include "helicoid_internal.h"

/* Random numbers of strand j are keyed (seed, j, STREAM + c): independent of the count. */
enum { STREAM = 0x5769 /* "Wi" */ };

hk_Status hk_phelicoid_wisp(const hk_PHelicoid *guide, int count, double radius, double spread, uint64_t seed,
                            double step, const hk_Waviness *w, hk_Vec3 *points, hk_Error *err)
{
    hk_Status st = hk_phelicoid_check(guide, err);
    if (st != HK_OK) return st;
    if (count < 0) return hk_error_set(err, HK_ERR_INVALID, "wisp: strand count must be >= 0, got %d", count);
    if (!(radius >= 0.0) || !isfinite(radius))
        return hk_error_set(err, HK_ERR_INVALID, "wisp: radius must be >= 0, got %g", radius);
    if (!(spread >= 0.0) || !(spread <= HK_PI))
        return hk_error_set(err, HK_ERR_INVALID, "wisp: spread must be in [0, pi] radians, got %g", spread);
    const int n = hk_phelicoid_point_count(guide, step);
    if (n < 0)
        return hk_error_set(err, HK_ERR_INVALID, "wisp: step must be > 0 and give at most %d points, got %g",
                            HK_HELICOID_MAX_POINTS, step);
    if (w && (!isfinite(w->amplitude) || !isfinite(w->frequency) || !isfinite(w->phase) || w->amplitude < 0.0))
        return hk_error_set(err, HK_ERR_INVALID,
                            "wisp: waviness needs a finite amplitude >= 0 and frequency, "
                            "got %g, %g",
                            w->amplitude, w->frequency);
    if (count == 0) return HK_OK;
    if (!points) return hk_error_set(err, HK_ERR_INVALID, "wisp: NULL points");

    /* The guide's pieces sit where its own trace puts them: place them once for all strands. */
    hk_HelicoidPlacement placement;
    placement.origin[0] = guide->root;
    placement.frame[0] = guide->frame;
    if (guide->piece_count > 1) {
        st = hk_phelicoid_trace_with(guide, step, HK_HELICOID_AUTO, NULL, NULL, NULL, NULL, NULL, &placement, err);
        if (st != HK_OK) return st;
    }
    const hk_Mat3 *q = &guide->frame;
    for (int j = 0; j < count; j++) {
        double u[4];
        for (int c = 0; c < 4; c++) u[c] = hk_rng_uniform(seed, (uint64_t)j, (uint64_t)(STREAM + c));
        /* Uniform in the disc: the radius goes as the square root of a uniform number. */
        const double rho = radius * sqrt(u[0]), t = (2.0 * HK_PI) * u[1];
        const hk_Vec3 offset = hk_v3(0.0, rho * cos(t), rho * sin(t));
        hk_Vec3 *p = points + (size_t)j * (size_t)n;
        st = hk_phelicoid_trace_with(guide, step, HK_HELICOID_AUTO, w, &offset, &placement, p, NULL, NULL, err);
        if (st != HK_OK) return st;
        if (spread > 0.0) {
            /* Tilt about an axis of the root's E_N-E_B plane, so the strand's initial direction
             * leans away from E_T by the angle; rigid, about the strand's own root. */
            const double at = (2.0 * HK_PI) * u[3];
            const hk_Vec3 axis = hk_m3_mul_v3(q, hk_v3(0.0, cos(at), sin(at)));
            const hk_Mat3 r = hk_helicoid_axis_angle(axis, spread * u[2]);
            const hk_Vec3 c = hk_v3_add(guide->root, hk_m3_mul_v3(q, offset));
            for (int i = 0; i < n; i++) p[i] = hk_v3_add(c, hk_m3_mul_v3(&r, hk_v3_sub(p[i], c)));
        }
    }
    return HK_OK;
}
