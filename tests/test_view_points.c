/* The passes over every hair point of a picture (src/render/view_points.c, camera.c):
 * their AVX paths (points_avx.h, four points at a time) must give the same bits as the
 * scalar code, the projection hk_view_project's of each point and the camera's fit the
 * same view, whatever the count of points (the last ones, fewer than four, go through
 * the scalar code) and the threads.
 *  - test_projection_same_bits: random points, perspective and orthographic views,
 *    points behind the eye (depth 0 there), counts 0 to 13, 1 and 2 threads.
 *  - test_camera_fit_same_bits: hk_camera_frame of random hair with and without a head,
 *    with the AVX paths allowed and not: the same view, byte for byte.
 *  - test_scene_bounds: hk_scene_bounds (render.c; four points a step in SSE, the rest
 *    one by one) against the points' plain min and max, for counts 0 to 40 and 1 and 2
 *    threads, and a NaN or an infinity at every place refused; hk_hair_extent (the same
 *    code, core/float_bounds.c) the widest side of that box. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"
#include "hairkit/hair_formats.h"
#include "hairkit/render.h"
#include "render/render_internal.h"

static void random_hair(hk_HairFile *h, uint32_t strands, uint32_t points)
{
    uint32_t *counts = malloc(sizeof *counts * (strands ? strands : 1));
    assert_non_null(counts);
    for (uint32_t s = 0; s < strands; s++) counts[s] = points;
    assert_int_equal(hk_hair_alloc(h, strands, counts, NULL), HK_OK);
    free(counts);
    for (size_t i = 0; i < 3 * (size_t)h->point_count; i++) h->points[i] = (float)(hk_test_uniform() - 0.5);
}

static hk_View test_view(int perspective)
{
    hk_View v;
    memset(&v, 0, sizeof v);
    v.perspective = perspective;
    v.origin = hk_v3(0.1, -0.2, perspective ? -0.4 : 0.05);
    v.forward = hk_v3_normalize(hk_v3(0.1, 0.2, 1.0));
    v.right = hk_v3_normalize(hk_v3_cross(v.forward, hk_v3(0, 1, 0)));
    v.up = hk_v3_cross(v.right, v.forward);
    v.focal = perspective ? 900.0 : 512.0 / 0.8;
    v.depth_offset = perspective ? 0.0 : 0.4;
    v.width = perspective ? 1200 : 512, v.height = perspective ? 900 : 512;
    return v;
}

static void test_projection_same_bits(void **state)
{
    (void)state;
    for (uint32_t strands = 0; strands <= 13; strands++)
        for (int perspective = 0; perspective < 2; perspective++)
            for (int threads = 1; threads <= 2; threads++) {
                hk_HairFile h;
                random_hair(&h, strands * 7, 3); /* 0 to 273 points, every remainder of 4 */
                const hk_View v = test_view(perspective);
                hk_RasterPoint *got = malloc(sizeof *got * (h.point_count + 1));
                assert_non_null(got);
                hk_view_project_points(&v, &h, got, threads);
                for (uint32_t i = 0; i < h.point_count; i++) {
                    const hk_RasterPoint want = hk_view_project(&v, hk_hair_point(&h, i));
                    assert_memory_equal(&got[i], &want, sizeof want);
                }
                free(got);
                hk_hair_free(&h);
            }
}

static void test_camera_fit_same_bits(void **state)
{
    (void)state;
    const int had_avx = hk_avx_paths_allow(1);
    if (!had_avx) print_message("no AVX on this CPU: the scalar path alone\n");
    hk_Mesh ball;
    assert_int_equal(hk_mesh_alloc(&ball, 5, 1, NULL), HK_OK);
    for (int i = 0; i < 5; i++) ball.positions[i] = hk_v3(0.3 * (i - 2), 0.05 * i, -0.1 * i);
    for (int k = 0; k < 3; k++) ball.triangles[k] = k;
    for (uint32_t strands = 1; strands <= 301; strands += 60)
        for (int with_head = 0; with_head < 2; with_head++) {
            hk_HairFile h;
            random_hair(&h, strands, 5);
            const hk_RenderDef o = hk_default_render_def();
            const hk_Visuality vis = hk_default_visuality();
            hk_Scene sc;
            memset(&sc, 0, sizeof sc);
            sc.hair = &h, sc.head = with_head ? &ball : NULL, sc.vis = &vis, sc.opt = &o, sc.threads = 2;
            hk_Error err;
            assert_int_equal(hk_scene_bounds(&sc, &err), HK_OK);
            hk_View view[2];
            for (int avx = 0; avx < 2; avx++) {
                hk_avx_paths_allow(avx);
                view[avx] = hk_camera_frame(&sc);
            }
            hk_avx_paths_allow(1);
            assert_memory_equal(&view[0], &view[1], sizeof view[0]);
            assert_true(view[0].distance > 0.1);
            hk_hair_free(&h);
        }
    hk_mesh_free(&ball);
}

static void test_scene_bounds(void **state)
{
    (void)state;
    const hk_RenderDef o = hk_default_render_def();
    const hk_Visuality vis = hk_default_visuality();
    for (uint32_t strands = 1; strands <= 20; strands++)
        for (int threads = 1; threads <= 2; threads++) {
            hk_HairFile h;
            random_hair(&h, strands, 2); /* 2 to 40 points */
            hk_Scene sc;
            memset(&sc, 0, sizeof sc);
            sc.hair = &h, sc.vis = &vis, sc.opt = &o, sc.threads = threads;
            hk_Error err;
            assert_int_equal(hk_scene_bounds(&sc, &err), HK_OK);
            double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
            for (size_t i = 0; i < 3 * (size_t)h.point_count; i++) {
                lo[i % 3] = fmin(lo[i % 3], h.points[i]);
                hi[i % 3] = fmax(hi[i % 3], h.points[i]);
            }
            const hk_Vec3 want_lo = hk_v3(lo[0], lo[1], lo[2]), want_hi = hk_v3(hi[0], hi[1], hi[2]);
            assert_memory_equal(&sc.lo, &want_lo, sizeof want_lo);
            assert_memory_equal(&sc.hi, &want_hi, sizeof want_hi);
            /* hk_hair_extent, the same box's widest side (core/float_bounds.c, shared) */
            const double extent = fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
            assert_true(hk_hair_extent(&h) == extent);
            for (size_t i = 0; i < 3 * (size_t)h.point_count; i++) {
                const float kept = h.points[i];
                h.points[i] = i % 2 ? NAN : -INFINITY;
                assert_int_equal(hk_scene_bounds(&sc, &err), HK_ERR_INVALID);
                h.points[i] = kept;
            }
            hk_hair_free(&h);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_projection_same_bits),
        cmocka_unit_test(test_camera_fit_same_bits),
        cmocka_unit_test(test_scene_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
