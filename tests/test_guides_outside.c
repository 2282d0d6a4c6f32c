/* Guides in motion stay within 2 mm of the body's surface (issue 12 item 2;
 * docs/dynamics.md, "Limitations"): the 201 guides of examples/guides200, grown,
 * solved and stepped as `hairkit simulate` does (hk_hair_sim_def_for: the
 * linearly implicit Euler step at dt = 1/30 s), under the scripted nod and tilt of
 * `hairkit simulate --motion` (25 degrees, 1 Hz), 40 frames from rest (the deepest
 * moments of 60-frame runs come before). Before the fix they went 6.7 mm into the
 * neck under nod (samples arriving during a step, which sees the contacts of its
 * start only) and 7.7 mm under tilt (also tips, which lie beyond the last collision
 * sample). The reference, 2 mm, is the aim of issue 12; depth is the thesis's dent of
 * the body shapes themselves (§4.1.2.1: no envelope; the styling sphere before the
 * face is no body) at points every 2.5 mm along each guide and at its tip. The guides
 * here step without their neighbours' contacts and without the settling second of
 * `simulate` (tools/hair_depth measures the full simulation); so stepped, a shake
 * takes no guide into the body at all, and is left out. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/groom.h"
#include "hairkit/simulate.h"
#include "hairkit/statics.h"

static void head_state(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

#define GUIDES_MAX 256

/* The guides at rest, solved once for every motion. */
typedef struct Head {
    hk_Hairstyle style;
    hk_CollisionSet collision;
    hk_Shape body[8];
    int body_count;
    hk_Mesh wick;
    hk_Follicles f;
    hk_SuperHelix *guide[GUIDES_MAX];
    double *rest[GUIDES_MAX];
    hk_Vec3 root[GUIDES_MAX]; /* the rest pose's root and root frame (head space) */
    hk_Mat3 frame[GUIDES_MAX];
} Head;

static Head head;

static int setup(void **state)
{
    (void)state;
    hk_Error err;
    Head *h = &head;
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/guides200/hairstyle.txt", &h->style, &err), HK_OK);
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/default/collision.txt", &h->collision, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick-200.obj", &h->wick, &err), HK_OK);
    assert_int_equal(hk_follicles_from_wick(&h->wick, &h->f, &err), HK_OK);
    assert_true(h->f.count <= GUIDES_MAX);
    for (int k = 0; k < h->collision.count && h->body_count < 8; k++)
        if (!h->collision.shapes[k].styling) h->body[h->body_count++] = h->collision.shapes[k];
    assert_int_equal(h->body_count, 3); /* cranium, face and jaw, neck */
    for (int i = 0; i < h->f.count; i++) {
        /* as hair_sim.c's make_guide: the statics rest shape with its follicle's envelope */
        assert_int_equal(hk_superhelix_from_def(&h->style.strand, h->f.position[i], h->f.normal[i], &h->guide[i], &err),
                         HK_OK);
        hk_StrandEnvDef env = hk_default_strand_env_def();
        env.shapes = h->collision.shapes;
        env.shape_count = h->collision.count;
        env.envelope_alpha = h->f.alpha[i];
        env.collision_step = h->style.strand.collision_step;
        hk_StaticsDef so = hk_default_statics_def();
        hk_MinimizeResult res;
        assert_int_equal(hk_statics_solve(h->guide[i], &env, &so, &res, &err), HK_OK);
        const size_t dim = 3 * (size_t)h->guide[i]->n;
        h->rest[i] = malloc(dim * sizeof(double));
        memcpy(h->rest[i], h->guide[i]->q, dim * sizeof(double));
        h->root[i] = h->guide[i]->root;
        h->frame[i] = h->guide[i]->root_frame;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    Head *h = &head;
    for (int i = 0; i < h->f.count; i++) {
        hk_superhelix_destroy(h->guide[i]);
        free(h->rest[i]);
    }
    hk_follicles_free(&h->f);
    hk_mesh_free(&h->wick);
    hk_collision_free(&h->collision);
    hk_hairstyle_free(&h->style);
    return 0;
}

/* Deepest a guide's point lies inside a body shape over `frames` frames of `motion`,
 * every guide starting from rest. */
static double deepest_in_motion(const char *motion, int frames)
{
    Head *h = &head;
    hk_Error err;
    hk_HeadMotion *m = NULL;
    assert_int_equal(hk_head_motion_scripted(motion, 25.0, 1.0, hk_default_head_pivot(), &m, &err), HK_OK);
    const hk_HairSimDef o = hk_hair_sim_def_for(&h->style);
    assert_int_equal(o.dynamics.integrator, HK_INTEGRATOR_LINEAR_EULER);
    double deepest = 0.0;
    int deepest_guide = -1, deepest_frame = -1, over = 0;
    long steps = 0;
    for (int i = 0; i < h->f.count; i++) {
        hk_SuperHelix *sh = h->guide[i];
        memcpy(sh->q, h->rest[i], 3 * (size_t)sh->n * sizeof(double));
        sh->root = h->root[i]; /* head space: the dynamics takes its root pose from here */
        sh->root_frame = h->frame[i];
        hk_StrandEnvDef env = hk_default_strand_env_def();
        env.shapes = h->collision.shapes;
        env.shape_count = h->collision.count;
        env.envelope_alpha = h->f.alpha[i];
        env.collision_step = h->style.strand.collision_step;
        hk_StrandDynamics *d = NULL;
        assert_int_equal(hk_strand_dynamics_create(sh, &o.dynamics, &env, &d, &err), HK_OK);
        const int points = hk_superhelix_sample_count(sh, 0.0025);
        hk_Vec3 pos[128];
        assert_true(points <= 128);
        double worst = 0.0;
        for (int k = 0; k < frames; k++) {
            int taken = 0;
            assert_int_equal(hk_strand_dynamics_advance(d, head_state, m, k / 30.0, 1.0 / 30.0, NULL, 0, &taken, &err),
                             HK_OK);
            steps += taken;
            hk_RigidState pose;
            hk_head_motion_eval(m, (k + 1) / 30.0, &pose);
            hk_superhelix_sample(sh, NULL, 0.0025, NULL, pos, NULL); /* world: the root is placed */
            for (int j = 1; j < points; j++) {
                const hk_Vec3 x = hk_m3_tmul_v3(&pose.rot, hk_v3_sub(pos[j], pose.trans));
                const double depth = hk_collision_depth(h->body, h->body_count, 0.0, x);
                worst = fmax(worst, depth);
                if (depth > deepest) deepest = depth, deepest_guide = i, deepest_frame = k + 1;
            }
        }
        over += worst > 0.002;
        hk_strand_dynamics_destroy(d);
    }
    print_message("%s: deepest %.2f mm inside the body (guide %d, frame %d); %d guides deeper than 2 mm; %.3f steps "
                  "per guide and frame\n",
                  motion, 1e3 * deepest, deepest_guide, deepest_frame, over, (double)steps / (h->f.count * frames));
    hk_head_motion_destroy(m);
    return deepest;
}

static void test_nod(void **state)
{
    (void)state;
    assert_true(deepest_in_motion("nod", 40) <= 0.002);
}

static void test_tilt(void **state)
{
    (void)state;
    assert_true(deepest_in_motion("tilt", 40) <= 0.002);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nod),
        cmocka_unit_test(test_tilt),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
