/* Marschner's hair scattering (src/render/marschner.c) against what the model must
 * satisfy by construction (Marschner et al. 2003): finite and non-negative, the
 * fibre's reciprocity S(l, e) = S(e, l), the R lobe a Gaussian of width beta_R about
 * alpha_R in theta_h, TT dominating forward scattering and vanishing in an opaque
 * fibre, colour from absorption, and the energy balance of a fibre (d'Eon et al.
 * 2011: int S cos(theta_o) d omega_o <= 1 for a lossless fibre). */
#include <math.h>

#include "hk_test.h"
#include "render/shading.h"


static hk_Vec3 random_unit(void)
{
    const double z = 2.0 * hk_test_uniform() - 1.0, a = 2.0 * HK_PI * hk_test_uniform(), r = sqrt(1.0 - z * z);
    return hk_v3(r * cos(a), r * sin(a), z);
}

/* S itself: the shading value divided by the projected irradiance cos(theta_i). */
static hk_Vec3 scattering(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_MarschnerParams *p)
{
    const double sin_i = hk_v3_dot(t, l);
    return hk_v3_scale(hk_shade_marschner(t, l, e, p), 1.0 / sqrt(1.0 - sin_i * sin_i));
}

/* Directions from longitudinal angle theta (from the normal plane) and azimuth phi,
 * for the fibre t = +x. */
static hk_Vec3 dir(double theta, double phi) { return hk_v3(sin(theta), cos(theta) * cos(phi), cos(theta) * sin(phi)); }

static void test_finite_non_negative(void **state)
{
    (void)state;
    const hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.3, 0.15, 0.05));
    for (int i = 0; i < 20000; i++) {
        const hk_Vec3 c = hk_shade_marschner(random_unit(), random_unit(), random_unit(), &p);
        assert_true(isfinite(c.x) && isfinite(c.y) && isfinite(c.z));
        assert_true(c.x >= 0.0 && c.y >= 0.0 && c.z >= 0.0);
    }
    const hk_Vec3 t = hk_v3(1, 0, 0), u = hk_v3(0, 1, 0);
    const hk_Vec3 cases[][2] = {{t, u}, {u, t}, {t, t}, {t, hk_v3_neg(t)}, {u, u}, {u, hk_v3_neg(u)}};
    for (int i = 0; i < 6; i++) {
        const hk_Vec3 c = hk_shade_marschner(t, cases[i][0], cases[i][1], &p);
        assert_true(isfinite(c.x) && c.x >= 0.0);
    }
}

/* Every factor of S is symmetric in l and e: theta_h and phi are, theta_d changes
 * sign (cos^2 and the Fresnel and absorption terms use its cosine). */
static void test_reciprocity(void **state)
{
    (void)state;
    const hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.6, 0.4, 0.2));
    for (int i = 0; i < 5000; i++) {
        const hk_Vec3 t = random_unit(), l = random_unit(), e = random_unit();
        if (fabs(hk_v3_dot(t, l)) > 0.99 || fabs(hk_v3_dot(t, e)) > 0.99) continue;
        const hk_Vec3 a = scattering(t, l, e, &p), b = scattering(t, e, l, &p);
        hk_assert_rel(a.x, b.x, 1e-9, 1e-300);
        hk_assert_rel(a.z, b.z, 1e-9, 1e-300);
    }
}

/* In an opaque fibre only R is left; at fixed theta_d and phi = 0 it is proportional
 * to M_R(theta_h) = Gaussian(beta_R; theta_h - alpha_R). */
static void test_r_lobe(void **state)
{
    (void)state;
    hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.5, 0.5, 0.5));
    p.sigma_a = hk_v3(1e4, 1e4, 1e4);
    const hk_Vec3 t = hk_v3(1, 0, 0);
    const double theta_d = 0.2;
    double best = -1.0, best_h = 0.0;
    for (int k = -400; k <= 400; k++) {
        const double h = k * 0.001;
        const double v = scattering(t, dir(h - theta_d, 0.0), dir(h + theta_d, 0.0), &p).x;
        if (v > best) best = v, best_h = h;
    }
    hk_assert_near(best_h, p.alpha_r, 0.001);
    const double at = scattering(t, dir(p.alpha_r - theta_d, 0.0), dir(p.alpha_r + theta_d, 0.0), &p).x;
    const double off =
        scattering(t, dir(p.alpha_r + p.beta_r - theta_d, 0.0), dir(p.alpha_r + p.beta_r + theta_d, 0.0), &p).x;
    hk_assert_rel(off / at, exp(-0.5), 1e-9, 0.0);
}

static void test_forward_scattering(void **state)
{
    (void)state;
    const hk_Vec3 t = hk_v3(1, 0, 0), l = dir(0.1, 0.0);
    hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.9, 0.9, 0.9));
    const double behind = scattering(t, l, dir(-0.1, HK_PI), &p).x; /* light shining through */
    const double front = scattering(t, l, dir(-0.1, 0.0), &p).x;
    assert_true(behind > 10.0 * front);
    p.sigma_a = hk_v3(1e4, 1e4, 1e4);
    assert_true(scattering(t, l, dir(-0.1, HK_PI), &p).x < 1e-6 * behind);
}

/* Darker channels absorb more (Chiang et al. 2016's mapping is monotonic), and light
 * through a red fibre comes out red. */
static void test_colour(void **state)
{
    (void)state;
    const hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.8, 0.3, 0.1));
    assert_true(p.sigma_a.x < p.sigma_a.y && p.sigma_a.y < p.sigma_a.z);
    const hk_Vec3 c = scattering(hk_v3(1, 0, 0), dir(0.1, 0.0), dir(-0.1, HK_PI), &p);
    assert_true(c.x > c.y && c.y > c.z);
    const hk_MarschnerParams white = hk_marschner_params_from_color(hk_v3(1, 1, 1));
    assert_true(white.sigma_a.x < 1e-5); /* a white fibre barely absorbs */
}

/* int S cos(theta_o) d omega_o over the sphere (midpoint rule, 300 x 600). */
static double albedo(const hk_MarschnerParams *p, double theta_i)
{
    const int n = 300;
    const hk_Vec3 t = hk_v3(1, 0, 0), l = dir(theta_i, 0.0);
    double sum = 0.0;
    for (int a = 0; a < n; a++) {
        const double th = -HK_PI / 2 + HK_PI * (a + 0.5) / n;
        for (int b = 0; b < 2 * n; b++) {
            const double ph = 2 * HK_PI * (b + 0.5) / (2 * n);
            sum += scattering(t, l, dir(th, ph), p).x * cos(th) * cos(th) * (HK_PI / n) * (HK_PI / n);
        }
    }
    return sum;
}

/* A lossless fibre at normal incidence scatters at most what it receives (here 0.97:
 * Fresnel and the fitted azimuthal terms). At oblique incidence Marschner's
 * 1 / cos^2(theta_d) lets the lossless fibre gain up to 13% at 57 degrees, a known
 * limitation of the model (d'Eon et al. 2011), so there only absorbing fibres are
 * held to the bound. */
static void test_energy(void **state)
{
    (void)state;
    hk_MarschnerParams p = hk_marschner_params_from_color(hk_v3(0.5, 0.5, 0.5));
    p.sigma_a = hk_v3(0, 0, 0);
    const double lossless = albedo(&p, 0.0);
    assert_true(lossless <= 1.0 && lossless > 0.9);
    p.sigma_a = hk_v3(0.5, 0.5, 0.5);
    for (int k = 0; k < 3; k++) {
        const double a = albedo(&p, 0.5 * k);
        assert_true(a < 0.5 && a > 0.3);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_finite_non_negative), cmocka_unit_test(test_reciprocity), cmocka_unit_test(test_r_lobe),
        cmocka_unit_test(test_forward_scattering),  cmocka_unit_test(test_colour),      cmocka_unit_test(test_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
