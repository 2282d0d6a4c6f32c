/* Velocities, bias accelerations and Jacobians along a moving Super-Helix, and the
 * per-element terms of the equations of motion (paper 000 §3.3; docs/dynamics.md).
 *
 * Over element P the frame is R(u) = R_P E(u; k) and the centreline r(u) = r_P +
 * R_P d(u; k) (hairkit/rod.h). With Lambda the element's rotation Jacobian (d E E^T =
 * [Lambda dk]x) differentiating in time gives
 *     w(u)  = w_P + R_P Lambda k'
 *     r'(u) = r'_P + w_P x R_P d + R_P (dd/dk) k'
 * and once more, keeping only what does not multiply k'' (the bias):
 *     w'(u)  = w'_P + w_P x (R_P Lambda k') + R_P (sum_b k'_b (dLambda e_b/dk) k')
 *     r''(u) = r''_P + w'_P x R_P d + w_P x (w_P x R_P d) + 2 w_P x (R_P (dd/dk) k')
 *              + R_P (sum_ab k'_a k'_b d2d/dk_a dk_b).
 * The element's end values start the next element: O(N) for the whole strand.
 *
 * GCC 12's -O2 keeps most of the small loops here rolled (a counter, and tests such as
 * i == j made at run time); `#pragma GCC unroll` writes them out, the same operations
 * in the same order, so the same bits (docs/dynamics.md, "Speed", 6 December 2026,
 * night). */
#include <string.h>

#include "dynamics_internal.h"
#include "rod/helix_local.h"

void hk_point_kinematics(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, int order,
                         hk_PointKinematics *out)
{
    hk_ElementLocal el;
    hk_Vec3 spin_rate = hk_v3_zero(), curve = hk_v3_zero();
    if (order >= 2)
        hk_element_local_rates(k, u, kd, &el, &spin_rate, &curve);
    else
        hk_element_local(k, u, order, 0, &el);
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3 d = hk_m3_mul_v3(r, hk_m3_col(&el.lam, 0));
    out->jac = hk_m3_mul(r, &el.dd);
    out->jac_rot = hk_m3_mul(r, &el.lam);
    hk_FrameKinematics *o = &out->k;
    o->frame = hk_m3_mul(r, &el.rot);
    o->pos = hk_v3_add(start->pos, d);
    const hk_Vec3 spin = hk_m3_mul_v3(&out->jac_rot, kd); /* R_P Lambda k' */
    const hk_Vec3 slide = hk_m3_mul_v3(&out->jac, kd);    /* R_P dd k' */
    o->omega = hk_v3_add(start->omega, spin);
    o->vel = hk_v3_add(hk_v3_add(start->vel, hk_v3_cross(start->omega, d)), slide);
    if (order < 2) {
        o->alpha = hk_v3_zero();
        o->acc = hk_v3_zero();
        return;
    }
    o->alpha = hk_v3_add(hk_v3_add(start->alpha, hk_v3_cross(start->omega, spin)), hk_m3_mul_v3(r, spin_rate));
    hk_Vec3 acc = hk_v3_add(start->acc, hk_v3_cross(start->alpha, d));
    acc = hk_v3_add(acc, hk_v3_cross(start->omega, hk_v3_cross(start->omega, d)));
    acc = hk_v3_madd(acc, hk_v3_cross(start->omega, slide), 2.0);
    o->acc = hk_v3_add(acc, hk_m3_mul_v3(r, curve));
}

void hk_end_kinematics(const hk_FrameKinematics *start, const hk_EndPose *pose, hk_Vec3 kd, hk_PointKinematics *out)
{
    /* hk_point_kinematics of order 1, the element's closed forms already applied */
    const hk_Vec3 d = hk_m3_col(&pose->jac_rot, 0);
    out->jac = pose->jac;
    out->jac_rot = pose->jac_rot;
    hk_FrameKinematics *o = &out->k;
    o->frame = pose->frame;
    o->pos = pose->pos;
    const hk_Vec3 spin = hk_m3_mul_v3(&out->jac_rot, kd), slide = hk_m3_mul_v3(&out->jac, kd);
    o->omega = hk_v3_add(start->omega, spin);
    o->vel = hk_v3_add(hk_v3_add(start->vel, hk_v3_cross(start->omega, d)), slide);
    o->alpha = hk_v3_zero();
    o->acc = hk_v3_zero();
}

void hk_point_kinematics2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2],
                          hk_PointKinematics out[2])
{
    hk_ElementRates2 el;
    hk_element_local_rates2(k, u, kd, &el);
    /* hk_point_kinematics of order 2, lane by lane */
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3x2 d = mul_v3_x2(r, col_x2(&el.lam, 0));
    const hk_Mat3x2 jac = mul_m3_x2(r, &el.dd), jac_rot = mul_m3_x2(r, &el.lam), frame = mul_m3_x2(r, &el.rot);
    const hk_Vec3x2 spin = mul_x2_v3(&jac_rot, kd), slide = mul_x2_v3(&jac, kd);
    const hk_Vec3x2 omega0 = lanes3(start->omega), alpha0 = lanes3(start->alpha);
    const hk_Vec3x2 pos = add_x2(lanes3(start->pos), d), omega = add_x2(omega0, spin);
    const hk_Vec3x2 vel = add_x2(add_x2(lanes3(start->vel), cross_x2(omega0, d)), slide);
    const hk_Vec3x2 alpha = add_x2(add_x2(alpha0, cross_x2(omega0, spin)), mul_v3_x2(r, el.spin_rate));
    hk_Vec3x2 acc = add_x2(lanes3(start->acc), cross_x2(alpha0, d));
    acc = add_x2(acc, cross_x2(omega0, cross_x2(omega0, d)));
    acc = madd_x2(acc, cross_x2(omega0, slide), lanes(2.0));
    acc = add_x2(acc, mul_v3_x2(r, el.curve));
#pragma GCC unroll 2
    for (int l = 0; l < 2; l++) {
        hk_FrameKinematics *o = &out[l].k;
        out[l].jac = lane_m3(&jac, l);
        out[l].jac_rot = lane_m3(&jac_rot, l);
        o->frame = lane_m3(&frame, l);
        o->pos = lane_v3(pos, l);
        o->omega = lane_v3(omega, l);
        o->vel = lane_v3(vel, l);
        o->alpha = lane_v3(alpha, l);
        o->acc = lane_v3(acc, l);
    }
}

void hk_point_motion(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_FrameKinematics *out)
{
    hk_Mat3 rot;
    hk_Vec3 offset, spin, slide;
    hk_element_motion(k, u, kd, &rot, &offset, &spin, &slide);
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3 d = hk_m3_mul_v3(r, offset);
    out->frame = hk_m3_mul(r, &rot);
    out->pos = hk_v3_add(start->pos, d);
    out->omega = hk_v3_add(start->omega, hk_m3_mul_v3(r, spin));
    out->vel = hk_v3_add(hk_v3_add(start->vel, hk_v3_cross(start->omega, d)), hk_m3_mul_v3(r, slide));
    out->alpha = hk_v3_zero();
    out->acc = hk_v3_zero();
}

void hk_point_velocity(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_Vec3 *pos, hk_Vec3 *vel)
{
    hk_Vec3 offset, slide;
    hk_element_slide(k, u, kd, &offset, &slide);
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3 d = hk_m3_mul_v3(r, offset);
    *pos = hk_v3_add(start->pos, d);
    if (vel) *vel = hk_v3_add(hk_v3_add(start->vel, hk_v3_cross(start->omega, d)), hk_m3_mul_v3(r, slide));
}

void hk_point_velocity2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2], hk_Vec3 pos[2],
                        hk_Vec3 *vel)
{
    hk_Vec3x2 offset, slide;
    hk_element_slide2(k, u, kd, &offset, vel ? &slide : NULL);
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3x2 d = mul_v3_x2(r, offset), p = add_x2(lanes3(start->pos), d);
    pos[0] = lane_v3(p, 0);
    pos[1] = lane_v3(p, 1);
    if (!vel) return;
    const hk_Vec3x2 v = add_x2(add_x2(lanes3(start->vel), cross_x2(lanes3(start->omega), d)), mul_v3_x2(r, slide));
    vel[0] = lane_v3(v, 0);
    vel[1] = lane_v3(v, 1);
}

void hk_point_jacobian(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, double u, hk_Vec3 *pos, hk_Vec3 *vel,
                       hk_Mat3 *jac)
{
    hk_Mat3 dd;
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3 d = hk_m3_mul_v3(r, hk_element_offset(k, u, &dd, NULL));
    *jac = hk_m3_mul(r, &dd);
    *pos = hk_v3_add(start->pos, d);
    *vel = hk_v3_add(hk_v3_add(start->vel, hk_v3_cross(start->omega, d)), hk_m3_mul_v3(jac, kd));
}

/* Two points of an element at once (two lanes): their positions p, velocities v and
 * Jacobians j, and with tangent non-NULL column 0 of their frames (the tangent) in
 * world axes: the work hk_point_jacobian2 and hk_point_contact2 share. */
static inline __attribute__((always_inline)) void offset_motion2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd,
                                                                 const double u[2], hk_Vec3x2 *p, hk_Vec3x2 *v,
                                                                 hk_Mat3x2 *j, hk_Vec3x2 *tangent)
{
    hk_Vec3x2 offset;
    hk_Mat3x2 dd;
    hk_element_offset2(k, u, &offset, &dd, tangent);
    const hk_Mat3 *r = &start->frame;
    const hk_Vec3x2 d = mul_v3_x2(r, offset);
    if (tangent) *tangent = mul_v3_x2(r, *tangent);
    *j = mul_m3_x2(r, &dd);
    *p = add_x2(lanes3(start->pos), d);
    *v = add_x2(add_x2(lanes3(start->vel), cross_x2(lanes3(start->omega), d)), mul_x2_v3(j, kd));
}

void hk_point_jacobian2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2], hk_Vec3 pos[2],
                        hk_Vec3 vel[2], hk_Mat3 jac[2])
{
    hk_Vec3x2 p, v;
    hk_Mat3x2 j;
    offset_motion2(start, k, kd, u, &p, &v, &j, NULL);
#pragma GCC unroll 2
    for (int l = 0; l < 2; l++) {
        pos[l] = lane_v3(p, l);
        vel[l] = lane_v3(v, l);
        jac[l] = lane_m3(&j, l);
    }
}

void hk_point_contact2(const hk_FrameKinematics *start, hk_Vec3 k, hk_Vec3 kd, const double u[2],
                       hk_PointKinematics out[2])
{
    hk_Vec3x2 p, v, n0;
    hk_Mat3x2 j;
    offset_motion2(start, k, kd, u, &p, &v, &j, &n0);
#pragma GCC unroll 2
    for (int l = 0; l < 2; l++) {
        out[l].k.pos = lane_v3(p, l);
        out[l].k.vel = lane_v3(v, l);
        out[l].jac = lane_m3(&j, l);
        out[l].k.frame.m[0][0] = n0.x[l], out[l].k.frame.m[1][0] = n0.y[l], out[l].k.frame.m[2][0] = n0.z[l];
    }
}

static void add6(double *acc, hk_Vec3 ang, hk_Vec3 lin)
{
    acc[0] += ang.x, acc[1] += ang.y, acc[2] += ang.z;
    acc[3] += lin.x, acc[4] += lin.y, acc[5] += lin.z;
}

void hk_element_terms_add(hk_ElementTerms *t, hk_Vec3 p, const hk_Mat3 *a, const hk_Mat3 *b, const hk_Mat3 *jac,
                          const hk_Mat3 *jac_rot, hk_Vec3 f, hk_Vec3 tau)
{
    /* A point moved by the screw (w; v) has velocity T (w; v) with T = [-[p]x, I]; its
     * spatial inertia is T^T a T (plus b on the angular block). */
    const hk_Mat3 px = hk_m3_skew(p);
    const hk_Mat3 pa = hk_m3_mul(&px, a);
    const hk_Mat3 pap = hk_m3_mul(&pa, &px);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            t->inertia[i][j] -= pap.m[i][j] - (b ? b->m[i][j] : 0.0);
            t->inertia[i][j + 3] += pa.m[i][j];
            t->inertia[j + 3][i] += pa.m[i][j]; /* -A [p]x = ([p]x A)^T */
            t->inertia[i + 3][j + 3] += a->m[i][j];
        }
    hk_Vec3 aj[3], bj[3];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) {
        const hk_Vec3 jc = hk_m3_col(jac, c);
        aj[c] = hk_m3_mul_v3(a, jc);
        bj[c] = hk_v3_zero();
        if (b) bj[c] = hk_m3_mul_v3(b, hk_m3_col(jac_rot, c));
        add6(t->coupling[c], hk_v3_add(hk_v3_cross(p, aj[c]), bj[c]), aj[c]);
        t->load[c] += hk_v3_dot(jc, f);
        if (jac_rot) t->load[c] += hk_v3_dot(hk_m3_col(jac_rot, c), tau);
    }
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 3
        for (int e = 0; e < 3; e++) {
            double m = hk_v3_dot(hk_m3_col(jac, c), aj[e]);
            if (b) m += hk_v3_dot(hk_m3_col(jac_rot, c), bj[e]);
            t->mass[c][e] += m;
        }
    add6(t->wrench, hk_v3_add(hk_v3_cross(p, f), tau), f);
}

void hk_element_terms_add_quadrature(hk_ElementTerms *t, hk_Vec3 p, double a, const hk_Mat3 *b, const hk_Mat3 *jac,
                                     const hk_Mat3 *jac_rot, hk_Vec3 f, hk_Vec3 tau)
{
    /* hk_element_terms_add with the mass matrix a I: T^T (a I) T = a [[|p|^2 I - p p^T,
     * [p]x], [-[p]x, I]], without the 3x3 products. */
    const double pp = hk_v3_dot(p, p), pv[3] = {p.x, p.y, p.z};
    const hk_Mat3 px = hk_m3_skew(p);
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            t->inertia[i][j] += a * ((i == j ? pp : 0.0) - pv[i] * pv[j]) + b->m[i][j];
            t->inertia[i][j + 3] += a * px.m[i][j];
            t->inertia[j + 3][i] += a * px.m[i][j];
        }
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) t->inertia[i + 3][i + 3] += a;
    hk_Vec3 aj[3], bj[3];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) {
        const hk_Vec3 jc = hk_m3_col(jac, c), wc = hk_m3_col(jac_rot, c);
        aj[c] = hk_v3_scale(jc, a);
        bj[c] = hk_m3_mul_v3(b, wc);
        add6(t->coupling[c], hk_v3_add(hk_v3_cross(p, aj[c]), bj[c]), aj[c]);
        t->load[c] += hk_v3_dot(jc, f) + hk_v3_dot(wc, tau);
    }
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 3
        for (int e = 0; e < 3; e++)
            t->mass[c][e] += hk_v3_dot(hk_m3_col(jac, c), aj[e]) + hk_v3_dot(hk_m3_col(jac_rot, c), bj[e]);
    add6(t->wrench, hk_v3_add(hk_v3_cross(p, f), tau), f);
}

/* *x += v[0], then += v[1]: two points' terms in the order of two calls. */
static inline void add_lanes(double *x, hk_Lanes v) { *x = (*x + v[0]) + v[1]; }

/* add_lanes of v to x[0] and of w to x[1], both in one vector sum. */
static inline void add_lanes_pair(double *x, hk_Lanes v, hk_Lanes w)
{
    hk_Lanes s;
    memcpy(&s, x, sizeof s);
    s = (s + (hk_Lanes){v[0], w[0]}) + (hk_Lanes){v[1], w[1]};
    memcpy(x, &s, sizeof s);
}

static inline hk_Vec3x2 lanes_v3(hk_Vec3 a, hk_Vec3 b) { return (hk_Vec3x2){{a.x, b.x}, {a.y, b.y}, {a.z, b.z}}; }

static inline hk_Vec3x2 lanes_col(const hk_Mat3 *a, const hk_Mat3 *b, int j)
{
    return lanes_v3(hk_m3_col(a, j), hk_m3_col(b, j));
}

void hk_element_terms_add_quadrature2(hk_ElementTerms *t, const hk_PointKinematics pk[2], const double a[2],
                                      const hk_Mat3 b[2], const hk_Vec3 f[2], const hk_Vec3 tau[2])
{
    /* hk_element_terms_add_quadrature's terms, point l in lane l (the same operations),
     * each then added as the two calls would add it, two neighbouring entries at once. */
    const hk_Lanes al = {a[0], a[1]}, zero = lanes(0.0);
    const hk_Vec3x2 p = lanes_v3(pk[0].k.pos, pk[1].k.pos);
    const hk_Lanes pp = dot_x2(p, p), pv[3] = {p.x, p.y, p.z};
    const hk_Lanes px[3][3] = {{zero, -p.z, p.y}, {p.z, zero, -p.x}, {-p.y, p.x, zero}};
    hk_Lanes bl[3][3], apx[3][3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            bl[i][j] = (hk_Lanes){b[0].m[i][j], b[1].m[i][j]};
            apx[i][j] = al * px[i][j];
        }
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) {
        hk_Lanes row[3];
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) row[j] = al * ((i == j ? pp : zero) - pv[i] * pv[j]) + bl[i][j];
        double *r = t->inertia[i], *s = t->inertia[i + 3];
        add_lanes_pair(r, row[0], row[1]);
        add_lanes_pair(r + 2, row[2], apx[i][0]);
        add_lanes_pair(r + 4, apx[i][1], apx[i][2]);
        /* row i + 3: [i + 3][j] += a px[j][i], and a on the diagonal */
        add_lanes_pair(s, apx[0][i], apx[1][i]);
        add_lanes(s + 2, apx[2][i]);
        add_lanes(s + 3 + i, al);
    }
    const hk_Vec3x2 fl = lanes_v3(f[0], f[1]), taul = lanes_v3(tau[0], tau[1]);
    hk_Vec3x2 jc[3], wc[3], aj[3], bj[3];
    hk_Lanes load[3];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++) {
        jc[c] = lanes_col(&pk[0].jac, &pk[1].jac, c);
        wc[c] = lanes_col(&pk[0].jac_rot, &pk[1].jac_rot, c);
        aj[c] = scale_x2(jc[c], al);
        bj[c] = (hk_Vec3x2){bl[0][0] * wc[c].x + bl[0][1] * wc[c].y + bl[0][2] * wc[c].z,
                            bl[1][0] * wc[c].x + bl[1][1] * wc[c].y + bl[1][2] * wc[c].z,
                            bl[2][0] * wc[c].x + bl[2][1] * wc[c].y + bl[2][2] * wc[c].z};
        const hk_Vec3x2 ang = add_x2(cross_x2(p, aj[c]), bj[c]);
        add_lanes_pair(t->coupling[c], ang.x, ang.y);
        add_lanes_pair(t->coupling[c] + 2, ang.z, aj[c].x);
        add_lanes_pair(t->coupling[c] + 4, aj[c].y, aj[c].z);
        load[c] = dot_x2(jc[c], fl) + dot_x2(wc[c], taul);
    }
    add_lanes_pair(t->load, load[0], load[1]);
    add_lanes(t->load + 2, load[2]);
    hk_Lanes mass[9];
#pragma GCC unroll 3
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 3
        for (int e = 0; e < 3; e++) mass[3 * c + e] = dot_x2(jc[c], aj[e]) + dot_x2(wc[c], bj[e]);
    double *m = &t->mass[0][0];
#pragma GCC unroll 4
    for (int k = 0; k < 8; k += 2) add_lanes_pair(m + k, mass[k], mass[k + 1]);
    add_lanes(m + 8, mass[8]);
    const hk_Vec3x2 moment = add_x2(cross_x2(p, fl), taul);
    add_lanes_pair(t->wrench, moment.x, moment.y);
    add_lanes_pair(t->wrench + 2, moment.z, fl.x);
    add_lanes_pair(t->wrench + 4, fl.y, fl.z);
}

void hk_element_terms_set_screw(hk_ElementTerms *t, const hk_PointKinematics *end)
{
    /* Changing k_P b rotates everything beyond the end r_{P+1} by w_b and moves it by
     * t_b: p moves by w_b x (p - r_{P+1}) + t_b = w_b x p + (t_b + r_{P+1} x w_b). */
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
        const hk_Vec3 w = hk_m3_col(&end->jac_rot, b);
        const hk_Vec3 v = hk_v3_add(hk_m3_col(&end->jac, b), hk_v3_cross(end->k.pos, w));
        double *x = t->xi[b];
        x[0] = w.x, x[1] = w.y, x[2] = w.z, x[3] = v.x, x[4] = v.y, x[5] = v.z;
    }
}

static double dot6(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
}

void hk_terms_generalized_force(int n, const hk_ElementTerms *terms, double *out)
{
    double beyond[6] = {0, 0, 0, 0, 0, 0};
    for (int p = n - 1; p >= 0; p--) {
        const hk_ElementTerms *t = &terms[p];
#pragma GCC unroll 3
        for (int b = 0; b < 3; b++) out[3 * p + b] = t->load[b] + dot6(t->xi[b], beyond);
#pragma GCC unroll 6
        for (int i = 0; i < 6; i++) beyond[i] += t->wrench[i];
    }
}
