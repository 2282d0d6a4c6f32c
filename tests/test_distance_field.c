/* Signed distance fields of meshes (hk_distance_field_build/_eval) against analytic
 * shapes meshed:
 * - a sphere of 8 cm as a subdivided icosahedron: every 7th node against the exact
 *   distance to the mesh (brute force over the triangles, hk_mesh_closest_point): to
 *   float rounding within exact_reach (1 cm) of it, within 10 % beyond (the chamfer
 *   distance); the sign against the analytic
 *   sphere where the node is clearly inside or outside; and the
 *   interpolated field between nodes within 6 mm of the sphere against |p| - R,
 *   within the mesh's own deviation from the sphere plus the trilinear interpolation
 *   error 3 h^2 / (8 |p|);
 * - a cube with its faces, edges and corners on grid nodes, so that columns of the sign
 *   test run exactly along its edges and through its corners: every node's sign against
 *   the analytic box;
 * - the field as a body shape (hk_shape_field) against the analytic sphere shape of the
 *   same radius: dents and their gradients at points near the surface, the same after
 *   both are posed by a rigid motion, and a strand at rest pressed onto each (the rest
 *   shapes within the mesh's deviation from the sphere);
 * - a collision file's Mesh line (the icosphere written as an OBJ in millimetres, z up,
 *   read with Scale 0.001 and Up +z) against a Sphere line of the same centre and radius:
 *   a strand pressed onto each by gravity comes to the same rest (statics), and falls
 *   onto each to the same rest (dynamics, 6 s), within the field's accuracy;
 * - errors: a mesh without triangles, a spacing that gives absurd grids, the memory
 *   budget. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/collide.h"
#include "hairkit/dynamics.h"
#include "hairkit/io.h"
#include "hairkit/mesh.h"
#include "hairkit/rng.h"
#include "hairkit/rod.h"
#include "hairkit/statics.h"

/* A triangle soup: count triangles, 3 vertices each, vertex 3t + c of triangle t. */
static void soup_mesh(hk_Mesh *m, const hk_Vec3 *corners, int triangles)
{
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(m, 3 * triangles, triangles, &err), HK_OK);
    for (int i = 0; i < 3 * triangles; i++) {
        m->positions[i] = corners[i];
        m->triangles[i] = i;
    }
    hk_mesh_compute_normals(m);
}

static int subdivide(const hk_Vec3 *in, int count, hk_Vec3 *out, double r)
{
    int k = 0;
    for (int t = 0; t < count; t++) {
        const hk_Vec3 a = in[3 * t], b = in[3 * t + 1], c = in[3 * t + 2];
        const hk_Vec3 ab = hk_v3_scale(hk_v3_normalize(hk_v3_add(a, b)), r);
        const hk_Vec3 bc = hk_v3_scale(hk_v3_normalize(hk_v3_add(b, c)), r);
        const hk_Vec3 ca = hk_v3_scale(hk_v3_normalize(hk_v3_add(c, a)), r);
        const hk_Vec3 tris[12] = {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca};
        memcpy(out + k, tris, sizeof tris);
        k += 12;
    }
    return count * 4;
}

/* An icosahedron of circumradius r subdivided `levels` times onto the sphere. */
static int icosphere(hk_Mesh *m, double r, int levels)
{
    const double p = (1.0 + sqrt(5.0)) / 2.0;
    const hk_Vec3 v[12] = {hk_v3(-1, p, 0), hk_v3(1, p, 0), hk_v3(-1, -p, 0), hk_v3(1, -p, 0),
                           hk_v3(0, -1, p), hk_v3(0, 1, p), hk_v3(0, -1, -p), hk_v3(0, 1, -p),
                           hk_v3(p, 0, -1), hk_v3(p, 0, 1), hk_v3(-p, 0, -1), hk_v3(-p, 0, 1)};
    const int f[20][3] = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                          {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                          {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    int count = 20;
    hk_Vec3 *a = malloc(sizeof(hk_Vec3) * 3 * 20 * (size_t)pow(4, levels));
    hk_Vec3 *b = malloc(sizeof(hk_Vec3) * 3 * 20 * (size_t)pow(4, levels));
    for (int t = 0; t < 20; t++)
        for (int c = 0; c < 3; c++) a[3 * t + c] = hk_v3_scale(hk_v3_normalize(v[f[t][c]]), r);
    for (int l = 0; l < levels; l++) {
        count = subdivide(a, count, b, r);
        hk_Vec3 *s = a;
        a = b, b = s;
    }
    soup_mesh(m, a, count);
    free(a);
    free(b);
    return count;
}

static void test_sphere(void **state)
{
    (void)state;
    const double r = 0.08;
    hk_Mesh m = {0};
    const int tris = icosphere(&m, r, 3); /* 1,280 triangles */
    hk_DistanceFieldDef def = hk_default_distance_field_def();
    def.spacing = 0.004;
    hk_DistanceField f;
    hk_Error err;
    assert_int_equal(hk_distance_field_build(&m, &def, &f, &err), HK_OK);
    /* How far the flat faces sit inside the sphere: at most at a face's centroid. */
    double sag = 0.0;
    for (int t = 0; t < tris; t++) {
        const hk_Vec3 c = hk_v3_scale(
            hk_v3_add(m.positions[3 * t], hk_v3_add(m.positions[3 * t + 1], m.positions[3 * t + 2])), 1.0 / 3.0);
        sag = fmax(sag, r - hk_v3_norm(c));
    }
    /* every 7th node against the brute-force distance to the mesh */
    double worst = 0.0, worst_far = 0.0;
    long checked = 0, wrong_sign = 0;
    const long nodes = (long)f.size[0] * f.size[1] * f.size[2];
    for (long x = 0; x < nodes; x += 7) {
        const int i = (int)(x % f.size[0]), j = (int)(x / f.size[0] % f.size[1]), k = (int)(x / f.size[0] / f.size[1]);
        const hk_Vec3 p = hk_v3(f.origin.x + i * f.spacing, f.origin.y + j * f.spacing, f.origin.z + k * f.spacing);
        const double exact = hk_mesh_closest_point(&m, p, NULL, NULL);
        const double radial = hk_v3_norm(p);
        const double value = f.distance[x];
        if (exact < def.exact_reach - f.spacing)
            worst = fmax(worst, fabs(fabs(value) - exact));
        else if (exact > def.exact_reach + f.spacing)
            worst_far = fmax(worst_far, fabs(fabs(value) - exact) / exact);
        if (radial < r - sag - 1e-9 && value >= 0.0) wrong_sign++;
        if (radial > r + 1e-9 && value <= 0.0) wrong_sign++;
        checked++;
    }
    print_message("sphere of %d triangles (faces up to %.2f mm inside), %d x %d x %d nodes: %ld checked, largest "
                  "|distance| error %.3g m within 1 cm of the mesh, %.3g of the distance beyond; %ld wrong signs\n",
                  tris, 1e3 * sag, f.size[0], f.size[1], f.size[2], checked, worst, worst_far, wrong_sign);
    /* Within exact_reach the closest triangles are found (float storage: ~1e-8 m);
     * beyond, the chamfer distance of the 26 neighbours with steps 1, sqrt 2, sqrt 3 is
     * at most about 8 % long (it is exact along those 13 directions). */
    assert_true(worst < 1e-6);
    assert_true(worst_far < 0.10);
    assert_int_equal(wrong_sign, 0);
    /* between nodes: against the sphere itself */
    double between = 0.0, angle = 0.0;
    for (int s = 0; s < 20000; s++) {
        const hk_Vec3 p =
            hk_v3(0.24 * hk_rng_uniform(7, 0, (uint64_t)s) - 0.12, 0.24 * hk_rng_uniform(7, 1, (uint64_t)s) - 0.12,
                  0.24 * hk_rng_uniform(7, 2, (uint64_t)s) - 0.12);
        hk_Vec3 g;
        const double value = hk_distance_field_eval(&f, p, &g);
        if (fabs(hk_v3_norm(p) - r) > 0.006) continue; /* cells whose nodes are within 1 cm */
        between = fmax(between, fabs(value - (hk_v3_norm(p) - r)));
        angle = fmax(angle, acos(fmin(1.0, hk_v3_dot(hk_v3_normalize(g), hk_v3_normalize(p)))));
    }
    /* trilinear interpolation errs by at most 3 h^2 M / 8 where the Hessian is below M:
     * 1 / |p| for |p| - R, |p| >= R - 1 cm here */
    const double bound = sag + 3.0 * f.spacing * f.spacing / (8.0 * (r - 0.01)) + 1e-6;
    print_message("between nodes: largest error against |p| - R %.3g m (bound %.3g m); gradient within %.1f "
                  "degrees of the normal (within 6 mm of the surface)\n",
                  between, bound, angle * 180.0 / HK_PI);
    assert_true(between <= bound);
    assert_true(angle < 10.0 * HK_PI / 180.0);
    /* far outside the grid: the distance grows with the way out */
    hk_assert_near(hk_distance_field_eval(&f, hk_v3(1.0, 0.0, 0.0), NULL), 1.0 - r, sag + 0.01);
    hk_distance_field_free(&f);
    hk_mesh_free(&m);
}

/* The cube [-a, a]^3 as 12 triangles. */
static void cube(hk_Mesh *m, double a)
{
    const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {2, 3, 7}, {2, 7, 6}, {1, 2, 6}, {1, 6, 5}, {0, 4, 7}, {0, 7, 3}};
    hk_Vec3 v[8];
    for (int i = 0; i < 8; i++) v[i] = hk_v3((i & 1) ^ ((i >> 1) & 1) ? a : -a, i & 2 ? a : -a, i & 4 ? a : -a);
    hk_Vec3 corners[36];
    for (int t = 0; t < 12; t++)
        for (int c = 0; c < 3; c++) corners[3 * t + c] = v[f[t][c]];
    soup_mesh(m, corners, 12);
}

static void test_cube_on_the_grid(void **state)
{
    (void)state;
    hk_Mesh m = {0};
    cube(&m, 0.05);
    hk_DistanceFieldDef def = hk_default_distance_field_def();
    def.spacing = 0.005; /* the cube's faces on nodes: margin a multiple of the spacing */
    def.margin = 0.02;
    hk_DistanceField f;
    hk_Error err;
    assert_int_equal(hk_distance_field_build(&m, &def, &f, &err), HK_OK);
    long wrong = 0, checked = 0;
    double worst = 0.0;
    for (int k = 0; k < f.size[2]; k++)
        for (int j = 0; j < f.size[1]; j++)
            for (int i = 0; i < f.size[0]; i++) {
                const hk_Vec3 p =
                    hk_v3(f.origin.x + i * f.spacing, f.origin.y + j * f.spacing, f.origin.z + k * f.spacing);
                /* the box's signed distance */
                const hk_Vec3 q = hk_v3(fabs(p.x) - 0.05, fabs(p.y) - 0.05, fabs(p.z) - 0.05);
                const hk_Vec3 qo = hk_v3(fmax(q.x, 0.0), fmax(q.y, 0.0), fmax(q.z, 0.0));
                const double exact = hk_v3_norm(qo) + fmin(fmax(q.x, fmax(q.y, q.z)), 0.0);
                const double value =
                    f.distance[((size_t)k * (size_t)f.size[1] + (size_t)j) * (size_t)f.size[0] + (size_t)i];
                if (fabs(exact) < def.exact_reach - f.spacing) worst = fmax(worst, fabs(value - exact));
                if (fabs(exact) > 1e-9 && (value > 0.0) != (exact > 0.0)) wrong++;
                checked++;
            }
    print_message("cube on the grid: %ld nodes, %ld wrong signs, largest error within 1 cm %.3g m\n", checked, wrong,
                  worst);
    assert_int_equal(wrong, 0);
    assert_true(worst < 1e-6);
    hk_distance_field_free(&f);
    hk_mesh_free(&m);
}

static void test_field_as_shape(void **state)
{
    (void)state;
    const double r = 0.08;
    hk_Mesh m = {0};
    icosphere(&m, r, 4); /* 5,120 triangles: faces within 0.09 mm of the sphere */
    hk_DistanceField f;
    hk_Error err;
    assert_int_equal(hk_distance_field_build(&m, NULL, &f, &err), HK_OK);
    hk_Shape shapes[2] = {hk_shape_field(&f, 0.0, 1e4), hk_shape_sphere(hk_v3_zero(), r, 0.0, 1e4)};
    /* posed: turned 40 degrees about (1, 2, 3) and moved */
    hk_RigidState head = {0};
    const hk_Vec3 axis = hk_v3_normalize(hk_v3(1.0, 2.0, 3.0));
    const double c = cos(0.7), sn = sin(0.7);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            head.rot.m[i][j] = c * (i == j) + (1.0 - c) * hk_v3_get(axis, i) * hk_v3_get(axis, j) +
                               sn * ((i == 1 && j == 0) - (i == 0 && j == 1)) * axis.z +
                               sn * ((i == 0 && j == 2) - (i == 2 && j == 0)) * axis.y +
                               sn * ((i == 2 && j == 1) - (i == 1 && j == 2)) * axis.x;
    head.trans = hk_v3(0.3, 1.5, -0.2);
    hk_Shape posed[2];
    hk_shapes_posed(shapes, 2, &head, posed);
    double worst = 0.0, worst_angle = 0.0;
    for (int s = 0; s < 5000; s++) {
        const hk_Vec3 dir =
            hk_v3_normalize(hk_v3(hk_rng_uniform(3, 0, (uint64_t)s) - 0.5, hk_rng_uniform(3, 1, (uint64_t)s) - 0.5,
                                  hk_rng_uniform(3, 2, (uint64_t)s) - 0.5));
        const hk_Vec3 p = hk_v3_scale(dir, r + 0.008 * (hk_rng_uniform(3, 3, (uint64_t)s) - 0.5));
        hk_Vec3 world;
        hk_rigid_point(&head, p, &world, NULL, NULL);
        for (int k = 0; k < 2; k++) {
            const hk_Shape *pair = k ? posed : shapes;
            const hk_Vec3 x = k ? world : p;
            hk_Vec3 gf, gs;
            const double df = hk_shape_dent(&pair[0], x, &gf, NULL), ds = hk_shape_dent(&pair[1], x, &gs, NULL);
            worst = fmax(worst, fabs(df - ds));
            worst_angle = fmax(worst_angle, acos(fmin(1.0, hk_v3_dot(hk_v3_normalize(gf), gs))));
        }
    }
    print_message("field shape against the sphere within 4 mm of its surface, resting and posed: dents within "
                  "%.3g m, gradients within %.1f degrees\n",
                  worst, worst_angle * 180.0 / HK_PI);
    assert_true(worst < 3e-4); /* faces 0.09 mm in, trilinear 3 h^2 / (8 * 7.6 cm) = 0.02 mm */
    assert_true(worst_angle < 5.0 * HK_PI / 180.0);

    /* A strand of 20 cm from the top of the sphere, pressed down on it by gravity. */
    hk_StrandDef sd = hk_default_strand_def();
    double lengths[10] = {0};
    for (int e = 0; e < 10; e++) lengths[e] = 0.02;
    sd.element_count = 10;
    sd.element_lengths = lengths;
    sd.radius1 = sd.radius2 = 5e-5;
    sd.young = 3e9;
    hk_Vec3 rest[2][11];
    for (int k = 0; k < 2; k++) {
        hk_SuperHelix *sh = NULL;
        assert_int_equal(hk_superhelix_from_def(&sd, hk_v3(0.0, r, 0.0), hk_v3(1.0, 0.3, 0.2), &sh, &err), HK_OK);
        hk_StrandEnvDef env = hk_default_strand_env_def();
        env.shapes = &shapes[k];
        env.shape_count = 1;
        env.collision_step = 0.005;
        hk_MinimizeResult res;
        assert_int_equal(hk_statics_solve(sh, &env, NULL, &res, &err), HK_OK);
        hk_superhelix_nodes(sh, NULL, rest[k], NULL);
        hk_superhelix_destroy(sh);
    }
    double apart = 0.0, drop = rest[1][0].y - rest[1][10].y;
    for (int i = 0; i <= 10; i++) apart = fmax(apart, hk_v3_dist(rest[0][i], rest[1][i]));
    print_message("a strand at rest on the field and on the sphere: nodes within %.3g m (the tip %.3g m below "
                  "the root)\n",
                  apart, drop);
    assert_true(drop > 0.05); /* it hangs over the sphere */
    assert_true(apart < 1e-3);
    hk_distance_field_free(&f);
    hk_mesh_free(&m);
}

/* A strand of 20 cm, 10 elements, rooted at `root` on top of a body and pointing along
 * (1, 0.3, 0.2), in the environment of `set`'s shapes. */
static hk_SuperHelix *strand_over(const hk_CollisionSet *set, hk_Vec3 root, hk_StrandEnvDef *env)
{
    static double lengths[10] = {0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02, 0.02};
    hk_StrandDef sd = hk_default_strand_def();
    sd.element_count = 10;
    sd.element_lengths = lengths;
    sd.radius1 = sd.radius2 = 5e-5;
    sd.young = 3e9;
    *env = hk_default_strand_env_def();
    env->shapes = set->shapes;
    env->shape_count = set->count;
    env->collision_step = 0.005;
    hk_Error err;
    hk_SuperHelix *sh = NULL;
    assert_int_equal(hk_superhelix_from_def(&sd, root, hk_v3(1.0, 0.3, 0.2), &sh, &err), HK_OK);
    return sh;
}

/* The strand's statics rest on each set. */
static void rest_on(const hk_CollisionSet sets[2], hk_Vec3 root, hk_Vec3 rest[2][11])
{
    for (int k = 0; k < 2; k++) {
        hk_StrandEnvDef env;
        hk_SuperHelix *sh = strand_over(&sets[k], root, &env);
        hk_MinimizeResult res;
        hk_Error err;
        assert_int_equal(hk_statics_solve(sh, &env, NULL, &res, &err), HK_OK);
        hk_superhelix_nodes(sh, NULL, rest[k], NULL);
        hk_superhelix_destroy(sh);
    }
}

/* The strand started straight falls onto each set for `seconds` (frames of 1/60 s): the
 * largest distance between the two strands' nodes at any frame, the last frame's. */
static void fall_on(const hk_CollisionSet sets[2], hk_Vec3 root, double seconds, double *largest, double *last)
{
    hk_SuperHelix *sh[2];
    hk_StrandDynamics *d[2];
    hk_Error err;
    const hk_DynamicsDef dd = hk_default_dynamics_def();
    for (int k = 0; k < 2; k++) {
        hk_StrandEnvDef env;
        sh[k] = strand_over(&sets[k], root, &env);
        assert_int_equal(hk_strand_dynamics_create(sh[k], &dd, &env, &d[k], &err), HK_OK);
    }
    const double dt = 1.0 / 60.0;
    *largest = 0.0;
    for (int f = 0; f < (int)(seconds / dt + 0.5); f++) {
        hk_Vec3 nodes[2][11];
        for (int k = 0; k < 2; k++) {
            assert_int_equal(hk_strand_dynamics_advance(d[k], NULL, NULL, f * dt, dt, NULL, 0, NULL, &err), HK_OK);
            hk_superhelix_nodes(sh[k], NULL, nodes[k], NULL);
        }
        *last = 0.0;
        for (int i = 0; i <= 10; i++) *last = fmax(*last, hk_v3_dist(nodes[0][i], nodes[1][i]));
        *largest = fmax(*largest, *last);
    }
    for (int k = 0; k < 2; k++) {
        hk_strand_dynamics_destroy(d[k]);
        hk_superhelix_destroy(sh[k]);
    }
}

static void test_collision_file_mesh(void **state)
{
    (void)state;
    const double r = 0.08;
    const hk_Vec3 centre = hk_v3(0.01, 0.02, 0.03);
    hk_Mesh m = {0};
    icosphere(&m, r, 4); /* 5,120 triangles: faces within 0.09 mm of the sphere */
    /* Written as another tool would: millimetres, z up. The collision file's transform,
     * p = (x, z, -y) / 1000 (hk_v3_up_to_y of +z), brings it back onto the sphere. */
    for (int i = 0; i < m.vertex_count; i++) {
        const hk_Vec3 p = hk_v3_add(m.positions[i], centre);
        m.positions[i] = hk_v3_scale(hk_v3(p.x, -p.z, p.y), 1000.0);
    }
    hk_mesh_compute_normals(&m);
    hk_Error err;
    char mesh_path[1024];
    snprintf(mesh_path, sizeof mesh_path, "%s/sphere_mm.obj", hk_test_tmpdir());
    assert_int_equal(hk_obj_save(mesh_path, &m, "an icosphere of 80 mm, z up", &err), HK_OK);
    hk_mesh_free(&m);

    hk_CollisionSet sets[2]; /* the Mesh line, the Sphere line */
    assert_int_equal(
        hk_collision_load(hk_test_write_text("meshed.txt", "Mesh 0 1e4 sphere_mm.obj 0.001 +z\n"), &sets[0], &err),
        HK_OK);
    char line[128];
    snprintf(line, sizeof line, "Sphere 0 1e4 %.17g %.17g %.17g %.17g\n", centre.x, centre.y, centre.z, r);
    assert_int_equal(hk_collision_load(hk_test_write_text("analytic.txt", line), &sets[1], &err), HK_OK);
    assert_int_equal(sets[0].count, 1);
    assert_int_equal(sets[0].field_count, 1);
    assert_int_equal(sets[0].shapes[0].kind, HK_SHAPE_FIELD);
    assert_int_equal(sets[0].shapes[0].styling, 0);
    assert_ptr_equal(sets[0].shapes[0].field, sets[0].fields[0]);
    hk_assert_near(sets[0].fields[0]->spacing, 0.002, 0); /* the default grid, in metres */

    hk_Vec3 rest[2][11];
    const hk_Vec3 root = hk_v3_add(centre, hk_v3(0.0, r, 0.0));
    rest_on(sets, root, rest);
    double apart = 0.0;
    for (int i = 0; i <= 10; i++) apart = fmax(apart, hk_v3_dist(rest[0][i], rest[1][i]));
    const double drop = root.y - rest[1][10].y;
    double largest = 0.0, last = 0.0;
    fall_on(sets, root, 6.0, &largest, &last);
    print_message("a strand on the collision file's Mesh and on its Sphere: at rest (statics) nodes within %.3g m "
                  "(the tip %.3g m below the root); falling onto them (dynamics) within %.3g m at most, %.3g m "
                  "after 6 s\n",
                  apart, drop, largest, last);
    assert_true(drop > 0.05); /* it hangs over the sphere */
    /* The field's accuracy as test_field_as_shape measures it (faces 0.09 mm inside the
     * sphere, the trilinear field, gradients within 2.7 degrees) moves a draped strand by
     * at most 0.4 mm: both rests within 1 mm. */
    assert_true(apart < 1e-3);
    assert_true(last < 1e-3);
    /* On the way the faceted field and the sphere meet the strand at slightly different
     * moments: a bounded lag, not another path (the strand moves by 19 cm). */
    assert_true(largest < 1e-2);
    hk_collision_free(&sets[0]);
    hk_collision_free(&sets[1]);
    hk_collision_free(&sets[0]); /* a freed set may be freed again */
}

static void test_errors(void **state)
{
    (void)state;
    hk_Mesh m = {0};
    hk_DistanceField f;
    hk_Error err;
    assert_int_equal(hk_distance_field_build(&m, NULL, &f, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "no triangles");
    cube(&m, 0.05);
    hk_DistanceFieldDef def = hk_default_distance_field_def();
    def.spacing = 1e-9;
    assert_int_equal(hk_distance_field_build(&m, &def, &f, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "nodes along an axis");
    def.spacing = 0.0;
    assert_int_equal(hk_distance_field_build(&m, &def, &f, &err), HK_ERR_INVALID);
    /* 50,000^3 nodes would pass the per-axis check but not the memory budget */
    def.spacing = 2e-6;
    assert_int_equal(hk_distance_field_build(&m, &def, &f, &err), HK_ERR_NOMEM);
    assert_null(f.distance);
    hk_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere),         cmocka_unit_test(test_cube_on_the_grid),
        cmocka_unit_test(test_field_as_shape), cmocka_unit_test(test_collision_file_mesh),
        cmocka_unit_test(test_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
