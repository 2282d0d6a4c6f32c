/* The simulation manifest DIR/simulation.txt (src/io/simulation_file.c): an exact round
 * trip of both motion kinds, refusals with file:line messages, and a fuzz loop of
 * random edits that must never crash, leak or accept nonsense. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/simulation_file.h"

static hk_SimulationManifest scripted(void)
{
    hk_SimulationManifest m;
    memset(&m, 0, sizeof m);
    m.version = HK_SIMULATION_FILE_VERSION;
    m.setup = (char *)"/data/heads/setup with space.txt";
    m.seed = 12345678901234ull;
    m.frames = 90;
    m.fps = 29.97;
    m.guides = 201;
    m.points = 41;
    m.interpolated = 1;
    m.full_hair = 0;
    m.hairstyle_hash = 0x0123456789abcdefull;
    m.wick_hash = 0xfedcba9876543210ull;
    m.has_collision = 1;
    m.collision_hash = 0x1ull;
    m.motion_script = (char *)"shake";
    m.motion_amplitude = 25.000000000000004;
    m.motion_frequency = 1.0 / 3.0;
    m.motion_pivot[0] = 0.0;
    m.motion_pivot[1] = -0.01;
    m.motion_pivot[2] = -0.015;
    return m;
}

static void test_round_trip(void **state)
{
    (void)state;
    const char *path = hk_test_write_text("simulation.txt", "");
    hk_SimulationManifest m = scripted(), back;
    hk_Error err;
    for (int kind = 0; kind < 2; kind++) {
        if (kind == 1) {
            m.motion_script = NULL;
            m.motion_file = (char *)"/data/motions/nod and shake.txt";
            m.motion_hash = 0xdeadbeefcafef00dull;
            m.has_collision = 0;
            m.full_hair = 1;
        }
        assert_int_equal(hk_simulation_manifest_save(path, &m, &err), HK_OK);
        assert_int_equal(hk_simulation_manifest_load(path, &back, &err), HK_OK);
        assert_string_equal(back.setup, m.setup);
        assert_true(back.seed == m.seed && back.frames == m.frames && back.fps == m.fps);
        assert_true(back.guides == m.guides && back.points == m.points);
        assert_true(back.interpolated == m.interpolated && back.full_hair == m.full_hair);
        assert_true(back.hairstyle_hash == m.hairstyle_hash && back.wick_hash == m.wick_hash);
        assert_int_equal(back.has_collision, m.has_collision);
        if (m.has_collision) assert_true(back.collision_hash == m.collision_hash);
        if (kind == 0) {
            assert_string_equal(back.motion_script, "shake");
            /* %.17g: every double comes back exactly */
            assert_true(back.motion_amplitude == m.motion_amplitude);
            assert_true(back.motion_frequency == m.motion_frequency);
            for (int i = 0; i < 3; i++) assert_true(back.motion_pivot[i] == m.motion_pivot[i]);
        } else {
            assert_string_equal(back.motion_file, m.motion_file);
            assert_true(back.motion_hash == m.motion_hash);
        }
        hk_simulation_manifest_free(&back);
    }
}

/* A valid manifest as written by hk_simulation_manifest_save. */
static char *valid_text(size_t *len)
{
    const char *path = hk_test_write_text("base.txt", "");
    hk_SimulationManifest m = scripted();
    hk_Error err;
    assert_int_equal(hk_simulation_manifest_save(path, &m, &err), HK_OK);
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    char *buf = calloc(1, 4096);
    *len = fread(buf, 1, 4095, fp);
    fclose(fp);
    return buf;
}

static void test_refusals_name_the_line(void **state)
{
    (void)state;
    size_t len;
    char *base = valid_text(&len);
    struct {
        const char *from, *to, *message;
    } cases[] = {
        {"Seed             12345678901234", "Seed -3", "Seed"},
        {"Fps ", "Fps nan ", "Fps"},
        {"HairkitSimulation 2", "HairkitSimulation 1", "format"},
        {"Motion           shake", "Motion           shake 25", "Motion"},
        {"Motion           shake", "Motion           spin 25 1 0 -0.01 -0.015", "spin"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char *at = strstr(base, cases[c].from);
        if (!at) { /* the writer aligns its values: match the key alone */
            char key[64];
            snprintf(key, sizeof key, "%.*s", (int)strcspn(cases[c].from, " "), cases[c].from);
            at = strstr(base, key);
        }
        assert_non_null(at);
        const size_t line_end = strcspn(at, "\n");
        char text[4096];
        snprintf(text, sizeof text, "%.*s%s%s", (int)(at - base), base, cases[c].to, at + line_end);
        const char *path = hk_test_write_text("refused.txt", text);
        hk_SimulationManifest m;
        hk_Error err;
        assert_int_not_equal(hk_simulation_manifest_load(path, &m, &err), HK_OK);
        hk_assert_contains(err.message, path);
        hk_assert_contains(err.message, ":");
        print_message("%s\n", err.message);
    }
    free(base);
}

static void test_fuzz(void **state)
{
    (void)state;
    size_t base_len;
    char *base = valid_text(&base_len);
    static const char *const junk[] = {"\"",
                                       "Motion shake 1 1 0 0 0\n",
                                       "MotionFile \"/x\"\n",
                                       "\n\n",
                                       "#",
                                       "1e308",
                                       "-0",
                                       "nan",
                                       "0x",
                                       "Seed 18446744073709551616\n",
                                       "\t",
                                       "Frames 0\n"};
    unsigned long long x = 0x9e3779b97f4a7c15ull;
    int accepted = 0;
    for (int iter = 0; iter < 3000; iter++) {
        char buf[4096];
        size_t len = base_len;
        memcpy(buf, base, len);
        for (int e = 0; e <= iter % 4; e++)
            len = hk_test_mutate(buf, len, sizeof buf, " \t\n#\"-.e0123456789abcdef", junk, 12, &x);
        const char *path = hk_test_write_file("fuzz_simulation.txt", buf, len);
        hk_SimulationManifest m;
        hk_Error err;
        err.message[0] = '\0';
        const hk_Status st = hk_simulation_manifest_load(path, &m, &err);
        if (st == HK_OK) {
            assert_non_null(m.setup);
            assert_true(m.frames >= 1 && isfinite(m.fps) && m.fps > 0.0);
            assert_true(m.guides >= 0 && m.points >= 0);
            assert_true((m.motion_script != NULL) != (m.motion_file != NULL));
            hk_simulation_manifest_free(&m);
            accepted++;
        } else {
            assert_true(st == HK_ERR_PARSE || st == HK_ERR_INVALID || st == HK_ERR_NOMEM);
            assert_true(strncmp(err.message, path, strlen(path)) == 0);
        }
    }
    print_message("fuzz: %d of 3000 edited manifests accepted\n", accepted);
    assert_true(accepted > 0);
    free(base);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip),
        cmocka_unit_test(test_refusals_name_the_line),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
