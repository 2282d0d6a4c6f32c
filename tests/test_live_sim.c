/* A head simulated live (hk_live_sim, live_sim.h: what `hairkit view --simulate` steps) on
 * the light scene (201 guides, about 2,000 strands):
 *  - its hair is hairkit simulate's: after every step, the same bytes as hk_hair_sim
 *    advanced alone with the same motion and regrown by hk_hair_sim_groom (a path that
 *    shares the guides' dynamics but not the live stepping, timing or regrowth buffers);
 *  - the same bytes with 1 and 2 threads; time k / fps after k steps; the head where
 *    the motion puts it; the same strands of the same points every step;
 *  - bad input is refused. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/live_sim.h"
#include "hairkit/scene.h"

static void load(hk_Scene *sc)
{
    hk_Error err;
    assert_int_equal(hk_scene_load(hk_test_light_setup(), HK_SCENE_GROOMING, sc, &err), HK_OK);
}

static hk_LiveSimDef quick(int threads)
{
    hk_LiveSimDef o = hk_default_live_sim_def();
    o.preroll = o.preroll_max = 0.0; /* the statics' rest shape, as hk_hair_sim_create leaves it */
    o.threads = threads;
    return o;
}

static void assert_same_hair(const hk_HairFile *a, const hk_HairFile *b)
{
    assert_int_equal(a->strand_count, b->strand_count);
    assert_int_equal(a->point_count, b->point_count);
    assert_memory_equal(a->first_point, b->first_point, ((size_t)a->strand_count + 1) * sizeof(uint32_t));
    assert_memory_equal(a->points, b->points, (size_t)a->point_count * 3 * sizeof(float));
}

static void test_live_is_simulate(void **state)
{
    (void)state;
    hk_Scene sc;
    load(&sc);
    hk_Error err;
    hk_HeadMotion *shake = NULL;
    assert_int_equal(hk_head_motion_scripted("shake", 25.0, 2.0, hk_default_head_pivot(), &shake, &err), HK_OK);
    const hk_LiveSimDef o = quick(2);
    hk_LiveSim *live = NULL;
    assert_int_equal(hk_live_sim_create(&sc, &o, &live, &err), HK_OK);
    hk_HairSimDef so = hk_hair_sim_def_for(&sc.style);
    so.threads = 2;
    hk_HairSim *sim = NULL;
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &so, &sim, &err),
                     HK_OK);
    const uint32_t strands = hk_live_sim_hair(live)->strand_count;
    assert_int_equal(hk_live_sim_guide_count(live), 201);
    assert_true(strands > 1500);
    for (int k = 0; k <= 4; k++) {
        if (k > 0) {
            assert_int_equal(hk_live_sim_step(live, shake, NULL, &err), HK_OK);
            hk_HairSimStats stats;
            assert_int_equal(hk_hair_sim_advance(sim, shake, (k - 1) / 30.0, 1.0 / 30.0, &stats, &err), HK_OK);
        }
        hk_GroomDef go = hk_default_groom_def();
        go.seed = o.seed;
        hk_Groom g;
        hk_HairFile ref;
        memset(&ref, 0, sizeof ref);
        assert_int_equal(hk_hair_sim_groom(sim, &sc.wick, &go, &g, &err), HK_OK);
        assert_int_equal(hk_groom_to_hair(&g, &sc.style.strand, &ref, &err), HK_OK);
        assert_same_hair(hk_live_sim_hair(live), &ref);
        hk_groom_free(&g);
        hk_hair_free(&ref);
        assert_int_equal(hk_live_sim_steps(live), k);
        assert_true(hk_live_sim_time(live) == k * (1.0 / 30.0));
        /* the head where the motion puts it at the end of the step */
        hk_RigidState want, got = hk_live_sim_head(live);
        hk_head_motion_eval(shake, hk_live_sim_time(live), &want);
        assert_true(hk_v3_norm(hk_v3_sub(got.trans, want.trans)) < 1e-12);
        assert_true(fabs(got.rot.m[0][2] - want.rot.m[0][2]) < 1e-12);
    }
    /* the head turned: the hair moved */
    assert_true(fabs(hk_live_sim_head(live).rot.m[0][2]) > 0.01);
    hk_hair_sim_destroy(sim);
    hk_live_sim_destroy(live);
    hk_head_motion_destroy(shake);
    hk_scene_free(&sc);
}

static void test_live_threads(void **state)
{
    (void)state;
    hk_Scene sc;
    load(&sc);
    hk_Error err;
    hk_HeadMotion *sway = NULL;
    assert_int_equal(hk_head_motion_scripted("sway", 0.05, 2.0, hk_default_head_pivot(), &sway, &err), HK_OK);
    hk_LiveSim *one = NULL, *two = NULL;
    const hk_LiveSimDef o1 = quick(1), o2 = quick(2);
    assert_int_equal(hk_live_sim_create(&sc, &o1, &one, &err), HK_OK);
    assert_int_equal(hk_live_sim_create(&sc, &o2, &two, &err), HK_OK);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(hk_live_sim_step(one, sway, NULL, &err), HK_OK);
        assert_int_equal(hk_live_sim_step(two, sway, NULL, &err), HK_OK);
        assert_same_hair(hk_live_sim_hair(one), hk_live_sim_hair(two));
    }
    hk_live_sim_destroy(one);
    hk_live_sim_destroy(two);
    hk_head_motion_destroy(sway);
    hk_scene_free(&sc);
}

static void test_live_errors(void **state)
{
    (void)state;
    hk_Scene sc;
    hk_Error err;
    hk_LiveSim *live = (hk_LiveSim *)1;
    load(&sc);
    hk_LiveSimDef o = quick(1);
    o.fps = 0.0;
    assert_int_equal(hk_live_sim_create(&sc, &o, &live, &err), HK_ERR_INVALID);
    assert_null(live);
    assert_non_null(strstr(err.message, "frames per second"));
    o = quick(1);
    o.preroll = -1.0;
    assert_int_equal(hk_live_sim_create(&sc, &o, &live, &err), HK_ERR_INVALID);
    hk_scene_free(&sc);
    /* a scene read without its wick cannot grow guides */
    assert_int_equal(hk_scene_load(hk_test_light_setup(), HK_SCENE_HAIRSTYLE | HK_SCENE_COLLISION, &sc, &err), HK_OK);
    assert_int_equal(hk_live_sim_create(&sc, NULL, &live, &err), HK_ERR_INVALID);
    assert_non_null(strstr(err.message, "WickModel"));
    hk_scene_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_live_is_simulate),
        cmocka_unit_test(test_live_threads),
        cmocka_unit_test(test_live_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
