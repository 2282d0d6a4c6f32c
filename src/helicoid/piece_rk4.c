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
#include "helicoid_internal.h"

/* |w|^2 below which the point is on the singular axis w = 0, where the field has no direction:
 * the direction then comes from psi, which stops turning. */
#define AXIS_R2 1e-200

typedef struct Deriv {
    double x, y, z, psi;
} Deriv;

/* The field at (x, y, z) with continued psi: the tangent E_T and d psi/ds; a gets the angles. */
static inline Deriv field(const hk_Helicoid *k, double x, double y, double z, double psi, hk_HelicoidAngles *a)
{
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y;
    const double r2 = wr * wr + wi * wi;
    const double t = psi + k->kb * z;
    const int off_axis = r2 > AXIS_R2;
    const double ir = off_axis ? 1.0 / sqrt(r2) : 0.0; /* 1/|w|; ir^2 serves psi' below */
    a->theta = t;
    if (off_axis) {
        double cz = 1.0, sz = 0.0;
        if (k->kb != 0.0) {
            cz = cos(k->kb * z);
            sz = sin(k->kb * z);
        }
        a->ct = (wr * cz - wi * sz) * ir;
        a->st = (wi * cz + wr * sz) * ir;
    } else {
        a->ct = cos(t);
        a->st = sin(t);
    }
    const double phi = k->alpha * t;
    a->cp = cos(phi);
    a->sp = sin(phi);
    Deriv d;
    d.x = a->cp * a->ct;
    d.y = a->cp * a->st;
    d.z = a->sp;
    const double dwr = k->kn * d.x - k->kt * d.y, dwi = k->kt * d.x + k->kn * d.y;
    d.psi = (dwi * wr - dwr * wi) * (ir * ir);
    return d;
}

/* Most the field may turn over one RK4 step (rad): random helicoids with k_T up to 60/m
 * traced at 3.4 mm then stay within 0.5 micron of a trace 64 times finer (0.1 rad: 16 nm,
 * at twice the cost). Output spacings that would turn it more are split into substeps. */
#define MAX_TURN_PER_STEP 0.25
#define MAX_SUBSTEPS      64

/* Substeps for an output step h starting at local (x, y): the field's direction turns at
 * most at hk_helicoid_turn_bound's rate, |w| taken where the step starts. Without this a fit could
 * use curvatures of a radian per sample, or pass next to the singular axis w = 0, and be
 * right only at the step it was fitted at: the parameters must describe the curve, not
 * one discretisation of it. */
static int substeps(const hk_Helicoid *k, double x, double y, double a, double b)
{
    /* a, b: the bound's two terms times h / MAX_TURN_PER_STEP: the substeps are
     * ceil(a / |w| + b); one when a <= (1 - b) |w|, checked without a square root (the
     * common case). */
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y, r2 = wr * wr + wi * wi;
    if (b < 1.0 && a * a <= (1.0 - b) * (1.0 - b) * r2) return 1;
    const double n = ceil(a / fmax(sqrt(r2), 1e-12) + b);
    return n < 1.0 ? 1 : (n > MAX_SUBSTEPS ? MAX_SUBSTEPS : (int)n);
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
        const int sub = substeps(k, x, y, sa, sb);
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
