/* Closed forms of one helical element in its own frame (Bertails et al. 2006 Appendix A).
 *
 * Everything reduces to the entire functions
 *     c_n(x) = sum_{k>=0} (-x)^k / (2k + n)!,     x = theta^2,
 * (c_0 = cos theta, c_1 = sin theta / theta, c_2 = (1 - cos theta) / theta^2, ...), which
 * are smooth at x = 0, so no formula divides by a small |Omega|. With phi = u k and
 * Phi = [phi]x:
 *     exp(Phi)      = I + c_1 Phi + c_2 Phi^2                       (frame rotation)
 *     Lambda(u; k)  = u (I + c_2 Phi + c_3 Phi^2)                  (int_0^u exp(v[k]x) dv)
 *     d(u; k)       = Lambda(u; k) e0                               (centreline offset)
 *     g(u; k)       = u^2 (e0/2 + c_3 Phi e0 + c_4 Phi^2 e0)        (int_0^u d(v; k) dv)
 * Derivatives use dc_n/dx = -(c_{n+1} - n c_{n+2}) / 2 (docs/physics.md). */
#ifndef HK_ROD_HELIX_LOCAL_H
#define HK_ROD_HELIX_LOCAL_H

#include "hairkit/vecmath.h"

#define HK_CN_COUNT 9

/* c[n] = c_n(x) for n = 0..HK_CN_COUNT-1, x >= 0, accurate to a few ulps of each
 * value's magnitude: upward recurrence from cos and sin where it does not cancel,
 * series for the two highest orders and a stable downward recurrence elsewhere. */
void hk_helix_cn(double x, double c[HK_CN_COUNT]);

/* The vector function  h(phi) = alpha w + c_m(x) (phi x w) + c_{m+1}(x) phi x (phi x w)
 * (x = phi . phi) with its derivatives in phi. */
typedef struct hk_HelixTerm {
    hk_Vec3 value;
    hk_Mat3 jac;        /* jac.m[i][j] = d value_i / d phi_j */
    hk_Vec3 hess[3][3]; /* hess[a][b] = d^2 value / d phi_a d phi_b (symmetric in a, b) */
} hk_HelixTerm;

/* order 0: value; 1: value and jac; 2: also hess. c from hk_helix_cn(phi . phi).
 * Requires m + 5 <= HK_CN_COUNT - 1 + 1 for order 2 (m <= 3). */
void hk_helix_term(const double c[HK_CN_COUNT], int m, double alpha, hk_Vec3 phi, hk_Vec3 w, int order,
                   hk_HelixTerm *out);

/* The first and second derivatives of the same h along one direction e of phi (alpha w,
 * constant, has none): d1 = sum_a e_a dh/dphi_a and d2 = sum_ab e_a e_b d2h/dphi_a dphi_b
 * (either may be NULL).
 * What a moving element's bias needs (the rates contracted with themselves), at the
 * cost of one column instead of the whole Jacobian and Hessian. */
void hk_helix_term_along(const double c[HK_CN_COUNT], int m, hk_Vec3 phi, hk_Vec3 w, hk_Vec3 e, hk_Vec3 *d1,
                         hk_Vec3 *d2);

/* Rotation exp([phi]x) from the c_n of x = |phi|^2. */
hk_Mat3 hk_helix_rotation(const double c[HK_CN_COUNT], hk_Vec3 phi);

/* Element quantities at arc length u for curvature/twist k, in the element's own
 * frame, with derivatives with respect to k (not phi). */
typedef struct hk_ElementLocal {
    hk_Mat3 rot;       /* exp(u [k]x) */
    hk_Mat3 lam;       /* Lambda(u; k): column b is the world-rate of rotation per unit k_b */
    hk_Mat3 dlam[3];   /* dlam[b].m[i][a] = d (Lambda e_b)_i / d k_a   (order >= 2 only) */
    hk_Mat3 dd;        /* dd.m[i][a] = d d_i / d k_a (order >= 1); d = column 0 of lam */
    hk_Vec3 d2d[3][3]; /* d^2 d / d k_a d k_b (order >= 2) */
    hk_Vec3 g;         /* g(u; k) (with_g only) */
    hk_Mat3 dg;        /* d g / d k (with_g, order >= 1) */
    hk_Vec3 d2g[3][3]; /* d^2 g / d k_a d k_b (with_g, order >= 2) */
} hk_ElementLocal;

/* order 0: rot, column 0 of lam (the offset d), and g; 1: all of lam, dd (and dg);
 * 2: + dlam, d2d (and d2g). */
void hk_element_local(hk_Vec3 k, double u, int order, int with_g, hk_ElementLocal *out);

/* hk_element_local of order 1 (rot, lam, dd) with, for curvature rates kd, the two
 * contractions of the order-2 derivatives that the bias acceleration takes (paper 000
 * §3.3; dynamics/strand_kinematics.c): spin_rate = sum_b kd_b dlam[b] kd and
 * curve = sum_ab kd_a kd_b d2d[a][b], both in the element's frame. */
void hk_element_local_rates(hk_Vec3 k, double u, hk_Vec3 kd, hk_ElementLocal *out, hk_Vec3 *spin_rate, hk_Vec3 *curve);

/* Two lanes of doubles (a GCC vector extension, as in helicoid/piece_rk4_tangent.c):
 * two points of one element at once, each lane with the scalar code's operations in
 * their order, hence its bits (no contraction into fused multiply-adds: the build has
 * none, docs/library.md). */
typedef double hk_Lanes __attribute__((vector_size(16)));
typedef struct hk_Vec3x2 {
    hk_Lanes x, y, z;
} hk_Vec3x2;
typedef struct hk_Mat3x2 {
    hk_Lanes m[3][3];
} hk_Mat3x2;

/* hairkit/vecmath.h's operations on two lanes, each lane's the same bits as theirs (their
 * loops unrolled as vecmath.h's are: the same operations, without the counters). */
static inline hk_Lanes lanes(double s) { return (hk_Lanes){s, s}; }
static inline hk_Vec3x2 lanes3(hk_Vec3 v) { return (hk_Vec3x2){lanes(v.x), lanes(v.y), lanes(v.z)}; }
static inline hk_Lanes dot_x2(hk_Vec3x2 a, hk_Vec3x2 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline hk_Vec3x2 cross_x2(hk_Vec3x2 a, hk_Vec3x2 b)
{
    return (hk_Vec3x2){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline hk_Vec3x2 scale_x2(hk_Vec3x2 a, hk_Lanes s) { return (hk_Vec3x2){a.x * s, a.y * s, a.z * s}; }
static inline hk_Vec3x2 madd_x2(hk_Vec3x2 a, hk_Vec3x2 b, hk_Lanes s)
{
    return (hk_Vec3x2){a.x + s * b.x, a.y + s * b.y, a.z + s * b.z};
}
static inline hk_Vec3x2 add_x2(hk_Vec3x2 a, hk_Vec3x2 b) { return (hk_Vec3x2){a.x + b.x, a.y + b.y, a.z + b.z}; }
/* r v for a matrix common to both lanes */
static inline hk_Vec3x2 mul_v3_x2(const hk_Mat3 *r, hk_Vec3x2 v)
{
    hk_Lanes o[3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) o[i] = lanes(r->m[i][0]) * v.x + lanes(r->m[i][1]) * v.y + lanes(r->m[i][2]) * v.z;
    return (hk_Vec3x2){o[0], o[1], o[2]};
}
/* a v for a vector common to both lanes */
static inline hk_Vec3x2 mul_x2_v3(const hk_Mat3x2 *a, hk_Vec3 v)
{
    hk_Lanes o[3];
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++) o[i] = a->m[i][0] * lanes(v.x) + a->m[i][1] * lanes(v.y) + a->m[i][2] * lanes(v.z);
    return (hk_Vec3x2){o[0], o[1], o[2]};
}
/* r b for a matrix r common to both lanes */
static inline hk_Mat3x2 mul_m3_x2(const hk_Mat3 *r, const hk_Mat3x2 *b)
{
    hk_Mat3x2 o;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++)
            o.m[i][j] =
                lanes(r->m[i][0]) * b->m[0][j] + lanes(r->m[i][1]) * b->m[1][j] + lanes(r->m[i][2]) * b->m[2][j];
    return o;
}
static inline hk_Vec3x2 col_x2(const hk_Mat3x2 *a, int j) { return (hk_Vec3x2){a->m[0][j], a->m[1][j], a->m[2][j]}; }
static inline hk_Vec3 lane_v3(hk_Vec3x2 v, int i) { return hk_v3(v.x[i], v.y[i], v.z[i]); }
static inline hk_Mat3 lane_m3(const hk_Mat3x2 *a, int l)
{
    hk_Mat3 o;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) o.m[i][j] = a->m[i][j][l];
    return o;
}

/* hk_helix_cn of each lane's x, the same bits (both below 1, the common case inside an
 * element, in the lanes; otherwise lane by lane, whose branches differ). */
void hk_helix_cn_x2(hk_Lanes x, hk_Lanes c[HK_CN_COUNT]);

/* What hk_element_local_rates gives (rot, lam, dd, spin_rate, curve), for the offsets
 * u[0] and u[1] of one element at once, lane i for u[i]: the same bits. */
typedef struct hk_ElementRates2 {
    hk_Mat3x2 rot, lam, dd;
    hk_Vec3x2 spin_rate, curve;
} hk_ElementRates2;
void hk_element_local_rates2(hk_Vec3 k, const double u[2], hk_Vec3 kd, hk_ElementRates2 *out);

/* hk_element_local of order 2 with g for two elements at once, out[i] for the
 * curvatures k[i] at u[i]: the same bits, lane by lane. */
void hk_element_local_order2(const hk_Vec3 k[2], const double u[2], hk_ElementLocal out[2]);

/* hk_element_offset with its Jacobian dd (not NULL) for the offsets u[0] and u[1] of one
 * element at once: the same bits, lane by lane; with tangent (may be NULL) column 0 of
 * the rotation exp(u [k]x), hk_element_local's bits. */
void hk_element_offset2(hk_Vec3 k, const double u[2], hk_Vec3x2 *offset, hk_Mat3x2 *dd, hk_Vec3x2 *tangent);

/* hk_element_offset_derivs (from hk_element_offset_begin's c) for the offsets u[0] and
 * u[1] of one element at once: dd[i] and, when d2d0 is not NULL, the second
 * derivatives into d2d0 and d2d1; the same bits, lane by lane. */
void hk_element_offset_derivs2(hk_Vec3 k, const double u[2], hk_Mat3 dd[2], hk_Vec3 d2d0[3][3], hk_Vec3 d2d1[3][3]);

/* hk_element_slide's offset and slide (slide may be NULL: the offset alone, which is
 * also hk_element_offset's) for the offsets u[0] and u[1] of one element at once: the
 * same bits, lane by lane. */
void hk_element_slide2(hk_Vec3 k, const double u[2], hk_Vec3 kd, hk_Vec3x2 *offset, hk_Vec3x2 *slide);

/* Rotation exp(u [k]x), Lambda(u; k) applied to kd and the offset's derivative along
 * kd (dd kd), in the element's frame: what a point's velocity takes, without the
 * Jacobians' matrices. d (column 0 of Lambda) in *offset. */
void hk_element_motion(hk_Vec3 k, double u, hk_Vec3 kd, hk_Mat3 *rot, hk_Vec3 *offset, hk_Vec3 *spin, hk_Vec3 *slide);

/* hk_element_motion's offset and slide alone (the same bits), without the rotation and
 * Lambda: what a point's position and velocity take inside its element. */
void hk_element_slide(hk_Vec3 k, double u, hk_Vec3 kd, hk_Vec3 *offset, hk_Vec3 *slide);

/* Only the offset d(u; k) and, when dd is not NULL, its Jacobian in k (order 1), and
 * when d2d is not NULL its second derivatives (order 2): the cheap path used for
 * collision samples inside an element. */
hk_Vec3 hk_element_offset(hk_Vec3 k, double u, hk_Mat3 *dd, hk_Vec3 d2d[3][3]);

/* The same in two stages, so that a caller can test the position before paying for
 * derivatives: hk_element_offset_begin fills c and returns d;
 * hk_element_offset_derivs then reuses c. */
hk_Vec3 hk_element_offset_begin(hk_Vec3 k, double u, double c[HK_CN_COUNT]);
void hk_element_offset_derivs(hk_Vec3 k, double u, const double c[HK_CN_COUNT], hk_Mat3 *dd, hk_Vec3 d2d[3][3]);

#endif
