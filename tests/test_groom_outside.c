/* Interpolated hair stays out of the body (src/groom/body_projection.c,
 * docs/grooming.md "Keeping hair outside the body"):
 *  - the default head (examples/default at a lower HairDensity, the same guides and
 *    wick): no point of a strand more than 2 mm inside a body shape, at most 0.05 %
 *    more than 1 mm (blending guides from both sides of the crown put 1.2 % of the
 *    points up to 10 cm deep before), the soft styling sphere in front of the face
 *    excepted;
 *  - the projection keeps every segment of the unprojected blend at its length, leaves
 *    the roots and every strand that touches no body shape as they were;
 *  - regrowing the strands from moved guides (a simulated frame) projects them too;
 *  - a straight strand through a sphere is pushed out around it;
 *  - the quick tests that pass over points clearly outside change no byte;
 *  - the same bytes with 1 and 2 threads. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "groom/groom_internal.h"
#include "hairkit/groom.h"
#include "hairkit/io.h"

typedef struct Head {
    hk_Hairstyle style;
    hk_CollisionSet collision;
    hk_Shape *body;
    int body_count;
    hk_Mesh wick;
    hk_Groom groom; /* grown once (the guides' statics is the slow part), 1 thread */
} Head;

/* Group setup: the default head, grown once; the tests regrow its strands from its
 * guides with other options (hk_groom_interpolate_guides, as a simulated frame does). */
static int load_head(void **state)
{
    static Head head;
    Head *h = &head;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/default/hairstyle.txt", &h->style, &err), HK_OK);
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/default/collision.txt", &h->collision, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick.obj", &h->wick, &err), HK_OK);
    /* A fifth of the hair (about 25,000 strands): the same triangles and guides, enough
     * points to measure 0.05 %, quick under the sanitizers. */
    h->style.interpolation.hair_density = 50.0;
    assert_int_equal(hk_groom_body_shapes(h->collision.shapes, h->collision.count, &h->body, &h->body_count, &err),
                     HK_OK);
    /* The head, the face and the neck; the sphere before the face is styling. */
    assert_int_equal(h->body_count, 3);
    hk_GroomDef o = hk_default_groom_def();
    o.threads = 1;
    assert_int_equal(hk_groom_grow(&h->style.strand, &h->style.interpolation, h->collision.shapes, h->collision.count,
                                   &h->wick, &o, &h->groom, &err),
                     HK_OK);
    assert_true(h->groom.strand_count > 20000);
    *state = h;
    return 0;
}

static int free_head(void **state)
{
    Head *h = *state;
    hk_groom_free(&h->groom);
    hk_hairstyle_free(&h->style);
    hk_collision_free(&h->collision);
    hk_free(h->body);
    hk_mesh_free(&h->wick);
    return 0;
}

/* The head's strands regrown from a copy of its guides, each point of which `sag`
 * lowers by sag * (its index / the last index). */
static void regrow(const Head *h, int keep_outside, int threads, double sag, hk_Groom *g)
{
    const int n = h->groom.points_per_strand;
    const size_t values = (size_t)h->groom.guide_count * n * 3;
    memset(g, 0, sizeof *g);
    g->guide_count = h->groom.guide_count;
    g->points_per_strand = n;
    g->guides = hk_alloc_array(values, sizeof(double), NULL);
    assert_non_null(g->guides);
    memcpy(g->guides, h->groom.guides, values * sizeof(double));
    for (size_t v = 1; v < values; v += 3) g->guides[v] -= sag * (double)((v / 3) % n) / (n - 1);
    hk_GroomDef o = hk_default_groom_def();
    o.keep_outside = keep_outside;
    o.threads = threads;
    hk_Error err;
    assert_int_equal(hk_groom_interpolate_guides(&h->style.interpolation, h->collision.shapes, h->collision.count,
                                                 &h->wick, &o, g, &err),
                     HK_OK);
}

static double depth_at(const Head *h, const float *p)
{
    return hk_collision_depth(h->body, h->body_count, 0.0, hk_v3(p[0], p[1], p[2]));
}

/* The requirement: no point after the root more than 2 mm inside a body shape, at most
 * 0.05 % of them more than 1 mm. */
static void assert_outside(const Head *h, const hk_Groom *g)
{
    long over = 0;
    double deepest = 0.0;
    const int n = g->points_per_strand;
    for (int s = 0; s < g->strand_count; s++)
        for (int j = 1; j < n; j++) {
            const double d = depth_at(h, g->strands + ((size_t)s * n + j) * 3);
            over += d > 0.001;
            deepest = fmax(deepest, d);
        }
    print_message("deepest point %.3g mm inside, %ld of %ld more than 1 mm\n", 1e3 * deepest, over,
                  (long)g->strand_count * (n - 1));
    assert_true(deepest <= 0.002);
    assert_true(over <= 0.0005 * (double)g->strand_count * (n - 1));
}

static void test_default_head_outside_body(void **state)
{
    const Head *h = *state;
    assert_outside(h, &h->groom);
}

static double seg_len(const float *p, int j)
{
    const double dx = (double)p[3 * j] - p[3 * j - 3], dy = (double)p[3 * j + 1] - p[3 * j - 2],
                 dz = (double)p[3 * j + 2] - p[3 * j - 1];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* Against the unprojected blend; and the same bytes with 1 and 2 threads. The blend of
 * every triangle's three guides, MaxTipDistance 0: the default's fade leaves few strands
 * that enter the body (12 of these 24,661, against 701), too few to try the projection
 * on. */
static void test_projection_keeps_lengths(void **state)
{
    Head plain = *(const Head *)state[0];
    plain.style.interpolation.max_tip_distance = 0.0;
    const Head *h = &plain;
    hk_Groom kept1, blend, kept2;
    const hk_Groom *kept = &kept1;
    regrow(h, 1, 1, 0.0, &kept1);
    regrow(h, 0, 0, 0.0, &blend);
    regrow(h, 1, 2, 0.0, &kept2);
    assert_int_equal(blend.strand_count, kept->strand_count);
    assert_int_equal(kept2.strand_count, kept->strand_count);
    assert_memory_equal(kept->strands, kept2.strands,
                        (size_t)kept->strand_count * kept->points_per_strand * 3 * sizeof(float));
    const int n = blend.points_per_strand;
    long moved = 0;
    for (int s = 0; s < blend.strand_count; s++) {
        const float *a = blend.strands + (size_t)s * n * 3, *b = kept->strands + (size_t)s * n * 3;
        assert_memory_equal(a, b, 3 * sizeof(float)); /* the root stays on the scalp */
        int touches = 0;
        for (int j = 1; j < n; j++) touches |= depth_at(h, a + 3 * j) > 0.0;
        if (!touches) {
            assert_memory_equal(a, b, (size_t)n * 3 * sizeof(float));
            continue;
        }
        moved++;
        /* Each segment as long as the blend's, up to the rounding of the float points
         * (coordinates below 0.3 m: a few 1e-8 m each). */
        for (int j = 1; j < n; j++) hk_assert_near(seg_len(b, j), seg_len(a, j), 2e-7);
    }
    assert_true(moved > 100); /* the blend does enter the head */
    hk_groom_free(&kept1);
    hk_groom_free(&blend);
    hk_groom_free(&kept2);
}

/* A simulated frame regrows the strands from guides the dynamics moved
 * (hk_groom_interpolate_guides); guides sagging 3 cm into the head (farther than any
 * frame of a shaking head lets them) still give strands outside it. */
static void test_regrown_strands_outside(void **state)
{
    const Head *h = *state;
    hk_Groom g;
    regrow(h, 1, 0, 0.03, &g);
    assert_outside(h, &g);
    hk_groom_free(&g);
}

/* The quick tests of body_projection.c (a point clearly outside every shape is not
 * asked of hk_collision_deepest) change no byte: every strand of the blend
 * (MaxTipDistance 0, hundreds of which enter the head), and strands laid across the
 * surfaces of the head's three ellipsoids at relative offsets from 1e-5 down to 1e-12
 * of their radii (where the quick tests' slack lies), kept outside by the body shapes
 * with the quick tests and by the same shapes with six far spheres added, more shapes
 * than the quick tests take (8), so that every point is asked of hk_collision_deepest:
 * the same floats. */
static void test_quick_tests_same_bytes(void **state)
{
    Head plain = *(const Head *)state[0];
    plain.style.interpolation.max_tip_distance = 0.0;
    const Head *h = &plain;
    hk_Shape padded[9];
    memcpy(padded, h->body, 3 * sizeof(hk_Shape));
    for (int i = 3; i < 9; i++) padded[i] = hk_shape_sphere(hk_v3(100.0 + i, 0, 0), 0.01, 0.0, 1.0);
    hk_Groom blend;
    regrow(h, 0, 1, 0.0, &blend);
    const int n = blend.points_per_strand;
    float *a = hk_alloc_array((size_t)n, 3 * sizeof(float), NULL),
          *b = hk_alloc_array((size_t)n, 3 * sizeof(float), NULL);
    assert_non_null(a);
    assert_non_null(b);
    long moved = 0;
    for (int s = 0; s < blend.strand_count; s++) {
        memcpy(a, blend.strands + (size_t)s * n * 3, (size_t)n * 3 * sizeof(float));
        memcpy(b, a, (size_t)n * 3 * sizeof(float));
        hk_groom_keep_outside(h->body, 3, a, n);
        hk_groom_keep_outside(padded, 9, b, n);
        assert_memory_equal(a, b, (size_t)n * 3 * sizeof(float));
        moved += memcmp(a, blend.strands + (size_t)s * n * 3, (size_t)n * 3 * sizeof(float)) != 0;
    }
    assert_true(moved > 100);
    /* Across the surfaces: strands of two points, the root a tenth of the radius outside
     * and the point at (1 + e) times the surface's radius in its direction, e running
     * through +-1e-5 ... +-1e-12 and 0 (the root is never moved nor tested). */
    enum { OFFSETS = 17 };
    const double e[OFFSETS] = {1e-5,  -1e-5, 1e-6,   -1e-6, 2e-7,   -2e-7, 1e-8, -1e-8, 1e-9,
                               -1e-9, 1e-10, -1e-10, 1e-12, -1e-12, 0.0,   3e-6, -3e-6};
    long near = 0, pushed = 0;
    for (int shape = 0; shape < 3; shape++)
        for (int dir = 0; dir < 400; dir++) {
            const hk_Shape *sh = &h->body[shape];
            /* directions spread over the sphere (a Fibonacci lattice) */
            const double z = 1.0 - (2.0 * dir + 1.0) / 400.0, r = sqrt(1.0 - z * z), phi = 2.399963229728653 * dir;
            const hk_Vec3 u = hk_v3(r * cos(phi), r * sin(phi), z);
            /* the ellipsoid's radius along u: 1 / sqrt(sum (u.axis_k / half_k)^2) */
            double inv2 = 0.0;
            for (int k = 0; k < 3; k++) {
                const double c = hk_v3_dot(u, sh->axis[k]) / hk_v3_get(sh->half, k);
                inv2 += c * c;
            }
            const double radius = 1.0 / sqrt(inv2);
            for (int j = 0; j < OFFSETS; j++) {
                const hk_Vec3 root = hk_v3_madd(sh->centre, u, radius * 1.1),
                              x = hk_v3_madd(sh->centre, u, radius * (1.0 + e[j]));
                float p[6] = {(float)root.x, (float)root.y, (float)root.z, (float)x.x, (float)x.y, (float)x.z}, q[6];
                near += fabs(hk_shape_dent(sh, hk_v3(p[3], p[4], p[5]), NULL, NULL)) < 1e-7;
                memcpy(q, p, sizeof p);
                hk_groom_keep_outside(h->body, 3, p, 2);
                hk_groom_keep_outside(padded, 9, q, 2);
                assert_memory_equal(p, q, sizeof p);
                pushed += p[3] != (float)x.x || p[4] != (float)x.y || p[5] != (float)x.z;
            }
        }
    print_message("%ld strands of the blend moved; %ld points within 1e-7 m of a surface, %ld pushed\n", moved, near,
                  pushed);
    assert_true(near > 5000 && pushed > 5000);
    hk_free(a);
    hk_free(b);
    hk_groom_free(&blend);
}

/* A straight strand from above a sphere of radius 5 cm straight through it: pushed
 * out, it goes round the sphere with every segment at its length. A styling sphere is
 * not body: hk_groom_body_shapes leaves it out. */
static void test_strand_through_sphere(void **state)
{
    (void)state;
    enum { N = 41 };
    float p[3 * N], q[3 * N];
    for (int j = 0; j < N; j++) { /* from (0.01, 0.07, 0) down to (0.01, -0.13, 0) */
        p[3 * j] = 0.01f;
        p[3 * j + 1] = (float)(0.07 - 0.005 * j);
        p[3 * j + 2] = 0.0f;
    }
    memcpy(q, p, sizeof p);
    hk_Shape shapes[2] = {hk_shape_sphere(hk_v3(0, 0, 0), 0.05, 0.01, 10.0),
                          hk_shape_sphere(hk_v3(0, -0.1, 0), 0.05, 0.0, 1.0)};
    shapes[1].styling = 1;
    hk_Shape *body;
    int body_count;
    hk_Error err;
    assert_int_equal(hk_groom_body_shapes(shapes, 2, &body, &body_count, &err), HK_OK);
    assert_int_equal(body_count, 1);
    hk_groom_keep_outside(body, body_count, q, N);
    assert_memory_equal(p, q, 3 * 4 * sizeof(float)); /* above the sphere: untouched */
    for (int j = 1; j < N; j++) {
        const hk_Vec3 x = hk_v3(q[3 * j], q[3 * j + 1], q[3 * j + 2]);
        assert_true(hk_shape_dent(&shapes[0], x, NULL, NULL) <= 1e-6);
        hk_assert_near(seg_len(q, j), 0.005, 1e-7);
    }
    /* It went round, not through: the tip is below the sphere's centre. */
    assert_true(q[3 * (N - 1) + 1] < -0.01f);
    /* No body shapes, or a one-point strand: nothing moves. */
    hk_groom_keep_outside(NULL, 0, p, N);
    hk_groom_keep_outside(body, body_count, p, 1);
    for (int j = 0; j < N; j++) hk_assert_near(p[3 * j + 1], 0.07 - 0.005 * j, 1e-7);
    hk_free(body);
}

int main(void)
{
    const struct CMUnitTest head[] = {
        cmocka_unit_test(test_default_head_outside_body),
        cmocka_unit_test(test_projection_keeps_lengths),
        cmocka_unit_test(test_regrown_strands_outside),
        cmocka_unit_test(test_quick_tests_same_bytes),
    };
    const struct CMUnitTest alone[] = {cmocka_unit_test(test_strand_through_sphere)};
    return cmocka_run_group_tests(head, load_head, free_head) | cmocka_run_group_tests(alone, NULL, NULL);
}
