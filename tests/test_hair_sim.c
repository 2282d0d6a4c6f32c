/* The full head in motion (Bertails et al. 2006 §4.1) on the 201-guide scene of examples/guides200:
 *  - with the head still, every guide keeps its statics rest shape (the dynamics'
 *    equilibrium is the Newton minimum of the same energy, an independent method),
 *    also for guides pressed into the layered envelopes of the head;
 *  - a shaking head never lets hair into the head deeper than a collision reaches:
 *    for a strand of mass rho S per length hitting the penalty k at speed v the depth
 *    is v sqrt(rho S / k) (kinetic energy into penalty energy), with v the fastest
 *    sample's speed relative to the head (the tips whip at a few m/s);
 *  - guides and interpolated hair are the same bytes with 1 and 2 threads (the guides
 *    with 3 too: the contacts' sweeps visit a colour's units in parallel), and the
 *    interpolated hair stays out of the body where the head moved to, also in every
 *    frame a simulation writes to a folder and in its rebuild (the same bytes);
 *  - bad input is refused. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"
#include "hairkit/simulate.h"

typedef struct Scene {
    hk_Hairstyle style;
    hk_CollisionSet collision;
    hk_Mesh wick;
} Scene;

static void load_scene(Scene *s)
{
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/guides200/hairstyle.txt", &s->style, &err), HK_OK);
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/default/collision.txt", &s->collision, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick-200.obj", &s->wick, &err), HK_OK);
}

static void free_scene(Scene *s)
{
    hk_hairstyle_free(&s->style);
    hk_collision_free(&s->collision);
    hk_mesh_free(&s->wick);
}

static double *guides_now(const hk_HairSim *sim)
{
    const size_t n = (size_t)hk_hair_sim_guide_count(sim) * (size_t)hk_hair_sim_points_per_strand(sim) * 3;
    double *g = malloc(n * sizeof(double));
    hk_hair_sim_guides(sim, g);
    return g;
}

static void test_still_head_keeps_rest_shape(void **state)
{
    (void)state;
    Scene sc;
    load_scene(&sc);
    hk_HairSimDef o = hk_hair_sim_def_for(&sc.style);
    o.hair_contacts = 0; /* the statics knows no guide-guide contacts */
    hk_HairSim *sim = NULL;
    hk_Error err;
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err),
                     HK_OK);
    assert_int_equal(hk_hair_sim_guide_count(sim), 201);
    double *rest = guides_now(sim);
    for (int f = 0; f < 30; f++)
        assert_int_equal(hk_hair_sim_advance(sim, NULL, f / 30.0, 1.0 / 30.0, NULL, &err), HK_OK);
    double *now = guides_now(sim);
    const size_t n = (size_t)201 * (size_t)hk_hair_sim_points_per_strand(sim) * 3;
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) worst = fmax(worst, fabs(now[i] - rest[i]));
    print_message("still head: guides moved at most %.3g m in 1 s\n", worst);
    assert_true(worst < 1e-6);
    free(rest);
    free(now);
    hk_hair_sim_destroy(sim);
    free_scene(&sc);
}

static double shaking_depth(int substeps, double *reach_out)
{
    Scene sc;
    load_scene(&sc);
    hk_HairSimDef o = hk_hair_sim_def_for(&sc.style);
    hk_HairSim *sim = NULL;
    hk_HeadMotion *shake = NULL;
    hk_Error err;
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err),
                     HK_OK);
    assert_int_equal(hk_head_motion_scripted("shake", 40.0, 1.5, hk_default_head_pivot(), &shake, &err), HK_OK);
    const int points = hk_hair_sim_points_per_strand(sim);
    /* The head itself: the collision file's stiff shapes (its soft face sphere, penalty
     * 0.01, only keeps hair off the face and may be entered). */
    hk_Shape hard[8];
    int hard_count = 0;
    for (int k = 0; k < sc.collision.count && hard_count < 8; k++)
        if (sc.collision.shapes[k].penalty >= 1.0) hard[hard_count++] = sc.collision.shapes[k];
    assert_true(hard_count >= 3);
    double deepest = 0.0, fastest = 0.0;
    int contacts = 0;
    long body = 0;
    double *prev = calloc((size_t)201 * (size_t)points * 3, sizeof(double));
    for (int f = -1; f < 18; f++) {
        hk_HairSimStats stats;
        memset(&stats, 0, sizeof stats);
        /* frame -1 is the rest state: the previous positions for the speeds */
        for (int sub = 0; f >= 0 && sub < substeps; sub++)
            assert_int_equal(hk_hair_sim_advance(sim, shake, (f + (double)sub / substeps) / 30.0, 1.0 / 30.0 / substeps,
                                                 &stats, &err),
                             HK_OK);
        contacts += stats.contacts;
        body += stats.body_contacts;
        double *g = guides_now(sim);
        hk_RigidState head;
        hk_head_motion_eval(shake, (f + 1) / 30.0, &head);
        /* depth inside the shapes themselves (envelope level 0), skipping the roots,
         * which grow from inside the scalp's envelope */
        for (int i = 0; i < 201; i++)
            for (int j = 4; j < points; j++) {
                const double *p = g + ((size_t)i * points + j) * 3;
                const hk_Vec3 x = hk_m3_tmul_v3(&head.rot, hk_v3_sub(hk_v3(p[0], p[1], p[2]), head.trans));
                deepest = fmax(deepest, hk_collision_depth(hard, hard_count, 0.0, x));
                double *px = prev + ((size_t)i * points + j) * 3;
                if (f >= 0) fastest = fmax(fastest, hk_v3_dist(x, hk_v3(px[0], px[1], px[2])) * 30.0);
                px[0] = x.x, px[1] = x.y, px[2] = x.z;
            }
        free(g);
    }
    /* the stiffest shape's penalty; the frame-average speed underestimates the peak, by
     * up to a factor two for a tip reversing within a frame */
    double k = 0.0;
    for (int i = 0; i < hard_count; i++) k = fmax(k, hard[i].penalty);
    const double reach =
        2.0 * fastest * sqrt(sc.style.strand.density * HK_PI * sc.style.strand.radius1 * sc.style.strand.radius2 / k);
    print_message("shaking head, %d steps per frame: deepest guide sample %.3g m inside the head, penalty reach "
                  "%.3g m at %.2f m/s; %d guide-guide contacts\n",
                  substeps, deepest, reach, fastest, contacts);
    assert_true(contacts > 0);
    /* not vacuous: the guides press on the head (with static friction between the
     * guides, none needs to enter it at the fine step) */
    assert_true(body > 0);
    if (reach_out) *reach_out = reach;
    free(prev);
    hk_head_motion_destroy(shake);
    hk_hair_sim_destroy(sim);
    free_scene(&sc);
    return deepest;
}

static void test_shaking_head_keeps_hair_out(void **state)
{
    (void)state;
    /* A reference with steps 4 times smaller: the penetration is the penalty's (below
     * its reach at the measured speeds), and the paper's step adds at most what a
     * sample may travel in one step before the penalty sees it (max_travel). */
    double reach;
    const double fine = shaking_depth(4, &reach), coarse = shaking_depth(1, NULL);
    assert_true(fine <= reach);
    assert_true(coarse <= fine + hk_default_dynamics_def().max_travel);
}

static void run_frames(const Scene *sc, int threads, double **guides, hk_Groom *groom)
{
    hk_HairSimDef o = hk_hair_sim_def_for(&sc->style);
    o.threads = threads;
    hk_HairSim *sim = NULL;
    hk_HeadMotion *nod = NULL;
    hk_Error err;
    assert_int_equal(
        hk_hair_sim_create(&sc->style, sc->collision.shapes, sc->collision.count, &sc->wick, &o, &sim, &err), HK_OK);
    assert_int_equal(hk_head_motion_scripted("nod", 30.0, 2.0, hk_default_head_pivot(), &nod, &err), HK_OK);
    assert_int_equal(hk_hair_sim_settle(sim, NULL, 0.1, 1.0 / 30.0, &err), HK_OK);
    for (int f = 0; f < 6; f++)
        assert_int_equal(hk_hair_sim_advance(sim, nod, f / 30.0, 1.0 / 30.0, NULL, &err), HK_OK);
    *guides = guides_now(sim);
    hk_GroomDef go = hk_default_groom_def();
    go.threads = threads;
    assert_int_equal(hk_hair_sim_groom(sim, &sc->wick, &go, groom, &err), HK_OK);
    hk_head_motion_destroy(nod);
    hk_hair_sim_destroy(sim);
}

/* Strands of n points each (the root first) are outside the body where the head is
 * (they are grown from world-space guides; the shapes are in head space): back in head
 * space no point after a root is more than 2 mm inside a body shape, at most 0.05 % more
 * than 1 mm (docs/grooming.md). */
static void assert_points_outside(const Scene *sc, const hk_RigidState *head, const float *points, long strands, int n)
{
    hk_Shape body[8];
    int body_count = 0;
    for (int k = 0; k < sc->collision.count && body_count < 8; k++)
        if (!sc->collision.shapes[k].styling) body[body_count++] = sc->collision.shapes[k];
    long over = 0;
    double deepest = 0.0;
    for (long s = 0; s < strands; s++)
        for (int j = 1; j < n; j++) {
            const float *p = points + ((size_t)s * n + j) * 3;
            const hk_Vec3 x = hk_m3_tmul_v3(&head->rot, hk_v3_sub(hk_v3(p[0], p[1], p[2]), head->trans));
            const double d = hk_collision_depth(body, body_count, 0.0, x);
            over += d > 0.001;
            deepest = fmax(deepest, d);
        }
    print_message("  %ld strands: deepest point %.2f mm inside the body, %ld points deeper than 1 mm\n", strands,
                  1e3 * deepest, over);
    assert_true(deepest <= 0.002);
    assert_true(over <= 0.0005 * (double)strands * (n - 1));
}

/* The groom's strands where the nod took the head after `frames` frames. */
static void assert_strands_outside(const Scene *sc, const hk_Groom *g, int frames)
{
    hk_HeadMotion *nod = NULL;
    hk_Error err;
    assert_int_equal(hk_head_motion_scripted("nod", 30.0, 2.0, hk_default_head_pivot(), &nod, &err), HK_OK);
    hk_RigidState head;
    hk_head_motion_eval(nod, frames / 30.0, &head);
    hk_head_motion_destroy(nod);
    assert_points_outside(sc, &head, g->strands, g->strand_count, g->points_per_strand);
}

static void test_same_bytes_with_any_threads(void **state)
{
    (void)state;
    Scene sc;
    load_scene(&sc);
    double *g1, *g2;
    hk_Groom a, b;
    run_frames(&sc, 1, &g1, &a);
    run_frames(&sc, 2, &g2, &b);
    const size_t n = (size_t)a.guide_count * (size_t)a.points_per_strand * 3;
    assert_memory_equal(g1, g2, n * sizeof(double));
    {
        double *g3;
        hk_Groom c;
        run_frames(&sc, 3, &g3, &c);
        assert_memory_equal(g1, g3, n * sizeof(double));
        free(g3);
        hk_groom_free(&c);
    }
    assert_int_equal(a.strand_count, b.strand_count);
    assert_true(a.strand_count > 1000);
    assert_memory_equal(a.strands, b.strands, (size_t)a.strand_count * (size_t)a.points_per_strand * 3 * sizeof(float));
    /* the interpolated hair follows the moved guides: roots on the guides' roots */
    assert_memory_equal(a.guides, g1, n * sizeof(double));
    assert_strands_outside(&sc, &a, 6);
    free(g1);
    free(g2);
    hk_groom_free(&a);
    hk_groom_free(&b);
    free_scene(&sc);
}

/* Every frame of a simulation written to a folder keeps its interpolated hair out of the
 * body where the head is at that frame (a shake of 90 degrees at 2 Hz: the face turns by
 * 58 degrees at frame 3), and --rebuild grows the same bytes from the guides and the
 * manifest (which records the motion). */
static void test_run_frames_outside_posed_body(void **state)
{
    (void)state;
    Scene sc;
    load_scene(&sc);
    hk_Error err;
    hk_HeadMotion *shake = NULL;
    assert_int_equal(hk_head_motion_scripted("shake", 90.0, 2.0, hk_default_head_pivot(), &shake, &err), HK_OK);
    hk_SimRunDef o = hk_default_sim_run_def();
    o.frames = 4;
    o.fps = 20.0;
    o.preroll = 0.0;
    o.full_hair = 1;
    o.video = 0;
    o.threads = 2;
    o.motion = shake;
    o.render.width = 48;
    o.render.height = 36;
    o.render.shadow_map_size = 32;
    char dir[4096], frame[4096], rebuilt[4096];
    snprintf(dir, sizeof dir, "%s/shake", hk_test_tmpdir());
    snprintf(rebuilt, sizeof rebuilt, "%s/rebuilt.hair", hk_test_tmpdir());
    const hk_Status st = hk_simulation_run(hk_test_light_setup(), dir, &o, NULL, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    for (long k = 0; k < o.frames; k++) {
        hk_RigidState head;
        hk_head_motion_eval(shake, k / o.fps, &head);
        const double turned = acos(fmin(1.0, 0.5 * (head.rot.m[0][0] + head.rot.m[1][1] + head.rot.m[2][2] - 1.0)));
        print_message("frame %ld, the head turned by %.0f degrees:\n", k, turned * 180.0 / HK_PI);
        if (k == 3) assert_true(turned > 50.0 * HK_PI / 180.0);
        hk_HairFile hair;
        assert_int_equal(hk_simulation_frame_path(frame, sizeof frame, dir, "frame", k, "hair", &err), HK_OK);
        assert_int_equal(hk_hair_load(frame, &hair, &err), HK_OK);
        const uint32_t guides = 201, n = hair.first_point[1];
        assert_true(hair.strand_count > 1500);
        for (uint32_t i = 0; i <= hair.strand_count; i++) assert_int_equal(hair.first_point[i], i * n);
        assert_points_outside(&sc, &head, hair.points + (size_t)guides * n * 3, (long)(hair.strand_count - guides),
                              (int)n);
        hk_hair_free(&hair);
        /* the rebuild: the same bytes */
        assert_int_equal(hk_simulation_rebuild(dir, k, 1, &hair, &err), HK_OK);
        assert_int_equal(hk_hair_save(rebuilt, &hair, &err), HK_OK);
        hk_hair_free(&hair);
        size_t a_size, b_size;
        char *a = hk_test_read_file(frame, &a_size), *b = hk_test_read_file(rebuilt, &b_size);
        assert_int_equal(a_size, b_size);
        assert_memory_equal(a, b, a_size);
        free(a);
        free(b);
    }
    hk_head_motion_destroy(shake);
    free_scene(&sc);
}

static void test_bad_input(void **state)
{
    (void)state;
    Scene sc;
    load_scene(&sc);
    hk_HairSimDef o = hk_hair_sim_def_for(&sc.style);
    hk_HairSim *sim = NULL;
    hk_Error err;
    o.dynamics.air_drag = -1.0;
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err),
                     HK_ERR_INVALID);
    assert_null(sim);
    o = hk_hair_sim_def_for(&sc.style);
    o.contacts.distance = 0.0;
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err),
                     HK_ERR_INVALID);
    o = hk_hair_sim_def_for(&sc.style);
    assert_int_equal(hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err),
                     HK_OK);
    assert_int_equal(hk_hair_sim_settle(sim, NULL, 1.0, 0.0, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_sim_advance(sim, NULL, 0.0, -1.0, NULL, &err), HK_ERR_INVALID);
    hk_hair_sim_destroy(sim);
    free_scene(&sc);
}

/* The guides' evaluation compiled for AVX (its twins: the free steps, the contact
 * points' Jacobians, the commits, the samples; core/avx_twins.h), the contacts' solve's
 * AVX paths (the answers' back substitution, the sweeps and their rows' sums:
 * hair_contact_solve.c) and the baseline's give the same guides to the byte after the
 * head's shake (contacts coupled, 2 threads). */
static void test_same_bytes_on_the_avx_path(void **state)
{
    (void)state;
    if (!hk_avx_paths_allow(1)) {
        print_message("no AVX on this machine: nothing to compare\n");
        return;
    }
    Scene sc;
    load_scene(&sc);
    double *guides[2];
    size_t n = 0;
    for (int avx = 1; avx >= 0; avx--) {
        hk_avx_paths_allow(avx);
        hk_HairSimDef o = hk_hair_sim_def_for(&sc.style);
        o.threads = 2;
        hk_HairSim *sim = NULL;
        hk_HeadMotion *shake = NULL;
        hk_Error err;
        assert_int_equal(
            hk_hair_sim_create(&sc.style, sc.collision.shapes, sc.collision.count, &sc.wick, &o, &sim, &err), HK_OK);
        assert_int_equal(hk_head_motion_scripted("shake", 25.0, 1.0, hk_default_head_pivot(), &shake, &err), HK_OK);
        assert_int_equal(hk_hair_sim_settle(sim, NULL, 0.1, 1.0 / 30.0, &err), HK_OK);
        for (int f = 0; f < 6; f++)
            assert_int_equal(hk_hair_sim_advance(sim, shake, f / 30.0, 1.0 / 30.0, NULL, &err), HK_OK);
        guides[avx] = guides_now(sim);
        n = (size_t)hk_hair_sim_guide_count(sim) * (size_t)hk_hair_sim_points_per_strand(sim) * 3;
        hk_head_motion_destroy(shake);
        hk_hair_sim_destroy(sim);
    }
    hk_avx_paths_allow(1);
    assert_memory_equal(guides[0], guides[1], n * sizeof(double));
    free(guides[0]);
    free(guides[1]);
    free_scene(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_still_head_keeps_rest_shape),   cmocka_unit_test(test_shaking_head_keeps_hair_out),
        cmocka_unit_test(test_same_bytes_with_any_threads),   cmocka_unit_test(test_same_bytes_on_the_avx_path),
        cmocka_unit_test(test_run_frames_outside_posed_body), cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
