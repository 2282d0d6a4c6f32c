/* hk_helicoid_fit_wavy: a p-helicoid with eq. 4's waves on top (Piuze et al. 2011 §3.2),
 * against the project's own examples, whose files are the reference (the strands are traced
 * from them as `hairkit helicoid trace` does; each fit is traced again, with its waves, 4
 * times finer and compared with the strand both ways, not by the fitter's own measure):
 *  - examples/helicoid/wavy.txt (one piece, waves of 3 mm at 157 rad/m): the waves recovered
 *    (amplitude to 0.1 %, frequency to 0.1 %) and the strand to 10 microns, the floor of the
 *    comparison being the chords of the strand's 1 mm polyline (the waves' curvature of
 *    60/m sags them by up to 7.6 microns: measured 5.8); the fitter's own error is exact
 *    (the same points) to a micron;
 *  - examples/helicoid/wisp.txt (a 2-piece strand and 256 streamlines of its field from roots
 *    in a 6 mm disc, fanned out, waves of 2 mm at 120 rad/m): every 128th strand to 0.1 mm
 *    (issue 17) with at most 5 pieces, where the plain fitter needs 45 (test_helicoid_fit.c);
 *  - examples/helicoid/messy.txt (no waves): no waves found, the plain fit's error;
 *  - bad input refused. */
#include "hk_test.h"
#include "hk_test_curves.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "hairkit/hairfile.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/helicoid_hair.h"

/* The strands of an example helicoid file, traced at its own step. */
static void trace_example(const char *name, hk_HairFile *hair)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/helicoid/%s", HK_SOURCE_DIR, name);
    hk_HelicoidSet set = {0};
    hk_Error err;
    if (hk_helicoid_file_load(path, &set, &err) != HK_OK) fail_msg("%s: %s", name, err.message);
    assert_int_equal(hk_helicoid_set_trace(&set, set.step, 1, 1, hair, &err), HK_OK);
    hk_helicoid_set_free(&set);
}

typedef struct Result {
    hk_PHelicoid fit;
    hk_Waviness wave;
    double error;    /* the fitter's report */
    double distance; /* the fit traced with its waves against the strand (hk_test_curves.h) */
} Result;

static Result fit_strand(hk_HelicoidFitter *f, const hk_HairFile *hair, uint32_t s)
{
    const uint32_t a = hair->first_point[s], count = hair->first_point[s + 1] - a;
    hk_Vec3 *p = malloc((size_t)count * sizeof *p);
    for (uint32_t i = 0; i < count; i++)
        p[i] = hk_v3(hair->points[3 * (a + i)], hair->points[3 * (a + i) + 1], hair->points[3 * (a + i) + 2]);
    Result r;
    hk_Error err;
    if (hk_helicoid_fit_wavy(f, p, (int)count, NULL, &r.fit, &r.wave, &r.error, &err) != HK_OK)
        fail_msg("strand %u: %s", s, err.message);
    const double step = hk_phelicoid_length(&r.fit) / (4.0 * (count - 1));
    const int m = hk_phelicoid_point_count(&r.fit, step);
    hk_Vec3 *traced = malloc((size_t)m * sizeof *traced);
    assert_int_equal(hk_phelicoid_trace(&r.fit, step, &r.wave, NULL, traced, NULL, &err), HK_OK);
    r.distance = hk_test_polyline_distance(p, (int)count, traced, m);
    free(traced);
    free(p);
    return r;
}

static void test_wavy_example(void **state)
{
    (void)state;
    hk_HairFile hair = {0};
    trace_example("wavy.txt", &hair);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(4096, NULL);
    const Result r = fit_strand(f, &hair, 0);
    print_message("  wavy.txt: %d pieces, waves %.4f mm at %.2f rad/m, %.2g mm\n", r.fit.piece_count,
                  1e3 * r.wave.amplitude, r.wave.frequency, 1e3 * r.distance);
    hk_assert_rel(r.wave.amplitude, 0.003, 1e-3, 0.0);
    hk_assert_rel(r.wave.frequency, 157.0, 1e-3, 0.0);
    assert_true(r.distance <= 1e-5);
    assert_true(r.error <= 1e-6);
    hk_helicoid_fitter_destroy(f);
    hk_hair_free(&hair);
}

static void test_wisp_example(void **state)
{
    (void)state;
    hk_HairFile hair = {0};
    trace_example("wisp.txt", &hair);
    assert_int_equal(hair.strand_count, 257);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(4096, NULL);
    double sum = 0.0;
    int n = 0;
    for (uint32_t s = 0; s < hair.strand_count; s += 128, n++) {
        const Result r = fit_strand(f, &hair, s);
        print_message("  wisp.txt strand %u: %d pieces, waves %.4f mm at %.2f rad/m, %.3f mm\n", s, r.fit.piece_count,
                      1e3 * r.wave.amplitude, r.wave.frequency, 1e3 * r.distance);
        assert_true(r.fit.piece_count <= 5);
        hk_assert_rel(r.wave.amplitude, 0.002, 0.02, 0.0);
        hk_assert_rel(r.wave.frequency, 120.0, 0.01, 0.0);
        sum += r.distance;
    }
    assert_true(sum / n <= 1e-4);
    hk_helicoid_fitter_destroy(f);
    hk_hair_free(&hair);
}

/* A strand without waves: the waves found are none and the fit is the plain one. */
static void test_no_waves(void **state)
{
    (void)state;
    hk_HairFile hair = {0};
    trace_example("messy.txt", &hair);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(4096, NULL);
    const Result r = fit_strand(f, &hair, 0);
    const uint32_t count = hair.first_point[1];
    hk_Vec3 *p = malloc(count * sizeof *p);
    for (uint32_t i = 0; i < count; i++)
        p[i] = hk_v3(hair.points[3 * i], hair.points[3 * i + 1], hair.points[3 * i + 2]);
    hk_PHelicoid plain;
    hk_CurveFit report;
    assert_int_equal(hk_helicoid_fit(f, p, (int)count, NULL, &plain, &report, NULL), HK_OK);
    assert_true(r.wave.amplitude == 0.0);
    assert_true(r.error == report.error);
    assert_int_equal(r.fit.piece_count, plain.piece_count);
    free(p);
    hk_helicoid_fitter_destroy(f);
    hk_hair_free(&hair);
}

static void test_bad_input(void **state)
{
    (void)state;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, NULL);
    hk_Vec3 p[20];
    for (int i = 0; i < 20; i++) p[i] = hk_v3(0.01 * i, 0.001 * sin(i), 0.0);
    hk_PHelicoid out;
    hk_Waviness wave;
    double error;
    hk_Error err;
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 7, NULL, &out, &wave, &error, &err), HK_ERR_INVALID);
    assert_int_equal(hk_helicoid_fit_wavy(NULL, p, 20, NULL, &out, &wave, &error, &err), HK_ERR_INVALID);
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 20, NULL, &out, NULL, &error, &err), HK_ERR_INVALID);
    hk_WavyFitDef o = hk_default_wavy_fit_def();
    o.rounds = 0;
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 20, &o, &out, &wave, &error, &err), HK_ERR_INVALID);
    o = hk_default_wavy_fit_def(), o.base_piece_length = NAN;
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 20, &o, &out, &wave, &error, &err), HK_ERR_INVALID);
    p[5].y = NAN;
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 20, NULL, &out, &wave, &error, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "point 5");
    for (int i = 0; i < 20; i++) p[i] = hk_v3(0.0, 0.0, 0.0);
    assert_int_equal(hk_helicoid_fit_wavy(f, p, 20, NULL, &out, &wave, &error, &err), HK_ERR_INVALID);
    hk_helicoid_fitter_destroy(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_wavy_example),
        cmocka_unit_test(test_wisp_example),
        cmocka_unit_test(test_no_waves),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
