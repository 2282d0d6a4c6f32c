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

/* ---- the search's plain step in pairs --------------------------------------------------
 * The phased state (rk4_field.h) as the pairs (x, y), (cos, sin k_B z), (cos, sin phi) and
 * z, in GCC's two-lane vectors (as piece_rk4_tangent.c's columns): the plain search trace
 * is a quarter of a fit's instructions, and in scalar code the compiler spilled most of
 * its seven unknowns between the stages. The operations are phased_eval's, phased_axpy's
 * and phased_sum's, lane by lane in the same order: a - b as a + (-b), x as x + (-0),
 * both exact, so the trace is the same bits as theirs (and as the differentiated trace's
 * points). */
typedef double Pair __attribute__((vector_size(16)));
typedef struct PairState {
    Pair xy, czsz, cpsp;
    double z;
} PairState;

static inline Pair splat(double a) { return (Pair){a, a}; }

/* phased_eval(k, u).d */
static inline __attribute__((always_inline)) PairState pair_field(const hk_Helicoid *k, const PairState *u)
{
    const Pair kx = {k->kn, k->kt}, ky = {-k->kt, k->kn};
    /* (w_r, w_i) = (1 + k_N x - k_T y, k_T x + k_N y) */
    const Pair w = (kx * splat(u->xy[0]) + (Pair){1.0, -0.0}) + ky * splat(u->xy[1]);
    const Pair ww = w * w;
    const double r2 = ww[0] + ww[1];
    const int off_axis = r2 > AXIS_R2;
    const double inv_r2 = off_axis ? 1.0 / r2 : 0.0;
    /* (cos, sin theta) = w e^{i k_B z} / |w|, on the axis the phase's alone */
    Pair t = u->czsz;
    if (off_axis) {
        const double ir = sqrt(r2) * inv_r2;
        t = (w * splat(u->czsz[0]) + (Pair){-w[1], w[0]} * splat(u->czsz[1])) * splat(ir);
    }
    PairState d;
    d.xy = splat(u->cpsp[0]) * t;
    d.z = u->cpsp[1];
    const Pair dw = kx * splat(d.xy[0]) + ky * splat(d.xy[1]);
    const Pair c = dw * (Pair){w[1], w[0]};
    const double q = k->kb * d.z, th = (c[1] - c[0]) * inv_r2 + q, p = k->alpha * th;
    d.czsz = (Pair){-u->czsz[1], u->czsz[0]} * splat(q);
    d.cpsp = (Pair){-u->cpsp[1], u->cpsp[0]} * splat(p);
    return d;
}

static inline PairState pair_axpy(const PairState *u, double h, const PairState *d)
{
    const Pair hh = splat(h);
    return (PairState){u->xy + hh * d->xy, u->czsz + hh * d->czsz, u->cpsp + hh * d->cpsp, u->z + h * d->z};
}

static inline PairState pair_of(const Phased *u)
{
    return (PairState){{u->x, u->y}, {u->cz, u->sz}, {u->cp, u->sp}, u->z};
}

static inline Phased phased_of(const PairState *u)
{
    return (Phased){u->xy[0], u->xy[1], u->z, u->czsz[0], u->czsz[1], u->cpsp[0], u->cpsp[1]};
}

/* One RK4 step of length h of the phased state u (rk4_field.h), d1 the field there; on
 * return the new state and the field at it (phased_eval's, phased_axpy's and
 * phased_sum's step, in pairs). */
static inline void phased_step(const hk_Helicoid *k, double h, Phased *u, Phased *d1)
{
    const double h2 = 0.5 * h, h6 = h / 6.0;
    PairState v = pair_of(u), e1 = pair_of(d1);
    PairState t = pair_axpy(&v, h2, &e1);
    const PairState e2 = pair_field(k, &t);
    t = pair_axpy(&v, h2, &e2);
    const PairState e3 = pair_field(k, &t);
    t = pair_axpy(&v, h, &e3);
    const PairState e4 = pair_field(k, &t);
    const Pair h6p = splat(h6), two = splat(2.0);
    v.xy += h6p * (e1.xy + two * (e2.xy + e3.xy) + e4.xy);
    v.czsz += h6p * (e1.czsz + two * (e2.czsz + e3.czsz) + e4.czsz);
    v.cpsp += h6p * (e1.cpsp + two * (e2.cpsp + e3.cpsp) + e4.cpsp);
    v.z += h6 * (e1.z + 2.0 * (e2.z + e3.z) + e4.z);
    e1 = pair_field(k, &v);
    *u = phased_of(&v);
    *d1 = phased_of(&e1);
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
            const hk_Vec3 u0 = hk_v3(u.x, u.y, u.z), f0 = hk_v3(d1.x, d1.y, d1.z);
            const double h = g * step;
            phased_step(k, h, &u, &d1);
            const hk_Vec3 u1 = hk_v3(u.x, u.y, u.z), f1 = hk_v3(d1.x, d1.y, d1.z);
            for (int q = 1; q < g; q++) {
                const Hermite c = hermite(h, (double)q / (double)g);
                points[i + q] = hermite_point(&c, u0, f0, u1, f1);
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
