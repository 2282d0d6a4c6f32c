/* The dual scattering approximation (src/render/dual_scattering.c; Zinke et al. 2008)
 * against what it must satisfy: its table of a_f and a_b against the same integrals
 * of Marschner's lobes done another way; the bounds of the local scattering sums
 * (a fibre returns at most what it receives); a fibre deep in shadow still lit, the
 * more the lighter the hair; with opaque fibres nothing is added to single scattering
 * beyond the computed local term; the forward-scattered fraction between 0 and the
 * light the fibres in front stop. */
#include <math.h>

#include "hk_test.h"
#include "render/shading.h"


static double ch(hk_Vec3 v, int c) { return c == 0 ? v.x : c == 1 ? v.y : v.z; }

/* A fibre of the hair colour c (linear), as the renderer makes it. */
static hk_MarschnerParams fibre(hk_Vec3 c) { return hk_marschner_params_from_color(c); }

/* Unit vectors making an orthonormal frame with t. */
static void frame(hk_Vec3 t, hk_Vec3 *u, hk_Vec3 *w)
{
    const hk_Vec3 a = fabs(t.x) < 0.9 ? hk_v3(1, 0, 0) : hk_v3(0, 1, 0);
    *u = hk_v3_normalize(hk_v3_cross(t, a));
    *w = hk_v3_cross(t, *u);
}

/* a_f and a_b of a fibre along a tilted tangent, lit at incidence theta_i, by the
 * midpoint rule in the equal-area coordinates z = t.e and psi about t (d omega = dz
 * dpsi): int S cos(theta_o) d omega over the half-spaces, S = lobes / cos(theta_i), the
 * forward one where e's and l's projections on the normal plane point apart. The
 * table integrates in (theta_o, phi) about the fibre x axis on another grid. */
static void integrate(const hk_MarschnerParams *p, double theta_i, hk_Vec3 *a_f, hk_Vec3 *a_b)
{
    const hk_Vec3 t = hk_v3_normalize(hk_v3(0.3, 0.8, -0.5));
    hk_Vec3 u, w;
    frame(t, &u, &w);
    const hk_Vec3 l = hk_v3_add(hk_v3_scale(t, sin(theta_i)),
                                hk_v3_scale(hk_v3_add(hk_v3_scale(u, 0.6), hk_v3_scale(w, 0.8)), cos(theta_i)));
    const hk_Vec3 lp = hk_v3_madd(l, t, -hk_v3_dot(t, l));
    enum { NZ = 600, NPSI = 400 };
    *a_f = *a_b = hk_v3_zero();
    for (int i = 0; i < NZ; i++) {
        const double z = -1.0 + (i + 0.5) * 2.0 / NZ, r = sqrt(1.0 - z * z);
        for (int j = 0; j < NPSI; j++) {
            const double psi = (j + 0.5) * 2.0 * HK_PI / NPSI;
            const hk_Vec3 e =
                hk_v3_add(hk_v3_scale(t, z), hk_v3_add(hk_v3_scale(u, r * cos(psi)), hk_v3_scale(w, r * sin(psi))));
            const hk_Vec3 s = hk_shade_marschner(t, l, e, p);
            const double weight = r / cos(theta_i) * (2.0 / NZ) * (2.0 * HK_PI / NPSI);
            const hk_Vec3 ep = hk_v3_madd(e, t, -z);
            hk_Vec3 *sum = hk_v3_dot(ep, lp) < 0.0 ? a_f : a_b;
            *sum = hk_v3_madd(*sum, s, weight);
        }
    }
}

static void test_table_against_integration(void **state)
{
    (void)state;
    const hk_Vec3 colours[] = {hk_v3(0.19, 0.045, 0.002), hk_v3(0.6, 0.45, 0.3), hk_v3(0.02, 0.02, 0.02)};
    const int incidences[] = {4, 8, 9, 12, 15}; /* -45, -5, 5, 35 and 65 degrees */
    for (int c = 0; c < 3; c++) {
        const hk_MarschnerParams p = fibre(colours[c]);
        hk_DualScattering ds;
        hk_dual_scattering_init(&p, &ds);
        for (int k = 0; k < 5; k++) {
            const int at = incidences[k];
            const double ti = -0.5 * HK_PI + HK_PI * (at + 0.5) / HK_DUAL_THETA;
            hk_Vec3 af, ab;
            integrate(&p, ti, &af, &ab);
            /* The table scales a fibre that would return more than it receives (the
             * blond one, at oblique incidence) down to 1. */
            for (int q = 0; q < 3; q++) {
                const double total = ch(af, q) + ch(ab, q), keep = total > 1.0 ? 1.0 / total : 1.0;
                if (c != 1) assert_true(total < 1.0);
                hk_assert_rel(ch(ds.at[at].a_f, q), keep * ch(af, q), 0.01, 1e-3);
                hk_assert_rel(ch(ds.at[at].a_b, q), keep * ch(ab, q), 0.01, 1e-3);
                /* the lobes' albedos add up to both */
                const double lobes = ch(ds.at[at].lobe[0], q) + ch(ds.at[at].lobe[1], q) + ch(ds.at[at].lobe[2], q);
                hk_assert_rel(lobes, ch(ds.at[at].a_f, q) + ch(ds.at[at].a_b, q), 1e-9, 1e-12);
            }
            /* Brown and blond hair scatter mostly forward (TT), at normal incidence. */
            if (c < 2 && (at == 8 || at == 9)) assert_true(ds.at[at].a_f.x > 3.0 * ds.at[at].a_b.x);
        }
        /* The lookup interpolates between the table's entries and meets them there. */
        const double ti = -0.5 * HK_PI + HK_PI * 10.0 / HK_DUAL_THETA; /* between entries 9 and 10 */
        const hk_DualEntry en = hk_dual_lookup(&ds, sin(ti));
        hk_assert_rel(en.a_f.x, 0.5 * (ds.at[9].a_f.x + ds.at[10].a_f.x), 1e-9, 1e-12);
        const hk_DualEntry exact = hk_dual_lookup(&ds, sin(-0.5 * HK_PI + HK_PI * 9.5 / HK_DUAL_THETA));
        hk_assert_rel(exact.A_b.y, ds.at[9].A_b.y, 1e-9, 1e-12);
    }
}

/* A lossless fibre: the table's a_f + a_b is what the fibre returns, at most 1 (scaled
 * down where Marschner's model gains), and the local sums are bounded: with a_f + a_b
 * <= 1, A_1 = a_b a_f^2 / (1 - a_f^2) <= a_f^2 / (1 + a_f) < 1/2 and A_3 =
 * a_b^3 a_f^2 / (1 - a_f^2)^3 <= a_f^2 / (1 + a_f)^3 < 1/8. */
static void test_local_bounds(void **state)
{
    (void)state;
    hk_MarschnerParams p = fibre(hk_v3(0.5, 0.5, 0.5));
    const hk_Vec3 sigmas[] = {hk_v3(0, 0, 0), hk_v3(0.01, 0.1, 1.0), hk_v3(3, 10, 1e4)};
    for (int s = 0; s < 3; s++) {
        p.sigma_a = sigmas[s];
        hk_DualScattering ds;
        hk_dual_scattering_init(&p, &ds);
        for (int k = 0; k < HK_DUAL_THETA; k++)
            for (int c = 0; c < 3; c++) {
                const double af = ch(ds.at[k].a_f, c), ab = ch(ds.at[k].a_b, c), A = ch(ds.at[k].A_b, c);
                assert_true(af >= 0.0 && ab >= 0.0 && af + ab <= 1.0 + 1e-12);
                assert_true(A >= 0.0 && A < 0.625);
                assert_true(isfinite(ch(ds.at[k].delta_b, c)) && ch(ds.at[k].sigma_b2, c) > 0.0);
            }
        if (s == 0) /* lossless at normal incidence: Fresnel's and the fits' 3% lost */
            assert_true(ds.at[9].a_f.x + ds.at[9].a_b.x > 0.9);
    }
}

/* int f cos(theta_o) d omega of a shading function over the sphere, for the fibre x
 * lit at incidence theta_i (f: the returned value over cos(theta_i)). */
static hk_Vec3 sphere_integral(hk_Vec3 (*shade)(const void *, hk_Vec3, hk_Vec3, hk_Vec3), const void *user,
                               double theta_i)
{
    const hk_Vec3 t = hk_v3(1, 0, 0), l = hk_v3(sin(theta_i), cos(theta_i), 0);
    enum { N = 240 };
    hk_Vec3 sum = hk_v3_zero();
    for (int a = 0; a < N; a++) {
        const double th = -0.5 * HK_PI + HK_PI * (a + 0.5) / N;
        for (int b = 0; b < 2 * N; b++) {
            const double ph = HK_PI * (b + 0.5) / N;
            const hk_Vec3 e = hk_v3(sin(th), cos(th) * cos(ph), cos(th) * sin(ph));
            sum = hk_v3_madd(sum, shade(user, t, l, e), cos(th) * cos(th) * (HK_PI / N) * (HK_PI / N) / cos(theta_i));
        }
    }
    return sum;
}

static hk_Vec3 local_of(const void *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e) { return hk_dual_local(ds, t, l, e); }
static hk_Vec3 dual_minus_single(const void *user, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e)
{
    const hk_DualScattering *ds = user;
    const hk_Vec3 d = hk_v3_sub(hk_shade_dual_marschner(ds, t, l, e, 0.0), hk_shade_marschner(t, l, e, &ds->fibre));
    return hk_v3(fabs(d.x), fabs(d.y), fabs(d.z));
}

/* In full light (no fibre in front) dual scattering adds the local backscattering
 * d_b B to the single lobes and nothing else; B sends A_b into the backward
 * half-space, and as much on the forward side (the paper's lobe has no azimuth), so
 * it adds 2 d_b A_b at most. With opaque fibres (only the surface reflection R left)
 * A_b is tiny and the dual model tends to the single one. */
static void test_unshadowed_tends_to_single(void **state)
{
    (void)state;
    hk_MarschnerParams p = fibre(hk_v3(0.3, 0.2, 0.1));
    const double sigma[] = {0.05, 1e4};
    for (int s = 0; s < 2; s++) {
        p.sigma_a = hk_v3(sigma[s], sigma[s], sigma[s]);
        hk_DualScattering ds;
        hk_dual_scattering_init(&p, &ds);
        for (int k = 0; k < 3; k++) {
            const double ti = -0.6 + 0.6 * k;
            const hk_DualEntry en = hk_dual_lookup(&ds, sin(ti));
            const double bound = 2.0 * HK_DUAL_DB * en.A_b.x;
            const hk_Vec3 local = sphere_integral(local_of, &ds, ti);
            const hk_Vec3 added = sphere_integral(dual_minus_single, &ds, ti);
            assert_true(local.x <= bound * 1.02 + 1e-9);
            hk_assert_rel(added.x, local.x, 1e-6, 1e-12);
            if (s == 1) {
                assert_true(en.A_b.x < 0.01);
                assert_true(added.x < 0.02);
            } else {
                assert_true(local.x > 0.02); /* translucent hair: a real local term */
            }
        }
    }
}

/* A fibre deep in shadow, behind 12 fibres (1 in 160,000 rays gets through unscattered):
 * single scattering leaves it dark, dual scattering lights it with the light forward-
 * scattered through the fibres, more for lighter hair, and coloured: the channels the
 * fibre absorbs least come through most. */
static void test_shadowed_fibre(void **state)
{
    (void)state;
    const hk_Vec3 t = hk_v3(0, 1, 0), l = hk_v3_normalize(hk_v3(0.3, 0.2, 1.0)),
                  e = hk_v3_normalize(hk_v3(-0.2, 0.1, 1.0));
    const double n = 12.0, greys[] = {0.1, 0.3, 0.6, 0.9};
    double last_m = 0.0, last_k = 0.0;
    for (int g = 0; g < 4; g++) {
        const hk_Vec3 c = hk_v3(greys[g], greys[g], greys[g]);
        const hk_MarschnerParams p = fibre(c);
        hk_DualScattering ds;
        hk_dual_scattering_init(&p, &ds);
        hk_Visuality v = hk_default_visuality();
        v.diffuse = c;
        const hk_Vec3 m = hk_shade_dual_marschner(&ds, t, l, e, n), k = hk_shade_dual_kajiya_kay(&ds, t, l, e, n, &v);
        const double single_m = exp(-n) * hk_shade_marschner(t, l, e, &p).x,
                     single_k = exp(-n) * hk_shade_kajiya_kay(t, l, e, &v).x;
        assert_true(m.x > last_m && k.x > last_k);
        last_m = m.x, last_k = k.x;
        if (g >= 1) {
            assert_true(m.x > 100.0 * single_m);
            assert_true(k.x > 100.0 * single_k);
        }
    }
    assert_true(last_m > 1e-3 && last_k > 1e-2);
    /* Brown: red comes through more than green, green more than blue. */
    const hk_Vec3 brown = hk_v3(0.19, 0.045, 0.01);
    const hk_MarschnerParams p = fibre(brown);
    hk_DualScattering ds;
    hk_dual_scattering_init(&p, &ds);
    const hk_Vec3 m = hk_shade_dual_marschner(&ds, t, l, e, 4.0);
    assert_true(m.x > 2.0 * m.y && m.y > 2.0 * m.z);
}

/* The forward-scattered fraction G = d_f (exp(-n (1 - a_f)) - exp(-n)): 0 with no fibre
 * in front and with fibres that scatter nothing forward, never more than d_f times the
 * light the fibres stop (1 - exp(-n)), largest at a moderate count, and growing with
 * a_f. */
static void test_global_fraction(void **state)
{
    (void)state;
    hk_DualEntry en = {0};
    en.a_f = hk_v3(0.8, 0.4, 0.0);
    const hk_Vec3 none = hk_dual_global_fraction(&en, 0.0);
    assert_true(none.x == 0.0 && none.y == 0.0 && none.z == 0.0);
    double prev = -1.0;
    for (int i = 1; i <= 200; i++) {
        const double n = 0.1 * i;
        const hk_Vec3 g = hk_dual_global_fraction(&en, n);
        assert_true(g.x <= HK_DUAL_DF * (1.0 - exp(-n)) + 1e-15);
        assert_true(g.x >= g.y && g.y >= g.z && g.z == 0.0);
        if (n > 6.0) assert_true(g.x < prev); /* decays deep inside */
        prev = g.x;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_against_integration),
        cmocka_unit_test(test_local_bounds),
        cmocka_unit_test(test_unshadowed_tends_to_single),
        cmocka_unit_test(test_shadowed_fibre),
        cmocka_unit_test(test_global_fraction),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
