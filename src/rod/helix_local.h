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
