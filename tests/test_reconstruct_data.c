/* Captured grooms rebuilt from the p-helicoids fitted to one strand in ten (Piuze, Kry and
 * Siddiqi 2011, §5.4; issue 17, item 3), from ../shared/hair-data (SOURCES.md; never copied
 * into this repository; skipped, saying so, when absent). The reference is the capture
 * itself: each rebuilt strand against its original, the mean leash of their Fréchet
 * coupling (hk_helicoid_reconstruct's report). Issue 17 asks at most 4 mm on TressFX
 * Sintel; blending the fits' parameters (§4.2) gave 7.7 mm there, 15.7 mm on CT2Hair Bangs
 * and 13.9 mm on Curly, the blend of shapes 3.8, 10.5 and 10.5 mm
 * (docs/helicoid-fitting.md). */
#include "hk_test.h"

#include "hairkit/hair_formats.h"
#include "hairkit/helicoid_hair.h"

static void rebuild(const char *name, double scale, double mean_at_most)
{
    hk_Error err;
    hk_HairFile h, out;
    if (hk_hair_read(hk_test_shared_path(name), HK_HAIR_FORMAT_AUTO, &h, &err) != HK_OK) fail_msg("%s", err.message);
    assert_int_equal(hk_hair_scale(&h, scale, &err), HK_OK);
    hk_HelicoidReconstruction r;
    if (hk_helicoid_reconstruct(&h, 10, NULL, 3.0, 0.002, 1, 0, NULL, NULL, &out, &r, &err) != HK_OK)
        fail_msg("%s: %s", name, err.message);
    print_message("  %s: %ld strands from %ld fits: mean error %.2f mm, worst %.1f mm\n", name, r.strands, r.fitted,
                  1e3 * r.mean_error, 1e3 * r.max_error);
    assert_int_equal(out.strand_count, h.strand_count);
    assert_true(r.mean_error <= mean_at_most);
    hk_hair_free(&out);
    hk_hair_free(&h);
}

static void test_sintel(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    rebuild("SintelHairOriginal-sintel_hair.16points.tfx", 1.0, 4e-3); /* the target */
}

/* 100 strands each, in millimetres: 10 fits. Held below the parameter blend's figures. */
static void test_ct2hair(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    rebuild("Bangs_100.hair", 0.001, 11e-3);
    rebuild("Curly_100.ply", 0.001, 11e-3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sintel),
        cmocka_unit_test(test_ct2hair),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
