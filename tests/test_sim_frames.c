/* hairkit simulate draws two frames at once, each on a thread of its own, when it has
 * two threads or more (src/simulate/sim_run.c): the files must be the same bytes as
 * frame after frame on one thread, and the frames reported in order. */
#include "hk_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/simulate.h"

typedef struct Seen {
    long frames[16];
    int count, at_once;
} Seen;

static void record(void *user, const hk_SimProgress *p)
{
    Seen *s = user;
    if (p->frame == 0 || s->count >= 16) return; /* frame 0: the hair at rest */
    s->frames[s->count++] = p->frame;
    s->at_once = p->frames_at_once;
}

#define FRAMES 5

static void run(const char *setup, const char *name, int threads, Seen *seen)
{
    hk_HeadMotion *shake = NULL;
    hk_Error err;
    assert_int_equal(hk_head_motion_scripted("shake", 90.0, 2.0, hk_default_head_pivot(), &shake, &err), HK_OK);
    hk_SimRunDef o = hk_default_sim_run_def();
    o.frames = FRAMES;
    o.fps = 20.0;
    o.preroll = 0.0;
    o.full_hair = 1;
    o.video = 0;
    o.threads = threads;
    o.motion = shake;
    o.render.width = 64;
    o.render.height = 48;
    o.render.shadow_map_size = 64;
    o.progress = record;
    o.progress_user = seen;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/%s", hk_test_tmpdir(), name);
    const hk_Status st = hk_simulation_run(setup, dir, &o, NULL, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    hk_head_motion_destroy(shake);
}

static void assert_same_file(const char *name, const char *a_dir, const char *b_dir)
{
    char a_path[4096], b_path[4096];
    snprintf(a_path, sizeof a_path, "%s/%s/%s", hk_test_tmpdir(), a_dir, name);
    snprintf(b_path, sizeof b_path, "%s/%s/%s", hk_test_tmpdir(), b_dir, name);
    size_t a_size, b_size;
    char *a = hk_test_read_file(a_path, &a_size), *b = hk_test_read_file(b_path, &b_size);
    print_message("%s: %zu and %zu bytes\n", name, a_size, b_size);
    assert_int_equal(a_size, b_size);
    assert_memory_equal(a, b, a_size);
    free(a);
    free(b);
}

/* 1 thread: one frame at a time; 2 and 3 threads: two at once (with 3, the steps keep a
 * thread of their own). Every frame's guides, full hair and picture the same bytes, the
 * frames reported 1, 2, ... in order. */
static void test_frames_at_once_same_bytes(void **state)
{
    (void)state;
    const char *setup = hk_test_light_setup();
    const int threads[3] = {1, 2, 3};
    const char *names[3] = {"one", "two", "three"};
    for (int r = 0; r < 3; r++) {
        Seen seen;
        memset(&seen, 0, sizeof seen);
        run(setup, names[r], threads[r], &seen);
        assert_int_equal(seen.at_once, threads[r] >= 2 ? 2 : 1);
        assert_int_equal(seen.count, FRAMES);
        for (int k = 0; k < FRAMES; k++) assert_int_equal(seen.frames[k], k + 1);
    }
    for (int r = 1; r < 3; r++)
        for (long k = 0; k < FRAMES; k++) {
            char name[64];
            snprintf(name, sizeof name, "guides_%04ld.hair", k);
            assert_same_file(name, names[0], names[r]);
            snprintf(name, sizeof name, "frame_%04ld.hair", k);
            assert_same_file(name, names[0], names[r]);
            snprintf(name, sizeof name, "frame_%04ld.png", k);
            assert_same_file(name, names[0], names[r]);
        }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frames_at_once_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
