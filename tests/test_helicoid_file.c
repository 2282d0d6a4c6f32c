/* Helicoid files (src/io/helicoid_file.c): a sample with every key, save -> load
 * gives back the same numbers and the same bytes, every error class with its file:line
 * message, and a fuzz loop that never crashes. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hairfile.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_hair.h"

static const char *const sample = "# two guides\n"
                                  "Step      0.001\n"
                                  "Waviness  0.0005 300\n"
                                  "\n"
                                  "Strand\n"
                                  "Root      0 0.15 0.02\n"
                                  "Frame     0 1 0   1 0 0        # up, E_N along x (E_B = -z)\n"
                                  "Piece     20 -1 3 0.5 0.05\n"
                                  "Piece     40 0 0 0 0.1\n"
                                  "Wisp      16 0.004 0.1\n"
                                  "Strand\n"
                                  "Root      0.02 0.15 0\n"
                                  "Frame     1 1 0   -1 1 0\n"
                                  "Piece     0 0 0 0 0.2\n";

static void test_sample(void **state)
{
    (void)state;
    hk_HelicoidSet set;
    hk_Error err;
    assert_int_equal(hk_helicoid_file_load(hk_test_write_text("guides.txt", sample), &set, &err), HK_OK);
    assert_int_equal(set.count, 2);
    hk_assert_near(set.step, 0.001, 0.0);
    hk_assert_near(set.waviness.amplitude, 0.0005, 0.0);
    hk_assert_near(set.waviness.frequency, 300.0, 0.0);
    hk_assert_near(set.wave_jitter, 0.0, 0.0); /* two numbers: waves in step */
    const hk_PHelicoid *a = &set.strands[0], *b = &set.strands[1];
    assert_int_equal(a->piece_count, 2);
    hk_assert_near(a->k[0].kt, 20.0, 0.0);
    hk_assert_near(a->k[0].kn, -1.0, 0.0);
    hk_assert_near(a->k[0].kb, 3.0, 0.0);
    hk_assert_near(a->k[0].alpha, 0.5, 0.0);
    hk_assert_near(a->length[1], 0.1, 0.0);
    assert_int_equal(set.wisp_count[0], 16);
    assert_int_equal(set.wisp_count[1], 0);
    /* frames are rotations, E_B = E_T x E_N, the second one normalised */
    hk_assert_near(a->frame.m[2][2], -1.0, 1e-15);
    hk_assert_near(b->frame.m[0][0], sqrt(0.5), 1e-15);
    hk_assert_near(b->frame.m[0][1], -sqrt(0.5), 1e-15);
    assert_int_equal(hk_phelicoid_check(a, &err), HK_OK);
    assert_int_equal(hk_phelicoid_check(b, &err), HK_OK);

    /* save -> load -> save: the same numbers and bytes */
    char first[512], second[512];
    snprintf(first, sizeof first, "%s/saved1.txt", hk_test_tmpdir());
    snprintf(second, sizeof second, "%s/saved2.txt", hk_test_tmpdir());
    assert_int_equal(hk_helicoid_file_save(first, &set, "test", &err), HK_OK);
    hk_HelicoidSet again;
    assert_int_equal(hk_helicoid_file_load(first, &again, &err), HK_OK);
    assert_int_equal(again.count, 2);
    assert_memory_equal(&again.strands[0].k[0], &a->k[0], 2 * sizeof(hk_Helicoid));
    assert_memory_equal(again.strands[0].length, a->length, 2 * sizeof(double));
    assert_memory_equal(&again.strands[1].frame, &b->frame, sizeof(hk_Mat3));
    assert_int_equal(hk_helicoid_file_save(second, &again, "test", &err), HK_OK);
    FILE *f1 = fopen(first, "rb"), *f2 = fopen(second, "rb");
    char b1[4096], b2[4096];
    const size_t n1 = fread(b1, 1, sizeof b1, f1), n2 = fread(b2, 1, sizeof b2, f2);
    fclose(f1), fclose(f2);
    assert_int_equal(n1, n2);
    assert_memory_equal(b1, b2, n1);
    hk_helicoid_set_free(&again);
    hk_helicoid_set_free(&set);
}

/* The optional phase jitter of Waviness: read, written back, read again the same. */
static void test_wave_jitter(void **state)
{
    (void)state;
    hk_Error err;
    hk_HelicoidSet set, again;
    const char *path = hk_test_write_text("jitter.txt", "Waviness 0.002 150 0.25\nStrand\nRoot 0 0 0\n"
                                                        "Frame 1 0 0  0 1 0\nPiece 10 0 0 0 0.1\n");
    assert_int_equal(hk_helicoid_file_load(path, &set, &err), HK_OK);
    hk_assert_near(set.wave_jitter, 0.25, 0.0);
    char saved[512];
    snprintf(saved, sizeof saved, "%s/jitter2.txt", hk_test_tmpdir());
    assert_int_equal(hk_helicoid_file_save(saved, &set, "test", &err), HK_OK);
    assert_int_equal(hk_helicoid_file_load(saved, &again, &err), HK_OK);
    hk_assert_near(again.wave_jitter, 0.25, 0.0);
    hk_assert_near(again.waviness.amplitude, 0.002, 0.0);
    hk_helicoid_set_free(&again);
    hk_helicoid_set_free(&set);
}

/* A strand's own waves (Waves, as helicoid fit --waves writes them): read, written back
 * to the same bytes, and traced in place of the file's Waviness - the reference being
 * hk_phelicoid_trace with those waves given directly - while a strand without them keeps
 * the file's. */
static void test_own_waves(void **state)
{
    (void)state;
    hk_Error err;
    hk_HelicoidSet set, again;
    const char *path = hk_test_write_text("waves.txt", "Step 0.002\nWaviness 0.001 100\n"
                                                       "Strand\nRoot 0 0 0\nFrame 1 0 0  0 1 0\n"
                                                       "Piece 10 0 0 0 0.1\nWaves 0.003 157 0.25\n"
                                                       "Strand\nRoot 0.01 0 0\nFrame 1 0 0  0 1 0\n"
                                                       "Piece 10 0 0 0 0.1\n");
    assert_int_equal(hk_helicoid_file_load(path, &set, &err), HK_OK);
    assert_int_equal(set.has_waves[0], 1);
    assert_int_equal(set.has_waves[1], 0);
    hk_assert_near(set.waves[0].amplitude, 0.003, 0.0);
    hk_assert_near(set.waves[0].frequency, 157.0, 0.0);
    hk_assert_near(set.waves[0].phase, 0.25, 0.0);
    char saved[512];
    snprintf(saved, sizeof saved, "%s/waves2.txt", hk_test_tmpdir());
    assert_int_equal(hk_helicoid_file_save(saved, &set, NULL, &err), HK_OK);
    assert_int_equal(hk_helicoid_file_load(saved, &again, &err), HK_OK);
    assert_int_equal(again.has_waves[0], 1);
    assert_int_equal(again.has_waves[1], 0);
    assert_memory_equal(&again.waves[0], &set.waves[0], sizeof(hk_Waviness));
    hk_HairFile hair;
    assert_int_equal(hk_helicoid_set_trace(&set, 0.002, 1, 1, &hair, &err), HK_OK);
    for (int s = 0; s < 2; s++) {
        const int n = (int)(hair.first_point[s + 1] - hair.first_point[s]);
        hk_Vec3 ref[64];
        assert_true(n <= 64);
        const hk_Waviness *w = s == 0 ? &set.waves[0] : &set.waviness; /* jitter 0: phase 0 */
        assert_int_equal(hk_phelicoid_trace(&set.strands[s], 0.002, w, NULL, ref, NULL, &err), HK_OK);
        for (int i = 0; i < n; i++) {
            const float *p = hair.points + 3 * (size_t)(hair.first_point[s] + (uint32_t)i);
            assert_true(p[0] == (float)ref[i].x && p[1] == (float)ref[i].y && p[2] == (float)ref[i].z);
        }
    }
    hk_hair_free(&hair);
    hk_helicoid_set_free(&again);
    hk_helicoid_set_free(&set);
}

static void expect_error(const char *text, const char *where, const char *what)
{
    hk_HelicoidSet set;
    hk_Error err;
    const char *path = hk_test_write_text("bad.txt", text);
    const hk_Status st = hk_helicoid_file_load(path, &set, &err);
    if (st == HK_OK) fail_msg("accepted: %s", text);
    hk_assert_contains(err.message, where);
    hk_assert_contains(err.message, what);
    assert_null(set.strands);
}

static void test_errors(void **state)
{
    (void)state;
    expect_error("", "bad.txt", "empty");
    expect_error("Step 0.001\n", "bad.txt", "no Strand");
    expect_error("Root 0 0 0\nStrand\n", "bad.txt:1", "before the first Strand");
    expect_error("Strand\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 0.1\n", "bad.txt:1", "no Root");
    expect_error("Strand\nRoot 0 0 0\nPiece 1 0 0 0 0.1\n", "bad.txt:1", "no Frame");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\n", "bad.txt:1", "no Piece");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nStrand\n", "bad.txt:1", "no Piece");
    expect_error("Strand\nRoot 0 0 0\nRoot 0 0 0\n", "bad.txt:3", "second Root");
    expect_error("Strand\nRoot 0 0\n", "bad.txt:2", "3 numbers");
    expect_error("Strand\nRoot 0 0 x\n", "bad.txt:2", "");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 1 1 0\n", "bad.txt:3", "orthogonal");
    expect_error("Strand\nRoot 0 0 0\nFrame 0 0 0 0 1 0\n", "bad.txt:3", "non-zero");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 0\n", "bad.txt:4", "length");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 -1\n", "bad.txt:4", "length");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1e9 0 0 0 1\n", "bad.txt:4", "absurd");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece nan 0 0 0 1\n", "bad.txt:4", "");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nWisp 2.5 0 0\n", "bad.txt:5", "Wisp");
    expect_error("Strand 3\n", "bad.txt:1", "no values");
    expect_error("Step 0\nStrand\n", "bad.txt:1", "Step");
    expect_error("Step 0.1\nStep 0.1\nStrand\n", "bad.txt:2", "duplicate");
    expect_error("Strand\nStep 0.1\n", "bad.txt:2", "before the first Strand");
    expect_error("Waviness -1 3\nStrand\n", "bad.txt:1", "Waviness");
    expect_error("Waviness 0.001 3 1.5\nStrand\n", "bad.txt:1", "phase jitter in [0, 1]");
    expect_error("Waviness 0.001 3 0.5 2\nStrand\n", "bad.txt:1", "2 or 3 numbers");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nBend 3\n", "bad.txt:5", "unknown key");
    expect_error("Waves 0.001 100 0\nStrand\n", "bad.txt:1", "before the first Strand");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nWaves 0.001 100\n", "bad.txt:5", "3 numbers");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nWaves -0.001 100 0\n", "bad.txt:5",
                 "Waves needs");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nWaves 0.001 100 inf\n", "bad.txt:5", "");
    expect_error("Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\nPiece 1 0 0 0 1\nWaves 0 0 0\nWaves 0 0 0\n", "bad.txt:6",
                 "second Waves");
    /* 65 pieces */
    char buf[8192] = "Strand\nRoot 0 0 0\nFrame 1 0 0 0 1 0\n";
    for (int i = 0; i < 65; i++) strcat(buf, "Piece 1 0 0 0 0.01\n");
    expect_error(buf, "bad.txt:68", "pieces");
    expect_error("Strand\n\x01\n", "bad.txt", "");
}

static void test_fuzz(void **state)
{
    (void)state;
    static const char *const junk[8] = {"1e308 ", "-", "nan", "Strand\n", "#", "Piece 1 2 3 4 5\n", "\r\n", "0x1p3"};
    unsigned long long x = 0x9E3779B97F4A7C15ULL;
    int rejected = 0, accepted = 0;
    for (int iter = 0; iter < 1500; iter++) {
        char buf[4096];
        size_t len = strlen(sample);
        memcpy(buf, sample, len);
        for (int e = 0; e < 1 + iter % 4; e++)
            len = hk_test_mutate(buf, len, sizeof buf, " \t\n#-.e0123456789", junk, 8, &x);
        const char *path = hk_test_write_file("fuzz.txt", buf, len);
        hk_HelicoidSet set;
        hk_Error err;
        if (hk_helicoid_file_load(path, &set, &err) == HK_OK) {
            for (int s = 0; s < set.count; s++) assert_int_equal(hk_phelicoid_check(&set.strands[s], &err), HK_OK);
            hk_helicoid_set_free(&set);
            accepted++;
        } else {
            assert_true(strncmp(err.message, path, strlen(path)) == 0);
            rejected++;
        }
    }
    print_message("helicoid file fuzz: %d rejected, %d accepted\n", rejected, accepted);
    assert_true(rejected > 300 && accepted > 50);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sample),    cmocka_unit_test(test_errors), cmocka_unit_test(test_wave_jitter),
        cmocka_unit_test(test_own_waves), cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
