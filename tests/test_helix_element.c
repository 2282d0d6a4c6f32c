/* Closed forms of one helical element (src/rod/helix_*.c) against independent
 * references: long-double evaluations of the c_n functions, Rodrigues' rotation with an
 * explicit axis and angle, numerical quadrature of the integrals Lambda, d and g, and
 * finite differences for the derivatives. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "rod/helix_local.h"

/* Reference c_n(x) in long double: series where it does not cancel, otherwise the
 * trigonometric closed form with upward recurrence (both in 64-bit mantissa). */
static long double ref_cn(long double x, int n)
{
    if (x < 4.0L || x < (long double)((n + 1) * (n + 2))) {
        long double term = 1.0L, sum;
        for (int k = 1; k <= n; k++) term /= k;
        sum = term;
        for (int k = 0; k < 200; k++) {
            term *= -x / ((long double)(2 * k + n + 1) * (long double)(2 * k + n + 2));
            sum += term;
            if (fabsl(term) < 1e-30L) break;
        }
        return sum;
    }
    long double th = sqrtl(x);
    long double c[12];
    c[0] = cosl(th);
    c[1] = sinl(th) / th;
    long double f = 1.0L;
    for (int k = 2; k <= n; k++) {
        f = 1.0L;
        for (int j = 2; j <= k - 2; j++) f *= j;
        c[k] = (1.0L / f - c[k - 2]) / x;
    }
    return c[n];
}

/* Natural magnitude of the terms c_n multiplies in the closed forms: 1/n! near 0 and
 * about 1/((n-2)! x) for large x (from c_n = (1/(n-2)! - c_{n-2}) / x). */
static double cn_scale(double x, int n)
{
    double f = 1.0;
    for (int k = 2; k <= n; k++) f *= k;
    if (n == 0) return 1.0;
    if (n == 1) return 1.0 / fmax(1.0, sqrt(x));
    return fmin(1.0 / f, n * (n - 1) / (f * x));
}

static void check_cn_at(double x, double *worst)
{
    double c[HK_CN_COUNT];
    hk_helix_cn(x, c);
    for (int n = 0; n < HK_CN_COUNT; n++) {
        long double r = ref_cn((long double)x, n);
        /* theta = sqrt(x) itself carries a rounding of ulp(theta), so the absolute
         * error of cos(theta) is inherently ~ eps * theta: the tolerance grows with it. */
        double tol = 4e-15 * fmax(1.0, sqrt(x)) * cn_scale(x, n);
        double err = fabs((double)(c[n] - r));
        if (err / tol > *worst) *worst = err / tol;
        if (err > tol) print_error("x = %.17g n = %d: c = %.17g ref = %.17Lg\n", x, n, c[n], r);
    }
}

static void test_cn_against_long_double(void **state)
{
    (void)state;
    double worst = 0.0;
    /* 24 decades of x, from straight elements to hundreds of turns per element. */
    for (int i = 0; i <= 600; i++) check_cn_at(i == 0 ? 0.0 : pow(10.0, -12.0 + 16.0 * (i - 1) / 599.0), &worst);
    /* Both sides of every switch between series and recurrence (x = 1 and
     * x = (n-1) n / 2): a wrong threshold would show up here first. */
    const double switches[] = {1.0, 3.0, 6.0, 10.0, 15.0, 21.0, 28.0};
    for (size_t s = 0; s < sizeof switches / sizeof *switches; s++) {
        check_cn_at(nextafter(switches[s], 0.0), &worst);
        check_cn_at(switches[s], &worst);
    }
    assert_true(worst <= 1.0);
}

static hk_Mat3 rodrigues(hk_Vec3 axis, double angle)
{
    /* R = cos a I + sin a [k]x + (1 - cos a) k k^T with unit k: an independent form. */
    hk_Vec3 k = hk_v3_normalize(axis);
    hk_Mat3 r = hk_m3_outer(k, k), s = hk_m3_skew(k);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = (1.0 - cos(angle)) * r.m[i][j] + sin(angle) * s.m[i][j] + (i == j) * cos(angle);
    return r;
}

static void test_rotation_matches_rodrigues(void **state)
{
    (void)state;
    const hk_Vec3 ks[] = {{1, 0, 0}, {0.3, -2, 0.7}, {40, 150, -3}, {1e-3, 2e-3, -1e-3}, {0, 0, 500}};
    const double us[] = {0.01, 0.2, 0.05, 1.0, 0.03};
    for (size_t t = 0; t < sizeof ks / sizeof *ks; t++) {
        hk_ElementLocal el;
        hk_element_local(ks[t], us[t], 0, 0, &el);
        hk_Mat3 ref = rodrigues(ks[t], hk_v3_norm(ks[t]) * us[t]);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) hk_assert_near(el.rot.m[i][j], ref.m[i][j], 2e-15);
    }
}

/* Gauss-Legendre 8-point rule on [a, b] applied to f sampled through a callback. */
static const double gl_x[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290, -0.1834346424956498,
                               0.1834346424956498,  0.5255324099163290,  0.7966664774136267,  0.9602898564975363};
static const double gl_w[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873, 0.3626837833783620,
                               0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};

/* Lambda(u) by composite Gauss-Legendre quadrature of exp(v [k]x) (Rodrigues). */
static hk_Mat3 quad_lambda(hk_Vec3 k, double u)
{
    hk_Mat3 acc = hk_m3_zero();
    const int pieces = 64;
    for (int p = 0; p < pieces; p++) {
        double a = u * p / pieces, b = u * (p + 1) / pieces;
        for (int g = 0; g < 8; g++) {
            double v = 0.5 * (a + b) + 0.5 * (b - a) * gl_x[g];
            double th = hk_v3_norm(k) * v;
            hk_Mat3 r = th > 0 ? rodrigues(k, th) : hk_m3_identity();
            hk_Mat3 w = hk_m3_scale(&r, 0.5 * (b - a) * gl_w[g]);
            acc = hk_m3_add(&acc, &w);
        }
    }
    return acc;
}

static void test_integrals_match_quadrature(void **state)
{
    (void)state;
    const hk_Vec3 ks[] = {{5, 30, 0}, {120, 160, 0}, {-20, 10, 300}, {0.5, 0.1, -0.2}};
    const double u = 0.04;
    for (size_t t = 0; t < sizeof ks / sizeof *ks; t++) {
        hk_ElementLocal el;
        hk_element_local(ks[t], u, 1, 1, &el);
        hk_Mat3 lam = quad_lambda(ks[t], u);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) hk_assert_near(el.lam.m[i][j], lam.m[i][j], 1e-15);
        /* g(u) = int_0^u d(v) dv, d(v) = Lambda(v) e0: quadrature of our d (itself
         * checked above) against the closed form g. */
        hk_Vec3 g = hk_v3_zero();
        const int pieces = 64;
        for (int p = 0; p < pieces; p++) {
            double a = u * p / pieces, b = u * (p + 1) / pieces;
            for (int q = 0; q < 8; q++) {
                double v = 0.5 * (a + b) + 0.5 * (b - a) * gl_x[q];
                hk_Mat3 lv = quad_lambda(ks[t], v);
                g = hk_v3_madd(g, hk_m3_col(&lv, 0), 0.5 * (b - a) * gl_w[q]);
            }
        }
        hk_assert_near(el.g.x, g.x, 1e-16);
        hk_assert_near(el.g.y, g.y, 1e-16);
        hk_assert_near(el.g.z, g.z, 1e-16);
    }
}

static void check_term_derivatives(int m, double alpha, hk_Vec3 phi, hk_Vec3 w)
{
    double c[HK_CN_COUNT];
    hk_HelixTerm t;
    hk_helix_cn(hk_v3_dot(phi, phi), c);
    hk_helix_term(c, m, alpha, phi, w, 2, &t);
    const double h = 1e-5 * fmax(1.0, hk_v3_norm(phi));
    for (int j = 0; j < 3; j++) {
        hk_HelixTerm tp, tm;
        hk_Vec3 pp = phi, pm = phi;
        hk_v3_set(&pp, j, hk_v3_get(phi, j) + h);
        hk_v3_set(&pm, j, hk_v3_get(phi, j) - h);
        double cp[HK_CN_COUNT], cm[HK_CN_COUNT];
        hk_helix_cn(hk_v3_dot(pp, pp), cp);
        hk_helix_cn(hk_v3_dot(pm, pm), cm);
        hk_helix_term(cp, m, alpha, pp, w, 1, &tp);
        hk_helix_term(cm, m, alpha, pm, w, 1, &tm);
        for (int i = 0; i < 3; i++) {
            /* Central differences: truncation ~ h^2 |h'''| / 6, here < 1e-9. */
            double fd = (hk_v3_get(tp.value, i) - hk_v3_get(tm.value, i)) / (2 * h);
            hk_assert_near(t.jac.m[i][j], fd, 1e-9);
            for (int a = 0; a < 3; a++) {
                double fd2 = (tp.jac.m[i][a] - tm.jac.m[i][a]) / (2 * h);
                hk_assert_near(hk_v3_get(t.hess[a][j], i), fd2, 1e-8);
            }
        }
    }
}

static void test_term_derivatives_fd(void **state)
{
    (void)state;
    const hk_Vec3 phis[] = {{0, 0, 0},        {1e-6, -2e-6, 3e-7}, {0.3, 0.2, -0.1}, {0.9, 0.4, 0.1},
                            {2.0, -1.0, 0.5}, {3.5, 4.0, -2.0},    {-6.0, 1.0, 8.0}};
    for (size_t t = 0; t < sizeof phis / sizeof *phis; t++)
        for (int b = 0; b < 3; b++) {
            check_term_derivatives(2, 1.0, phis[t], hk_v3_unit(b));
            check_term_derivatives(3, 0.5, phis[t], hk_v3_unit(b));
        }
}

static void test_element_local_scaling(void **state)
{
    (void)state;
    /* d/dk = u d/dphi: compare dd and d2d with finite differences in k directly. */
    const hk_Vec3 k = {30, -80, 12};
    const double u = 0.03, h = 1e-4;
    hk_ElementLocal el;
    hk_element_local(k, u, 2, 1, &el);
    for (int a = 0; a < 3; a++) {
        hk_Vec3 kp = k, km = k;
        hk_v3_set(&kp, a, hk_v3_get(k, a) + h);
        hk_v3_set(&km, a, hk_v3_get(k, a) - h);
        hk_ElementLocal ep, em;
        hk_element_local(kp, u, 2, 1, &ep);
        hk_element_local(km, u, 2, 1, &em);
        for (int i = 0; i < 3; i++) {
            hk_assert_near(el.dd.m[i][a], (ep.lam.m[i][0] - em.lam.m[i][0]) / (2 * h), 1e-11);
            hk_assert_near(el.dg.m[i][a], (hk_v3_get(ep.g, i) - hk_v3_get(em.g, i)) / (2 * h), 1e-13);
            for (int b = 0; b < 3; b++) {
                hk_assert_near(el.dlam[b].m[i][a], (ep.lam.m[i][b] - em.lam.m[i][b]) / (2 * h), 1e-11);
                hk_assert_near(hk_v3_get(el.d2d[a][b], i), (ep.dd.m[i][b] - em.dd.m[i][b]) / (2 * h), 1e-12);
                hk_assert_near(hk_v3_get(el.d2g[a][b], i), (ep.dg.m[i][b] - em.dg.m[i][b]) / (2 * h), 1e-14);
            }
        }
    }
    /* The cheap offset path agrees with the full element. */
    hk_Mat3 dd;
    hk_Vec3 d2d[3][3];
    hk_Vec3 d = hk_element_offset(k, u, &dd, d2d);
    hk_assert_near(d.x, el.lam.m[0][0], 0.0);
    hk_assert_near(dd.m[1][2], el.dd.m[1][2], 0.0);
    hk_assert_near(d2d[2][1].z, el.d2d[2][1].z, 0.0);
}

/* The bias contractions of hk_element_local_rates against two references: the full
 * order-2 element's dlam and d2d contracted term by term, and finite differences along
 * the rates (d/de of Lambda(k + e kd) kd and d2/de2 of d(k + e kd)). */
static void test_element_rates_contractions(void **state)
{
    (void)state;
    const hk_Vec3 ks[] = {{0, 0, 0}, {1e-5, 2e-5, -1e-5}, {30, -80, 12}, {-5, 3, 40}, {200, 150, -90}};
    const hk_Vec3 kds[] = {{1, -2, 0.5}, {0, 0, 3}, {-40, 25, 10}};
    const double us[] = {0.0, 0.004, 0.03};
    for (size_t t = 0; t < sizeof ks / sizeof *ks; t++)
        for (size_t r = 0; r < sizeof kds / sizeof *kds; r++)
            for (size_t q = 0; q < sizeof us / sizeof *us; q++) {
                const hk_Vec3 k = ks[t], kd = kds[r];
                const double u = us[q], kv[3] = {kd.x, kd.y, kd.z};
                hk_ElementLocal full, fast;
                hk_element_local(k, u, 2, 0, &full);
                hk_Vec3 spin_rate, curve;
                hk_element_local_rates(k, u, kd, &fast, &spin_rate, &curve);
                hk_Vec3 ref_spin = hk_v3_zero(), ref_curve = hk_v3_zero();
                for (int b = 0; b < 3; b++) {
                    ref_spin = hk_v3_madd(ref_spin, hk_m3_mul_v3(&full.dlam[b], kd), kv[b]);
                    for (int a = 0; a < 3; a++) ref_curve = hk_v3_madd(ref_curve, full.d2d[a][b], kv[a] * kv[b]);
                }
                const double scale_spin = u * u * hk_v3_norm2(kd) + 1e-30, scale_curve = scale_spin * u + 1e-30;
                for (int i = 0; i < 3; i++) {
                    hk_assert_near(hk_v3_get(spin_rate, i), hk_v3_get(ref_spin, i), 1e-13 * scale_spin);
                    hk_assert_near(hk_v3_get(curve, i), hk_v3_get(ref_curve, i), 1e-13 * scale_curve);
                    for (int j = 0; j < 3; j++) {
                        hk_assert_near(fast.lam.m[i][j], full.lam.m[i][j], 1e-15 * (u + 1e-30));
                        hk_assert_near(fast.dd.m[i][j], full.dd.m[i][j], 0.0);
                        hk_assert_near(fast.rot.m[i][j], full.rot.m[i][j], 1e-15);
                    }
                }
                /* The velocity-only path: the same rotation, offset, Lambda kd and dd kd. */
                hk_Mat3 rot;
                hk_Vec3 offset, spin, slide;
                hk_element_motion(k, u, kd, &rot, &offset, &spin, &slide);
                const hk_Vec3 ref_lam_kd = hk_m3_mul_v3(&full.lam, kd), ref_dd_kd = hk_m3_mul_v3(&full.dd, kd);
                const double scale_rate = u * sqrt(hk_v3_norm2(kd)) + 1e-30;
                for (int i = 0; i < 3; i++) {
                    hk_assert_near(hk_v3_get(offset, i), full.lam.m[i][0], 1e-15 * (u + 1e-30));
                    hk_assert_near(hk_v3_get(spin, i), hk_v3_get(ref_lam_kd, i), 1e-14 * scale_rate);
                    hk_assert_near(hk_v3_get(slide, i), hk_v3_get(ref_dd_kd, i), 1e-14 * scale_rate * u);
                    for (int j = 0; j < 3; j++) hk_assert_near(rot.m[i][j], full.rot.m[i][j], 1e-15);
                }
                /* Finite differences along kd (step e, central; truncation ~ e^2). */
                const double e = 1e-4 / sqrt(hk_v3_norm2(kd));
                hk_ElementLocal ep, em;
                hk_element_local(hk_v3_madd(k, kd, e), u, 1, 0, &ep);
                hk_element_local(hk_v3_madd(k, kd, -e), u, 1, 0, &em);
                const hk_Vec3 fd_spin =
                    hk_v3_scale(hk_v3_sub(hk_m3_mul_v3(&ep.lam, kd), hk_m3_mul_v3(&em.lam, kd)), 0.5 / e);
                const hk_Vec3 fd_curve =
                    hk_v3_scale(hk_v3_sub(hk_m3_mul_v3(&ep.dd, kd), hk_m3_mul_v3(&em.dd, kd)), 0.5 / e);
                for (int i = 0; i < 3; i++) {
                    hk_assert_near(hk_v3_get(spin_rate, i), hk_v3_get(fd_spin, i), 1e-7 * scale_spin);
                    hk_assert_near(hk_v3_get(curve, i), hk_v3_get(fd_curve, i), 1e-7 * scale_curve);
                }
            }
}

static double largest_entry(const hk_Mat3 *m)
{
    double big = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) big = fmax(big, fabs(m->m[i][j]));
    return big;
}

/* The elements' terms along e0 (the offset's and g's Jacobians, written out for w = e0)
 * against hk_helix_term's general w, and the point-only path (hk_element_slide) against
 * hk_element_motion bit for bit. */
static void test_e0_terms_against_general(void **state)
{
    (void)state;
    const hk_Vec3 ks[] = {{0, 0, 0}, {1e-5, 2e-5, -1e-5}, {30, -80, 12}, {-5, 3, 40}, {200, 150, -90}};
    const double us[] = {0.0, 0.004, 0.03};
    const hk_Vec3 kd = {-40, 25, 10};
    for (size_t t = 0; t < sizeof ks / sizeof *ks; t++)
        for (size_t q = 0; q < sizeof us / sizeof *us; q++) {
            const double u = us[q];
            const hk_Vec3 phi = hk_v3_scale(ks[t], u);
            double c[HK_CN_COUNT];
            hk_helix_cn(hk_v3_dot(phi, phi), c);
            hk_HelixTerm d, g;
            hk_helix_term(c, 2, 1.0, phi, hk_v3_unit(0), 1, &d);
            hk_helix_term(c, 3, 0.5, phi, hk_v3_unit(0), 1, &g);
            const hk_Mat3 ref_dd = hk_m3_scale(&d.jac, u * u), ref_dg = hk_m3_scale(&g.jac, u * u * u);
            hk_ElementLocal el;
            hk_element_local(ks[t], u, 1, 1, &el);
            const double tol_dd = 1e-15 * largest_entry(&ref_dd), tol_dg = 1e-15 * largest_entry(&ref_dg);
            for (int i = 0; i < 3; i++) {
                hk_assert_near(hk_v3_get(el.g, i), hk_v3_get(g.value, i) * u * u, 1e-16 * u * u);
                for (int j = 0; j < 3; j++) {
                    hk_assert_near(el.dd.m[i][j], ref_dd.m[i][j], tol_dd);
                    hk_assert_near(el.dg.m[i][j], ref_dg.m[i][j], tol_dg);
                }
            }
            hk_Mat3 rot;
            hk_Vec3 offset, spin, slide, offset2, slide2;
            hk_element_motion(ks[t], u, kd, &rot, &offset, &spin, &slide);
            hk_element_slide(ks[t], u, kd, &offset2, &slide2);
            for (int i = 0; i < 3; i++) {
                hk_assert_near(hk_v3_get(offset2, i), hk_v3_get(offset, i), 0.0);
                hk_assert_near(hk_v3_get(slide2, i), hk_v3_get(slide, i), 0.0);
            }
        }
}

static int same_vec(hk_Vec3 a, hk_Vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }
static int same_mat(const hk_Mat3 *a, const hk_Mat3 *b) { return memcmp(a, b, sizeof *a) == 0; }

/* The two-lane paths (two offsets or two elements at once) against the scalar ones, bit
 * for bit, signed zeros included: each lane must repeat the scalar operations in their
 * order. Lanes take different curvatures, offsets and branches of c_n (x below and
 * above 1). */
static void test_two_lanes_bit_for_bit(void **state)
{
    (void)state;
    const hk_Vec3 ks[] = {{0, 0, 0}, {1e-5, 2e-5, -1e-5}, {30, -80, 12}, {-5, 3, 40}, {200, 150, -90}};
    const double us[] = {0.0, 0.004, 0.03};
    const hk_Vec3 kd = {-40, 25, 10};
    const size_t nk = sizeof ks / sizeof *ks, nu = sizeof us / sizeof *us;
    const double xs[] = {0.0, 1e-12, 0.3, 0.9999999999999999, 1.0, 1.5, 27.0, 400.0};
    const size_t nx = sizeof xs / sizeof *xs;
    for (size_t a = 0; a < nx; a++)
        for (size_t b = 0; b < nx; b++) { /* both lanes below 1, one, neither */
            hk_Lanes c[HK_CN_COUNT];
            double ca[HK_CN_COUNT], cb[HK_CN_COUNT];
            hk_helix_cn_x2((hk_Lanes){xs[a], xs[b]}, c);
            hk_helix_cn(xs[a], ca);
            hk_helix_cn(xs[b], cb);
            for (int n = 0; n < HK_CN_COUNT; n++) {
                const double la = c[n][0], lb = c[n][1];
                assert_true(memcmp(&la, &ca[n], sizeof la) == 0 && memcmp(&lb, &cb[n], sizeof lb) == 0);
            }
        }
    for (size_t t = 0; t < nk; t++)
        for (size_t q = 0; q < nu; q++) {
            const hk_Vec3 k2[2] = {ks[t], ks[(t + 2) % nk]};
            const double u[2] = {us[q], us[(q + 1) % nu]};
            hk_ElementLocal pair[2], one;
            hk_element_local_order2(k2, u, pair);
            hk_ElementRates2 rates;
            hk_element_local_rates2(ks[t], u, kd, &rates);
            hk_Vec3x2 offset, slide, offset_only, offset_dd, tangent;
            hk_Mat3x2 dd;
            hk_element_slide2(ks[t], u, kd, &offset, &slide);
            hk_element_slide2(ks[t], u, kd, &offset_only, NULL);
            hk_element_offset2(ks[t], u, &offset_dd, &dd, &tangent);
            hk_Mat3 dd2[2];
            hk_Vec3 d2d0[3][3], d2d1[3][3];
            hk_element_offset_derivs2(ks[t], u, dd2, d2d0, d2d1);
            for (int l = 0; l < 2; l++) {
                hk_element_local(k2[l], u[l], 2, 1, &one);
                assert_true(memcmp(&pair[l], &one, sizeof one) == 0);
                hk_ElementLocal el;
                hk_Vec3 spin_rate, curve;
                hk_element_local_rates(ks[t], u[l], kd, &el, &spin_rate, &curve);
                const hk_Mat3 rot = lane_m3(&rates.rot, l), lam = lane_m3(&rates.lam, l), rdd = lane_m3(&rates.dd, l);
                assert_true(same_mat(&rot, &el.rot) && same_mat(&lam, &el.lam) && same_mat(&rdd, &el.dd));
                assert_true(same_vec(lane_v3(tangent, l), hk_m3_col(&el.rot, 0)));
                assert_true(same_vec(lane_v3(rates.spin_rate, l), spin_rate));
                assert_true(same_vec(lane_v3(rates.curve, l), curve));
                hk_Vec3 o, sl;
                hk_element_slide(ks[t], u[l], kd, &o, &sl);
                assert_true(same_vec(lane_v3(offset, l), o) && same_vec(lane_v3(slide, l), sl));
                assert_true(same_vec(lane_v3(offset_only, l), o));
                hk_Mat3 ref_dd;
                hk_Vec3 ref_d2d[3][3];
                assert_true(same_vec(lane_v3(offset_dd, l), hk_element_offset(ks[t], u[l], &ref_dd, ref_d2d)));
                const hk_Mat3 odd = lane_m3(&dd, l);
                assert_true(same_mat(&odd, &ref_dd) && same_mat(&dd2[l], &ref_dd));
                assert_true(memcmp(l == 0 ? d2d0 : d2d1, ref_d2d, sizeof ref_d2d) == 0);
            }
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cn_against_long_double),     cmocka_unit_test(test_rotation_matches_rodrigues),
        cmocka_unit_test(test_integrals_match_quadrature), cmocka_unit_test(test_term_derivatives_fd),
        cmocka_unit_test(test_element_local_scaling),      cmocka_unit_test(test_element_rates_contractions),
        cmocka_unit_test(test_e0_terms_against_general),   cmocka_unit_test(test_two_lanes_bit_for_bit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
