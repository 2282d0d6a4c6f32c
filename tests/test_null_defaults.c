/* NULL for a parameter struct means its defaults, in every entry point that takes one
 * (docs/library.md, "Conventions"): each is called with NULL and gives what it gives with
 * the default struct passed explicitly (or, where the defaults leave a value to be set,
 * the same error), never a crash. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hairkit.h"

/* ---- rendering ------------------------------------------------------------------ */

/* Three short strands around the origin. */
static void small_hair(hk_HairFile *hair)
{
    const uint32_t points[3] = {4, 4, 4};
    assert_int_equal(hk_hair_alloc(hair, 3, points, NULL), HK_OK);
    for (int s = 0; s < 3; s++)
        for (int i = 0; i < 4; i++) {
            float *p = hair->points + 3 * (4 * s + i);
            p[0] = 0.01f * (float)s;
            p[1] = -0.02f * (float)i;
            p[2] = 0.005f * (float)(s * i);
        }
}

static void test_render(void **state)
{
    (void)state;
    hk_HairFile hair = {0};
    small_hair(&hair);
    const hk_RenderDef defaults = hk_default_render_def();
    const hk_Visuality colours = hk_default_visuality();
    hk_Error err;
    hk_Canvas a = {0}, b = {0};
    /* hk_render with NULL options: the defaults (it crashed) */
    assert_int_equal(hk_render(&hair, NULL, NULL, NULL, &a, NULL, &err), HK_OK);
    assert_int_equal(hk_render(&hair, NULL, &colours, &defaults, &b, NULL, &err), HK_OK);
    assert_int_equal(a.width, defaults.width);
    assert_int_equal(a.height, defaults.height);
    assert_int_equal(a.width, b.width);
    assert_memory_equal(a.rgb, b.rgb, (size_t)a.width * (size_t)a.height * 3 * sizeof *a.rgb);
    hk_canvas_free(&a);
    hk_canvas_free(&b);

    hk_Renderer *r;
    assert_int_equal(hk_renderer_create(&r, &err), HK_OK);
    assert_int_equal(hk_renderer_draw(r, &hair, NULL, NULL, NULL, NULL, &err), HK_OK);
    hk_renderer_destroy(r);

    hk_Vec3 t1, t2;
    double d1, d2;
    assert_int_equal(hk_render_fit_camera(&hair, NULL, NULL, &t1, &d1, &err), HK_OK);
    assert_int_equal(hk_render_fit_camera(&hair, NULL, &defaults, &t2, &d2, &err), HK_OK);
    assert_memory_equal(&t1, &t2, sizeof t1);
    assert_true(d1 == d2);
    hk_hair_free(&hair);
}

/* ---- minimisers ------------------------------------------------------------------ */

static double bowl(void *user, const double *x)
{
    (void)user;
    return (x[0] - 1.0) * (x[0] - 1.0) + 2.0 * (x[1] + 0.5) * (x[1] + 0.5);
}

static double bowl_derivs(void *user, const double *x, double *grad, double *hess)
{
    if (grad) grad[0] = 2.0 * (x[0] - 1.0), grad[1] = 4.0 * (x[1] + 0.5);
    if (hess) hess[0] = 2.0, hess[1] = hess[2] = 0.0, hess[3] = 4.0;
    return bowl(user, x);
}

static int bowl_residuals(void *user, const double *x, double *r)
{
    (void)user;
    r[0] = x[0] - 1.0, r[1] = sqrt(2.0) * (x[1] + 0.5);
    return 0;
}

static void test_minimizers(void **state)
{
    (void)state;
    hk_Error err;
    const double scale[2] = {0.1, 0.1};

    double x[2] = {0, 0}, y[2] = {0, 0};
    hk_MinimizeResult r1, r2;
    const hk_RosenbrockDef ro = hk_default_rosenbrock_def();
    assert_int_equal(hk_rosenbrock_minimize(2, x, bowl, NULL, NULL, &r1, &err), HK_OK);
    assert_int_equal(hk_rosenbrock_minimize(2, y, bowl, NULL, &ro, &r2, &err), HK_OK);
    assert_memory_equal(x, y, sizeof x);

    const hk_NewtonDef no = hk_default_newton_def();
    x[0] = x[1] = y[0] = y[1] = 0.0;
    assert_int_equal(hk_newton_minimize(2, x, bowl_derivs, NULL, NULL, NULL, &r1, &err), HK_OK);
    assert_int_equal(hk_newton_minimize(2, y, bowl_derivs, NULL, NULL, &no, &r2, &err), HK_OK);
    assert_memory_equal(x, y, sizeof x);
    hk_assert_near(x[0], 1.0, 1e-6);

    const hk_NelderMeadDef nm = hk_default_nelder_mead_def();
    hk_MinimizeResult n1, n2;
    x[0] = x[1] = y[0] = y[1] = 0.0;
    assert_int_equal(hk_nelder_mead_minimize(2, x, scale, bowl, NULL, NULL, &n1, &err), HK_OK);
    assert_int_equal(hk_nelder_mead_minimize(2, y, scale, bowl, NULL, &nm, &n2, &err), HK_OK);
    assert_memory_equal(x, y, sizeof x);

    const hk_LeastSquaresDef lo = hk_default_least_squares_def();
    double work[HK_LEAST_SQUARES_WORK(2, 2)];
    hk_MinimizeResult l1, l2;
    x[0] = x[1] = y[0] = y[1] = 0.0;
    assert_int_equal(hk_least_squares_minimize(2, 2, x, scale, bowl_residuals, NULL, NULL, work, &l1, &err), HK_OK);
    assert_int_equal(hk_least_squares_minimize(2, 2, y, scale, bowl_residuals, NULL, &lo, work, &l2, &err), HK_OK);
    assert_memory_equal(x, y, sizeof x);
}

/* ---- a strand: energy, statics, dynamics --------------------------------------- */

static hk_SuperHelix *strand(void)
{
    const double lengths[3] = {0.03, 0.03, 0.03};
    hk_SuperHelix *sh;
    assert_int_equal(hk_superhelix_create(3, lengths, &sh, NULL), HK_OK);
    sh->material = hk_rod_material(4e-5, 4e-5, 3e9, 0.48, 1300, hk_v3(0, -9.81, 0));
    sh->root_frame = hk_root_frame(hk_v3(1, 0, 0));
    return sh;
}

static void test_strand(void **state)
{
    (void)state;
    hk_Error err;
    hk_SuperHelix *sh = strand();
    const hk_StrandEnvDef env = hk_default_strand_env_def();
    assert_int_equal(hk_strand_collision_sample_count(sh, NULL), 0);
    hk_StrandWorkspace *ws;
    assert_int_equal(hk_strand_workspace_create(sh, NULL, &ws, &err), HK_OK);
    double g1[9], g2[9];
    const double e1 = hk_strand_energy(sh, NULL, sh->q, ws, g1, NULL, NULL);
    const double e2 = hk_strand_energy(sh, &env, sh->q, ws, g2, NULL, NULL);
    assert_true(e1 == e2);
    assert_memory_equal(g1, g2, sizeof g1);
    assert_true(hk_strand_max_penetration(sh, NULL, sh->q, ws) == 0.0);
    hk_strand_workspace_destroy(ws);

    /* statics: NULL environment and options, against the defaults */
    hk_SuperHelix *other = strand();
    const hk_StaticsDef so = hk_default_statics_def();
    hk_MinimizeResult r1, r2;
    assert_int_equal(hk_statics_solve(sh, NULL, NULL, &r1, &err), HK_OK);
    assert_int_equal(hk_statics_solve(other, &env, &so, &r2, &err), HK_OK);
    assert_memory_equal(sh->q, other->q, 9 * sizeof(double));

    /* dynamics: NULL parameters and body, one step each */
    const hk_DynamicsDef dp = hk_default_dynamics_def();
    hk_StrandDynamics *d1, *d2;
    assert_int_equal(hk_strand_dynamics_create(sh, NULL, NULL, &d1, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_create(other, &dp, &env, &d2, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_step(d1, NULL, NULL, 0, 1.0 / 30.0, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_step(d2, NULL, NULL, 0, 1.0 / 30.0, &err), HK_OK);
    assert_memory_equal(sh->q, other->q, 9 * sizeof(double));
    hk_strand_dynamics_destroy(d1);
    hk_strand_dynamics_destroy(d2);
    hk_superhelix_destroy(sh);
    hk_superhelix_destroy(other);

    /* capture: a fit and an inverse with NULL parameters, against the defaults */
    const hk_Vec3 pts[4] = {hk_v3(0, 0, 0), hk_v3(0.01, -0.01, 0), hk_v3(0.015, -0.02, 0.003),
                            hk_v3(0.016, -0.03, 0.01)};
    const hk_SuperHelixFitDef fd = hk_default_superhelix_fit_def();
    hk_SuperHelix *f1, *f2;
    assert_int_equal(hk_superhelix_fit(pts, 4, NULL, NULL, &f1, NULL, &err), HK_OK);
    assert_int_equal(hk_superhelix_fit(pts, 4, NULL, &fd, &f2, NULL, &err), HK_OK);
    assert_int_equal(f1->n, f2->n);
    assert_memory_equal(f1->q, f2->q, 3 * (size_t)f1->n * sizeof(double));
    const hk_InverseStaticsDef id = hk_default_inverse_statics_def();
    assert_int_equal(hk_statics_invert(f1, NULL, NULL, NULL, &err), HK_OK);
    assert_int_equal(hk_statics_invert(f2, &env, &id, NULL, &err), HK_OK);
    assert_memory_equal(f1->q_rest, f2->q_rest, 3 * (size_t)f1->n * sizeof(double));
    hk_superhelix_destroy(f1);
    hk_superhelix_destroy(f2);

    hk_HairContacts *c;
    assert_int_equal(hk_hair_contacts_create(2, NULL, &c, &err), HK_OK);
    hk_hair_contacts_destroy(c);
}

/* ---- fitting and follicles ------------------------------------------------------ */

static hk_Vec3 unit_sphere_points[26];

static double sphere_eval(const void *user, hk_Vec3 x, hk_Vec3 *grad)
{
    (void)user;
    if (grad) *grad = hk_v3_scale(x, 2.0);
    return hk_v3_dot(x, x) - 1.0;
}

static void test_fitting(void **state)
{
    (void)state;
    hk_Error err;
    /* an arc of a helix */
    hk_Vec3 arc[40];
    for (int i = 0; i < 40; i++) {
        const double t = 0.05 * i;
        arc[i] = hk_v3(0.02 * cos(t), 0.02 * sin(t), 0.004 * t);
    }
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, &err);
    assert_non_null(f);
    const hk_CurveFitDef hf = hk_default_helicoid_fit_def();
    hk_PHelicoid h1, h2;
    hk_CurveFit c1, c2;
    memset(&h1, 0, sizeof h1), memset(&h2, 0, sizeof h2);
    assert_int_equal(hk_helicoid_fit(f, arc, 40, NULL, &h1, &c1, &err), HK_OK);
    assert_int_equal(hk_helicoid_fit(f, arc, 40, &hf, &h2, &c2, &err), HK_OK);
    assert_true(c1.error == c2.error);
    assert_memory_equal(&h1, &h2, sizeof h1);
    hk_helicoid_fitter_destroy(f);

    double seed[2] = {10.0, 5.0}, scale[2] = {1.0, 1.0};
    assert_int_equal(
        hk_curve_fit_piecewise(arc, 40, hk_curve_model_frenet_helix, NULL, 2, seed, scale, NULL, &c1, &err), HK_OK);

    /* an implicit sphere fitted to points on it, NULL def */
    int n = 0;
    for (int i = -1; i <= 1; i++)
        for (int j = -1; j <= 1; j++)
            for (int k = -1; k <= 1; k++)
                if (i || j || k) unit_sphere_points[n++] = hk_v3_normalize(hk_v3(i, j, k));
    hk_ImplicitSurface *surface;
    assert_int_equal(hk_implicit_surface_fit(unit_sphere_points, unit_sphere_points, n, NULL, &surface, &err), HK_OK);
    hk_implicit_surface_destroy(surface);

    /* The sampling defaults leave the spacing to be set: NULL gives that error. */
    hk_FollicleSamples out;
    const hk_ImplicitFunction fn = {sphere_eval, NULL};
    assert_int_equal(hk_sample_follicles(fn, unit_sphere_points, n, NULL, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "spacing");
    hk_Mesh wick = {0};
    assert_int_equal(hk_mesh_alloc(&wick, 3, 1, &err), HK_OK);
    for (int i = 0; i < 3; i++) {
        wick.positions[i] = unit_sphere_points[i];
        wick.normals[i] = unit_sphere_points[i];
        wick.triangles[i] = i;
    }
    assert_int_equal(hk_wick_follicles(NULL, &wick, NULL, &out, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "spacing");
    hk_mesh_free(&wick);
}

/* ---- a head: grooming, the scene, the simulation -------------------------------- */

static void test_head(void **state)
{
    (void)state;
    hk_Error err;
    hk_Scene scene;
    assert_int_equal(hk_scene_load(hk_test_light_setup(), HK_SCENE_GROOMING, &scene, &err), HK_OK);
    hk_HairFile a = {0}, b = {0};
    const hk_GroomDef go = hk_default_groom_def();
    assert_int_equal(hk_scene_hair(&scene, NULL, &a, NULL, &err), HK_OK);
    assert_int_equal(hk_scene_hair(&scene, &go, &b, NULL, &err), HK_OK);
    assert_int_equal(a.point_count, b.point_count);
    assert_memory_equal(a.points, b.points, 3 * (size_t)a.point_count * sizeof(float));
    hk_hair_free(&a);
    hk_hair_free(&b);

    /* the simulation's plain defaults: contacts of a 20 cm hair of 40 um radius; for
     * this hairstyle, scaled to its hair */
    const hk_HairSimDef plain = hk_default_hair_sim_def(), mine = hk_hair_sim_def_for(&scene.style);
    assert_true(plain.contacts.stiffness > 0.0 && plain.contacts.damping > 0.0);
    assert_true(mine.contacts.stiffness > 0.0);
    assert_int_equal(plain.dynamics.integrator, mine.dynamics.integrator);

    hk_Groom g = {0};
    assert_int_equal(hk_groom_grow(&scene.style.strand, &scene.style.interpolation, scene.collision.shapes,
                                   scene.collision.count, &scene.wick, NULL, &g, &err),
                     HK_OK);
    assert_int_equal(hk_groom_interpolate_guides(&scene.style.interpolation, scene.collision.shapes,
                                                 scene.collision.count, &scene.wick, NULL, &g, &err),
                     HK_OK);
    hk_groom_free(&g);

    /* the simulation's defaults: one frame at 30 frames/s */
    char dir[1024], frame[1100];
    snprintf(dir, sizeof dir, "%s/null-sim", hk_test_tmpdir());
    hk_SimProgress p;
    assert_int_equal(hk_simulation_run(hk_test_light_setup(), dir, NULL, &p, &err), HK_OK);
    assert_int_equal(hk_simulation_frame_path(frame, sizeof frame, dir, "frame", 0, "png", &err), HK_OK);
    size_t size;
    free(hk_test_read_file(frame, &size));
    assert_true(size > 0);
    hk_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_render),  cmocka_unit_test(test_minimizers), cmocka_unit_test(test_strand),
        cmocka_unit_test(test_fitting), cmocka_unit_test(test_head),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
