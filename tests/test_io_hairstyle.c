/* Hairstyle Info files (src/io/hairstyle.c): the thesis's Appendix B sample, spellings
 * and defaults, every error class with its file:line message, and a fuzz loop. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hairkit/io.h"

/* Lansink 2010 Appendix B, "Hairstyle Info", as printed: `Maxiter`, tabs, banner. */
static const char *const thesis_hairstyle = "\n"
                                            "#######################################\n"
                                            "## Hairstyle File: Medium Straight ##\n"
                                            "#######################################\n"
                                            "\n"
                                            "# Precision\n"
                                            "\n"
                                            "VisualityStep\t0.0025\n"
                                            "CollisionStep\t0.0050\n"
                                            "\n"
                                            "# Minimization\n"
                                            "\n"
                                            "Maxiter\t5\n"
                                            "Epsilon\t0.0001\n"
                                            "\n"
                                            "# Hair Shape\n"
                                            "\n"
                                            "HairLengths\t0.01 0.01 0.01 0.01 0.01 0.01 0.01 0.01\n"
                                            "HairDensity\t80\n"
                                            "\n"
                                            "# Elasticity\n"
                                            "\n"
                                            "HairRadius1\t0.000035\n"
                                            "HairRadius2\t0.000050\n"
                                            "HelixRadius\t0.050\n"
                                            "HelixStep\t0.050\n"
                                            "Poisson\t0.48\n"
                                            "Young\t1000000000\n"
                                            "\n"
                                            "# Gravity\n"
                                            "\n"
                                            "Density\t13000\n"
                                            "Gravity\t9.81\n";

/* Every key once, one per line, so that line n is the n-th key. */
static const char *const full_hairstyle = "VisualityStep 0.0025\n"                 /* 1 */
                                          "CollisionStep 0.005\n"                  /* 2 */
                                          "MaxIter 20\n"                           /* 3 */
                                          "Epsilon 0.0001\n"                       /* 4 */
                                          "HairLengths 0.02 0.02 0.02 0.02 0.02\n" /* 5 */
                                          "HairDensity 250\n"                      /* 6 */
                                          "HairRadius1 0.00005\n"                  /* 7 */
                                          "HairRadius2 0.00004\n"                  /* 8 */
                                          "HelixRadius 0.006\n"                    /* 9 */
                                          "HelixStep 0.005\n"                      /* 10 */
                                          "Poisson 0.48\n"                         /* 11 */
                                          "Young 1.5e9\n"                          /* 12 */
                                          "Density 1300\n"                         /* 13 */
                                          "Gravity 9.81\n"                         /* 14 */
                                          "GravityDirection 0 -1 0\n";             /* 15 */

/* Everything a successful load promises. */
static void assert_sane(const hk_Hairstyle *d)
{
    assert_true(d->strand.element_count >= 1 && d->strand.element_count <= HK_MAX_ELEMENTS);
    assert_non_null(d->strand.element_lengths);
    for (int i = 0; i < d->strand.element_count; i++)
        assert_true(d->strand.element_lengths[i] > 0.0 && d->strand.element_lengths[i] <= 10.0);
    const double len = hk_strand_def_length(&d->strand);
    assert_true(d->strand.visuality_step > 0.0 && len / d->strand.visuality_step <= HK_MAX_SAMPLES_PER_STRAND);
    assert_true(d->strand.collision_step > 0.0 && len / d->strand.collision_step <= HK_MAX_SAMPLES_PER_STRAND);
    assert_true(d->strand.max_iter >= 1 && d->strand.max_iter <= 1000000000);
    assert_true(d->strand.epsilon > 0.0 && isfinite(d->strand.epsilon));
    assert_true(d->interpolation.hair_density >= 0.0 && d->interpolation.hair_density <= 100000.0);
    assert_true(d->strand.radius1 > 0.0 && d->strand.radius1 < 0.01);
    assert_true(d->strand.radius2 > 0.0 && d->strand.radius2 < 0.01);
    assert_true(d->strand.helix_radius >= 0.0 && isfinite(d->strand.helix_radius));
    assert_true(isfinite(d->strand.helix_step));
    assert_true(d->strand.poisson > -1.0 && d->strand.poisson < 0.5);
    assert_true(d->strand.young > 0.0 && isfinite(d->strand.young));
    assert_true(d->strand.density > 0.0 && isfinite(d->strand.density));
    assert_true(d->strand.gravity >= 0.0 && isfinite(d->strand.gravity));
    const hk_Vec3 g = d->strand.gravity_dir;
    hk_assert_near(sqrt(g.x * g.x + g.y * g.y + g.z * g.z), 1.0, 1e-12);
    assert_true(d->interpolation.clump >= 0.0 && d->interpolation.clump < 1.0);
    assert_true(d->interpolation.clump_profile > 0.0 && isfinite(d->interpolation.clump_profile));
    assert_true(d->interpolation.stray_hairs == 0 || d->interpolation.stray_hairs == 1);
    assert_true(d->interpolation.max_tip_distance >= 0.0 && isfinite(d->interpolation.max_tip_distance));
}

/* Loads `text`; fails the test unless it succeeds. */
static void load_ok(const char *text, hk_Hairstyle *d)
{
    hk_Error err;
    hk_Status st = hk_hairstyle_load(hk_test_write_text("hairstyle.txt", text), d, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_sane(d);
}

static void test_thesis_sample(void **state)
{
    (void)state;
    hk_Hairstyle d;
    load_ok(thesis_hairstyle, &d);
    hk_assert_near(d.strand.visuality_step, 0.0025, 0);
    hk_assert_near(d.strand.collision_step, 0.005, 0);
    assert_int_equal(d.strand.max_iter, 5);
    hk_assert_near(d.strand.epsilon, 1e-4, 0);
    assert_int_equal(d.strand.element_count, 8);
    for (int i = 0; i < 8; i++) hk_assert_near(d.strand.element_lengths[i], 0.01, 0);
    hk_assert_near(hk_strand_def_length(&d.strand), 0.08, 1e-15);
    hk_assert_near(d.interpolation.hair_density, 80, 0);
    hk_assert_near(d.strand.radius1, 35e-6, 0);
    hk_assert_near(d.strand.radius2, 50e-6, 0);
    hk_assert_near(d.strand.helix_radius, 0.05, 0);
    hk_assert_near(d.strand.helix_step, 0.05, 0);
    hk_assert_near(d.strand.poisson, 0.48, 0);
    hk_assert_near(d.strand.young, 1e9, 0);
    hk_assert_near(d.strand.density, 13000, 0); /* the thesis's value, kept as written */
    hk_assert_near(d.strand.gravity, 9.81, 0);
    hk_assert_near(d.strand.gravity_dir.x, 0, 0);
    hk_assert_near(d.strand.gravity_dir.y, -1, 0);
    hk_assert_near(d.strand.gravity_dir.z, 0, 0);
    hk_hairstyle_free(&d);
    assert_null(d.strand.element_lengths);
    assert_int_equal(d.strand.element_count, 0);
}

static void test_defaults(void **state)
{
    (void)state;
    hk_Hairstyle def = hk_default_hairstyle();
    hk_assert_near(def.strand.visuality_step, 0.0025, 0);
    hk_assert_near(def.strand.collision_step, 0.005, 0);
    assert_int_equal(def.strand.max_iter, 20);
    hk_assert_near(def.strand.epsilon, 1e-4, 0);
    hk_assert_near(def.interpolation.hair_density, 250, 0);
    hk_assert_near(def.strand.poisson, 0.48, 0);
    hk_assert_near(def.strand.density, 1300, 0);
    hk_assert_near(def.strand.gravity, 9.81, 0);
    hk_assert_near(def.strand.gravity_dir.y, -1, 0);
    hk_assert_near(def.interpolation.clump, 0.25, 0);
    hk_assert_near(def.interpolation.clump_profile, 1.0, 0);
    assert_int_equal(def.interpolation.stray_hairs, 0);
    hk_assert_near(def.interpolation.max_tip_distance, 0.08, 0); /* docs/file-formats.md */
    assert_null(def.strand.element_lengths);
    assert_int_equal(def.strand.element_count, 0);
    hk_assert_near(hk_strand_def_length(&def.strand), 0, 0);
    hk_hairstyle_free(&def); /* safe on a default */

    /* Only the required keys: every optional one takes its default. */
    hk_Hairstyle d;
    load_ok("HairLengths 0.1\nHairRadius1 5e-5\nHairRadius2 4e-5\nHelixRadius 0\nHelixStep 0\nYoung 1e9\n", &d);
    hk_assert_near(d.strand.visuality_step, def.strand.visuality_step, 0);
    hk_assert_near(d.strand.collision_step, def.strand.collision_step, 0);
    assert_int_equal(d.strand.max_iter, def.strand.max_iter);
    hk_assert_near(d.strand.epsilon, def.strand.epsilon, 0);
    hk_assert_near(d.interpolation.hair_density, def.interpolation.hair_density, 0);
    hk_assert_near(d.strand.poisson, def.strand.poisson, 0);
    hk_assert_near(d.strand.density, def.strand.density, 0);
    hk_assert_near(d.strand.gravity, def.strand.gravity, 0);
    hk_assert_near(d.strand.gravity_dir.y, -1, 0);
    hk_assert_near(d.interpolation.clump, def.interpolation.clump, 0);
    hk_assert_near(d.interpolation.clump_profile, def.interpolation.clump_profile, 0);
    assert_int_equal(d.interpolation.stray_hairs, def.interpolation.stray_hairs);
    hk_assert_near(d.interpolation.max_tip_distance, def.interpolation.max_tip_distance, 0);
    hk_assert_near(d.strand.radius2, 4e-5, 0);
    hk_hairstyle_free(&d);
}

/* The grooming keys of the full head (docs/grooming.md). */
static void test_groom_keys(void **state)
{
    (void)state;
    static const char *const required =
        "HairLengths 0.1\nHairRadius1 5e-5\nHairRadius2 4e-5\nHelixRadius 0\nHelixStep 0\nYoung 1e9\n";
    char text[512];
    hk_Hairstyle d;
    snprintf(text, sizeof text, "%sclumpfactor 0.1\nClumpProfile 1.5\nSTRAYHAIRS yes\nMaxTipDistance 0.05\n", required);
    load_ok(text, &d);
    hk_assert_near(d.interpolation.clump, 0.1, 0);
    hk_assert_near(d.interpolation.clump_profile, 1.5, 0);
    assert_int_equal(d.interpolation.stray_hairs, 1);
    hk_assert_near(d.interpolation.max_tip_distance, 0.05, 0);
    hk_hairstyle_free(&d);
    snprintf(text, sizeof text, "%sClumpFactor 0\nClumpProfile 1e-3\nStrayHairs false\nMaxTipDistance 0\n", required);
    load_ok(text, &d);
    hk_assert_near(d.interpolation.clump, 0.0, 0);
    hk_assert_near(d.interpolation.clump_profile, 1e-3, 0);
    assert_int_equal(d.interpolation.stray_hairs, 0);
    hk_assert_near(d.interpolation.max_tip_distance, 0, 0); /* off: the plain blend */
    hk_hairstyle_free(&d);
}

static void test_spellings_and_layout(void **state)
{
    (void)state;
    /* Any case, the HairLength alias, CRLF, no final line end, comments after values,
     * '+' signs, GravityDirection normalised. */
    const char *text = "hairlength 0.1 +0.2 # two elements\r\n"
                       "HAIRRADIUS1 5e-5\r\nhairRadius2 4E-5\r\n\r\n"
                       "helixradius 0.01\r\nHeLiXsTeP -0.005\r\nYOUNG +1.5e9\r\n"
                       "maxiter 7\r\nPOISSON -0.25\r\ngravitydirection 0 0 -2\r\n"
                       "gravity 0\r\nDENSITY 1000";
    hk_Hairstyle d;
    load_ok(text, &d);
    assert_int_equal(d.strand.element_count, 2);
    hk_assert_near(d.strand.element_lengths[1], 0.2, 0);
    hk_assert_near(hk_strand_def_length(&d.strand), 0.3, 1e-15);
    hk_assert_near(d.strand.radius1, 5e-5, 0);
    hk_assert_near(d.strand.radius2, 4e-5, 0);
    hk_assert_near(d.strand.helix_radius, 0.01, 0);
    hk_assert_near(d.strand.helix_step, -0.005, 0); /* left-handed */
    hk_assert_near(d.strand.young, 1.5e9, 0);
    assert_int_equal(d.strand.max_iter, 7);
    hk_assert_near(d.strand.poisson, -0.25, 0);
    hk_assert_near(d.strand.gravity_dir.x, 0, 0);
    hk_assert_near(d.strand.gravity_dir.z, -1, 0);
    hk_assert_near(d.strand.gravity, 0, 0);
    hk_assert_near(d.strand.density, 1000, 0);
    hk_hairstyle_free(&d);

    /* Directions too large or too small to square are still normalised. */
    load_ok("HairLength 0.1\nHairRadius1 5e-5\nHairRadius2 5e-5\nHelixRadius 0\nHelixStep 0\n"
            "Young 1e9\nGravityDirection 1e300 -1e300 0\n",
            &d);
    hk_assert_near(d.strand.gravity_dir.x, sqrt(0.5), 1e-15);
    hk_assert_near(d.strand.gravity_dir.y, -sqrt(0.5), 1e-15);
    hk_hairstyle_free(&d);
    load_ok("HairLength 0.1\nHairRadius1 5e-5\nHairRadius2 5e-5\nHelixRadius 0\nHelixStep 0\n"
            "Young 1e9\nGravityDirection 0 3e-300 0\n",
            &d);
    hk_assert_near(d.strand.gravity_dir.y, 1.0, 1e-15);
    hk_hairstyle_free(&d);

    /* The largest allowed values at the edges of the closed ranges. */
    char text2[16384];
    int n = snprintf(text2, sizeof text2, "HairLengths");
    for (int i = 0; i < HK_MAX_ELEMENTS; i++) n += snprintf(text2 + n, sizeof text2 - (size_t)n, " 0.001");
    snprintf(text2 + n, sizeof text2 - (size_t)n,
             "\nHairRadius1 0.00999\nHairRadius2 1e-300\nHelixRadius 0\nHelixStep 0\nYoung 1e-300\n"
             "HairDensity 100000\nMaxIter 1000000000\nGravity 0\nPoisson 0.4999\n");
    load_ok(text2, &d);
    assert_int_equal(d.strand.element_count, HK_MAX_ELEMENTS);
    hk_assert_near(hk_strand_def_length(&d.strand), 1.0, 1e-12);
    assert_int_equal(d.strand.max_iter, 1000000000);
    hk_assert_near(d.interpolation.hair_density, 100000, 0);
    hk_hairstyle_free(&d);
    load_ok("HairLengths 10 10\nHairRadius1 5e-5\nHairRadius2 5e-5\nHelixRadius 0\nHelixStep 0\n"
            "Young 1e9\nHairDensity 0\nPoisson -0.9999\n",
            &d);
    hk_assert_near(d.strand.element_lengths[1], 10.0, 0);
    hk_hairstyle_free(&d);
}

static void test_copy(void **state)
{
    (void)state;
    hk_Hairstyle d, c;
    hk_Error err;
    load_ok(full_hairstyle, &d);
    memset(&c, 0x5A, sizeof c);
    assert_int_equal(hk_hairstyle_copy(&d, &c, &err), HK_OK);
    assert_ptr_not_equal(c.strand.element_lengths, d.strand.element_lengths);
    assert_int_equal(c.strand.element_count, 5);
    hk_assert_near(c.strand.young, 1.5e9, 0);
    hk_assert_near(c.strand.radius2, 4e-5, 0);
    hk_assert_near(c.strand.gravity_dir.y, -1, 0);
    hk_assert_near(c.interpolation.clump, 0.25, 0);
    hk_hairstyle_free(&d); /* the copy owns its own lengths */
    hk_assert_near(c.strand.element_lengths[4], 0.02, 0);
    hk_assert_near(hk_strand_def_length(&c.strand), 0.1, 1e-15);
    hk_hairstyle_free(&c);
    /* A default (no elements) copies to no array. */
    d = hk_default_hairstyle();
    assert_int_equal(hk_hairstyle_copy(&d, &c, &err), HK_OK);
    assert_null(c.strand.element_lengths);
    hk_hairstyle_free(&c);
}

/* full_hairstyle with the line starting "key " replaced by `line` (NULL deletes it);
 * appended as line 16 when no line starts with key. */
static const char *hairstyle_with(const char *key, const char *line)
{
    static char buf[32768];
    buf[0] = '\0';
    const char *p = full_hairstyle;
    int replaced = 0;
    while (*p) {
        const char *nl = strchr(p, '\n');
        size_t len = (size_t)(nl - p) + 1;
        if (!strncmp(p, key, strlen(key)) && p[strlen(key)] == ' ') {
            if (line) strcat(strcat(buf, line), "\n");
            replaced = 1;
        } else {
            strncat(buf, p, len);
        }
        p += len;
    }
    if (!replaced && line) strcat(strcat(buf, line), "\n");
    return hk_test_write_text("hairstyle.txt", buf);
}

/* Loading the file fails with `code`; the message starts with the path as given, then
 * ":line: " (or ": " for line 0), and contains `phrase`; `out` holds nothing to free. */
static void expect_error_in(const char *path, hk_Status code, int line, const char *phrase)
{
    hk_Hairstyle d;
    hk_Error err;
    memset(&d, 0x5A, sizeof d);
    err.message[0] = '\0';
    hk_Status st = hk_hairstyle_load(path, &d, &err);
    if (st != code) print_error("status %d (wanted %d), message '%s'\n", st, code, err.message);
    assert_int_equal(st, code);
    char prefix[700];
    if (line > 0)
        snprintf(prefix, sizeof prefix, "%s:%d: ", path, line);
    else
        snprintf(prefix, sizeof prefix, "%s: ", path);
    if (strncmp(err.message, prefix, strlen(prefix)) != 0) {
        print_error("message '%s' does not start with '%s'\n", err.message, prefix);
        fail();
    }
    hk_assert_contains(err.message, phrase);
    assert_int_equal(err.code, code);
    assert_null(d.strand.element_lengths);
    assert_int_equal(d.strand.element_count, 0);
    hk_hairstyle_free(&d);
}

static void expect_error(const char *key, const char *line, hk_Status code, int at, const char *phrase)
{
    expect_error_in(hairstyle_with(key, line), code, at, phrase);
}

static void test_key_errors(void **state)
{
    (void)state;
    expect_error("Foo", "Foo 1", HK_ERR_PARSE, 16, "unknown key 'Foo'");
    expect_error("Epsilon", "Epsilon: 0.001", HK_ERR_PARSE, 4, "unknown key 'Epsilon:'");
    expect_error("Extra", "young 2e9", HK_ERR_PARSE, 16, "duplicate key 'Young' (first given at line 12)");
    expect_error("Extra", "HairLength 0.1", HK_ERR_PARSE, 16, "duplicate key 'HairLengths' (first given at line 5)");
    expect_error("Extra", "MAXITER 3", HK_ERR_PARSE, 16, "duplicate key 'MaxIter' (first given at line 3)");
    static const char *const required[] = {"HairLengths", "HairRadius1", "HairRadius2",
                                           "HelixRadius", "HelixStep",   "Young"};
    for (int i = 0; i < 6; i++) {
        char phrase[64];
        snprintf(phrase, sizeof phrase, "missing required key '%s'", required[i]);
        expect_error(required[i], NULL, HK_ERR_PARSE, 0, phrase);
    }
    /* Optional keys may be left out. */
    static const char *const optional[] = {"VisualityStep", "CollisionStep", "MaxIter",
                                           "Epsilon",       "HairDensity",   "Poisson",
                                           "Density",       "Gravity",       "GravityDirection"};
    for (int i = 0; i < 9; i++) {
        hk_Hairstyle d;
        hk_Error err;
        assert_int_equal(hk_hairstyle_load(hairstyle_with(optional[i], NULL), &d, &err), HK_OK);
        hk_hairstyle_free(&d);
    }
}

static void test_number_errors(void **state)
{
    (void)state;
    expect_error("Gravity", "Gravity 9.81 1", HK_ERR_PARSE, 14, "expected 1 number after 'Gravity', got 2");
    expect_error("Young", "Young", HK_ERR_PARSE, 12, "expected 1 number after 'Young', got 0");
    expect_error("GravityDirection", "GravityDirection 0 -1", HK_ERR_PARSE, 15,
                 "expected 3 numbers after 'GravityDirection', got 2");
    expect_error("HairLengths", "HairLengths", HK_ERR_PARSE, 5, "'HairLengths' needs at least one number");
    expect_error("Density", "Density 1.0abc", HK_ERR_PARSE, 13,
                 "'1.0abc' is not a finite number (value 1 of 'Density')");
    expect_error("HairLengths", "HairLengths 0.01 0.01 O.01", HK_ERR_PARSE, 5,
                 "'O.01' is not a finite number (value 3");
    expect_error("MaxIter", "MaxIter 2.5", HK_ERR_PARSE, 3, "'2.5' is not a whole number");
    expect_error("MaxIter", "MaxIter ten", HK_ERR_PARSE, 3, "'ten' is not a whole number");
    expect_error("Young", "Young 1e999", HK_ERR_PARSE, 12, "'1e999' is out of the range");
    /* NaN and infinities are refused for every numeric key. */
    static const char *const keys[] = {"VisualityStep", "CollisionStep", "Epsilon",     "HairLengths", "HairDensity",
                                       "HairRadius1",   "HairRadius2",   "HelixRadius", "HelixStep",   "Poisson",
                                       "Young",         "Density",       "Gravity"};
    static const char *const words[] = {"nan", "inf", "-inf", "NAN", "Infinity"};
    for (int k = 0; k < 13; k++)
        for (int w = 0; w < 5; w++) {
            char line[64];
            snprintf(line, sizeof line, "%s %s", keys[k], words[w]);
            expect_error(keys[k], line, HK_ERR_PARSE, k < 2 ? k + 1 : k + 2, "is not a finite number");
        }
    expect_error("GravityDirection", "GravityDirection 0 nan 0", HK_ERR_PARSE, 15,
                 "'nan' is not a finite number (value 2");
    expect_error("Extra", "ClumpFactor nan", HK_ERR_PARSE, 16, "'nan' is not a finite number");
    expect_error("Extra", "ClumpProfile inf", HK_ERR_PARSE, 16, "'inf' is not a finite number");
    expect_error("Extra", "MaxTipDistance -inf", HK_ERR_PARSE, 16, "'-inf' is not a finite number");
    expect_error("Extra", "StrayHairs maybe", HK_ERR_PARSE, 16, "'StrayHairs' must be true or false, got 'maybe'");
    expect_error("Extra", "StrayHairs", HK_ERR_PARSE, 16, "expected one value after 'StrayHairs', got 0");
}

static void test_range_errors(void **state)
{
    (void)state;
    static const struct {
        const char *key, *line;
        int at;
        const char *phrase;
    } cases[] = {
        {"Young", "Young -3", 12, "Young must be > 0, got -3"},
        {"Young", "Young 0", 12, "Young must be > 0, got 0"},
        {"Young", "YOUNG -0.0", 12, "Young must be > 0, got -0.0"},
        {"HairLengths", "HairLengths 0.01 0 0.02", 5, "element length 2 must be in (0, 10] m, got 0"},
        {"HairLengths", "HairLengths -0.01", 5, "element length 1 must be in (0, 10] m, got -0.01"},
        {"HairLengths", "HairLengths 0.1 0.1 10.000001", 5, "element length 3 must be in (0, 10] m, got 10.000001"},
        {"HairRadius1", "HairRadius1 0", 7, "HairRadius1 must be in (0, 0.01) m, got 0"},
        {"HairRadius1", "HairRadius1 -5e-5", 7, "HairRadius1 must be in (0, 0.01) m"},
        {"HairRadius1", "HairRadius1 0.01", 7, "HairRadius1 must be in (0, 0.01) m, got 0.01"},
        {"HairRadius2", "HairRadius2 0", 8, "HairRadius2 must be in (0, 0.01) m, got 0"},
        {"HairRadius2", "HairRadius2 0.0100000001", 8, "HairRadius2 must be in (0, 0.01) m, got 0.0100000001"},
        {"HelixRadius", "HelixRadius -0.001", 9, "HelixRadius must be >= 0 (0 is straight hair), got -0.001"},
        {"Poisson", "Poisson 0.5", 11, "Poisson must be in (-1, 0.5), got 0.5"},
        {"Poisson", "Poisson -1", 11, "Poisson must be in (-1, 0.5), got -1"},
        {"Poisson", "Poisson 0.7", 11, "Poisson must be in (-1, 0.5)"},
        {"Density", "Density 0", 13, "Density must be > 0, got 0"},
        {"Density", "Density -1300", 13, "Density must be > 0"},
        {"Gravity", "Gravity -9.81", 14, "Gravity must be >= 0, got -9.81"},
        {"VisualityStep", "VisualityStep 0", 1, "VisualityStep must be > 0, got 0"},
        {"VisualityStep", "VisualityStep -0.001", 1, "VisualityStep must be > 0"},
        {"CollisionStep", "CollisionStep 0", 2, "CollisionStep must be > 0, got 0"},
        {"CollisionStep", "CollisionStep -1", 2, "CollisionStep must be > 0"},
        {"MaxIter", "MaxIter 0", 3, "MaxIter must be in [1, 1000000000], got 0"},
        {"MaxIter", "Maxiter -5", 3, "Maxiter must be in [1, 1000000000], got -5"},
        {"MaxIter", "MaxIter 1000000001", 3, "MaxIter must be in [1, 1000000000], got 1000000001"},
        {"MaxIter", "MaxIter 99999999999999999999", 3, "must be in [1, 1000000000]"},
        {"Epsilon", "Epsilon 0", 4, "Epsilon must be > 0, got 0"},
        {"Epsilon", "Epsilon -1e-4", 4, "Epsilon must be > 0"},
        {"HairDensity", "HairDensity -1", 6, "HairDensity must be in [0, 100000] hairs/cm^2, got -1"},
        {"HairDensity", "HairDensity 100001", 6, "HairDensity must be in [0, 100000] hairs/cm^2, got 100001"},
        {"GravityDirection", "GravityDirection 0 0 0", 15, "GravityDirection must not be zero"},
        {"GravityDirection", "GravityDirection -0 0.0 0e5", 15, "GravityDirection must not be zero"},
        {"Extra", "ClumpFactor 1", 16, "ClumpFactor must be in [0, 1), got 1"},
        {"Extra", "ClumpFactor -0.1", 16, "ClumpFactor must be in [0, 1), got -0.1"},
        {"Extra", "ClumpProfile 0", 16, "ClumpProfile must be > 0, got 0"},
        {"Extra", "MaxTipDistance -0.01", 16, "MaxTipDistance must be >= 0, got -0.01"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        expect_error(cases[i].key, cases[i].line, HK_ERR_INVALID, cases[i].at, cases[i].phrase);

    /* One element too many: refused from the count, before any value is read. */
    char many[16384];
    int n = snprintf(many, sizeof many, "HairLengths");
    for (int i = 0; i <= HK_MAX_ELEMENTS; i++) n += snprintf(many + n, sizeof many - (size_t)n, " x");
    expect_error("HairLengths", many, HK_ERR_INVALID, 5,
                 "HairLengths has 1001 values (elements), at most 1000 allowed");
}

/* Sample counts L / step, checked once the whole file is read. */
static void test_sample_limits(void **state)
{
    (void)state;
    /* The strand of full_hairstyle is 0.1 m long. */
    expect_error("VisualityStep", "VisualityStep 1e-8", HK_ERR_INVALID, 1,
                 "VisualityStep 1e-08 gives 1e+07 samples over the 0.1 m strand (at most 1000000)");
    expect_error("CollisionStep", "CollisionStep 9e-8", HK_ERR_INVALID, 2,
                 "CollisionStep 9e-08 gives 1.11e+06 samples over the 0.1 m strand (at most 1000000)");
    /* Just under the limit is fine. */
    hk_Hairstyle d;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(hairstyle_with("VisualityStep", "VisualityStep 1.01e-7"), &d, &err), HK_OK);
    hk_hairstyle_free(&d);
    assert_int_equal(hk_hairstyle_load(hairstyle_with("CollisionStep", "CollisionStep 1.01e-7"), &d, &err), HK_OK);
    hk_hairstyle_free(&d);
    /* Exactly HK_MAX_SAMPLES_PER_STRAND (1 m / 1e-6 m is exactly 1e6 in binary). */
    const char *one_metre = "HairLengths 0.5 0.5\nHairRadius1 5e-5\nHairRadius2 5e-5\nHelixRadius 0\n"
                            "HelixStep 0\nYoung 1e9\n";
    char text1[512];
    snprintf(text1, sizeof text1, "%sVisualityStep 1e-6\nCollisionStep 1e-6\n", one_metre);
    assert_int_equal(hk_hairstyle_load(hk_test_write_text("edge.txt", text1), &d, &err), HK_OK);
    hk_hairstyle_free(&d);
    snprintf(text1, sizeof text1, "%sVisualityStep 1e-6\nCollisionStep 9.99e-7\n", one_metre);
    expect_error_in(hk_test_write_text("edge.txt", text1), HK_ERR_INVALID, 8,
                    "CollisionStep 9.99e-07 gives 1e+06 samples");
    snprintf(text1, sizeof text1, "%sVisualityStep 9.99e-7\nCollisionStep 1e-6\n", one_metre);
    expect_error_in(hk_test_write_text("edge.txt", text1), HK_ERR_INVALID, 7, "VisualityStep 9.99e-07 gives");
    /* The step's line is reported even when the step comes after the lengths. */
    expect_error_in(hk_test_write_text("late.txt", "HairLengths 0.5 0.5\nHairRadius1 5e-5\nHairRadius2 5e-5\n"
                                                   "HelixRadius 0\nHelixStep 0\nYoung 1e9\nCollisionStep 1e-7\n"),
                    HK_ERR_INVALID, 7, "CollisionStep 1e-07 gives 1e+07 samples over the 1 m strand");
    /* A 10 km strand with the default steps: reported at HairLengths. */
    char *text = malloc(16384);
    assert_non_null(text);
    int n =
        snprintf(text, 16384, "HairRadius1 5e-5\nHairRadius2 5e-5\nHelixRadius 0\nHelixStep 0\nYoung 1e9\nHairLengths");
    for (int i = 0; i < HK_MAX_ELEMENTS; i++) n += snprintf(text + n, 16384 - (size_t)n, " 10");
    snprintf(text + n, 16384 - (size_t)n, "\n");
    expect_error_in(hk_test_write_text("long.txt", text), HK_ERR_INVALID, 6,
                    "VisualityStep 0.0025 (the default) gives 4e+06 samples over the 10000 m strand");
    free(text);
}

static void test_files(void **state)
{
    (void)state;
    hk_Hairstyle d;
    hk_Error err;
    memset(&d, 0x5A, sizeof d);
    assert_int_equal(hk_hairstyle_load("/nonexistent/dir/hairstyle.txt", &d, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/dir/hairstyle.txt: cannot open");
    assert_null(d.strand.element_lengths);
    expect_error_in(hk_test_write_text("empty.txt", ""), HK_ERR_PARSE, 0, "file is empty");
    expect_error_in(hk_test_write_text("blank.txt", "\n  \n# nothing\n"), HK_ERR_PARSE, 0,
                    "missing required key 'HairLengths'");
    static const char bin[] = "HairLengths 0.1\n\0\1\2binary";
    expect_error_in(hk_test_write_file("binary.txt", bin, sizeof bin - 1), HK_ERR_PARSE, 0,
                    "not a text file (binary data at line 2)");
    expect_error_in(hk_test_write_text("collision.txt", "Sphere 0 1 0 0 0 1\n"), HK_ERR_PARSE, 1,
                    "unknown key 'Sphere' in a hairstyle file");
    char path[600];
    snprintf(path, sizeof path, "%s/huge.txt", hk_test_tmpdir());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fseek(f, HK_MAX_INPUT_FILE_BYTES, SEEK_SET), 0);
    fputc('\n', f);
    assert_int_equal(fclose(f), 0);
    expect_error_in(path, HK_ERR_PARSE, 0, "larger than");
    unlink(path);

    /* "hairstyle.txt:12: Young must be > 0, got -3", with the path exactly as given. */
    char cwd[4096];
    assert_non_null(getcwd(cwd, sizeof cwd));
    assert_int_equal(chdir(hk_test_tmpdir()), 0);
    hairstyle_with("Young", "Young -3");
    hk_Status st = hk_hairstyle_load("hairstyle.txt", &d, &err);
    int back = chdir(cwd);
    assert_int_equal(back, 0);
    assert_int_equal(st, HK_ERR_INVALID);
    assert_string_equal(err.message, "hairstyle.txt:12: Young must be > 0, got -3");

    /* A NULL hk_Error is allowed. */
    assert_int_equal(hk_hairstyle_load(hairstyle_with("Young", "Young -3"), &d, NULL), HK_ERR_INVALID);
    assert_int_equal(hk_hairstyle_load(hairstyle_with("Young", "Young 3"), &d, NULL), HK_OK);
    hk_hairstyle_free(&d);
}

/* Mutated copies of the thesis file: each load either succeeds with sane values or
 * fails with a message naming the file; the sanitizer build checks crashes and leaks. */
static void test_fuzz(void **state)
{
    (void)state;
    static const char *const junk[12] = {"1e308 ", "-",           "nan",          "\"",
                                         "#",      "\r\n",        "Young 1\n",    "0x1p3",
                                         "\t\t",   "HairLength ", "\xEF\xBB\xBF", "99999999999"};
    unsigned long long x = 0x2545F4914F6CDD1DULL;
    int rejected = 0, accepted = 0;
    for (int iter = 0; iter < 2000; iter++) {
        char buf[4096];
        size_t len = strlen(thesis_hairstyle);
        memcpy(buf, thesis_hairstyle, len);
        int edits = 1 + iter % 4;
        for (int e = 0; e < edits; e++)
            len = hk_test_mutate(buf, len, sizeof buf, " \t\n#\"-.e0123456789", junk, 12, &x);
        const char *path = hk_test_write_file("fuzz_hairstyle.txt", buf, len);
        hk_Hairstyle d;
        hk_Error err;
        memset(&d, 0x5A, sizeof d);
        err.message[0] = '\0';
        hk_Status st = hk_hairstyle_load(path, &d, &err);
        if (st == HK_OK) {
            assert_sane(&d);
            hk_hairstyle_free(&d);
            accepted++;
        } else {
            assert_true(st == HK_ERR_PARSE || st == HK_ERR_INVALID);
            assert_true(strncmp(err.message, path, strlen(path)) == 0); /* names the file */
            assert_true(strlen(err.message) > strlen(path) + 3);
            assert_null(d.strand.element_lengths);
            rejected++;
        }
    }
    print_message("hairstyle fuzz: %d rejected, %d accepted\n", rejected, accepted);
    assert_true(rejected > 500 && accepted > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thesis_sample),
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_spellings_and_layout),
        cmocka_unit_test(test_groom_keys),
        cmocka_unit_test(test_copy),
        cmocka_unit_test(test_key_errors),
        cmocka_unit_test(test_number_errors),
        cmocka_unit_test(test_range_errors),
        cmocka_unit_test(test_sample_limits),
        cmocka_unit_test(test_files),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
