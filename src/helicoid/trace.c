/* Tracing a p-helicoid strand (Piuze et al. 2011 §3.1-3.4): piece after piece, each starting where
 * the previous one ended with the frame of eq. 2 there (§3.4), with the waviness of eq. 4 and
 * the root offset of wisps (§3.3). */
#include "helicoid_internal.h"

static void trace_piece(const hk_HelicoidPiece *pc, hk_HelicoidMethod method, hk_Vec3 *p, hk_HelicoidAngles *a,
                        const hk_HelicoidSink *out)
{
    if (method == HK_HELICOID_AUTO && pc->k->alpha == 0.0)
        hk_helicoid_piece_planar(pc, p, a, out);
    else
        hk_helicoid_piece_rk4(pc, p, a, out);
}

hk_Status hk_phelicoid_trace_with(const hk_PHelicoid *h, double step, hk_HelicoidMethod method, const hk_Waviness *wave,
                                  const hk_Vec3 *offset, const hk_HelicoidPlacement *placement, hk_Vec3 *points,
                                  hk_Mat3 *frames, hk_HelicoidPlacement *placed, hk_Error *err)
{
    hk_HelicoidPiece pc;
    pc.origin = h->root;
    pc.frame = h->frame;
    hk_Vec3 end = h->root; /* the strand's point at the current piece's start, world */
    double s = 0.0;
    int base = 0; /* index of the current piece's start point */
    for (int i = 0; i < h->piece_count; i++) {
        if (placement) {
            pc.origin = placement->origin[i];
            pc.frame = placement->frame[i];
        }
        if (placed) {
            placed->origin[i] = pc.origin;
            placed->frame[i] = pc.frame;
        }
        pc.k = &h->k[i];
        pc.length = h->length[i];
        pc.steps = hk_helicoid_piece_steps(h->length[i], step);
        /* Local start: the root offset for the first piece; later the strand's own end point,
         * which is the piece's origin itself unless the strand is offset from its guide. */
        hk_Vec3 p = hk_v3_zero();
        if (i == 0) {
            if (offset) p = *offset;
        } else if (placement) {
            p = hk_m3_tmul_v3(&pc.frame, hk_v3_sub(end, pc.origin));
        }
        /* theta = 0 at a piece's origin; nearby starts take the branch nearest to it. */
        hk_HelicoidAngles a;
        hk_helicoid_eval(pc.k, p.x, p.y, p.z, 0.0, &a);
        const hk_HelicoidSink out = {points ? points + base : NULL, frames ? frames + base : NULL, wave, s};
        if (i == 0) hk_helicoid_emit(&pc, &out, 0, p.x, p.y, p.z, &a, 0.0);
        trace_piece(&pc, method, &p, &a, &out);
        end = hk_v3_add(pc.origin, hk_m3_mul_v3(&pc.frame, p));
        if (!hk_v3_isfinite(end) || !isfinite(a.theta))
            return hk_error_set(err, HK_ERR_NUMERIC, "p-helicoid trace: piece %d is not finite (parameters too large?)",
                                i + 1);
        if (!placement) {
            /* §3.4: the next piece's field is aligned with the frame of eq. 2 at this end. */
            const hk_Mat3 f = hk_helicoid_frame_of(&a);
            pc.frame = hk_m3_mul(&pc.frame, &f);
            pc.origin = end;
        }
        s += h->length[i];
        base += pc.steps;
    }
    return HK_OK;
}

hk_Status hk_phelicoid_trace(const hk_PHelicoid *h, double step, const hk_Waviness *waviness,
                             const hk_Vec3 *root_offset, hk_Vec3 *points, hk_Mat3 *frames, hk_Error *err)
{
    hk_Status st = hk_phelicoid_check(h, err);
    if (st != HK_OK) return st;
    if (!(step > 0.0) || !isfinite(step))
        return hk_error_set(err, HK_ERR_INVALID, "p-helicoid trace: step must be > 0, got %g", step);
    if (hk_phelicoid_point_count(h, step) < 0)
        return hk_error_set(err, HK_ERR_INVALID, "p-helicoid trace: step %g gives more than %d points for length %g",
                            step, HK_HELICOID_MAX_POINTS, hk_phelicoid_length(h));
    if (waviness && (!isfinite(waviness->amplitude) || !isfinite(waviness->frequency) || !isfinite(waviness->phase) ||
                     waviness->amplitude < 0.0))
        return hk_error_set(err, HK_ERR_INVALID,
                            "p-helicoid trace: waviness needs a finite amplitude >= 0 and "
                            "frequency, got %g, %g",
                            waviness->amplitude, waviness->frequency);
    if (root_offset && !hk_v3_isfinite(*root_offset))
        return hk_error_set(err, HK_ERR_INVALID, "p-helicoid trace: root offset is not finite");
    if (!points) return hk_error_set(err, HK_ERR_INVALID, "p-helicoid trace: NULL points");
    if (!root_offset)
        return hk_phelicoid_trace_with(h, step, HK_HELICOID_AUTO, waviness, NULL, NULL, points, frames, NULL, err);
    /* An offset strand follows the guide's fields, which sit where the guide's own trace puts
     * them: place them first (a trace without output), then follow them. */
    hk_HelicoidPlacement placement;
    placement.origin[0] = h->root;
    placement.frame[0] = h->frame;
    if (h->piece_count > 1) {
        st = hk_phelicoid_trace_with(h, step, HK_HELICOID_AUTO, NULL, NULL, NULL, NULL, NULL, &placement, err);
        if (st != HK_OK) return st;
    }
    return hk_phelicoid_trace_with(h, step, HK_HELICOID_AUTO, waviness, root_offset, &placement, points, frames, NULL,
                                   err);
}
