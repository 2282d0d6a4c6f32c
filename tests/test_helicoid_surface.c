/* Interpolation of generalized helicoids on a surface (Piuze et al. 2011 §4.3): root frames averaged
 * relative to the surface normal (hk_phelicoid_interpolate_on_surface), the lift that makes
 * every strand leave the surface, the mesh query behind the guides' normals
 * (hk_mesh_closest_point), and the whole chain on the project's head: follicles on the wick,
 * the example guides interpolated at them. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/follicle_sampling.h"
#include "hairkit/helicoid.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/mesh.h"


static hk_Vec3 random_unit(void)
{
    for (;;) {
        const hk_Vec3 v = hk_v3(2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1, 2 * hk_test_uniform() - 1);
        const double n = hk_v3_norm(v);
        if (n > 0.1 && n <= 1.0) return hk_v3_scale(v, 1.0 / n);
    }
}

/* A rotation whose first column is t (unit), rolled by `roll` about it. */
static hk_Mat3 frame_along(hk_Vec3 t, double roll)
{
    const hk_Vec3 helper = fabs(t.x) < 0.9 ? hk_v3(1, 0, 0) : hk_v3(0, 1, 0);
    const hk_Vec3 a = hk_v3_normalize(hk_v3_cross(t, helper)), b = hk_v3_cross(t, a);
    const hk_Vec3 n = hk_v3_add(hk_v3_scale(a, cos(roll)), hk_v3_scale(b, sin(roll)));
    return hk_m3_from_cols(t, n, hk_v3_cross(t, n));
}

static void assert_rotation(const hk_Mat3 *q, double tol)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            hk_assert_near(hk_v3_dot(hk_m3_col(q, i), hk_m3_col(q, j)), i == j ? 1.0 : 0.0, tol);
    hk_assert_near(hk_v3_dot(hk_m3_col(q, 0), hk_v3_cross(hk_m3_col(q, 1), hk_m3_col(q, 2))), 1.0, tol);
}

/* n guides on the unit sphere, each leaving along its normal (E_T = the outward normal) with a
 * random roll, two pieces with random parameters. */
static void sphere_guides(int n, hk_PHelicoid *g, hk_Vec3 *normals)
{
    for (int i = 0; i < n; i++) {
        memset(&g[i], 0, sizeof g[i]);
        normals[i] = random_unit();
        g[i].root = normals[i];
        g[i].frame = frame_along(normals[i], 6.283 * hk_test_uniform());
        g[i].piece_count = 2;
        for (int j = 0; j < 2; j++) {
            g[i].k[j] = (hk_Helicoid){4 * hk_test_uniform() - 2, hk_test_uniform() - 0.5, hk_test_uniform() - 0.5,
                                      hk_test_uniform() - 0.5};
            g[i].length[j] = 0.2 + hk_test_uniform();
        }
    }
}

/* Guides that leave along their normals give strands that leave along theirs, exactly, all round
 * a sphere; averaging the frames in space instead (hk_phelicoid_interpolate) tilts them far off. */
static void test_frames_relative_to_the_surface(void **state)
{
    (void)state;
    enum { N = 12 };
    hk_PHelicoid g[N], a, b;
    hk_Vec3 normals[N];
    sphere_guides(N, g, normals);
    hk_Error err;
    double worst_plain = 0.0;
    for (int k = 0; k < 200; k++) {
        const hk_Vec3 n = random_unit();
        /* the normal of any length: the result is the same */
        const hk_Vec3 n2 = hk_v3_scale(n, 3.0);
        assert_int_equal(hk_phelicoid_interpolate_on_surface(g, normals, N, n, n2, 3.0, 0.0, &a, &err), HK_OK);
        assert_rotation(&a.frame, 1e-12);
        hk_assert_near(hk_v3_dot(hk_m3_col(&a.frame, 0), n), 1.0, 1e-12);
        /* everything but the frame is the plain interpolation's, to the bit */
        assert_int_equal(hk_phelicoid_interpolate(g, N, n, NULL, 3.0, &b, &err), HK_OK);
        assert_int_equal(a.piece_count, b.piece_count);
        assert_memory_equal(a.k, b.k, sizeof a.k);
        assert_memory_equal(a.length, b.length, sizeof a.length);
        assert_memory_equal(&a.root, &b.root, sizeof a.root);
        worst_plain = fmax(worst_plain, acos(fmin(1.0, hk_v3_dot(hk_m3_col(&b.frame, 0), n))));
    }
    print_message("largest angle between E_T and the normal, frames averaged in space: %.2f rad\n", worst_plain);
    assert_true(worst_plain > 0.5);
    /* at a guide's root: the guide itself (canonical), as in hk_phelicoid_interpolate */
    assert_int_equal(hk_phelicoid_interpolate_on_surface(g, normals, N, g[3].root, normals[3], 3.0, 0.3, &a, &err),
                     HK_OK);
    assert_int_equal(hk_phelicoid_interpolate(g, N, g[3].root, NULL, 3.0, &b, &err), HK_OK);
    assert_memory_equal(&a, &b, sizeof a);
}

/* The frame is carried by the smallest rotation between the normals: one guide lying along the
 * surface (E_T tangent, E_N along the normal) stays so, turned with the surface, and its
 * direction follows the great circle through the two points. */
static void test_transport_by_smallest_rotation(void **state)
{
    (void)state;
    hk_PHelicoid g;
    memset(&g, 0, sizeof g);
    g.root = hk_v3(0, 0, 1);
    g.frame = hk_m3_from_cols(hk_v3(1, 0, 0), hk_v3(0, 0, 1), hk_v3(0, -1, 0)); /* along +x, bending out */
    g.piece_count = 1;
    g.k[0] = (hk_Helicoid){1.0, 0.0, 0.0, 0.0};
    g.length[0] = 1.0;
    const hk_Vec3 gn = g.root;
    hk_Error err;
    hk_PHelicoid out;
    /* along the great circle x-z: E_T stays in that plane, tangent to the sphere */
    const double t = 0.7;
    const hk_Vec3 x = hk_v3(sin(t), 0, cos(t));
    assert_int_equal(hk_phelicoid_interpolate_on_surface(&g, &gn, 1, x, x, 3.0, 0.0, &out, &err), HK_OK);
    const hk_Vec3 et = hk_m3_col(&out.frame, 0), en = hk_m3_col(&out.frame, 1);
    hk_assert_near(et.x, cos(t), 1e-14);
    hk_assert_near(et.y, 0.0, 1e-14);
    hk_assert_near(et.z, -sin(t), 1e-14);
    hk_assert_near(hk_v3_dot(en, x), 1.0, 1e-14);
    /* the far side of the sphere (opposite normals): a half turn, still a rotation, still
     * tangent */
    const hk_Vec3 far = hk_v3(0, 0, -1);
    assert_int_equal(hk_phelicoid_interpolate_on_surface(&g, &gn, 1, far, far, 3.0, 0.0, &out, &err), HK_OK);
    assert_rotation(&out.frame, 1e-14);
    hk_assert_near(hk_v3_dot(hk_m3_col(&out.frame, 0), far), 0.0, 1e-14);
}

/* Strands never leave into the surface: an interpolated E_T below the minimum elevation is
 * raised to it by the smallest rotation (its azimuth kept); above it, nothing changes. */
static void test_lift_off_the_surface(void **state)
{
    (void)state;
    hk_PHelicoid g[2];
    hk_Vec3 gn[2] = {hk_v3(0, 1, 0), hk_v3(0, 1, 0)};
    memset(g, 0, sizeof g);
    for (int i = 0; i < 2; i++) {
        g[i].root = hk_v3(i ? 1.0 : -1.0, 0, 0);
        g[i].piece_count = 1;
        g[i].k[0] = (hk_Helicoid){0.5, 0.0, 0.0, 0.0};
        g[i].length[0] = 1.0;
    }
    /* E_T 20 degrees into the plane y = 0, towards +x and towards +z */
    const double e = 20.0 * HK_PI / 180.0;
    g[0].frame = frame_along(hk_v3(cos(e), -sin(e), 0), 0.3);
    g[1].frame = frame_along(hk_v3(0, -sin(e), cos(e)), 1.1);
    hk_Error err;
    hk_PHelicoid out;
    const double floors[] = {0.0, 0.1, 0.7, 1.5};
    for (int f = 0; f < 4; f++)
        for (int k = 0; k <= 10; k++) {
            const hk_Vec3 x = hk_v3(-0.9 + 0.18 * k, 0, 0.05);
            assert_int_equal(
                hk_phelicoid_interpolate_on_surface(g, gn, 2, x, hk_v3(0, 1, 0), 3.0, floors[f], &out, &err), HK_OK);
            assert_rotation(&out.frame, 1e-12);
            const hk_Vec3 et = hk_m3_col(&out.frame, 0);
            hk_assert_near(et.y, sin(floors[f]), 1e-12);
            /* the azimuth is kept: E_T's horizontal part points where it did */
            hk_PHelicoid plain;
            assert_int_equal(hk_phelicoid_interpolate(g, 2, x, NULL, 3.0, &plain, &err), HK_OK);
            const hk_Vec3 pt = hk_m3_col(&plain.frame, 0);
            hk_assert_near(atan2(et.z, et.x), atan2(pt.z, pt.x), 1e-12);
        }
    /* straight into the surface: raised towards E_N */
    g[0].frame = hk_m3_from_cols(hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(0, 0, 1));
    const hk_Vec3 up = hk_v3(0, 1, 0);
    assert_int_equal(hk_phelicoid_interpolate_on_surface(g, gn, 1, hk_v3(0, 0, 0), up, 3.0, 0.2, &out, &err), HK_OK);
    assert_rotation(&out.frame, 1e-12);
    hk_assert_near(out.frame.m[1][0], sin(0.2), 1e-12);
    assert_true(out.frame.m[0][0] > 0.9);
    /* already out of the surface: the frame is untouched */
    g[0].frame = frame_along(hk_v3(0, 1, 0), 0.4);
    g[1].frame = frame_along(hk_v3_normalize(hk_v3(0.3, 0.9, 0.1)), 0.2);
    hk_PHelicoid a, b;
    assert_int_equal(hk_phelicoid_interpolate_on_surface(g, gn, 2, hk_v3(0.2, 0, 0), up, 3.0, 0.0, &a, &err), HK_OK);
    assert_int_equal(hk_phelicoid_interpolate_on_surface(g, gn, 2, hk_v3(0.2, 0, 0), up, 3.0, 0.5, &b, &err), HK_OK);
    assert_memory_equal(&a.frame, &b.frame, sizeof a.frame);
}

static void test_surface_bad_input(void **state)
{
    (void)state;
    hk_PHelicoid g[2], out;
    hk_Vec3 gn[2];
    sphere_guides(2, g, gn);
    hk_Error err;
    const hk_Vec3 x = hk_v3(0, 0, 1), zero = hk_v3_zero();
#define EXPECT_BAD(call)                                                                                               \
    do {                                                                                                               \
        hk_error_clear(&err);                                                                                          \
        assert_int_equal((call), HK_ERR_INVALID);                                                                      \
        assert_true(err.message[0] != '\0');                                                                           \
    } while (0)
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, NULL, 2, x, x, 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(NULL, gn, 2, x, x, 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 0, x, x, 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, zero, 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, hk_v3(NAN, 0, 1), 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, hk_v3(NAN, 0, 0), x, 3.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 0.0, 0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, -0.1, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, HK_PI / 2, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, NAN, &out, &err));
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, 0.1, NULL, &err));
    gn[1] = zero;
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, 0.1, &out, &err));
    hk_assert_contains(err.message, "guide 1");
    gn[1] = hk_v3(INFINITY, 0, 0);
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, 0.1, &out, &err));
    gn[1] = hk_v3(0, 1, 0);
    g[0].length[0] = -1.0;
    EXPECT_BAD(hk_phelicoid_interpolate_on_surface(g, gn, 2, x, x, 3.0, 0.1, &out, &err));
    hk_assert_contains(err.message, "guide 0");
#undef EXPECT_BAD
}

/* Closest points and blended normals on a two-triangle square with tilted vertex normals. */
static void test_mesh_closest_point(void **state)
{
    (void)state;
    hk_Mesh m;
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(&m, 4, 2, &err), HK_OK);
    const hk_Vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    const int t[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 4; i++) {
        m.positions[i] = p[i];
        m.normals[i] = hk_v3_normalize(hk_v3(i == 1 || i == 2 ? 1.0 : 0.0, 0.0, 1.0));
    }
    memcpy(m.triangles, t, sizeof t);
    hk_Vec3 q, n;
    /* above the inside: straight down, the normal half-way between the vertices' */
    hk_assert_near(hk_mesh_closest_point(&m, hk_v3(0.5, 0.25, 2.0), &q, &n), 2.0, 1e-15);
    hk_assert_near(q.x, 0.5, 1e-15);
    hk_assert_near(q.y, 0.25, 1e-15);
    hk_assert_near(q.z, 0.0, 1e-15);
    const hk_Vec3 half = hk_v3_normalize(hk_v3(0.5 * sqrt(0.5), 0.0, 0.5 + 0.5 * sqrt(0.5)));
    hk_assert_near(hk_v3_dot(n, half), 1.0, 1e-14);
    /* beyond an edge and a corner */
    hk_assert_near(hk_mesh_closest_point(&m, hk_v3(0.5, -2.0, 0.0), &q, NULL), 2.0, 1e-15);
    hk_assert_near(q.y, 0.0, 1e-15);
    hk_assert_near(hk_mesh_closest_point(&m, hk_v3(2.0, 2.0, 1.0), &q, &n), sqrt(3.0), 1e-15);
    hk_assert_near(q.x, 1.0, 1e-15);
    hk_assert_near(q.y, 1.0, 1e-15);
    hk_assert_near(hk_v3_dot(n, m.normals[2]), 1.0, 1e-15);
    /* no answer for a non-finite point or an empty mesh */
    q = hk_v3(7, 7, 7);
    assert_true(hk_mesh_closest_point(&m, hk_v3(NAN, 0, 0), &q, NULL) < 0.0);
    hk_assert_near(q.x, 7.0, 0.0);
    m.triangle_count = 0;
    assert_true(hk_mesh_closest_point(&m, hk_v3(0, 0, 0), &q, NULL) < 0.0);
    m.triangle_count = 2;
    hk_mesh_free(&m);
}

/* The chain of `hairkit helicoid interpolate --follicles` on the project's head: follicles on
 * the wick, the example guides' normals from the wick, every strand interpolated there leaves
 * the scalp (E_T at least 10 degrees above the tangent plane, its first centimetre outside the
 * head), and the roots are the follicles, on the wick. */
static void test_follicles_on_the_head(void **state)
{
    (void)state;
    hk_Mesh head, wick;
    hk_Error err;
    hk_HelicoidSet guides;
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/head.obj", &head, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick.obj", &wick, &err), HK_OK);
    assert_int_equal(hk_helicoid_file_load(HK_SOURCE_DIR "/examples/helicoid/guides.txt", &guides, &err), HK_OK);
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    def.spacing = 0.015;
    hk_FollicleSamples f;
    assert_int_equal(hk_wick_follicles(&head, &wick, &def, &f, &err), HK_OK);
    hk_Vec3 *gn = malloc(sizeof(hk_Vec3) * (size_t)guides.count);
    assert_non_null(gn);
    for (int i = 0; i < guides.count; i++) {
        assert_true(hk_mesh_closest_point(&wick, guides.strands[i].root, NULL, &gn[i]) < 0.002);
        /* the example's guides leave along the normal */
        assert_true(hk_v3_dot(hk_m3_col(&guides.strands[i].frame, 0), gn[i]) > 0.99);
    }
    const double min_elevation = 10.0 * HK_PI / 180.0;
    double lowest = 1.0;
    for (int i = 0; i < f.count; i++) {
        assert_true(hk_mesh_closest_point(&wick, f.points[i], NULL, NULL) < 0.3 * def.spacing);
        hk_PHelicoid h;
        assert_int_equal(hk_phelicoid_interpolate_on_surface(guides.strands, gn, guides.count, f.points[i],
                                                             f.normals[i], 3.0, min_elevation, &h, &err),
                         HK_OK);
        const double up = hk_v3_dot(hk_m3_col(&h.frame, 0), f.normals[i]);
        lowest = fmin(lowest, up);
        assert_true(up >= sin(min_elevation) - 1e-12);
        /* traced without waves: 2 to 10 mm from the root, outside the head */
        hk_Vec3 pts[64];
        hk_PHelicoid first = h;
        first.piece_count = 1;
        first.length[0] = fmin(h.length[0], 0.01);
        assert_int_equal(hk_phelicoid_trace(&first, 0.001, NULL, NULL, pts, NULL, &err), HK_OK);
        const int n = hk_phelicoid_point_count(&first, 0.001);
        for (int k = 2; k < n; k++) {
            hk_Vec3 q, nq;
            hk_mesh_closest_point(&head, pts[k], &q, &nq);
            assert_true(hk_v3_dot(hk_v3_sub(pts[k], q), nq) > 0.0);
        }
    }
    /* the guides all leave along the normal, so do the strands: the floor is not what
     * holds them up */
    print_message("%d follicles; lowest E_T . n %.3f\n", f.count, lowest);
    assert_true(lowest > 0.9);
    free(gn);
    hk_follicle_samples_free(&f);
    hk_helicoid_set_free(&guides);
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_relative_to_the_surface),
        cmocka_unit_test(test_transport_by_smallest_rotation),
        cmocka_unit_test(test_lift_off_the_surface),
        cmocka_unit_test(test_surface_bad_input),
        cmocka_unit_test(test_mesh_closest_point),
        cmocka_unit_test(test_follicles_on_the_head),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
