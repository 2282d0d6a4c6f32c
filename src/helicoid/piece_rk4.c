/* Tracing one helicoid piece with classical RK4 (Piuze et al. 2011 §3.1 uses forward Euler, eq. 3,
 * whose O(h) error bends curly strands visibly at hair-like steps; RK4 costs four field
 * evaluations per step for an O(h^4) error). Used where no closed form exists (alpha != 0).
 *
 * Evaluating eq. 1 needs the continued argument psi of w = 1 + (k_N + i k_T)(x + i y) only for
 * phi = alpha (psi + k_B z): the direction in the E_T-E_N plane is e^{i theta} =
 * (w / |w|) e^{i k_B z}, a square root instead of an arctangent. psi itself is carried as a
 * fourth unknown, d psi / ds = Im(w' / w) = Im(w' conj w) / |w|^2 with w' = c (x' + i y'): the
 * same solution (psi = arg w along the exact streamline), the 2 pi cycles counted by
 * construction, and no atan2 on the critical path (the stages are sequential, so the latency
 * of one evaluation is what tracing costs: this halves it). Taking the planar direction from the
 * position rather than from psi keeps RK4 as accurate as with atan2 at every stage (on a circle
 * a direction from psi alone drifts, 100 times the error). */
#include "rk4_field.h"

/* The field at (x, y, z) with continued psi: the tangent E_T and d psi/ds; a gets the angles. */
static inline Deriv field(const hk_Helicoid *k, double x, double y, double z, double psi, hk_HelicoidAngles *a)
{
    FieldPoint f;
    rk4_field(k, x, y, z, psi, &f);
    *a = f.a;
    return f.d;
}

void hk_helicoid_piece_rk4(const hk_HelicoidPiece *pc, hk_Vec3 *p, hk_HelicoidAngles *a, const hk_HelicoidSink *out)
{
    const hk_Helicoid *k = pc->k;
    const double step = pc->length / pc->steps;
    double sa, sb;
    hk_helicoid_turn_bound(k, &sa, &sb);
    sa *= step / MAX_TURN_PER_STEP, sb *= step / MAX_TURN_PER_STEP;
    double x = p->x, y = p->y, z = p->z, psi = a->theta - k->kb * z;
    hk_HelicoidAngles a1, tmp;
    Deriv d1 = field(k, x, y, z, psi, &a1);
    for (int j = 1; j <= pc->steps; j++) {
        const int sub = rk4_substeps(k, x, y, sa, sb);
        const double h = step / sub, h2 = 0.5 * h, h6 = h / 6.0;
        for (int u = 0; u < sub; u++) {
            const Deriv d2 = field(k, x + h2 * d1.x, y + h2 * d1.y, z + h2 * d1.z, psi + h2 * d1.psi, &tmp);
            const Deriv d3 = field(k, x + h2 * d2.x, y + h2 * d2.y, z + h2 * d2.z, psi + h2 * d2.psi, &tmp);
            const Deriv d4 = field(k, x + h * d3.x, y + h * d3.y, z + h * d3.z, psi + h * d3.psi, &tmp);
            x += h6 * (d1.x + 2.0 * (d2.x + d3.x) + d4.x);
            y += h6 * (d1.y + 2.0 * (d2.y + d3.y) + d4.y);
            z += h6 * (d1.z + 2.0 * (d2.z + d3.z) + d4.z);
            psi += h6 * (d1.psi + 2.0 * (d2.psi + d3.psi) + d4.psi);
            /* The new point's angles: its frame, and the first stage of the next step. */
            d1 = field(k, x, y, z, psi, &a1);
        }
        const double s = j == pc->steps ? pc->length : j * step;
        hk_helicoid_emit(pc, out, j, x, y, z, &a1, out->s_start + s);
    }
    *p = hk_v3(x, y, z);
    *a = a1;
}

/* One RK4 step of length h of the phased state u (rk4_field.h), d1 the field there; on
 * return the new state and the field at it. */
static inline void phased_step(const hk_Helicoid *k, double h, Phased *u, Phased *d1)
{
    const double h2 = 0.5 * h, h6 = h / 6.0;
    Phased t = phased_axpy(u, h2, d1);
    const Phased d2 = phased_eval(k, &t).d;
    t = phased_axpy(u, h2, &d2);
    const Phased d3 = phased_eval(k, &t).d;
    t = phased_axpy(u, h, &d3);
    const Phased d4 = phased_eval(k, &t).d;
    *u = phased_sum(*u, h6, d1, &d2, &d3, &d4);
    *d1 = phased_eval(k, u).d;
}

void hk_helicoid_piece_rk4_local(const hk_Helicoid *k, double length, int steps, double turn, int span, hk_Vec3 *points,
                                 hk_HelicoidAngles *end)
{
    const double step = length / steps;
    double sa, sb;
    hk_helicoid_turn_bound(k, &sa, &sb);
    sa *= step / turn, sb *= step / turn;
    Phased u = {0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 0.0};
    Phased d1 = phased_eval(k, &u).d;
    points[0] = hk_v3_zero();
    for (int i = 0; i < steps;) {
        const int g = rk4_span(k, u.x, u.y, sa, sb, span < steps - i ? span : steps - i);
        if (g > 1) {
            /* one step over g samples, the ones inside interpolated */
            const Deriv u0 = {u.x, u.y, u.z, 0.0}, f0 = {d1.x, d1.y, d1.z, 0.0};
            const double h = g * step;
            phased_step(k, h, &u, &d1);
            const Deriv u1 = {u.x, u.y, u.z, 0.0}, f1 = {d1.x, d1.y, d1.z, 0.0};
            for (int q = 1; q < g; q++) {
                const Deriv p = hermite(u0, f0, u1, f1, h, (double)q / (double)g);
                points[i + q] = hk_v3(p.x, p.y, p.z);
            }
            i += g;
        } else {
            const int sub = rk4_substeps(k, u.x, u.y, sa, sb);
            for (int s = 0; s < sub; s++) phased_step(k, step / sub, &u, &d1);
            i++;
        }
        points[i] = hk_v3(u.x, u.y, u.z);
    }
    const Phased unit = phased_unit(&u, NULL, 0);
    const PhasedPoint f = phased_eval(k, &unit);
    *end = phased_angles(&f, &unit);
}
