/* Strand width of grooms made elsewhere (issue 14, item 4): other tools write a default
 * thickness of 1.0 whatever their units, which hairkit drew as slabs. The rule
 * (hk_hair_thickness_implausible: no per-point thickness, and the default over 1 % of
 * the groom's extent or over 0.5 mm), the units guess, and the picture: a groom with
 * thickness 1.0 drawn at 70 um covers a small part of what its slabs cover. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/render.h"

/* strands x 8 points hanging down in a box of side `size` (fall and spread), in any unit. */
static void groom(hk_HairFile *h, uint32_t strands, double size, float thickness)
{
    hk_Error err;
    uint32_t counts[400] = {0};
    for (uint32_t s = 0; s < strands; s++) counts[s] = 8;
    assert_int_equal(hk_hair_alloc(h, strands, counts, &err), HK_OK);
    for (uint32_t s = 0; s < strands; s++) {
        const double a = 2.0 * HK_PI * s / strands, x = 0.3 * size * cos(a), z = 0.3 * size * sin(a);
        for (uint32_t p = 0; p < 8; p++) {
            float *q = h->points + 3 * (size_t)(8 * s + p);
            q[0] = (float)(x * (1.0 + 0.1 * p)), q[1] = (float)(size * (1.0 - p / 7.0)),
            q[2] = (float)(z * (1.0 + 0.1 * p));
        }
    }
    h->default_thickness = thickness;
}

static void test_rule(void **state)
{
    (void)state;
    hk_HairFile h;
    /* Metres (extent about 0.3): 1.0 is over 1 % of it; 70 um is hair; 3 mm is under
     * 1 % of it but over 0.5 mm, so not hair either. */
    groom(&h, 50, 0.3, 1.0f);
    assert_true(hk_hair_extent(&h) > 0.29 && hk_hair_extent(&h) < 0.32);
    assert_true(hk_hair_guess_meters_per_unit(&h) == 1.0);
    assert_true(hk_hair_thickness_implausible(&h, 0.0));
    h.default_thickness = 70e-6f;
    assert_false(hk_hair_thickness_implausible(&h, 0.0));
    assert_false(hk_hair_thickness_implausible(&h, 1.0));
    h.default_thickness = 3e-3f;
    assert_true(hk_hair_thickness_implausible(&h, 0.0));
    /* A thickness per point says the width: never replaced. */
    h.default_thickness = 1.0f;
    h.thickness = hk_alloc_array(h.point_count, sizeof(float), NULL);
    assert_non_null(h.thickness);
    h.flags |= HK_HAIR_THICKNESS;
    assert_false(hk_hair_thickness_implausible(&h, 0.0));
    hk_hair_free(&h);
    /* Millimetres (extent 240): 1.0 is under 1 % of the extent but 1 mm across;
     * 0.07 (70 um) is hair. Centimetres (extent 24): 1.0 is 4 % of it. */
    groom(&h, 50, 240.0, 1.0f);
    assert_true(hk_hair_guess_meters_per_unit(&h) == 0.001);
    assert_true(hk_hair_thickness_implausible(&h, 0.0));
    assert_false(hk_hair_thickness_implausible(&h, 1e-6)); /* in micrometres, 1.0 is fine */
    h.default_thickness = 0.07f;
    assert_false(hk_hair_thickness_implausible(&h, 0.0));
    hk_hair_free(&h);
    groom(&h, 50, 24.0, 1.0f);
    assert_true(hk_hair_guess_meters_per_unit(&h) == 0.01);
    assert_true(hk_hair_thickness_implausible(&h, 0.0));
    hk_hair_free(&h);
    /* hairkit's own hair: a hairstyle's diameter (HairRadius1 + HairRadius2). */
    groom(&h, 50, 0.3, 1.6e-4f);
    assert_false(hk_hair_thickness_implausible(&h, 0.0));
    hk_hair_free(&h);
}

/* How much of picture a the hair covers, against b without it: the mean over the
 * pixels of the largest channel difference (0: nothing drawn; a pixel covered by
 * opaque hair counts by its contrast with the background). */
static double coverage(const hk_Canvas *a, const hk_Canvas *b)
{
    double sum = 0.0;
    const long pixels = (long)a->width * a->height;
    for (long i = 0; i < pixels; i++) {
        float d = 0.0f;
        for (int k = 0; k < 3; k++) d = fmaxf(d, fabsf(a->rgb[3 * i + k] - b->rgb[3 * i + k]));
        sum += d;
    }
    return sum / (double)pixels;
}

static void test_picture(void **state)
{
    (void)state;
    hk_HairFile h;
    groom(&h, 300, 0.3, 1.0f);
    hk_RenderDef ro = hk_default_render_def();
    ro.width = 160, ro.height = 120, ro.threads = 1, ro.shadows = 0;
    hk_Canvas none, slab, fine;
    hk_Error err;
    ro.hair_thickness = 1e-9; /* the same framing, no hair to see */
    assert_int_equal(hk_render(&h, NULL, NULL, &ro, &none, NULL, &err), HK_OK);
    ro.hair_thickness = 0.0; /* the file's 1.0 */
    assert_int_equal(hk_render(&h, NULL, NULL, &ro, &slab, NULL, &err), HK_OK);
    ro.hair_thickness = HK_HUMAN_HAIR_DIAMETER / hk_hair_guess_meters_per_unit(&h);
    assert_int_equal(hk_render(&h, NULL, NULL, &ro, &fine, NULL, &err), HK_OK);
    const double c_slab = coverage(&slab, &none), c_fine = coverage(&fine, &none);
    print_message("coverage: slabs %.3f, 70 um hair %.3f\n", c_slab, c_fine);
    assert_true(c_fine > 0.0);
    assert_true(c_fine < 0.1 * c_slab);
    hk_canvas_free(&none);
    hk_canvas_free(&slab);
    hk_canvas_free(&fine);
    hk_hair_free(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rule),
        cmocka_unit_test(test_picture),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
