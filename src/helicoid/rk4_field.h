/* The helicoid field as RK4 integrates it (piece_rk4.c explains the formulation: the
 * planar direction from w / |w|, the continued argument psi carried as a fourth unknown),
 * shared by the tracer and its differentiated form (piece_rk4_tangent.c), so that both
 * take the same steps and substeps; and the fitter's search traces, coarser and with the
 * phases carried (below). Piuze et al. 2011 §3, eq. 1-2. */
#ifndef HK_HELICOID_RK4_FIELD_H
#define HK_HELICOID_RK4_FIELD_H

#include "helicoid_internal.h"

/* |w|^2 below which the point is on the singular axis w = 0, where the field has no direction:
 * the direction then comes from psi, which stops turning. */
#define AXIS_R2 1e-200

/* Most the field may turn over one RK4 step (rad): random helicoids with k_T up to 60/m
 * traced at 3.4 mm then stay within 0.5 micron of a trace 64 times finer (0.1 rad: 16 nm,
 * at twice the cost). Output spacings that would turn it more are split into substeps. */
#define MAX_TURN_PER_STEP 0.25
#define MAX_SUBSTEPS      64

typedef struct Deriv {
    double x, y, z, psi;
} Deriv;

/* The field at one point with its intermediate values (which the differentiated form
 * reuses): w = wr + i wi, ir = 1/|w| (0 on the axis), cz, sz = cos, sin k_B z. */
typedef struct FieldPoint {
    double wr, wi, ir, cz, sz;
    int off_axis;
    hk_HelicoidAngles a;
    Deriv d; /* the tangent E_T and d psi/ds */
} FieldPoint;

/* The field at (x, y, z) with continued psi. */
static inline __attribute__((always_inline)) void rk4_field(const hk_Helicoid *k, double x, double y, double z,
                                                            double psi, FieldPoint *f)
{
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y;
    const double r2 = wr * wr + wi * wi;
    const double t = psi + k->kb * z;
    const int off_axis = r2 > AXIS_R2;
    const double ir = off_axis ? 1.0 / sqrt(r2) : 0.0; /* 1/|w|; ir^2 serves psi' below */
    hk_HelicoidAngles *a = &f->a;
    double cz = 1.0, sz = 0.0;
    a->theta = t;
    if (off_axis) {
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
    Deriv *d = &f->d;
    d->x = a->cp * a->ct;
    d->y = a->cp * a->st;
    d->z = a->sp;
    const double dwr = k->kn * d->x - k->kt * d->y, dwi = k->kt * d->x + k->kn * d->y;
    d->psi = (dwi * wr - dwr * wi) * (ir * ir);
    f->wr = wr, f->wi = wi, f->ir = ir, f->cz = cz, f->sz = sz, f->off_axis = off_axis;
}

/* Substeps for an output step h starting at local (x, y): the field's direction turns at
 * most at hk_helicoid_turn_bound's rate, |w| taken where the step starts. Without this a fit could
 * use curvatures of a radian per sample, or pass next to the singular axis w = 0, and be
 * right only at the step it was fitted at: the parameters must describe the curve, not
 * one discretisation of it. */
static inline int rk4_substeps(const hk_Helicoid *k, double x, double y, double a, double b)
{
    /* a, b: the bound's two terms times h / MAX_TURN_PER_STEP: the substeps are
     * ceil(a / |w| + b); one when a <= (1 - b) |w|, checked without a square root (the
     * common case). */
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y, r2 = wr * wr + wi * wi;
    if (b < 1.0 && a * a <= (1.0 - b) * (1.0 - b) * r2) return 1;
    const double n = ceil(a / fmax(sqrt(r2), 1e-12) + b);
    return n < 1.0 ? 1 : (n > MAX_SUBSTEPS ? MAX_SUBSTEPS : (int)n);
}

/* Output steps one RK4 step may span from local (x, y) (the fitter's traces, where samples
 * are dense: a strand resampled 4 times finer turns by a few hundredths of a radian a
 * sample): as many as the turn bound allows, at most `most`; a, b as for rk4_substeps.
 * 1 when one output step is all the bound allows (then rk4_substeps splits it). */
static inline int rk4_span(const hk_Helicoid *k, double x, double y, double a, double b, int most)
{
    if (most <= 1) return 1;
    const double wr = 1.0 + k->kn * x - k->kt * y, wi = k->kt * x + k->kn * y, r2 = wr * wr + wi * wi;
    const double turn = a / fmax(sqrt(r2), 1e-12) + b; /* per output step, in MAX_TURN_PER_STEP */
    if (!(turn * (double)most > 1.0)) return most;
    const int g = (int)(1.0 / turn);
    return g < 1 ? 1 : g;
}

/* Cubic Hermite interpolation at fraction t of a step of length h between states u0 and
 * u1 with derivatives f0 and f1 (RK4's dense output: error O(h^4), like the step's own,
 * and linear in the four, so that its tangents are the interpolated tangents). */
typedef struct Hermite {
    double c0, c1, c2, c3; /* the weights of u0, f0, u1, f1 */
} Hermite;

static inline Hermite hermite(double h, double t)
{
    const double t2 = t * t, t3 = t2 * t;
    const double c0 = 2.0 * t3 - 3.0 * t2 + 1.0;
    return (Hermite){c0, h * (t3 - 2.0 * t2 + t), 1.0 - c0, h * (t3 - t2)};
}

/* The interpolated point (positions and their derivatives: the traces' outputs). */
static inline hk_Vec3 hermite_point(const Hermite *c, hk_Vec3 u0, hk_Vec3 f0, hk_Vec3 u1, hk_Vec3 f1)
{
    return hk_v3(c->c0 * u0.x + c->c1 * f0.x + c->c2 * u1.x + c->c3 * f1.x,
                 c->c0 * u0.y + c->c1 * f0.y + c->c2 * u1.y + c->c3 * f1.y,
                 c->c0 * u0.z + c->c1 * f0.z + c->c2 * u1.z + c->c3 * f1.z);
}

/* The fitter's search traces without sines and cosines (piece_rk4.c, piece_rk4_tangent.c):
 * the phases e^{i k_B z} and e^{i phi} carried as four more unknowns of the same RK4
 * (their derivatives are i k_B z' and i alpha theta' times themselves, theta' = psi' +
 * k_B z'), so that a field evaluation costs a square root and a few products instead of
 * two sincos (36 % of a fit). The same curve, to its own RK4 error (the phases drift
 * from unit length by that much). */
typedef struct Phased {
    double x, y, z, cz, sz, cp, sp;
} Phased;

/* The phased field at u with the intermediate values its derivatives reuse. */
typedef struct PhasedPoint {
    Phased d;
    double wr, wi, ir, ct, st, dwr, dwi, num, q, th, p; /* q = k_B z', th = theta', p = alpha th */
    int off_axis;
} PhasedPoint;

static inline __attribute__((always_inline)) PhasedPoint phased_eval(const hk_Helicoid *k, const Phased *u)
{
    PhasedPoint f;
    f.wr = 1.0 + k->kn * u->x - k->kt * u->y, f.wi = k->kt * u->x + k->kn * u->y;
    const double r2 = f.wr * f.wr + f.wi * f.wi;
    f.off_axis = r2 > AXIS_R2;
    /* 1 / |w| as sqrt(r2) / r2: the square root and the division run side by side
     * instead of one after the other (the search's trace is bound by their latency,
     * docs/helicoid-fitting.md §7) */
    const double inv_r2 = f.off_axis ? 1.0 / r2 : 0.0;
    f.ir = f.off_axis ? sqrt(r2) * inv_r2 : 0.0;
    /* on the axis (refused by the fitter anyway) the direction is the phase's alone */
    f.ct = f.off_axis ? (f.wr * u->cz - f.wi * u->sz) * f.ir : u->cz;
    f.st = f.off_axis ? (f.wi * u->cz + f.wr * u->sz) * f.ir : u->sz;
    Phased *d = &f.d;
    d->x = u->cp * f.ct;
    d->y = u->cp * f.st;
    d->z = u->sp;
    f.dwr = k->kn * d->x - k->kt * d->y, f.dwi = k->kt * d->x + k->kn * d->y;
    f.num = f.dwi * f.wr - f.dwr * f.wi;
    f.q = k->kb * d->z;
    f.th = f.num * inv_r2 + f.q;
    f.p = k->alpha * f.th;
    d->cz = -u->sz * f.q;
    d->sz = u->cz * f.q;
    d->cp = -u->sp * f.p;
    d->sp = u->cp * f.p;
    return f;
}

static inline Phased phased_axpy(const Phased *u, double h, const Phased *d)
{
    return (Phased){u->x + h * d->x,   u->y + h * d->y,   u->z + h * d->z,  u->cz + h * d->cz,
                    u->sz + h * d->sz, u->cp + h * d->cp, u->sp + h * d->sp};
}

/* RK4's update of u from its four stages d1..d4, h6 = h / 6. */
static inline Phased phased_sum(Phased u, double h6, const Phased *d1, const Phased *d2, const Phased *d3,
                                const Phased *d4)
{
    u.x += h6 * (d1->x + 2.0 * (d2->x + d3->x) + d4->x);
    u.y += h6 * (d1->y + 2.0 * (d2->y + d3->y) + d4->y);
    u.z += h6 * (d1->z + 2.0 * (d2->z + d3->z) + d4->z);
    u.cz += h6 * (d1->cz + 2.0 * (d2->cz + d3->cz) + d4->cz);
    u.sz += h6 * (d1->sz + 2.0 * (d2->sz + d3->sz) + d4->sz);
    u.cp += h6 * (d1->cp + 2.0 * (d2->cp + d3->cp) + d4->cp);
    u.sp += h6 * (d1->sp + 2.0 * (d2->sp + d3->sp) + d4->sp);
    return u;
}

/* State u with its phases put back on the unit circle (they drift from it by RK4's
 * error; the frame of eq. 2 must be a rotation), and tangents du (may be NULL) carried
 * along: d (v / |v|) = (dv - v^ (v^ . dv)) / |v| for each phase v. */
static inline Phased phased_unit(const Phased *u, Phased *du, int tangents)
{
    Phased n = *u;
    const double rz = hypot(u->cz, u->sz), rp = hypot(u->cp, u->sp);
    n.cz /= rz, n.sz /= rz, n.cp /= rp, n.sp /= rp;
    for (int j = 0; j < tangents; j++) {
        const double gz = n.cz * du[j].cz + n.sz * du[j].sz, gp = n.cp * du[j].cp + n.sp * du[j].sp;
        du[j].cz = (du[j].cz - n.cz * gz) / rz, du[j].sz = (du[j].sz - n.sz * gz) / rz;
        du[j].cp = (du[j].cp - n.cp * gp) / rp, du[j].sp = (du[j].sp - n.sp * gp) / rp;
    }
    return n;
}

/* The angles of the field at a state of unit phases (theta is not carried: 0). */
static inline hk_HelicoidAngles phased_angles(const PhasedPoint *f, const Phased *unit)
{
    return (hk_HelicoidAngles){0.0, f->ct, f->st, unit->cp, unit->sp};
}

#endif
