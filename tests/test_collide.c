/* Collision shapes (src/collide/): penetration values at known points, gradients and
 * Hessians against finite differences, the layered envelopes of thesis §4.1.2.2 and
 * the quick-rejection bound. */
#include "hk_test.h"

#include <math.h>

#include "hairkit/collide.h"

static const hk_Vec3 rotated_axes[3] = {{0.8, 0.6, 0.0}, {-0.48, 0.64, 0.6}, {0.36, -0.48, 0.8}};

static hk_Shape shapes_for_test(int i)
{
    switch (i) {
    case 0: return hk_shape_sphere(hk_v3(0.1, -0.2, 0.3), 0.05, 0.01, 20.0);
    case 1: return hk_shape_ellipsoid(hk_v3(0.0, 0.07, 0.01), hk_v3(0.08, 0.11, 0.09), NULL, 0.02, 10.0);
    case 2: return hk_shape_ellipsoid(hk_v3(0.02, 0.0, -0.01), hk_v3(0.03, 0.05, 0.04), rotated_axes, 0.01, 5.0);
    default: return hk_shape_cuboid(hk_v3(-0.1, 0.05, 0.0), hk_v3(0.02, 0.03, 0.04), rotated_axes, 0.01, 8.0);
    }
}

static void test_known_values(void **state)
{
    (void)state;
    hk_Shape s = hk_shape_sphere(hk_v3(1, 2, 3), 0.5, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&s, hk_v3(1, 2, 3.2), NULL, NULL), 0.3, 1e-15);
    hk_assert_near(hk_shape_dent(&s, hk_v3(1, 2.5, 3), NULL, NULL), 0.0, 1e-15);
    hk_assert_near(hk_shape_dent(&s, hk_v3(2, 2, 3), NULL, NULL), -0.5, 1e-15);
    /* Ellipsoid radial measure: on each axis it is the semi-axis minus the distance. */
    hk_Shape e = hk_shape_ellipsoid(hk_v3(0, 0, 0), hk_v3(0.08, 0.11, 0.09), NULL, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&e, hk_v3(0.05, 0, 0), NULL, NULL), 0.03, 1e-15);
    hk_assert_near(hk_shape_dent(&e, hk_v3(0, -0.2, 0), NULL, NULL), -0.09, 1e-15);
    hk_assert_near(hk_shape_dent(&e, hk_v3(0, 0, 0.09), NULL, NULL), 0.0, 1e-15);
    /* Off-axis: along the ray through p the surface is at distance |p| / ratio. */
    hk_Vec3 p = hk_v3(0.03, 0.04, 0.05);
    double ratio = sqrt(pow(0.03 / 0.08, 2) + pow(0.04 / 0.11, 2) + pow(0.05 / 0.09, 2));
    hk_assert_near(hk_shape_dent(&e, p, NULL, NULL), hk_v3_norm(p) / ratio - hk_v3_norm(p), 1e-15);
    /* Rotated ellipsoid: a point along its first axis. */
    hk_Shape r = hk_shape_ellipsoid(hk_v3(1, 1, 1), hk_v3(0.3, 0.1, 0.2), rotated_axes, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&r, hk_v3_madd(hk_v3(1, 1, 1), rotated_axes[0], 0.1), NULL, NULL), 0.2, 1e-15);
    hk_assert_near(hk_shape_dent(&r, hk_v3_madd(hk_v3(1, 1, 1), rotated_axes[1], -0.25), NULL, NULL), -0.15, 1e-15);
    /* Cuboid: nearest face inside, negative outside. */
    hk_Shape c = hk_shape_cuboid(hk_v3(0, 0, 0), hk_v3(0.1, 0.2, 0.3), rotated_axes, 0.0, 1.0);
    hk_Vec3 q = hk_v3_add(hk_v3_scale(rotated_axes[0], 0.05), hk_v3_scale(rotated_axes[2], 0.28));
    hk_assert_near(hk_shape_dent(&c, q, NULL, NULL), 0.02, 1e-15);
    hk_Vec3 g;
    hk_shape_dent(&c, q, &g, NULL);
    hk_assert_near(hk_v3_dist(g, hk_v3_neg(rotated_axes[2])), 0.0, 1e-15);
    hk_assert_near(hk_shape_dent(&c, hk_v3_scale(rotated_axes[1], 0.5), NULL, NULL), -0.3, 1e-15);
}

static void test_centre_is_safe(void **state)
{
    (void)state;
    for (int i = 0; i < 4; i++) {
        hk_Shape s = shapes_for_test(i);
        hk_Vec3 g;
        hk_Mat3 h;
        double d = hk_shape_dent(&s, s.centre, &g, &h);
        assert_true(isfinite(d) && d > 0.0);
        assert_true(hk_v3_isfinite(g));
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) assert_true(isfinite(h.m[a][b]));
        double e = hk_collision_penalty(&s, 1, 1.0, hk_v3_madd(s.centre, hk_v3(1, 1, 1), 1e-300), &g, &h);
        assert_true(isfinite(e) && hk_v3_isfinite(g));
    }
}

/* Central differences with h = 1e-6 m on shapes of centimetre size: truncation
 * h^2 |f'''| ~ 1e-12 / q^2 (q the distance to the centre, >= 5 mm here) and
 * rounding eps / h ~ 1e-10, so 1e-6 of the derivative's scale (1 for gradients, 1/q
 * for Hessians) is safe; the cuboid is skipped where a kink lies within h. */
static void test_derivatives_fd(void **state)
{
    (void)state;
    const double h = 1e-6;
    for (int i = 0; i < 4; i++) {
        hk_Shape s = shapes_for_test(i);
        int checked = 0;
        for (int t = 0; t < 400; t++) {
            hk_Vec3 p = s.centre;
            for (int a = 0; a < 3; a++) hk_v3_set(&p, a, hk_v3_get(p, a) + (2 * hk_test_uniform() - 1) * 1.5 * s.bound);
            if (hk_v3_dist(p, s.centre) < 0.05 * s.bound) continue;
            hk_Vec3 g;
            hk_Mat3 hs;
            hk_shape_dent(&s, p, &g, &hs);
            int skip = 0;
            for (int a = 0; a < 3 && !skip; a++) {
                hk_Vec3 pp = p, pm = p, gp, gm;
                hk_v3_set(&pp, a, hk_v3_get(p, a) + h);
                hk_v3_set(&pm, a, hk_v3_get(p, a) - h);
                double fp = hk_shape_dent(&s, pp, &gp, NULL), fm = hk_shape_dent(&s, pm, &gm, NULL);
                if (s.kind == HK_SHAPE_CUBOID && hk_v3_dist(gp, gm) > 0) {
                    skip = 1; /* a face switch (kink) between p - h and p + h */
                    break;
                }
                hk_assert_near(hk_v3_get(g, a), (fp - fm) / (2 * h), 1e-6);
                for (int b = 0; b < 3; b++)
                    hk_assert_near(hs.m[b][a], (hk_v3_get(gp, b) - hk_v3_get(gm, b)) / (2 * h), 1e-6 / hk_v3_dist(p, s.centre));
            }
            checked += !skip;
        }
        assert_true(checked > 300);
    }
}

static void test_penalty_and_envelope(void **state)
{
    (void)state;
    hk_Shape s = hk_shape_sphere(hk_v3(0, 0, 0), 0.1, 0.02, 50.0);
    /* 1 cm outside the sphere: inside the envelope only when alpha v > 1 cm. */
    hk_Vec3 p = hk_v3(0.11, 0, 0);
    hk_assert_near(hk_shape_penalty(&s, 0.0, p, NULL, NULL), 0.0, 0.0);
    hk_assert_near(hk_shape_penalty(&s, 0.25, p, NULL, NULL), 0.0, 0.0);
    hk_assert_rel(hk_shape_penalty(&s, 1.0, p, NULL, NULL), 0.5 * 50.0 * 0.01 * 0.01, 1e-12, 1e-30);
    /* Negative volume shrinks the contact zone: 5 mm inside, v = -1 cm. */
    hk_Shape n = hk_shape_sphere(hk_v3(0, 0, 0), 0.1, -0.01, 50.0);
    hk_assert_near(hk_shape_penalty(&n, 1.0, hk_v3(0.095, 0, 0), NULL, NULL), 0.0, 0.0);
    hk_assert_rel(hk_shape_penalty(&n, 1.0, hk_v3(0.08, 0, 0), NULL, NULL), 0.5 * 50.0 * 0.01 * 0.01, 1e-12, 1e-30);
    /* Gradient and Hessian of the penalty: k phi grad and k (grad grad^T + phi hess). */
    hk_Vec3 g = hk_v3_zero();
    hk_Mat3 h = hk_m3_zero();
    double e = hk_collision_penalty(&s, 1, 0.5, hk_v3(0, 0.095, 0), &g, &h);
    const double phi = 0.005 + 0.01;
    hk_assert_rel(e, 0.5 * 50.0 * phi * phi, 1e-12, 0);
    hk_assert_near(g.y, -50.0 * phi, 1e-15);
    hk_assert_near(h.m[1][1], 50.0, 1e-12);                   /* radial: k */
    hk_assert_near(h.m[0][0], -50.0 * phi / 0.095, 1e-12);    /* tangential: k phi (-1/r) */
    /* Sums over shapes and the depth report. */
    hk_Shape two[2] = {s, hk_shape_sphere(hk_v3(0.2, 0, 0), 0.1, 0.0, 10.0)};
    double both = hk_collision_penalty(two, 2, 1.0, hk_v3(0.1, 0, 0), NULL, NULL);
    hk_assert_rel(both, 0.5 * 50.0 * 0.02 * 0.02, 1e-12, 0); /* the second sphere only touches */
    hk_assert_near(hk_collision_depth(two, 2, 1.0, hk_v3(0.1, 0, 0)), 0.02, 1e-15);
    hk_assert_near(hk_collision_depth(two, 2, 1.0, hk_v3(0.5, 0.5, 0)), 0.0, 0.0);
}

/* The quick rejection must never drop a point with a positive penalty: compare with
 * the penalty recomputed from hk_shape_dent (which never rejects) on points packed
 * around every shape, corners of the cuboid included, with large envelopes. */
static void test_bound_never_rejects_contacts(void **state)
{
    (void)state;
    for (int i = 0; i < 4; i++) {
        hk_Shape s = shapes_for_test(i);
        s.volume = 0.03; /* thick envelope: the sqrt(3) of the cuboid matters here */
        hk_shape_finish(&s);
        int contacts = 0;
        for (int t = 0; t < 20000; t++) {
            hk_Vec3 p = s.centre;
            double reach = s.bound + 2.0 * s.volume;
            for (int a = 0; a < 3; a++) hk_v3_set(&p, a, hk_v3_get(p, a) + (2 * hk_test_uniform() - 1) * reach);
            double phi = hk_shape_dent(&s, p, NULL, NULL) + s.volume;
            double e = hk_shape_penalty(&s, 1.0, p, NULL, NULL);
            hk_assert_near(e, phi > 0 ? 0.5 * s.penalty * phi * phi : 0.0, 1e-15);
            contacts += phi > 0;
        }
        assert_true(contacts > 100);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_values),
        cmocka_unit_test(test_centre_is_safe),
        cmocka_unit_test(test_derivatives_fd),
        cmocka_unit_test(test_penalty_and_envelope),
        cmocka_unit_test(test_bound_never_rejects_contacts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
