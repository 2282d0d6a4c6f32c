/* Collision shapes (src/collide/, Lansink 2010 §4.1.2): penetration values at known
 * points, gradients and Hessians against finite differences, the layered envelopes
 * of §4.1.2.2, the quick-rejection bound, sums over shapes and the centre. */
#include "hk_test.h"

#include <math.h>

#include "collide/collide_internal.h"
#include "hairkit/collide.h"

/* An exactly orthonormal, right-handed, non-trivial frame (rational entries). */
static const hk_Vec3 rotated_axes[3] = {{0.8, 0.6, 0.0}, {-0.48, 0.64, 0.6}, {0.36, -0.48, 0.8}};
/* Axes orthogonal only to within 1e-3, as the collision file reader accepts. */
static const hk_Vec3 skewed_axes[3] = {{1.0, 0.0, 0.0}, {1e-3, 1.0, 0.0}, {0.0, -8e-4, 1.0}};

enum { SHAPE_COUNT = 8 };

/* Shapes of centimetre size, as in the thesis's scenes, of every kind and frame. */
static hk_Shape test_shape(int i)
{
    switch (i) {
    case 0:
        return hk_shape_sphere(hk_v3(0.1, -0.2, 0.3), 0.05, 0.01, 20.0);
    case 1:
        return hk_shape_ellipsoid(hk_v3(0.0, 0.07, 0.01), hk_v3(0.08, 0.11, 0.09), NULL, 0.02, 10.0);
    case 2: /* rotated and elongated (aspect 4) */
        return hk_shape_ellipsoid(hk_v3(0.02, 0.0, -0.01), hk_v3(0.03, 0.12, 0.06), rotated_axes, 0.01, 5.0);
    case 3: /* nearly a sphere: the terms of the Hessian almost cancel */
        return hk_shape_ellipsoid(hk_v3(-0.3, 0.1, 0.0), hk_v3(0.05, 0.0500001, 0.0499999), rotated_axes, 0.005, 30.0);
    case 4:
        return hk_shape_ellipsoid(hk_v3(0.0, 0.0, 0.0), hk_v3(0.04, 0.06, 0.05), skewed_axes, -0.01, 7.0);
    case 5:
        return hk_shape_cuboid(hk_v3(-0.1, 0.05, 0.0), hk_v3(0.02, 0.03, 0.04), rotated_axes, 0.01, 8.0);
    case 6: /* a cube: the only cuboid whose corner needs the full sqrt(3) of the bound */
        return hk_shape_cuboid(hk_v3(0.2, 0.0, 0.1), hk_v3(0.03, 0.03, 0.03), rotated_axes, 0.03, 12.0);
    default:
        return hk_shape_cuboid(hk_v3(0.0, 0.3, 0.0), hk_v3(0.05, 0.01, 0.02), skewed_axes, -0.004, 3.0);
    }
}

static double max_half(const hk_Shape *s) { return fmax(s->half.x, fmax(s->half.y, s->half.z)); }
static double min_half(const hk_Shape *s) { return fmin(s->half.x, fmin(s->half.y, s->half.z)); }

/* centre + sum_i l_i axis_i */
static hk_Vec3 at_local(const hk_Shape *s, double u, double v, double w)
{
    hk_Vec3 p = hk_v3_madd(s->centre, s->axis[0], u);
    p = hk_v3_madd(p, s->axis[1], v);
    return hk_v3_madd(p, s->axis[2], w);
}

/* Uniform direction (rejection sampling in the unit ball). */
static hk_Vec3 random_direction(void)
{
    for (;;) {
        hk_Vec3 u = hk_v3(2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1);
        double n2 = hk_v3_norm2(u);
        if (n2 > 1e-4 && n2 <= 1.0) return hk_v3_scale(u, 1.0 / sqrt(n2));
    }
}

static double mat_max_diff(const hk_Mat3 *a, const hk_Mat3 *b)
{
    double m = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) m = fmax(m, fabs(a->m[i][j] - b->m[i][j]));
    return m;
}

static int mat_isfinite(const hk_Mat3 *a)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (!isfinite(a->m[i][j])) return 0;
    return 1;
}

/* The thesis's formulas written out independently of the library (§4.1.2.1). */
static double reference_dent(const hk_Shape *s, hk_Vec3 p)
{
    const hk_Vec3 d = hk_v3_sub(p, s->centre);
    const double pu = hk_v3_dot(d, s->axis[0]), pv = hk_v3_dot(d, s->axis[1]), pw = hk_v3_dot(d, s->axis[2]);
    const double a = s->half.x, b = s->half.y, c = s->half.z, dist = hk_v3_norm(d);
    switch (s->kind) {
    case HK_SHAPE_SPHERE:
        return a - dist;
    case HK_SHAPE_ELLIPSOID: {
        double ratio = sqrt((pu / a) * (pu / a) + (pv / b) * (pv / b) + (pw / c) * (pw / c));
        return dist / ratio - dist;
    }
    default:
        return fmin(a - fabs(pu), fmin(b - fabs(pv), c - fabs(pw)));
    }
}

/* ---- known values ------------------------------------------------------------- */

static void test_sphere_values(void **state)
{
    (void)state;
    hk_Shape s = hk_shape_sphere(hk_v3(1, 2, 3), 0.5, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&s, hk_v3(1, 2, 3.2), NULL, NULL), 0.3, 1e-15); /* inside: > 0 */
    hk_assert_near(hk_shape_dent(&s, hk_v3(1, 2.5, 3), NULL, NULL), 0.0, 1e-15); /* surface */
    hk_assert_near(hk_shape_dent(&s, hk_v3(0.5, 2, 3), NULL, NULL), 0.0, 1e-15); /* surface */
    hk_assert_near(hk_shape_dent(&s, hk_v3(2, 2, 3), NULL, NULL), -0.5, 1e-15);  /* outside: < 0 */
    /* Gradient -n and Hessian -(I - n n^T)/|d| at d = (0.3, 0, 0.4), |d| = 0.5. */
    hk_Vec3 g;
    hk_Mat3 h;
    hk_assert_near(hk_shape_dent(&s, hk_v3(1.3, 2, 3.4), &g, &h), 0.0, 1e-15);
    hk_assert_near(hk_v3_dist(g, hk_v3(-0.6, 0, -0.8)), 0.0, 1e-15);
    const double n[3] = {0.6, 0.0, 0.8};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) hk_assert_near(h.m[i][j], -((i == j) - n[i] * n[j]) / 0.5, 1e-14);
}

static void test_ellipsoid_values(void **state)
{
    (void)state;
    /* On every axis, both directions, inside, on and outside: the radial dent is the
     * semi-axis minus the distance (axis-aligned and rotated frames). */
    const hk_Vec3 radii = hk_v3(0.08, 0.11, 0.09);
    const hk_Shape shapes[2] = {hk_shape_ellipsoid(hk_v3(0.01, -0.02, 0.03), radii, NULL, 0.0, 1.0),
                                hk_shape_ellipsoid(hk_v3(1, 1, 1), radii, rotated_axes, 0.0, 1.0)};
    const double fractions[] = {0.1, 0.5, 1.0, 1.3, 4.0};
    for (int k = 0; k < 2; k++)
        for (int axis = 0; axis < 3; axis++)
            for (int side = -1; side <= 1; side += 2)
                for (int f = 0; f < 5; f++) {
                    const double a = hk_v3_get(radii, axis), t = fractions[f] * a;
                    hk_Vec3 l = hk_v3_zero();
                    hk_v3_set(&l, axis, side * t);
                    hk_Vec3 p = at_local(&shapes[k], l.x, l.y, l.z);
                    hk_assert_near(hk_shape_dent(&shapes[k], p, NULL, NULL), a - t, 1e-14);
                }
    /* The definition uses the world distance even when the axes are only nearly
     * orthogonal (as the file reader accepts): dist = |p - c|, not |(pU, pV, pW)|. */
    const hk_Shape skew = test_shape(4);
    for (int t = 0; t < 50; t++) {
        hk_Vec3 p = hk_v3_madd(skew.centre, random_direction(), 0.1 * hk_test_uniform());
        hk_assert_near(hk_shape_dent(&skew, p, NULL, NULL), reference_dent(&skew, p), 1e-15);
    }
    /* Off-axis, the dent follows the thesis's dist/ratio - dist, and points scaled
     * onto the surface along their ray have dent 0. */
    for (int k = 0; k < 2; k++)
        for (int t = 0; t < 50; t++) {
            hk_Vec3 u = random_direction();
            hk_Vec3 p = hk_v3_madd(shapes[k].centre, u, 0.2 * hk_test_uniform());
            hk_assert_near(hk_shape_dent(&shapes[k], p, NULL, NULL), reference_dent(&shapes[k], p), 1e-15);
            const double lu = hk_v3_dot(u, shapes[k].axis[0]) / radii.x, lv = hk_v3_dot(u, shapes[k].axis[1]) / radii.y,
                         lw = hk_v3_dot(u, shapes[k].axis[2]) / radii.z;
            hk_Vec3 on = hk_v3_madd(shapes[k].centre, u, 1.0 / sqrt(lu * lu + lv * lv + lw * lw));
            hk_assert_near(hk_shape_dent(&shapes[k], on, NULL, NULL), 0.0, 1e-15);
        }
    /* On the U axis at distance t (g = 0 there): gradient -U, and the Hessian has
     * U^T H U = 0 (dent = a - t is linear along the axis), no U-V coupling, and
     * V^T H V = a (1 - a^2/b^2) / t^2 - 1/t (expand dist/ratio to second order in the
     * V offset y: a + a (1 - a^2/b^2) y^2 / (2 t^2)), likewise for W. */
    const hk_Shape *r = &shapes[1];
    const double a = radii.x, b = radii.y, c = radii.z, t = 0.05;
    hk_Vec3 g;
    hk_Mat3 h;
    hk_shape_dent(r, at_local(r, t, 0, 0), &g, &h);
    hk_assert_near(hk_v3_dist(g, hk_v3_neg(r->axis[0])), 0.0, 1e-14);
    hk_Vec3 hu = hk_m3_mul_v3(&h, r->axis[0]), hv = hk_m3_mul_v3(&h, r->axis[1]), hw = hk_m3_mul_v3(&h, r->axis[2]);
    const double scale = 1.0 / t; /* size of the Hessian's entries */
    hk_assert_near(hk_v3_dot(r->axis[0], hu), 0.0, 1e-13 * scale);
    hk_assert_near(hk_v3_dot(r->axis[1], hu), 0.0, 1e-13 * scale);
    hk_assert_near(hk_v3_dot(r->axis[2], hv), 0.0, 1e-13 * scale);
    hk_assert_near(hk_v3_dot(r->axis[1], hv), a * (1 - a * a / (b * b)) / (t * t) - 1 / t, 1e-13 * scale);
    hk_assert_near(hk_v3_dot(r->axis[2], hw), a * (1 - a * a / (c * c)) / (t * t) - 1 / t, 1e-13 * scale);
}

static void test_cuboid_values(void **state)
{
    (void)state;
    hk_Shape c = hk_shape_cuboid(hk_v3(0.5, 0, -0.5), hk_v3(0.1, 0.2, 0.3), rotated_axes, 0.0, 1.0);
    hk_Vec3 g;
    hk_Mat3 h;
    /* Inside near the +W face: dent 0.02, gradient -W, Hessian zero. */
    hk_assert_near(hk_shape_dent(&c, at_local(&c, 0.05, -0.1, 0.28), &g, &h), 0.02, 1e-15);
    hk_assert_near(hk_v3_dist(g, hk_v3_neg(c.axis[2])), 0.0, 1e-15);
    hk_Mat3 zero = hk_m3_zero();
    hk_assert_near(mat_max_diff(&h, &zero), 0.0, 0.0);
    /* Inside near the -U face: gradient +U (pushes towards the nearer face). */
    hk_assert_near(hk_shape_dent(&c, at_local(&c, -0.09, 0.1, 0.1), &g, NULL), 0.01, 1e-15);
    hk_assert_near(hk_v3_dist(g, c.axis[0]), 0.0, 1e-15);
    /* On a face: 0. Outside: negative (beyond V by 0.3, a corner beyond all three). */
    hk_assert_near(hk_shape_dent(&c, at_local(&c, 0.0, -0.2, 0.1), NULL, NULL), 0.0, 1e-15);
    hk_assert_near(hk_shape_dent(&c, at_local(&c, 0.0, 0.5, 0.0), NULL, NULL), -0.3, 1e-15);
    hk_assert_near(hk_shape_dent(&c, at_local(&c, -0.15, 0.3, 0.31), NULL, NULL), -0.1, 1e-15);
    /* Ties pick the first minimal term: identity axes so |pU| == |pV| exactly. */
    hk_Shape cube = hk_shape_cuboid(hk_v3(0, 0, 0), hk_v3(0.1, 0.1, 0.1), NULL, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&cube, hk_v3(0.01, -0.01, 0.0), &g, NULL), 0.09, 1e-16);
    hk_assert_near(hk_v3_dist(g, hk_v3(-1, 0, 0)), 0.0, 0.0);
    hk_shape_dent(&cube, hk_v3(0.0, -0.02, 0.02), &g, NULL); /* V and W tie: V */
    hk_assert_near(hk_v3_dist(g, hk_v3(0, 1, 0)), 0.0, 0.0);
    hk_assert_near(hk_shape_dent(&cube, hk_v3(0, 0, 0), &g, NULL), 0.1, 0.0); /* all tie, + side */
    hk_assert_near(hk_v3_dist(g, hk_v3(-1, 0, 0)), 0.0, 0.0);
    /* On a symmetry plane (pU = +0 or -0) the sign is +: gradient -U. */
    hk_Shape slab = hk_shape_cuboid(hk_v3(0, 0, 0), hk_v3(0.01, 0.2, 0.3), NULL, 0.0, 1.0);
    hk_assert_near(hk_shape_dent(&slab, hk_v3(0.0, 0.05, 0.1), &g, NULL), 0.01, 0.0);
    hk_assert_near(hk_v3_dist(g, hk_v3(-1, 0, 0)), 0.0, 0.0);
    hk_shape_dent(&slab, hk_v3(-0.0, -0.05, -0.1), &g, NULL); /* pU = -0.0 exactly */
    hk_assert_near(hk_v3_dist(g, hk_v3(-1, 0, 0)), 0.0, 0.0);
    /* Values at random points (rotated and skewed frames) follow the formula. */
    const hk_Shape frames[2] = {c, test_shape(7)};
    for (int k = 0; k < 2; k++)
        for (int t = 0; t < 200; t++) {
            hk_Vec3 p = hk_v3_madd(frames[k].centre, random_direction(), 0.5 * hk_test_uniform());
            hk_assert_near(hk_shape_dent(&frames[k], p, &g, NULL), reference_dent(&frames[k], p), 1e-15);
            /* the gradient is a signed axis, the one of the minimal term */
            int hits = 0;
            for (int i = 0; i < 3; i++) {
                double pi = hk_v3_dot(hk_v3_sub(p, frames[k].centre), frames[k].axis[i]);
                double di = hk_v3_get(frames[k].half, i) - fabs(pi);
                if (hk_v3_dist(g, hk_v3_scale(frames[k].axis[i], pi < 0 ? 1 : -1)) == 0.0) {
                    hk_assert_near(di, reference_dent(&frames[k], p), 0.0);
                    hits++;
                }
            }
            assert_int_equal(hits, 1);
        }
}

/* ---- the centre and other degenerate inputs ------------------------------------- */

static void test_centre_and_degenerate(void **state)
{
    (void)state;
    hk_Mat3 zero = hk_m3_zero();
    for (int i = 0; i < SHAPE_COUNT; i++) {
        hk_Shape s = test_shape(i);
        hk_Vec3 g;
        hk_Mat3 h;
        /* Exactly at the centre: the smallest radius; flat for sphere and ellipsoid,
         * the cuboid's first-axis face for the cuboid (tie rule). */
        hk_assert_near(hk_shape_dent(&s, s.centre, &g, &h), min_half(&s), 0.0);
        if (s.kind == HK_SHAPE_CUBOID) {
            hk_assert_near(hk_v3_norm(g), 1.0, 1e-15);
        } else {
            hk_assert_near(hk_v3_norm(g), 0.0, 0.0);
            hk_assert_near(mat_max_diff(&h, &zero), 0.0, 0.0);
        }
        /* Very near the centre, on both sides of the guard, and underflowing offsets:
         * everything finite. */
        const double offsets[] = {1e-300, 1e-160, 1e-30, 1e-12, 5e-10, 2e-9, 1e-6};
        for (int k = 0; k < 7; k++) {
            hk_Vec3 p = hk_v3_madd(s.centre, hk_v3(0.6, -0.8, 0.3), offsets[k] * min_half(&s));
            double d = hk_shape_dent(&s, p, &g, &h);
            assert_true(isfinite(d) && d > 0.0 && d <= max_half(&s) * (1 + 1e-12));
            assert_true(hk_v3_isfinite(g) && mat_isfinite(&h));
            double e = hk_collision_penalty(&s, 1, 1.0, p, &g, &h);
            assert_true(isfinite(e) && e > 0.0 && hk_v3_isfinite(g) && mat_isfinite(&h));
            assert_true(isfinite(hk_collision_depth(&s, 1, 0.5, p)));
            /* the centre's fallback is confined to the centre: a micrometre-scale
             * offset (1e-6 of the radius) already follows the definition */
            if (offsets[k] >= 1e-6) hk_assert_near(d, reference_dent(&s, p), 1e-15);
        }
        /* Zero stiffness: no energy and no derivative anywhere, centre included. */
        s.penalty = 0.0;
        const hk_Vec3 points[3] = {s.centre, hk_v3_madd(s.centre, hk_v3(1, 0, 0), 1e-12),
                                   at_local(&s, 0.5 * s.half.x, 0, 0)};
        for (int k = 0; k < 3; k++) {
            double e = hk_collision_penalty(&s, 1, 1.0, points[k], &g, &h);
            hk_assert_near(e, 0.0, 0.0);
            hk_assert_near(hk_v3_norm(g), 0.0, 0.0);
            hk_assert_near(mat_max_diff(&h, &zero), 0.0, 0.0);
        }
    }
    /* No shapes at all. */
    hk_Vec3 g = hk_v3(1, 2, 3);
    hk_Mat3 h = hk_m3_identity();
    hk_assert_near(hk_collision_penalty(NULL, 0, 1.0, hk_v3(0, 0, 0), &g, &h), 0.0, 0.0);
    hk_assert_near(hk_v3_norm(g) + mat_max_diff(&h, &zero), 0.0, 0.0);
    hk_assert_near(hk_collision_depth(NULL, 0, 1.0, hk_v3(0, 0, 0)), 0.0, 0.0);
}

/* ---- derivatives against finite differences ------------------------------------ */

/* Step and tolerance. The step is relative, h = 1e-5 |d| (|d| = distance to the
 * centre), because the radial measure's derivatives scale with powers of 1/|d|:
 * along any line the k-th derivative of dent is C_k L / |d|^k with L <= amax and C_k
 * growing with the aspect ratio (about 4^k here). Central differences then err by
 *   truncation  h^2/6 * C_3 L/|d|^3  =  1e-10 C_3/6 * (L/|d|)     (~1e-9 relative)
 *   rounding    eps |dent| / h       =  2e-11 * (L/|d|)
 * relative to the gradient's size S_g = 1 + amax/|d|; for the Hessian (differences
 * of the analytic gradient) the same with one more 1/|d|, relative to S_h = S_g/|d|.
 * Both are below 1e-8, so a tolerance of 1e-6 S leaves a margin of 100 and more,
 * while any wrong term of the formulas is an O(1) relative error at |d| ~ a. Points
 * where the stencil crosses a cuboid edge (kink) or the clipping phi = 0 of the
 * penalty (where the second derivative jumps) are skipped and counted. */
#define FD_STEP 1e-5
#define FD_TOL  1e-6

/* Samples a point at distance in [lo, hi] * (bound + |volume|) from the centre. */
static hk_Vec3 random_point(const hk_Shape *s, double lo, double hi)
{
    const double reach = hk_shape_bound(s) + fabs(s->volume);
    return hk_v3_madd(s->centre, random_direction(), reach * (lo + (hi - lo) * hk_test_uniform()));
}

/* 1 when the points differ in which cuboid face is active (a kink between them). */
static int face_switch(const hk_Shape *s, hk_Vec3 p0, hk_Vec3 p1)
{
    if (s->kind != HK_SHAPE_CUBOID) return 0;
    hk_Vec3 g0, g1;
    hk_shape_dent(s, p0, &g0, NULL);
    hk_shape_dent(s, p1, &g1, NULL);
    return hk_v3_dist(g0, g1) != 0.0;
}

static void test_dent_derivatives(void **state)
{
    (void)state;
    for (int i = 0; i < SHAPE_COUNT; i++) {
        const hk_Shape s = test_shape(i);
        int checked = 0;
        for (int t = 0; t < 500; t++) {
            /* from deep inside (but >= 0.1 amin off the centre) to 1.5 x the reach */
            hk_Vec3 p = random_point(&s, 0.0, 1.5);
            const double q = hk_v3_dist(p, s.centre);
            if (q < 0.1 * min_half(&s)) continue;
            const double h = FD_STEP * q, sg = 1.0 + max_half(&s) / q, sh = sg / q;
            hk_Vec3 g, g_only;
            hk_Mat3 hs, h_only;
            const double d = hk_shape_dent(&s, p, &g, &hs);
            /* each output does not depend on the other being asked for */
            hk_assert_near(hk_shape_dent(&s, p, &g_only, NULL), d, 0.0);
            hk_shape_dent(&s, p, NULL, &h_only);
            hk_assert_near(hk_v3_dist(g, g_only), 0.0, 0.0);
            hk_assert_near(mat_max_diff(&hs, &h_only), 0.0, 0.0);
            int kink = 0;
            for (int a = 0; a < 3; a++) {
                hk_Vec3 pp = p, pm = p;
                hk_v3_set(&pp, a, hk_v3_get(p, a) + h);
                hk_v3_set(&pm, a, hk_v3_get(p, a) - h);
                kink |= face_switch(&s, pp, pm);
            }
            if (kink) continue;
            for (int a = 0; a < 3; a++) {
                hk_Vec3 pp = p, pm = p, gp, gm;
                hk_v3_set(&pp, a, hk_v3_get(p, a) + h);
                hk_v3_set(&pm, a, hk_v3_get(p, a) - h);
                const double fp = hk_shape_dent(&s, pp, &gp, NULL), fm = hk_shape_dent(&s, pm, &gm, NULL);
                hk_assert_near(hk_v3_get(g, a), (fp - fm) / (2 * h), FD_TOL * sg);
                for (int b = 0; b < 3; b++) {
                    hk_assert_near(hs.m[b][a], (hk_v3_get(gp, b) - hk_v3_get(gm, b)) / (2 * h), FD_TOL * sh);
                    hk_assert_near(hs.m[a][b], hs.m[b][a], 1e-12 * sh); /* symmetric */
                }
            }
            checked++;
        }
        assert_true(checked > 300); /* kinks are rare; most points are checked */
    }
}

/* The penalty's gradient k phi grad(dent) against differences of the energy and its
 * Hessian k (grad grad^T + phi hess(dent)) against differences of that gradient, at
 * points inside the shapes and outside within the envelope, for several levels. */
static void test_penalty_derivatives(void **state)
{
    (void)state;
    const double alphas[] = {0.0, 0.4, 1.0};
    for (int i = 0; i < SHAPE_COUNT; i++) {
        const hk_Shape s = test_shape(i);
        int inside = 0, envelope = 0, skipped = 0;
        for (int t = 0; t < 600; t++) {
            const double alpha = alphas[t % 3], extra = alpha * s.volume;
            hk_Vec3 p = random_point(&s, 0.0, 1.2);
            const double q = hk_v3_dist(p, s.centre);
            if (q < 0.1 * min_half(&s)) continue;
            const double h = FD_STEP * q, sg = 1.0 + max_half(&s) / q, sh = sg / q;
            const double L = max_half(&s) + fabs(extra);
            const double eg = s.penalty * L * sg, eh = s.penalty * (sg * sg + L * sh);
            const double phi = hk_shape_dent(&s, p, NULL, NULL) + extra;
            /* skip stencils that cross phi = 0 or a cuboid edge */
            int skip = 0;
            for (int a = 0; a < 3 && !skip; a++)
                for (int sign = -1; sign <= 1; sign += 2) {
                    hk_Vec3 pa = p;
                    hk_v3_set(&pa, a, hk_v3_get(p, a) + sign * h);
                    const double phia = hk_shape_dent(&s, pa, NULL, NULL) + extra;
                    if ((phia > 0) != (phi > 0) || face_switch(&s, p, pa)) skip = 1;
                }
            if (skip) {
                skipped++;
                continue;
            }
            hk_Vec3 g = hk_v3_zero();
            hk_Mat3 hs = hk_m3_zero();
            const double e = hk_shape_penalty(&s, alpha, p, &g, &hs);
            hk_assert_rel(e, phi > 0 ? 0.5 * s.penalty * phi * phi : 0.0, 1e-14, 1e-300);
            for (int a = 0; a < 3; a++) {
                hk_Vec3 pp = p, pm = p, gp = hk_v3_zero(), gm = hk_v3_zero();
                hk_v3_set(&pp, a, hk_v3_get(p, a) + h);
                hk_v3_set(&pm, a, hk_v3_get(p, a) - h);
                const double ep = hk_shape_penalty(&s, alpha, pp, &gp, NULL);
                const double em = hk_shape_penalty(&s, alpha, pm, &gm, NULL);
                hk_assert_near(hk_v3_get(g, a), (ep - em) / (2 * h), FD_TOL * eg);
                for (int b = 0; b < 3; b++)
                    hk_assert_near(hs.m[b][a], (hk_v3_get(gp, b) - hk_v3_get(gm, b)) / (2 * h), FD_TOL * eh);
            }
            if (phi > 0) {
                const double dent = phi - extra;
                inside += dent > 0;
                envelope += dent <= 0; /* outside the shape, inside its envelope */
            }
        }
        assert_true(inside > 50);
        if (s.volume > 0) assert_true(envelope > 10);
        assert_true(skipped < 100);
    }
}

/* ---- envelopes (§4.1.2.2) ------------------------------------------------------- */

static void test_envelope(void **state)
{
    (void)state;
    const double k = 50.0;
    /* For each kind, a point 1 cm outside along a face/axis direction, v = 2 cm. */
    const hk_Shape shapes[3] = {hk_shape_sphere(hk_v3(0, 0, 0), 0.1, 0.02, k),
                                hk_shape_ellipsoid(hk_v3(0.1, 0, 0), hk_v3(0.08, 0.11, 0.09), rotated_axes, 0.02, k),
                                hk_shape_cuboid(hk_v3(0, 0.2, 0), hk_v3(0.05, 0.06, 0.07), rotated_axes, 0.02, k)};
    const hk_Vec3 outside[3] = {at_local(&shapes[0], 0.0, 0.11, 0.0), at_local(&shapes[1], 0.0, 0.12, 0.0),
                                at_local(&shapes[2], 0.01, 0.02, 0.08)};
    for (int i = 0; i < 3; i++) {
        const hk_Shape *s = &shapes[i];
        hk_assert_near(hk_shape_dent(s, outside[i], NULL, NULL), -0.01, 1e-15);
        /* alpha 0: no envelope, the outside point is free */
        hk_assert_near(hk_shape_penalty(s, 0.0, outside[i], NULL, NULL), 0.0, 0.0);
        /* alpha v = 5 mm < 1 cm: still free; alpha v = 2 cm: 1 cm inside the envelope */
        hk_assert_near(hk_shape_penalty(s, 0.25, outside[i], NULL, NULL), 0.0, 0.0);
        hk_assert_rel(hk_shape_penalty(s, 1.0, outside[i], NULL, NULL), 0.5 * k * 0.01 * 0.01, 1e-12, 0);
        hk_assert_near(hk_collision_depth(s, 1, 1.0, outside[i]), 0.01, 1e-15);
        hk_assert_near(hk_collision_depth(s, 1, 0.25, outside[i]), 0.0, 0.0);
        /* the penalty grows with the level for v > 0 */
        double last = 0.0;
        for (int a = 6; a <= 10; a++) {
            double e = hk_shape_penalty(s, 0.1 * a, outside[i], NULL, NULL);
            assert_true(e > last);
            last = e;
        }
        /* Negative v shrinks the zone: 5 mm deep, v = -1 cm: free at alpha 1, in
         * contact at alpha 0 (no envelope) and 1 cm deep at 2 cm. */
        hk_Shape n = *s;
        n.volume = -0.01;
        const hk_Vec3 d = hk_v3_sub(outside[i], s->centre);
        const hk_Vec3 normal = hk_v3_normalize(i == 2 ? s->axis[2] : d);
        const hk_Vec3 surface = hk_v3_madd(outside[i], normal, -0.01);
        const hk_Vec3 deep5 = hk_v3_madd(surface, normal, -0.005), deep20 = hk_v3_madd(surface, normal, -0.02);
        hk_assert_near(hk_shape_dent(&n, deep5, NULL, NULL), 0.005, 1e-15);
        hk_assert_near(hk_shape_penalty(&n, 1.0, deep5, NULL, NULL), 0.0, 0.0);
        hk_assert_rel(hk_shape_penalty(&n, 0.0, deep5, NULL, NULL), 0.5 * k * 0.005 * 0.005, 1e-12, 0);
        hk_assert_rel(hk_shape_penalty(&n, 1.0, deep20, NULL, NULL), 0.5 * k * 0.01 * 0.01, 1e-12, 0);
        hk_assert_near(hk_collision_depth(&n, 1, 1.0, deep20), 0.01, 1e-15);
    }
    /* alpha 0 is the bare shape everywhere: 1/2 k max(dent, 0)^2. */
    for (int i = 0; i < SHAPE_COUNT; i++) {
        const hk_Shape s = test_shape(i);
        for (int t = 0; t < 300; t++) {
            hk_Vec3 p = random_point(&s, 0.0, 1.3);
            double dent = fmax(hk_shape_dent(&s, p, NULL, NULL), 0.0);
            hk_assert_rel(hk_shape_penalty(&s, 0.0, p, NULL, NULL), 0.5 * s.penalty * dent * dent, 1e-14, 1e-300);
        }
    }
    /* The cuboid's envelope keeps sharp corners: dent + extra is the box grown by
     * extra along each axis, so a point 5 mm beyond an edge on two axes touches a
     * 1 cm envelope by 5 mm. */
    const hk_Shape *c = &shapes[2];
    hk_Vec3 edge = at_local(c, 0.055, -0.065, 0.0);
    hk_assert_near(hk_shape_dent(c, edge, NULL, NULL), -0.005, 1e-15);
    hk_assert_rel(hk_shape_penalty(c, 0.5, edge, NULL, NULL), 0.5 * k * 0.005 * 0.005, 1e-9, 0);
}

/* ---- the quick rejection -------------------------------------------------------- */

/* Distance from the centre along direction u where dent + extra = 0 (dent decreases
 * along every ray from the centre), computed from the definitions. */
static double envelope_radius(const hk_Shape *s, hk_Vec3 u, double extra)
{
    const double lu = hk_v3_dot(u, s->axis[0]), lv = hk_v3_dot(u, s->axis[1]), lw = hk_v3_dot(u, s->axis[2]);
    const double a = s->half.x, b = s->half.y, c = s->half.z;
    switch (s->kind) {
    case HK_SHAPE_SPHERE:
        return a + extra;
    case HK_SHAPE_ELLIPSOID: /* |u| / ratio(u) + extra, with |u| = 1 */
        return 1.0 / sqrt((lu / a) * (lu / a) + (lv / b) * (lv / b) + (lw / c) * (lw / c)) + extra;
    default:
        return fmin((a + extra) / fabs(lu), fmin((b + extra) / fabs(lv), (c + extra) / fabs(lw)));
    }
}

/* Penalty and depth at p must agree with the values recomputed from hk_shape_dent,
 * which never rejects. Returns 1 when p is in contact. */
static int check_against_dent(const hk_Shape *s, double alpha, hk_Vec3 p)
{
    const double phi = hk_shape_dent(s, p, NULL, NULL) + alpha * s->volume;
    const double e = hk_shape_penalty(s, alpha, p, NULL, NULL);
    if (phi > 0) {
        assert_true(e > 0.0);
        hk_assert_rel(e, 0.5 * s->penalty * phi * phi, 1e-12, 1e-300);
        hk_assert_near(hk_collision_depth(s, 1, alpha, p), phi, 0.0);
    } else {
        hk_assert_near(e, 0.0, 0.0);
        hk_assert_near(hk_collision_depth(s, 1, alpha, p), 0.0, 0.0);
    }
    return phi > 0;
}

static void test_bound_never_rejects_contacts(void **state)
{
    (void)state;
    const double volumes[] = {0.0, 0.03, -0.02, 0.1};
    const double alphas[] = {1.0, 0.37};
    for (int i = 0; i < SHAPE_COUNT; i++)
        for (int vi = 0; vi < 4; vi++)
            for (int ai = 0; ai < 2; ai++) {
                hk_Shape s = test_shape(i);
                s.volume = volumes[vi];
                const double alpha = alphas[ai], extra = alpha * s.volume;
                const double reach = hk_shape_bound(&s) + sqrt(3.0) * fabs(extra);
                int contacts = 0;
                /* dense shell sampling up to past the reach */
                for (int t = 0; t < 2000; t++)
                    contacts += check_against_dent(
                        &s, alpha, hk_v3_madd(s.centre, random_direction(), 1.05 * reach * hk_test_uniform()));
                /* just inside / outside the envelope surface along random rays */
                for (int t = 0; t < 1000; t++) {
                    const hk_Vec3 u = random_direction();
                    const double rho = envelope_radius(&s, u, extra);
                    if (!(rho > 0)) continue; /* the envelope shrank past the centre */
                    const double fractions[] = {1 - 1e-3, 1 - 1e-7, 1 + 1e-7, 1 + 1e-3};
                    for (int f = 0; f < 4; f++) {
                        int in = check_against_dent(&s, alpha, hk_v3_madd(s.centre, u, rho * fractions[f]));
                        assert_int_equal(in, f < 2);
                    }
                }
                /* the eight corners of a cuboid's envelope, reached along the
                 * diagonals, are the points farthest from the centre (orthonormal
                 * frames: there local coordinates are the axis components) */
                const int orthonormal = fabs(hk_v3_dot(s.axis[0], s.axis[1])) + fabs(hk_v3_dot(s.axis[0], s.axis[2])) +
                                            fabs(hk_v3_dot(s.axis[1], s.axis[2])) <
                                        1e-12;
                if (s.kind == HK_SHAPE_CUBOID && orthonormal && extra > -min_half(&s))
                    for (int corner = 0; corner < 8; corner++) {
                        const double lu = (corner & 1 ? 1 : -1) * (s.half.x + extra);
                        const double lv = (corner & 2 ? 1 : -1) * (s.half.y + extra);
                        const double lw = (corner & 4 ? 1 : -1) * (s.half.z + extra);
                        const hk_Vec3 tip = at_local(&s, lu, lv, lw);
                        const double fractions[] = {1 - 1e-3, 1 - 1e-7};
                        for (int f = 0; f < 2; f++)
                            assert_true(check_against_dent(
                                &s, alpha, hk_v3_add(s.centre, hk_v3_scale(hk_v3_sub(tip, s.centre), fractions[f]))));
                    }
                /* the sampling finds contacts (200 or more) unless the envelope
                 * shrank to nothing: v = -2 cm swallows the thinnest cuboids */
                if (min_half(&s) + extra > 0.0) assert_true(contacts > 100);
            }
    /* For the cube the sqrt(3) is tight: its envelope's corner lies exactly on the
     * reach (up to rounding), so nothing smaller would do. */
    hk_Shape cube = test_shape(6);
    const double extra = cube.volume;
    const double corner = hk_v3_norm(hk_v3(cube.half.x + extra, cube.half.y + extra, cube.half.z + extra));
    hk_assert_rel(corner, hk_shape_bound(&cube) + sqrt(3.0) * extra, 1e-15, 0);
}

/* The bound is the largest radius (the cuboid's half-diagonal), computed from the
 * shape's fields at every call: a shape edited by hand after its constructor needs no
 * refresh (a cached bound would reject the contacts of a grown shape). */
static void test_bound_follows_edits(void **state)
{
    (void)state;
    hk_Shape s = hk_shape_sphere(hk_v3(0, 0, 0), 0.1, 0.01, 10.0);
    hk_assert_near(hk_shape_bound(&s), 0.1, 0.0);
    /* grown to 0.2 by hand: a point at 0.15 lies beyond the old reach 0.1 + sqrt(3) 0.01 */
    s.half = hk_v3(0.2, 0.2, 0.2);
    hk_assert_near(hk_shape_bound(&s), 0.2, 0.0);
    hk_assert_rel(hk_shape_penalty(&s, 1.0, hk_v3(0, 0.15, 0), NULL, NULL), 0.5 * 10.0 * pow(0.21 - 0.15, 2), 1e-12, 0);
    hk_assert_near(hk_collision_depth(&s, 1, 1.0, hk_v3(0, 0.15, 0)), 0.21 - 0.15, 1e-15);
    /* and beyond the new reach nothing */
    const double reach = 0.2 + sqrt(3.0) * 0.01;
    hk_assert_near(hk_shape_penalty(&s, 1.0, hk_v3(0, reach * 1.001, 0), NULL, NULL), 0.0, 0.0);
    /* an ellipsoid: its largest semi-axis; a cuboid: its half-diagonal */
    const hk_Shape e = hk_shape_ellipsoid(hk_v3(0, 0, 0), hk_v3(0.05, 0.12, 0.07), NULL, 0.0, 1.0);
    hk_assert_near(hk_shape_bound(&e), 0.12, 0.0);
    const hk_Shape c = hk_shape_cuboid(hk_v3(0, 0, 0), hk_v3(0.03, 0.04, 0.12), NULL, 0.0, 1.0);
    hk_assert_rel(hk_shape_bound(&c), 0.13, 1e-15, 0);
}

/* hk_shape_beyond (the dynamics' error control passes a shape without its dent there)
 * may only answer where the dent itself says dent + extra <= -margin, and
 * hk_shape_outside only where dent < 0; both must answer for most far points (a test
 * that never passes a shape would not show it is sound). Around the reach's sphere, on
 * the cube's diagonal (where the sqrt(3) is tight) and at random. */
static void test_beyond_and_outside(void **state)
{
    (void)state;
    const double volumes[] = {0.0, 0.03, -0.02};
    const double margins[] = {0.0, 1e-3, 0.02};
    for (int i = 0; i < SHAPE_COUNT; i++)
        for (int vi = 0; vi < 3; vi++)
            for (int mi = 0; mi < 3; mi++) {
                hk_Shape s = test_shape(i);
                s.volume = volumes[vi];
                const double extra = 0.8 * s.volume, margin = margins[mi];
                const double reach = hk_shape_bound(&s) + sqrt(3.0) * (fabs(extra) + margin);
                int beyond = 0, outside = 0;
                for (int t = 0; t < 3000; t++) {
                    const double r = t % 3 == 0 ? reach * (1.0 + 1e-6 * (2 * hk_test_uniform() - 1))
                                                : 2.0 * reach * hk_test_uniform();
                    const hk_Vec3 p = hk_v3_madd(s.centre, random_direction(), r);
                    const double dent = hk_shape_dent(&s, p, NULL, NULL);
                    if (hk_shape_beyond(&s, extra, margin, p)) {
                        beyond++;
                        assert_true(dent + extra <= -margin);
                    }
                    if (hk_shape_outside(&s, p)) {
                        outside++;
                        assert_true(dent < 0.0);
                    }
                }
                assert_true(beyond > 500);
                if (s.kind != HK_SHAPE_CUBOID) assert_true(outside > 1000);
                /* the cube's envelope corner at the reach: just beyond it is beyond */
                if (i == 6) {
                    const hk_Vec3 diag = hk_v3_normalize(hk_v3_add(hk_v3_add(s.axis[0], s.axis[1]), s.axis[2]));
                    const hk_Vec3 p = hk_v3_madd(s.centre, diag, reach * (1.0 + 1e-8));
                    assert_true(hk_shape_beyond(&s, extra, margin, p));
                    assert_true(hk_shape_dent(&s, p, NULL, NULL) + extra <= -margin);
                    assert_false(hk_shape_beyond(&s, extra, margin, hk_v3_madd(s.centre, diag, reach * 0.999)));
                }
            }
}

/* ---- sums over shapes ----------------------------------------------------------- */

static void test_sums(void **state)
{
    (void)state;
    hk_Shape all[SHAPE_COUNT];
    for (int i = 0; i < SHAPE_COUNT; i++) all[i] = test_shape(i);
    /* two overlapping spheres and a cuboid share a contact region */
    hk_Shape over[3] = {hk_shape_sphere(hk_v3(0, 0, 0), 0.1, 0.02, 50.0),
                        hk_shape_sphere(hk_v3(0.15, 0, 0), 0.1, 0.0, 10.0),
                        hk_shape_cuboid(hk_v3(0.05, 0.1, 0), hk_v3(0.05, 0.05, 0.05), rotated_axes, 0.01, 5.0)};
    const hk_Vec3 probe = hk_v3(0.08, 0.02, 0.01);
    int multi = 0;
    for (int pass = 0; pass < 2; pass++) {
        const hk_Shape *set = pass ? over : all;
        const int n = pass ? 3 : SHAPE_COUNT;
        for (int t = 0; t < 400; t++) {
            const hk_Vec3 p = pass ? hk_v3_madd(probe, random_direction(), 0.08 * hk_test_uniform())
                                   : random_point(&set[t % n], 0.0, 1.2);
            const double alpha = hk_test_uniform();
            /* the sum overwrites whatever the outputs held */
            hk_Vec3 g = hk_v3(1e300, -1, 7);
            hk_Mat3 h = hk_m3_scale(&(hk_Mat3){{{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}}, 1e200);
            const double e = hk_collision_penalty(set, n, alpha, p, &g, &h);
            /* each shape adds onto its outputs: accumulate from a non-zero start */
            hk_Vec3 ga = hk_v3(0.5, -0.25, 2.0);
            hk_Mat3 ha = hk_m3_identity();
            double es = 0.0, depth = 0.0;
            int touching = 0;
            for (int i = 0; i < n; i++) {
                hk_Vec3 gi = hk_v3_zero();
                hk_Mat3 hi = hk_m3_zero();
                const double ei = hk_shape_penalty(&set[i], alpha, p, &gi, &hi);
                hk_shape_penalty(&set[i], alpha, p, &ga, &ha);
                es += ei;
                touching += ei > 0;
                depth = fmax(depth, hk_shape_dent(&set[i], p, NULL, NULL) + alpha * set[i].volume);
            }
            multi += touching > 1;
            hk_assert_rel(e, es, 1e-14, 1e-300);
            hk_Vec3 gd = hk_v3_sub(ga, hk_v3(0.5, -0.25, 2.0));
            hk_Mat3 id = hk_m3_identity(), hd = hk_m3_scale(&id, -1.0);
            hd = hk_m3_add(&ha, &hd);
            const double gs = 1e-13 * (1.0 + hk_v3_norm(g)), hsc = 1e-13 * (1.0 + mat_max_diff(&h, &(hk_Mat3){{{0}}}));
            hk_assert_near(hk_v3_dist(g, gd), 0.0, gs);
            hk_assert_near(mat_max_diff(&h, &hd), 0.0, hsc);
            hk_assert_near(hk_collision_depth(set, n, alpha, p), depth, 0.0);
        }
    }
    assert_true(multi > 20);
    /* hess without grad: the Hessian still contains k grad grad^T (first call at
     * another point so stale stack values would show). */
    for (int i = 0; i < SHAPE_COUNT; i++) {
        const hk_Shape *s = &all[i];
        hk_Vec3 g;
        hk_Mat3 h_both, h_only;
        const hk_Vec3 p1 = at_local(s, 0.5 * s->half.x, -0.3 * s->half.y, 0.2 * s->half.z);
        const hk_Vec3 p2 = at_local(s, -0.2 * s->half.x, 0.6 * s->half.y, -0.1 * s->half.z);
        hk_collision_penalty(s, 1, 0.5, p1, &g, &h_both);
        hk_collision_penalty(s, 1, 0.5, p2, &g, &h_both);
        hk_collision_penalty(s, 1, 0.5, p1, NULL, &h_only);
        hk_collision_penalty(s, 1, 0.5, p1, &g, &h_both);
        hk_assert_near(mat_max_diff(&h_both, &h_only), 0.0, 0.0);
        hk_Mat3 zero = hk_m3_zero();
        assert_true(mat_max_diff(&h_only, &zero) > 0.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_values),
        cmocka_unit_test(test_ellipsoid_values),
        cmocka_unit_test(test_cuboid_values),
        cmocka_unit_test(test_centre_and_degenerate),
        cmocka_unit_test(test_dent_derivatives),
        cmocka_unit_test(test_penalty_derivatives),
        cmocka_unit_test(test_envelope),
        cmocka_unit_test(test_bound_never_rejects_contacts),
        cmocka_unit_test(test_bound_follows_edits),
        cmocka_unit_test(test_beyond_and_outside),
        cmocka_unit_test(test_sums),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
