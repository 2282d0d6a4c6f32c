/* Interpolated strands blend guides on their own side of the head (issue 12 item 6;
 * docs/grooming.md, "Keeping hair outside the body"): on the default head
 * (examples/default at a fifth of its HairDensity: the same guides and triangles) no
 * strand's tip ends more than 3 cm from the tips of all three guides it grows
 * between. Where a triangle's guides fell to different sides of the head (the
 * forehead before the styling sphere, the crown, the ears) the plain blend ends
 * between them, inside the head, and the body projection slides it round the scalp:
 * 207 strands ended more than 3 cm from every guide tip of their triangle, up to
 * 12.5 cm, drawn as stray strands across the forehead and temples. The reference: a
 * strand's tip is its nearest guide's tip plus at most ClumpFactor (0.25) of its two
 * other guides' offsets, each weighted by MaxTipDistance's fade (tip_fade in
 * src/groom/interpolate.c: full up to 4 cm, none from 8 cm on), so within
 * 2 x 0.25 x 4.2 cm = 2.1 cm of it; 3 cm leaves room for the segment lengths' restoring
 * and the projection. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/groom.h"
#include "hairkit/io.h"

static double tip_distance(const double *guide_tip, const float *tip)
{
    const double x = guide_tip[0] - tip[0], y = guide_tip[1] - tip[1], z = guide_tip[2] - tip[2];
    return sqrt(x * x + y * y + z * z);
}

static void test_tips_near_their_guides(void **state)
{
    (void)state;
    hk_Hairstyle style;
    hk_CollisionSet collision = {0};
    hk_Mesh wick;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/default/hairstyle.txt", &style, &err), HK_OK);
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/default/collision.txt", &collision, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick.obj", &wick, &err), HK_OK);
    style.interpolation.hair_density = 50.0; /* about 25,000 strands */
    hk_GroomDef o = hk_default_groom_def();
    hk_Groom g;
    assert_int_equal(
        hk_groom_grow(&style.strand, &style.interpolation, collision.shapes, collision.count, &wick, &o, &g, &err),
        HK_OK);
    assert_true(g.strand_count > 20000);
    const int n = g.points_per_strand;
    long far = 0;
    double farthest = 0.0;
    for (int s = 0; s < g.strand_count; s++) {
        const int *tri = wick.triangles + 3 * g.strand_triangle[s];
        const float *tip = g.strands + ((size_t)s * n + n - 1) * 3;
        double nearest = INFINITY;
        for (int k = 0; k < 3; k++)
            nearest = fmin(nearest, tip_distance(g.guides + ((size_t)tri[k] * n + n - 1) * 3, tip));
        far += nearest > 0.03;
        farthest = fmax(farthest, nearest);
    }
    print_message("%d strands: %ld tips more than 3 cm from every guide tip of their triangle; farthest %.1f cm\n",
                  g.strand_count, far, 100.0 * farthest);
    assert_int_equal(far, 0);
    hk_groom_free(&g);
    hk_collision_free(&collision);
    hk_mesh_free(&wick);
    hk_hairstyle_free(&style);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tips_near_their_guides),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
