/* Strand energy (src/rod/strand_energy.c): each term against an independent
 * evaluation, and the analytic gradient and Hessian against central finite
 * differences, for straight, curly, elliptic and colliding strands; the contacts the
 * energy reports per collision sample against the shapes evaluated at the samples. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/rod.h"
#include "collide/collide_internal.h"
#include "rod/rod_internal.h"

typedef struct Scene {
    hk_SuperHelix *sh;
    hk_Shape shapes[3];
    hk_StrandEnvDef env;
    hk_StrandWorkspace *ws;
} Scene;

/* A curly elliptic strand hanging from (0, 0.1, 0) over a sphere, an ellipsoid and a
 * cuboid placed so that some collision samples are inside each envelope. */
static void scene_init(Scene *sc, int n, int with_shapes, unsigned seed)
{
    double len[16];
    for (int i = 0; i < n; i++) len[i] = 0.2 / n * (1.0 + 0.2 * cos(1.3 * i));
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, len, &sc->sh, &err), HK_OK);
    sc->sh->material = hk_rod_material(4e-5, 5.5e-5, 1.5e9, 0.48, 1300.0, hk_v3(0.3, -9.81, 0.1));
    sc->sh->root = hk_v3(0.0, 0.1, 0.0);
    sc->sh->root_frame = hk_root_frame(hk_v3(1.0, 0.2, 0.3));
    hk_superhelix_set_uniform_rest(sc->sh, 30.0, 120.0, -10.0);
    srand(seed);
    for (int i = 0; i < 3 * n; i++) sc->sh->q[i] = sc->sh->q_rest[i] + 40.0 * (rand() / (double)RAND_MAX - 0.5);
    const hk_Vec3 axes[3] = {hk_v3_normalize(hk_v3(1, 0.2, 0)), hk_v3_normalize(hk_v3(-0.2, 1, 0)), hk_v3(0, 0, 1)};
    /* Put each shape around a point of the current strand so that it is in contact. */
    hk_Vec3 p[3];
    hk_superhelix_eval(sc->sh, NULL, 0.05, &p[0], NULL);
    hk_superhelix_eval(sc->sh, NULL, 0.11, &p[1], NULL);
    hk_superhelix_eval(sc->sh, NULL, 0.17, &p[2], NULL);
    sc->shapes[0] = hk_shape_sphere(hk_v3_add(p[0], hk_v3(0.0, -0.015, 0.004)), 0.02, 0.004, 50.0);
    sc->shapes[1] =
        hk_shape_ellipsoid(hk_v3_add(p[1], hk_v3(0.01, -0.02, 0.0)), hk_v3(0.02, 0.03, 0.025), axes, 0.003, 80.0);
    sc->shapes[2] =
        hk_shape_cuboid(hk_v3_add(p[2], hk_v3(0.0, -0.012, 0.0)), hk_v3(0.01, 0.015, 0.02), axes, 0.002, 30.0);
    sc->env = hk_default_strand_env_def();
    if (with_shapes) {
        sc->env.shapes = sc->shapes;
        sc->env.shape_count = 3;
        sc->env.envelope_alpha = 0.7;
        sc->env.collision_step = 0.004;
    }
    assert_int_equal(hk_strand_workspace_create(sc->sh, &sc->env, &sc->ws, &err), HK_OK);
}

static void scene_free(Scene *sc)
{
    hk_strand_workspace_destroy(sc->ws);
    hk_superhelix_destroy(sc->sh);
}

/* Central differences of the energy (gradient) and of the analytic gradient
 * (Hessian). Steps of 1e-3 / m on curvatures of ~100 / m keep truncation (h^2 E''' ~
 * 1e-6 relative) and rounding (eps E / h ~ 1e-13 relative) well below the tolerances:
 * 1e-6 of the largest entry. */
static void check_derivatives(Scene *sc)
{
    const int dim = 3 * sc->sh->n;
    double *g = calloc((size_t)dim, sizeof *g), *h = calloc((size_t)dim * dim, sizeof *h);
    double *gp = calloc((size_t)dim, sizeof *gp), *gm = calloc((size_t)dim, sizeof *gm);
    double *q = calloc((size_t)dim, sizeof *q);
    hk_strand_energy(sc->sh, &sc->env, sc->sh->q, sc->ws, g, h, NULL);
    double gmax = 0.0, hmax = 0.0;
    for (int i = 0; i < dim; i++) gmax = fmax(gmax, fabs(g[i]));
    for (int i = 0; i < dim * dim; i++) hmax = fmax(hmax, fabs(h[i]));
    const double step = 1e-3;
    for (int j = 0; j < dim; j++) {
        memcpy(q, sc->sh->q, (size_t)dim * sizeof *q);
        q[j] += step;
        double ep = hk_strand_energy(sc->sh, &sc->env, q, sc->ws, gp, NULL, NULL);
        q[j] -= 2 * step;
        double em = hk_strand_energy(sc->sh, &sc->env, q, sc->ws, gm, NULL, NULL);
        hk_assert_near(g[j], (ep - em) / (2 * step), 1e-6 * gmax);
        for (int i = 0; i < dim; i++) hk_assert_near(h[(size_t)i * dim + j], (gp[i] - gm[i]) / (2 * step), 1e-6 * hmax);
    }
    /* The Hessian is symmetric by construction, exactly. */
    for (int i = 0; i < dim; i++)
        for (int j = 0; j < i; j++) assert_true(h[(size_t)i * dim + j] == h[(size_t)j * dim + i]);
    free(g), free(h), free(gp), free(gm), free(q);
}

static void test_derivatives_free_strand(void **state)
{
    (void)state;
    for (unsigned seed = 1; seed <= 3; seed++) {
        Scene sc;
        scene_init(&sc, 5, 0, seed);
        check_derivatives(&sc);
        scene_free(&sc);
    }
}

static void test_derivatives_with_contacts(void **state)
{
    (void)state;
    for (unsigned seed = 1; seed <= 3; seed++) {
        Scene sc;
        scene_init(&sc, 6, 1, seed);
        hk_StrandEnergy parts;
        hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, NULL, NULL, &parts);
        assert_true(parts.collision > 0.0); /* the test must exercise contacts */
        check_derivatives(&sc);
        scene_free(&sc);
    }
}

static void test_energy_terms_independent(void **state)
{
    (void)state;
    Scene sc;
    scene_init(&sc, 6, 1, 7);
    hk_StrandEnergy parts;
    double total = hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, NULL, NULL, &parts);
    hk_assert_rel(total, parts.elastic + parts.gravity + parts.collision, 1e-15, 0);

    /* Elastic: sum l_Q K_i (q - q_rest)^2 / 2 written out directly. */
    double el = 0.0;
    for (int p = 0; p < sc.sh->n; p++)
        for (int i = 0; i < 3; i++) {
            double d = sc.sh->q[3 * p + i] - sc.sh->q_rest[3 * p + i];
            el += 0.5 * sc.sh->material.stiffness[i] * sc.sh->length[p] * d * d;
        }
    hk_assert_rel(parts.elastic, el, 1e-14, 0);

    /* Gravity: -rho S g . int r ds by composite Simpson over the reconstruction,
     * element by element (the closed form must agree to the quadrature error). */
    double grav = 0.0;
    const hk_Vec3 fg = hk_v3_scale(sc.sh->material.gravity, -sc.sh->material.mass_per_length);
    for (int p = 0; p < sc.sh->n; p++) {
        const int m = 400;
        const double a = sc.sh->s_start[p], hstep = sc.sh->length[p] / m;
        for (int j = 0; j <= m; j++) {
            hk_Vec3 r;
            hk_superhelix_eval(sc.sh, NULL, fmin(a + j * hstep, nextafter(sc.sh->s_start[p + 1], 0)), &r, NULL);
            double w = (j == 0 || j == m) ? 1.0 : (j % 2 ? 4.0 : 2.0);
            grav += w * hstep / 3.0 * hk_v3_dot(fg, r);
        }
    }
    hk_assert_rel(parts.gravity, grav, 1e-11, 0);

    /* Collision: the midpoint sum over ceil(L / step) pieces, evaluated here. */
    const int pieces = (int)ceil(sc.sh->total_length / sc.env.collision_step - 1e-9);
    const double w = sc.sh->total_length / pieces;
    double col = 0.0;
    for (int i = 0; i < pieces; i++) {
        hk_Vec3 r;
        hk_superhelix_eval(sc.sh, NULL, (i + 0.5) * w, &r, NULL);
        col += w * hk_collision_penalty(sc.shapes, 3, sc.env.envelope_alpha, r, NULL, NULL);
    }
    hk_assert_rel(parts.collision, col, 1e-12, 0);
    assert_true(parts.collision > 0.0);
    scene_free(&sc);
}

static void test_gravity_of_straight_rods(void **state)
{
    (void)state;
    /* A straight rod at angle a below horizontal: int y ds = -sin(a) L^2 / 2. */
    Scene sc;
    scene_init(&sc, 4, 0, 1);
    hk_superhelix_set_uniform_rest(sc.sh, 0, 0, 0);
    sc.sh->material.gravity = hk_v3(0, -9.81, 0);
    sc.sh->root = hk_v3(0, 0, 0);
    for (int t = 0; t < 5; t++) {
        double a = -1.0 + 0.5 * t;
        sc.sh->root_frame = hk_root_frame(hk_v3(cos(a), -sin(a), 0.0));
        hk_StrandEnergy parts;
        hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, NULL, NULL, &parts);
        double expected =
            sc.sh->material.mass_per_length * 9.81 * (-sin(a)) * 0.5 * sc.sh->total_length * sc.sh->total_length;
        hk_assert_near(parts.gravity, expected, 1e-18);
    }
    scene_free(&sc);
}

static void test_penetration_report(void **state)
{
    (void)state;
    Scene sc;
    scene_init(&sc, 6, 1, 2);
    double depth = hk_strand_max_penetration(sc.sh, &sc.env, sc.sh->q, sc.ws);
    assert_true(depth > 0.0);
    /* No shapes, no penetration. */
    sc.env.shape_count = 0;
    hk_StrandWorkspace *ws2;
    hk_Error err;
    assert_int_equal(hk_strand_workspace_create(sc.sh, &sc.env, &ws2, &err), HK_OK);
    hk_assert_near(hk_strand_max_penetration(sc.sh, &sc.env, sc.sh->q, ws2), 0.0, 0.0);
    hk_strand_workspace_destroy(ws2);
    scene_free(&sc);
}

/* hk_strand_workspace_contact: after an evaluation with a gradient, exactly the samples
 * inside an envelope are reported, each with w times the penalty gradient at its
 * position (s = (i + 1/2) w, reconstructed independently); none after an evaluation
 * without a gradient or a penetration query. */
static void test_contacts_per_sample(void **state)
{
    (void)state;
    Scene sc;
    scene_init(&sc, 6, 1, 3);
    const int m = hk_strand_collision_sample_count(sc.sh, &sc.env);
    const double w = sc.sh->total_length / m;
    double grad[18];
    hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, grad, NULL, NULL);
    int touching = 0;
    for (int i = 0; i < m; i++) {
        hk_Vec3 p, g, reported;
        hk_superhelix_eval(sc.sh, NULL, (i + 0.5) * w, &p, NULL);
        const double e = hk_collision_penalty(sc.shapes, 3, sc.env.envelope_alpha, p, &g, NULL);
        const int touches = hk_strand_workspace_contact(sc.ws, i, &reported);
        assert_int_equal(touches, e > 0.0);
        if (!touches) continue;
        touching++;
        hk_assert_near(hk_v3_dist(reported, hk_v3_scale(g, w)), 0.0, 1e-9 * w * hk_v3_norm(g));
    }
    assert_true(touching > 0 && touching < m);
    hk_Vec3 g;
    assert_int_equal(hk_strand_workspace_contact(sc.ws, -1, &g), 0);
    assert_int_equal(hk_strand_workspace_contact(sc.ws, m, &g), 0);
    hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, NULL, NULL, NULL);
    for (int i = 0; i < m; i++) assert_int_equal(hk_strand_workspace_contact(sc.ws, i, &g), 0);
    hk_strand_energy(sc.sh, &sc.env, sc.sh->q, sc.ws, grad, NULL, NULL);
    hk_strand_max_penetration(sc.sh, &sc.env, sc.sh->q, sc.ws);
    for (int i = 0; i < m; i++) assert_int_equal(hk_strand_workspace_contact(sc.ws, i, &g), 0);
    scene_free(&sc);
}

/* What one hk_strand_energy call gives: energy, gradient and Hessian for order 0, 1, 2
 * (dim 18 at most), and the contacts per sample. */
typedef struct Result {
    double e, g[18], h[18 * 18];
    int touches[512];
    hk_Vec3 reported[512];
} Result;

static void energy_of(Scene *sc, hk_StrandWorkspace *ws, const double *q, int order, Result *r)
{
    memset(r, 0, sizeof *r);
    r->e = hk_strand_energy(sc->sh, &sc->env, q, ws, order >= 1 ? r->g : NULL, order >= 2 ? r->h : NULL, NULL);
    const int m = hk_strand_collision_sample_count(sc->sh, &sc->env);
    assert_true(m <= 512);
    for (int i = 0; i < m; i++) r->touches[i] = hk_strand_workspace_contact(ws, i, &r->reported[i]);
}

/* hk_strand_workspace_prepare's walk: the next hk_strand_energy call with the same
 * coordinates, root pose, order and shapes starts from it and gives the bytes of a
 * workspace never prepared; a call with other coordinates, another root pose or another
 * order walks afresh (each also the bytes of a fresh workspace, and those inputs do
 * change the bytes: a key that left one out would fail here). The prepared nodes and
 * samples agree with the superhelix's own walk to rounding; a sample left out lies
 * beyond the reach of every shape. */
static void test_prepared_walk(void **state)
{
    (void)state;
    Scene sc;
    scene_init(&sc, 6, 1, 5);
    const int dim = 3 * sc.sh->n, m = hk_strand_collision_sample_count(sc.sh, &sc.env);
    hk_StrandWorkspace *fresh;
    hk_Error err;
    assert_int_equal(hk_strand_workspace_create(sc.sh, &sc.env, &fresh, &err), HK_OK);
    static Result a, b, c;
    double q[18], other[18];
    memcpy(q, sc.sh->q, (size_t)dim * sizeof(double));
    memcpy(other, q, sizeof other);
    other[4] += 1e-6;
    for (int order = 0; order <= 2; order++) {
        hk_strand_workspace_prepare(sc.sh, &sc.env, q, order, sc.ws);
        energy_of(&sc, sc.ws, q, order, &a);
        energy_of(&sc, fresh, q, order, &b);
        assert_memory_equal(&a, &b, sizeof a);
        /* prepared for other coordinates: not taken */
        hk_strand_workspace_prepare(sc.sh, &sc.env, other, order, sc.ws);
        energy_of(&sc, sc.ws, q, order, &a);
        assert_memory_equal(&a, &b, sizeof a);
        energy_of(&sc, fresh, other, order, &c);
        assert_memory_not_equal(&c, &b, sizeof c);
        /* prepared with the root elsewhere: not taken */
        const hk_Vec3 root = sc.sh->root;
        sc.sh->root = hk_v3_add(root, hk_v3(0.0, 1e-4, 0.0));
        hk_strand_workspace_prepare(sc.sh, &sc.env, q, order, sc.ws);
        energy_of(&sc, fresh, q, order, &c);
        assert_memory_not_equal(&c, &b, sizeof c);
        sc.sh->root = root;
        energy_of(&sc, sc.ws, q, order, &a);
        assert_memory_equal(&a, &b, sizeof a);
        /* prepared for another order: not taken (order 2's closed forms are the
         * two-element lane code's) */
        hk_strand_workspace_prepare(sc.sh, &sc.env, q, order == 2 ? 1 : 2, sc.ws);
        energy_of(&sc, sc.ws, q, order, &a);
        assert_memory_equal(&a, &b, sizeof a);
    }
    /* the prepared walk's nodes and samples, with a small sphere at the tip alone, so
     * that the elements far from the tip are out of its reach */
    hk_Vec3 nodes[7], walked[7], pos[512], at;
    unsigned char known[512];
    hk_superhelix_nodes(sc.sh, q, walked, NULL);
    const hk_Shape small = hk_shape_sphere(walked[sc.sh->n], 1e-3, 0.0, 10.0);
    hk_StrandEnvDef tip_only = sc.env;
    tip_only.shapes = &small;
    tip_only.shape_count = 1;
    hk_strand_workspace_prepare(sc.sh, &tip_only, q, 2, sc.ws);
    memcpy(nodes, hk_strand_workspace_nodes(sc.ws), sizeof nodes);
    hk_strand_workspace_samples(sc.ws, pos, known);
    for (int i = 0; i <= sc.sh->n; i++) hk_assert_near(hk_v3_dist(nodes[i], walked[i]), 0.0, 1e-12);
    const double w = sc.sh->total_length / m;
    int computed = 0;
    for (int i = 0; i < m; i++) {
        hk_superhelix_eval(sc.sh, q, (i + 0.5) * w, &at, NULL);
        if (known[i]) {
            computed++;
            hk_assert_near(hk_v3_dist(pos[i], at), 0.0, 1e-12);
            continue;
        }
        const hk_Shape *sh = &small;
        const double reach = hk_shape_bound(sh) + sqrt(3.0) * fabs(tip_only.envelope_alpha * sh->volume);
        assert_true(hk_v3_dist(at, sh->centre) > reach);
    }
    assert_true(computed > 0 && computed < m);
    hk_strand_workspace_destroy(fresh);
    scene_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_derivatives_free_strand),
        cmocka_unit_test(test_derivatives_with_contacts),
        cmocka_unit_test(test_energy_terms_independent),
        cmocka_unit_test(test_gravity_of_straight_rods),
        cmocka_unit_test(test_penetration_report),
        cmocka_unit_test(test_contacts_per_sample),
        cmocka_unit_test(test_prepared_walk),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
