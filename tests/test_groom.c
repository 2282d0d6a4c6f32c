/* Grooming a head (src/groom/): roots on the wick along its normals, strand counts
 * from area x density, inextensible strands, roots inside their triangles,
 * determinism across thread counts (of the hair and of the error when guides fail),
 * the thesis's clumping and stray-hair tables,
 * uniform roots, and semi-interpolation across diverging guides. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core_internal.h"
#include "groom/groom_internal.h"
#include "hairkit/groom.h"
#include "hairkit/io.h"
#include "hairkit/rod.h"

/* A small wick: a 4 x 4 cm square made of a 3 x 3 grid of quads (18 triangles),
 * gently domed, at height 0.1 m, normals pointing up and outwards. */
static void make_wick(hk_Mesh *m)
{
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(m, 16, 18, &err), HK_OK);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double x = -0.02 + 0.04 * i / 3, z = -0.02 + 0.04 * j / 3;
            m->positions[4 * i + j] = hk_v3(x, 0.1 - 2.0 * (x * x + z * z), z);
        }
    int t = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int a = 4 * i + j, b = a + 4, c = a + 1, d = b + 1;
            int *tri = m->triangles + 3 * t++;
            tri[0] = a, tri[1] = c, tri[2] = b;
            tri = m->triangles + 3 * t++;
            tri[0] = b, tri[1] = c, tri[2] = d;
        }
    hk_mesh_compute_normals(m);
}

static hk_Hairstyle make_style(double gravity, double helix_radius)
{
    hk_Hairstyle s = hk_default_hairstyle();
    static double lengths[4] = {0.02, 0.02, 0.02, 0.02};
    s.strand.element_count = 4;
    s.strand.element_lengths = lengths; /* not freed: static */
    s.strand.radius1 = s.strand.radius2 = 5e-5;
    s.strand.young = 1e9;
    s.strand.helix_radius = helix_radius;
    s.strand.helix_step = 0.02;
    s.strand.gravity = gravity;
    s.strand.visuality_step = 0.004;
    s.interpolation.hair_density = 300.0; /* per cm^2: about 4800 strands on 16 cm^2 */
    s.interpolation.clump = 0.25;
    s.interpolation.clump_profile = 1.0;
    return s;
}

static double strand_length(const float *p, int points)
{
    double len = 0.0;
    for (int j = 1; j < points; j++)
        len += sqrt(pow(p[3 * j] - p[3 * j - 3], 2) + pow(p[3 * j + 1] - p[3 * j - 2], 2) +
                    pow(p[3 * j + 2] - p[3 * j - 1], 2));
    return len;
}

static void test_straight_guides_follow_normals(void **state)
{
    (void)state;
    /* No gravity, no curl: every guide is the straight line along its follicle normal. */
    hk_Mesh wick;
    make_wick(&wick);
    hk_Hairstyle style = make_style(0.0, 0.0);
    hk_GroomDef o = hk_default_groom_def();
    hk_Groom g;
    hk_Error err;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &g, &err), HK_OK);
    assert_int_equal(g.guide_count, wick.vertex_count);
    assert_int_equal(g.points_per_strand, 21); /* 0.08 / 0.004 + 1 */
    for (int i = 0; i < g.guide_count; i++)
        for (int j = 0; j < g.points_per_strand; j++) {
            const double *p = g.guides + ((size_t)i * g.points_per_strand + j) * 3;
            hk_Vec3 ref = hk_v3_madd(wick.positions[i], wick.normals[i], 0.004 * j);
            hk_assert_near(hk_v3_dist(hk_v3(p[0], p[1], p[2]), ref), 0.0, 1e-12);
        }
    hk_groom_free(&g);
    hk_mesh_free(&wick);
}

static void test_roots_counts_lengths(void **state)
{
    (void)state;
    hk_Mesh wick;
    make_wick(&wick);
    hk_Hairstyle style = make_style(9.81, 0.01);
    hk_GroomDef o = hk_default_groom_def();
    hk_Groom g;
    hk_Error err;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &g, &err), HK_OK);
    const int n = g.points_per_strand;
    /* Guides: root on the wick vertex, first step along its normal: the chord of the
     * first 4 mm leans from the root tangent by at most kappa_max ds / 2, where the
     * curvature near the root is at most the natural one plus the bending of the whole
     * weight, rho S g L^2 / (2 E I) (moment balance at the clamped root). */
    hk_SuperHelix *probe;
    assert_int_equal(hk_superhelix_from_def(&style.strand, hk_v3(0, 0, 0), hk_v3(1, 0, 0), &probe, &err), HK_OK);
    const double kappa0 = hypot(probe->q_rest[0], probe->q_rest[1]);
    const double weight = probe->material.mass_per_length * 9.81 * 0.08 * 0.08 / 2.0;
    const double lean = (kappa0 + weight / probe->material.stiffness[2]) * 0.004 / 2.0;
    hk_superhelix_destroy(probe);
    double guide_min = 1e9, guide_max = 0.0;
    for (int i = 0; i < g.guide_count; i++) {
        const double *p = g.guides + (size_t)i * n * 3;
        hk_assert_near(hk_v3_dist(hk_v3(p[0], p[1], p[2]), wick.positions[i]), 0.0, 0.0);
        hk_Vec3 first = hk_v3_normalize(hk_v3(p[3] - p[0], p[4] - p[1], p[5] - p[2]));
        assert_true(hk_v3_dot(first, wick.normals[i]) >= cos(lean));
        float tmp[3 * 64];
        for (int k = 0; k < 3 * n; k++) tmp[k] = (float)p[k];
        double len = strand_length(tmp, n);
        guide_min = fmin(guide_min, len), guide_max = fmax(guide_max, len);
    }
    /* Counts: floor or ceil of area x density per triangle, the expected total overall. */
    int *count = calloc((size_t)wick.triangle_count, sizeof *count);
    for (int s = 0; s < g.strand_count; s++) count[g.strand_triangle[s]]++;
    double expected = 0.0;
    for (int t = 0; t < wick.triangle_count; t++) {
        double e = hk_mesh_triangle_area(&wick, t) * 1e4 * style.interpolation.hair_density;
        expected += e;
        assert_true(count[t] == (int)floor(e) || count[t] == (int)floor(e) + 1);
    }
    free(count);
    /* Stochastic rounding: the total is within a few sqrt(triangles) of the sum. */
    hk_assert_near((double)g.strand_count, expected, 4.0 * sqrt((double)wick.triangle_count) + 1);
    /* Roots inside their triangle (on the wick within float rounding), lengths kept. */
    for (int s = 0; s < g.strand_count; s++) {
        const int *tri = wick.triangles + 3 * g.strand_triangle[s];
        const float *w = g.strand_root_weights + 3 * s;
        for (int k = 0; k < 3; k++) assert_true(w[k] >= 0.0f && w[k] <= 1.0f);
        hk_Vec3 ref = hk_v3_zero();
        for (int k = 0; k < 3; k++) ref = hk_v3_madd(ref, wick.positions[tri[k]], w[k]);
        const float *p = g.strands + (size_t)s * n * 3;
        hk_assert_near(hk_v3_dist(hk_v3(p[0], p[1], p[2]), ref), 0.0, 1e-6);
        double len = strand_length(p, n);
        assert_true(len >= guide_min - 1e-6 && len <= guide_max + 1e-6);
    }
    /* And no strand is shorter than the strand's arc length by more than the chord
     * deficit of the guides' samples (the guides are sampled on arcs of length L). */
    assert_true(guide_max <= 0.08 + 1e-9 && guide_min > 0.08 * 0.99);
    hk_groom_free(&g);
    hk_mesh_free(&wick);
}

static void test_deterministic_across_threads(void **state)
{
    (void)state;
    hk_Mesh wick;
    make_wick(&wick);
    hk_Hairstyle style = make_style(9.81, 0.01);
    hk_Groom a, b, c;
    hk_Error err;
    hk_GroomDef o = hk_default_groom_def();
    o.seed = 42;
    o.threads = 1;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &a, &err), HK_OK);
    o.threads = 2;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &b, &err), HK_OK);
    assert_int_equal(a.strand_count, b.strand_count);
    const size_t bytes = (size_t)a.strand_count * a.points_per_strand * 3 * sizeof(float);
    assert_memory_equal(a.strands, b.strands, bytes);
    assert_memory_equal(a.guides, b.guides, (size_t)a.guide_count * a.points_per_strand * 3 * sizeof(double));
    o.seed = 43;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &c, &err), HK_OK);
    assert_true(c.strand_count != a.strand_count || memcmp(a.strands, c.strands, bytes) != 0);
    hk_groom_free(&a);
    hk_groom_free(&b);
    hk_groom_free(&c);
    hk_mesh_free(&wick);
}

/* Guides whose follicles have no direction fail: the error reported is the lowest
 * failing guide's, whatever the thread count and the order the guides finish in. */
static void test_first_failing_guide_reported(void **state)
{
    (void)state;
    enum { COUNT = 48 };
    hk_Vec3 position[COUNT], normal[COUNT];
    double alpha[COUNT];
    for (int i = 0; i < COUNT; i++) {
        position[i] = hk_v3(0.001 * i, 0.1, 0.0);
        normal[i] = hk_v3(0.0, 1.0, 0.0);
        alpha[i] = 0.0;
    }
    const int bad[3] = {41, 17, 30};
    for (int k = 0; k < 3; k++) normal[bad[k]] = hk_v3_zero();
    const hk_Follicles f = {COUNT, position, normal, alpha};
    hk_Hairstyle style = make_style(9.81, 0.01);
    hk_GroomDef o = hk_default_groom_def();
    char expected[128];
    snprintf(expected, sizeof expected, "guide 18 (follicle at %.4g, %.4g, %.4g): root direction must be a non-zero",
             position[17].x, position[17].y, position[17].z);
    for (int threads = 1; threads <= 4; threads++)
        for (int rep = 0; rep < 3; rep++) {
            o.threads = threads;
            hk_Groom g;
            memset(&g, 0, sizeof g);
            hk_Error err;
            assert_int_equal(hk_groom_solve_guides(&style.strand, NULL, 0, &f, &o, &g, &err), HK_ERR_INVALID);
            hk_assert_contains(err.message, expected);
            hk_groom_free(&g);
        }
}

/* Thesis §4.1.4.4, Table 4: where v1, v2, v3 go for each ordering of the root weights
 * when the stray-hair behaviour is kept. */
static void test_stray_hair_table(void **state)
{
    (void)state;
    /* root weights ordered as A > B > C, A > C > B, B > C > A, B > A > C, C > A > B, C > B > A */
    const double roots[6][3] = {{0.5, 0.3, 0.2}, {0.5, 0.2, 0.3}, {0.2, 0.5, 0.3},
                                {0.3, 0.5, 0.2}, {0.3, 0.2, 0.5}, {0.2, 0.3, 0.5}};
    /* expected index (1, 2, 3 for v1, v2, v3) given to A, B, C */
    const int table[6][3] = {{3, 2, 1}, {3, 1, 1}, {1, 3, 2}, {1, 3, 1}, {2, 1, 3}, {1, 1, 3}};
    const double clump = 0.25, u1 = 0.4, u2 = 0.8;
    const double v[4] = {0, clump * u1, clump * u2, 1 - clump * (u1 + u2)};
    for (int c = 0; c < 6; c++) {
        double b[3];
        hk_groom_tip_weights(roots[c], clump, u1, u2, 1, b);
        for (int k = 0; k < 3; k++) hk_assert_near(b[k], v[table[c][k]], 1e-15);
        /* Without stray hairs: v3 on the nearest guide, v1 and v2 on the others, sum 1. */
        hk_groom_tip_weights(roots[c], clump, u1, u2, 0, b);
        hk_assert_near(b[0] + b[1] + b[2], 1.0, 1e-15);
        int near = roots[c][0] > roots[c][1] && roots[c][0] > roots[c][2] ? 0 : (roots[c][1] > roots[c][2] ? 1 : 2);
        hk_assert_near(b[near], v[3], 1e-15);
    }
}

static void test_uniform_roots(void **state)
{
    (void)state;
    /* Uniform in the triangle: each weight has mean 1/3 and P(w_A < 1/2) = 3/4. */
    double mean[3] = {0, 0, 0};
    int below_half = 0;
    const int n = 200000;
    for (int i = 0; i < n; i++) {
        double b[3];
        hk_groom_root_weights(hk_test_uniform(), hk_test_uniform(), b);
        for (int k = 0; k < 3; k++) {
            assert_true(b[k] >= 0.0 && b[k] <= 1.0);
            mean[k] += b[k] / n;
        }
        below_half += b[0] < 0.5;
    }
    /* Standard errors: sqrt(1/18 / n) ~ 5e-4 for the means, sqrt(3/16 / n) ~ 1e-3. */
    for (int k = 0; k < 3; k++) hk_assert_near(mean[k], 1.0 / 3.0, 3e-3);
    hk_assert_near((double)below_half / n, 0.75, 5e-3);
}

static void test_semi_interpolation(void **state)
{
    (void)state;
    /* Guides that part in two directions (gravity along -x on a wick facing +y bends
     * all guides the same way; instead part them with a negative max tip distance:
     * any distance counts as far). With MaxTipDistance tiny, every strand copies its
     * nearest guide, translated to its own root. */
    hk_Mesh wick;
    make_wick(&wick);
    hk_Hairstyle style = make_style(9.81, 0.01);
    style.interpolation.max_tip_distance = 1e-9;
    hk_GroomDef o = hk_default_groom_def();
    hk_Groom g;
    hk_Error err;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &o, &g, &err), HK_OK);
    const int n = g.points_per_strand;
    for (int s = 0; s < g.strand_count; s += 37) {
        const float *w = g.strand_root_weights + 3 * s;
        const int near = w[0] >= w[1] && w[0] >= w[2] ? 0 : (w[1] >= w[2] ? 1 : 2);
        const int gi = wick.triangles[3 * g.strand_triangle[s] + near];
        const double *gp = g.guides + (size_t)gi * n * 3;
        const float *p = g.strands + (size_t)s * n * 3;
        for (int j = 1; j < n; j++)
            for (int k = 0; k < 3; k++) hk_assert_near(p[3 * j + k] - p[k], gp[3 * j + k] - gp[k], 2e-6);
    }
    hk_groom_free(&g);
    hk_mesh_free(&wick);
}

static void test_bad_wick(void **state)
{
    (void)state;
    hk_Mesh wick;
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(&wick, 3, 0, &err), HK_OK);
    hk_Follicles f;
    assert_int_equal(hk_follicles_from_wick(&wick, &f, &err), HK_ERR_INVALID);
    hk_mesh_free(&wick);
}

/* A wick of two triangles of area 5e39 m^2 (the vertex at 1e39, made in memory:
 * the OBJ reader refuses it now): area x HairDensity used to go through (long)floor,
 * overflow, and the running total wrap past the size checks, strands written at
 * negative indices. Now an error naming the count, before anything is allocated. */
static void test_huge_wick_refused(void **state)
{
    (void)state;
    hk_Mesh wick;
    hk_Error err;
    assert_int_equal(hk_mesh_alloc(&wick, 4, 2, &err), HK_OK);
    wick.positions[0] = hk_v3(0, 0, 0), wick.positions[1] = hk_v3(1e20, 0, 0);
    wick.positions[2] = hk_v3(0, 0, 1e20), wick.positions[3] = hk_v3(1e20, 0, 1e20);
    const int tris[6] = {0, 2, 1, 1, 2, 3};
    memcpy(wick.triangles, tris, sizeof tris);
    hk_mesh_compute_normals(&wick);
    hk_Hairstyle style = make_style(9.81, 0.0);
    hk_Groom g;
    memset(&g, 0, sizeof g);
    g.guide_count = 4, g.points_per_strand = 2;
    g.guides = calloc(4 * 2 * 3, sizeof(double));
    assert_non_null(g.guides);
    hk_GroomDef o = hk_default_groom_def();
    assert_int_equal(hk_groom_interpolate_guides(&style.interpolation, NULL, 0, &wick, &o, &g, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "HairDensity 300");
    hk_assert_contains(err.message, "more than 100000000 strands");
    assert_int_equal(g.strand_count, 0);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, &o, NULL, &err), HK_ERR_INVALID);
    /* A triangle whose area is not finite. */
    wick.positions[1] = hk_v3(1e200, 0, 0), wick.positions[2] = hk_v3(0, 0, 1e200);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, &o, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "wick triangle 1 has an area of inf");
    free(g.guides);
    hk_mesh_free(&wick);
}

/* The memory budget (core.h): a groom is refused from its counts, before the guides
 * are solved, with the need and the limit in the message; HAIRKIT_MEMORY_LIMIT moves
 * the limit. */
/* A progress callback that counts its calls (user: an int). */
static void count_progress(void *user, const char *stage, double fraction)
{
    (void)stage, (void)fraction;
    ++*(int *)user;
}

static void test_memory_budget(void **state)
{
    (void)state;
    hk_Mesh wick;
    make_wick(&wick);
    hk_Hairstyle style = make_style(9.81, 0.0);
    hk_Error err;
    long strands = 0;
    unsetenv(HK_MEMORY_LIMIT_ENV);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, NULL, &strands, &err), HK_OK);
    assert_true(strands > 4000 && strands < 6000); /* 300 per cm^2 on about 16 cm^2 */
    /* 21 points a strand: (24 x 21 + 26) bytes each and the 16 guides' (36 x 21 + 10). */
    const double bytes = (double)strands * 530.0 + 16.0 * 766.0;
    char limit[64];
    snprintf(limit, sizeof limit, "%.0f", bytes - 1.0);
    setenv(HK_MEMORY_LIMIT_ENV, limit, 1);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, NULL, NULL, &err), HK_ERR_NOMEM);
    hk_assert_contains(err.message, "strands of 21 points with their .hair would take about");
    hk_assert_contains(err.message, "over the limit of");
    hk_assert_contains(err.message, "HAIRKIT_MEMORY_LIMIT raises it");
    /* hk_groom_grow refuses it too, before solving anything. */
    hk_Groom g;
    hk_GroomDef counted = hk_default_groom_def();
    int reports = 0;
    counted.progress = count_progress;
    counted.progress_user = &reports;
    assert_int_equal(hk_groom_grow(&style.strand, &style.interpolation, NULL, 0, &wick, &counted, &g, &err),
                     HK_ERR_NOMEM);
    assert_int_equal(reports, 0); /* no guide was solved (each solved guide reports progress) */
    assert_null(g.guides);
    snprintf(limit, sizeof limit, "%.0f", bytes);
    setenv(HK_MEMORY_LIMIT_ENV, limit, 1);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, NULL, NULL, &err), HK_OK);
    setenv(HK_MEMORY_LIMIT_ENV, "1.5Gi", 1);
    double b = 0.0;
    assert_int_equal(hk_memory_limit(&b, &err), HK_OK);
    hk_assert_near(b, 1.5 * 1024.0 * 1024.0 * 1024.0, 0);
    setenv(HK_MEMORY_LIMIT_ENV, "16GB", 1);
    assert_int_equal(hk_memory_limit(&b, &err), HK_OK);
    hk_assert_near(b, 16e9, 0);
    setenv(HK_MEMORY_LIMIT_ENV, "0x10", 1);
    assert_int_equal(hk_groom_check_size(&style.strand, &style.interpolation, &wick, NULL, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "HAIRKIT_MEMORY_LIMIT='0x10' is not a size");
    unsetenv(HK_MEMORY_LIMIT_ENV);
    /* The default: 8 GB, the machine's memory when smaller. */
    assert_int_equal(hk_memory_limit(&b, &err), HK_OK);
    assert_true(b > 0.0 && b <= 8e9);
    hk_mesh_free(&wick);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_straight_guides_follow_normals),
        cmocka_unit_test(test_roots_counts_lengths),
        cmocka_unit_test(test_deterministic_across_threads),
        cmocka_unit_test(test_first_failing_guide_reported),
        cmocka_unit_test(test_stray_hair_table),
        cmocka_unit_test(test_uniform_roots),
        cmocka_unit_test(test_semi_interpolation),
        cmocka_unit_test(test_bad_wick),
        cmocka_unit_test(test_huge_wick_refused),
        cmocka_unit_test(test_memory_budget),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
