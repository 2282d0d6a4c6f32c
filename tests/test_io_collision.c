/* Collision Info files (src/io/collision_file.c): the thesis's Appendix B sample and
 * Appendix C's head lines, spellings, every error class with its file:line message,
 * the shape limit, and a fuzz loop. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collide/collide_internal.h"
#include "hairkit/io.h"

/* Lansink 2010 Appendix B, "Collision Info", as printed ("Elipsoid"). */
static const char *const thesis_collision = "\n"
                                            "#######################################\n"
                                            "## Collision File ##\n"
                                            "#######################################\n"
                                            "# Elipsoid [Volume:1] [Penalty:1] [Centre:3] [Dimensions:3] [Axis:9]\n"
                                            "# Cuboid [Volume:1] [Penalty:1] [Centre:3] [Dimensions:3] [Axis:9]\n"
                                            "# Sphere [Volume:1] [Penalty:1] [Centre:3] [Radius:1]\n"
                                            "\n"
                                            "\n"
                                            "# Collision List\n"
                                            "Elipsoid 0.04 10.00 0.00 0.07 0.01 0.08 0.08 0.11 1 0 0 0 1 0 0 0 1\n"
                                            "Sphere -0.02 0.01 0.00 0.04 0.16 0.10\n";

/* Appendix C (Hair Coupe 3): the head and the sphere in front of the face, with the
 * tables' '+' signs. */
static const char *const coupe_collision =
    "Ellipsoid\t0.04\t10.0\t-0.001 +0.068 +0.010\t0.080 0.080 0.110\t1 0 0 0 1 0 0 0 1\n"
    "Sphere\t0.15\t0.01\t+0.000 +0.033 +0.165\t0.080\n";

/* Loads `text`; fails the test unless it succeeds with `want` shapes. */
static hk_Shape *load_ok(const char *text, int want)
{
    hk_Shape *s = NULL;
    int n = -1;
    hk_Error err;
    hk_Status st = hk_collision_load(hk_test_write_text("collision.txt", text), &s, &n, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_int_equal(n, want);
    if (want == 0) assert_null(s);
    return s;
}

static void assert_vec(hk_Vec3 v, double x, double y, double z, double tol)
{
    hk_assert_near(v.x, x, tol);
    hk_assert_near(v.y, y, tol);
    hk_assert_near(v.z, z, tol);
}

static void test_thesis_sample(void **state)
{
    (void)state;
    hk_Shape *s = load_ok(thesis_collision, 2);
    assert_int_equal(s[0].kind, HK_SHAPE_ELLIPSOID);
    hk_assert_near(s[0].volume, 0.04, 0);
    hk_assert_near(s[0].penalty, 10, 0);
    assert_vec(s[0].centre, 0.0, 0.07, 0.01, 0);
    assert_vec(s[0].half, 0.08, 0.08, 0.11, 0);
    assert_vec(s[0].axis[0], 1, 0, 0, 0);
    assert_vec(s[0].axis[1], 0, 1, 0, 0);
    assert_vec(s[0].axis[2], 0, 0, 1, 0);
    hk_assert_near(hk_shape_bound(&s[0]), 0.11, 0); /* built by hk_shape_ellipsoid */
    assert_int_equal(s[1].kind, HK_SHAPE_SPHERE);
    hk_assert_near(s[1].volume, -0.02, 0);
    hk_assert_near(s[1].penalty, 0.01, 0);
    assert_vec(s[1].centre, 0.0, 0.04, 0.16, 0);
    assert_vec(s[1].half, 0.10, 0.10, 0.10, 0);
    assert_vec(s[1].axis[2], 0, 0, 1, 0);
    hk_free(s);

    s = load_ok(coupe_collision, 2);
    assert_int_equal(s[0].kind, HK_SHAPE_ELLIPSOID);
    assert_vec(s[0].centre, -0.001, 0.068, 0.010, 0);
    hk_assert_near(s[1].volume, 0.15, 0);
    assert_vec(s[1].centre, 0.0, 0.033, 0.165, 0);
    hk_assert_near(s[1].half.x, 0.08, 0);
    hk_free(s);
}

static void test_spellings_and_layout(void **state)
{
    (void)state;
    /* Either spelling in any case, CRLF, comments after values, no final line end. */
    const char *text = "# shapes\r\n"
                       "ELIPSOID 0 1 0 0 0 1 2 3 1 0 0 0 1 0 0 0 1 # head\r\n"
                       "ellipsoid 0 1 0 0 0 1 2 3 1 0 0 0 1 0 0 0 1\r\n"
                       "sphere 0 1 0 0 0 1\r\n"
                       "\r\n"
                       "CUBOID -0.5 0 1 2 3 0.1 0.2 0.3 0 0 2 0 3 0 4 0 0";
    hk_Shape *s = load_ok(text, 4);
    assert_int_equal(s[0].kind, HK_SHAPE_ELLIPSOID);
    assert_int_equal(s[1].kind, HK_SHAPE_ELLIPSOID);
    assert_int_equal(s[2].kind, HK_SHAPE_SPHERE);
    assert_int_equal(s[3].kind, HK_SHAPE_CUBOID);
    hk_assert_near(s[3].volume, -0.5, 0); /* may be negative: a shrunken envelope */
    hk_assert_near(s[3].penalty, 0, 0);
    assert_vec(s[3].centre, 1, 2, 3, 0);
    assert_vec(s[3].half, 0.1, 0.2, 0.3, 0);
    /* Axes normalised, in the order given. */
    assert_vec(s[3].axis[0], 0, 0, 1, 0);
    assert_vec(s[3].axis[1], 0, 1, 0, 0);
    assert_vec(s[3].axis[2], 1, 0, 0, 0);
    hk_assert_near(hk_shape_bound(&s[3]), sqrt(0.01 + 0.04 + 0.09), 1e-15);
    hk_free(s);

    /* Tilted axes, slightly off orthogonal but within 1e-3; huge and tiny axes. */
    const double c = cos(0.3), sn = sin(0.3);
    char tilted[512];
    snprintf(tilted, sizeof tilted,
             "Ellipsoid 0 1 0 0 0 1 1 1  %.17g %.17g 0  %.17g %.17g 0.0009  0 0 5\n"
             "Cuboid 0 1 0 0 0 1 1 1  1e300 1e300 0  -1e-300 1e-300 0  0 0 1e-200\n",
             c, sn, -sn, c);
    s = load_ok(tilted, 2);
    assert_vec(s[0].axis[0], c, sn, 0, 1e-15);
    hk_assert_near(hk_v3_norm(s[0].axis[1]), 1, 1e-15);
    assert_vec(s[0].axis[2], 0, 0, 1, 0);
    assert_vec(s[1].axis[0], sqrt(0.5), sqrt(0.5), 0, 1e-15);
    assert_vec(s[1].axis[1], -sqrt(0.5), sqrt(0.5), 0, 1e-15);
    assert_vec(s[1].axis[2], 0, 0, 1, 0);
    hk_free(s);

    /* Comments and blanks only: valid, no shapes. */
    load_ok("# nothing\n\n   \t\n", 0);
    load_ok("# Collision List\r\n# (none)", 0);
}

/* Loading the file fails with `code` at `line`, with `phrase`, and returns nothing. */
static void expect_error_in(const char *path, hk_Status code, int line, const char *phrase)
{
    hk_Shape *s = (hk_Shape *)&s; /* garbage the loader must overwrite */
    int n = -1;
    hk_Error err;
    err.message[0] = '\0';
    hk_Status st = hk_collision_load(path, &s, &n, &err);
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
    assert_null(s);
    assert_int_equal(n, 0);
}

static void expect_error(const char *text, hk_Status code, int line, const char *phrase)
{
    expect_error_in(hk_test_write_text("collision.txt", text), code, line, phrase);
}

/* The optional role after the numbers: Body (the default, also of the thesis's files)
 * or Styling, any case; a misspelt role is named. */
static void test_roles(void **state)
{
    (void)state;
    hk_Shape *s = load_ok(thesis_collision, 2);
    assert_int_equal(s[0].styling, 0);
    assert_int_equal(s[1].styling, 0);
    hk_free(s);
    s = load_ok("Ellipsoid 0.01 10 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1 Body\n"
                "Sphere 0.05 0.01 0 0.04 0.15 0.095 Styling # before the face\n"
                "cuboid 0 1 0 0 0 1 2 3 1 0 0 0 1 0 0 0 1 STYLING\n"
                "sphere 0 1 0 0 0 1 body\n",
                4);
    assert_int_equal(s[0].styling, 0);
    assert_int_equal(s[1].styling, 1);
    hk_assert_near(s[1].half.x, 0.095, 0);
    assert_int_equal(s[2].styling, 1);
    assert_int_equal(s[2].kind, HK_SHAPE_CUBOID);
    assert_int_equal(s[3].styling, 0);
    hk_free(s);
    expect_error("Sphere 0 1 0 0 0 1 Style\n", HK_ERR_PARSE, 1,
                 "unknown role 'Style' after the Sphere's numbers (expected Body or Styling)");
    /* A role does not stand in for a missing number. */
    expect_error("Sphere 0 1 0 0 0 Styling\n", HK_ERR_PARSE, 1,
                 "'Styling' is not a finite number (value 6 of 'Sphere')");
    expect_error("Sphere 0 1 0 0 0 1 Styling Body\n", HK_ERR_PARSE, 1, "expected 6 numbers after 'Sphere', got 8");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1 1e-3\n", HK_ERR_PARSE, 1,
                 "expected 17 numbers after 'Cuboid', got 18");
}

static void test_count_and_number_errors(void **state)
{
    (void)state;
    expect_error("# c\nSphere 0 10 0 0 0\n", HK_ERR_PARSE, 2, "expected 6 numbers after 'Sphere', got 5");
    expect_error("Sphere 0 10 0 0 0 1 2\n", HK_ERR_PARSE, 1, "expected 6 numbers after 'Sphere', got 7");
    expect_error("Sphere\n", HK_ERR_PARSE, 1, "expected 6 numbers after 'Sphere', got 0");
    expect_error("Sphere 0 1 0 0 0 1\nElipsoid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 0\n", HK_ERR_PARSE, 2,
                 "expected 17 numbers after 'Elipsoid', got 16");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1 0\n", HK_ERR_PARSE, 1,
                 "expected 17 numbers after 'Cuboid', got 18");
    /* The thesis's table notation "100010001" is not nine numbers. */
    expect_error("Ellipsoid 0.00 10.0 -0.001 +0.068 +0.010 0.080 0.080 0.110 100010001\n", HK_ERR_PARSE, 1,
                 "expected 17 numbers after 'Ellipsoid', got 9");
    expect_error("Sphere 0 1 0 zero 0 1\n", HK_ERR_PARSE, 1, "'zero' is not a finite number (value 4 of 'Sphere')");
    expect_error("Sphere 0 1 0 0 0 1.0abc\n", HK_ERR_PARSE, 1, "'1.0abc' is not a finite number (value 6");
    expect_error("Sphere 0 1 0 0 0 N/A\n", HK_ERR_PARSE, 1, "'N/A' is not a finite number");
    expect_error("Sphere nan 1 0 0 0 1\n", HK_ERR_PARSE, 1, "'nan' is not a finite number (value 1");
    expect_error("Sphere inf 1 0 0 0 1\n", HK_ERR_PARSE, 1, "'inf' is not a finite number");
    expect_error("Sphere 0 1 0 0 0 1e999\n", HK_ERR_PARSE, 1, "'1e999' is out of the range");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 0 -inf\n", HK_ERR_PARSE, 1,
                 "'-inf' is not a finite number (value 17");
    expect_error("Sphere 0 1 0 0 0 1\nBox 1 2\n", HK_ERR_PARSE, 2,
                 "unknown shape 'Box' (expected Sphere, Ellipsoid or Cuboid)");
    expect_error("Spheres 0 1 0 0 0 1\n", HK_ERR_PARSE, 1, "unknown shape 'Spheres'");
    expect_error("Young 1e9\n", HK_ERR_PARSE, 1, "unknown shape 'Young'");
}

static void test_range_errors(void **state)
{
    (void)state;
    expect_error("Sphere 0 -1 0 0 0 1\n", HK_ERR_INVALID, 1, "Penalty must be >= 0, got -1");
    expect_error("Ellipsoid 0 -0.5 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1\n", HK_ERR_INVALID, 1,
                 "Penalty must be >= 0, got -0.5");
    expect_error("Sphere 0 10 0 0 0 -1\n", HK_ERR_INVALID, 1, "sphere radius must be > 0, got -1");
    expect_error("\nSphere 0 10 0 0 0 0\n", HK_ERR_INVALID, 2, "sphere radius must be > 0, got 0");
    static const char *const dims[] = {"0 1 1", "1 0 1", "1 1 0", "1 1 -2"};
    for (int i = 0; i < 4; i++) {
        char text[128], phrase[64];
        snprintf(text, sizeof text, "Cuboid 0 1 0 0 0 %s 1 0 0 0 1 0 0 0 1\n", dims[i]);
        snprintf(phrase, sizeof phrase, "Cuboid dimensions must be > 0, got %s", dims[i]);
        expect_error(text, HK_ERR_INVALID, 1, phrase);
        snprintf(text, sizeof text, "Elipsoid 0 1 0 0 0 %s 1 0 0 0 1 0 0 0 1\n", dims[i]);
        snprintf(phrase, sizeof phrase, "Elipsoid dimensions must be > 0, got %s", dims[i]);
        expect_error(text, HK_ERR_INVALID, 1, phrase);
    }
    /* Zero axes, named. */
    expect_error("Cuboid 0 1 0 0 0 1 1 1 0 0 0 0 1 0 0 0 1\n", HK_ERR_INVALID, 1, "axis U of the Cuboid is zero");
    expect_error("Ellipsoid 0 1 0 0 0 1 1 1 1 0 0 0 0 0 0 0 1\n", HK_ERR_INVALID, 1, "axis V of the Ellipsoid is zero");
    expect_error("Ellipsoid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 -0 0.0 0e9\n", HK_ERR_INVALID, 1,
                 "axis W of the Ellipsoid is zero");
    /* Axes that are not orthogonal, each pair, named. */
    expect_error("Ellipsoid 0 1 0 0 0 1 1 1 1 0 0 1 1 0 0 0 1\n", HK_ERR_INVALID, 1,
                 "axes U and V of the Ellipsoid are not orthogonal (cosine 0.707");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 1 0 0\n", HK_ERR_INVALID, 1,
                 "axes U and W of the Cuboid are not orthogonal");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 -1 1\n", HK_ERR_INVALID, 1,
                 "axes V and W of the Cuboid are not orthogonal");
    expect_error("Cuboid 0 1 0 0 0 1 1 1 1 0 0 1 0 0 0 0 1\n", HK_ERR_INVALID, 1,
                 "axes U and V of the Cuboid are not orthogonal (cosine 1");
    /* Just outside the 1e-3 tolerance (cosine 0.0011 after normalisation). */
    expect_error("Ellipsoid 0 1 0 0 0 1 1 1 1 0 0 0.0011 1 0 0 0 1\n", HK_ERR_INVALID, 1, "axes U and V");
    /* The error names the offending line, not the first shape. */
    expect_error("Sphere 0 1 0 0 0 1\nSphere 0 1 0 0 0 1\n# c\nCuboid 0 1 0 0 0 1 1 1 1 1 0 0 1 0 0 0 1\n",
                 HK_ERR_INVALID, 4, "axes U and V");
}

/* HK_MAX_SHAPES shapes are fine; one more is refused at the first line too many. */
static void test_shape_limit(void **state)
{
    (void)state;
    const char *line = "Sphere 0 1 0 0 0 1\n";
    const size_t ll = strlen(line);
    char *text = malloc((HK_MAX_SHAPES + 2) * ll + 32);
    assert_non_null(text);
    char *p = text;
    p += sprintf(p, "# many\n");
    for (int i = 0; i < HK_MAX_SHAPES; i++) p += sprintf(p, "%s", line);
    hk_Shape *s = load_ok(text, HK_MAX_SHAPES);
    hk_free(s);
    sprintf(p, "%s", line);
    expect_error(text, HK_ERR_INVALID, HK_MAX_SHAPES + 2, "more than 10000 collision shapes");
    free(text);
}

static void test_files(void **state)
{
    (void)state;
    hk_Shape *s = (hk_Shape *)&s;
    int n = -1;
    hk_Error err;
    assert_int_equal(hk_collision_load("/nonexistent/collision.txt", &s, &n, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/collision.txt: cannot open");
    assert_null(s);
    assert_int_equal(n, 0);
    expect_error_in(hk_test_write_text("empty.txt", ""), HK_ERR_PARSE, 0, "file is empty");
    static const char bin[] = "Sphere 0 1 0 0 0 1\r\n\x89PNG\r\n\x1a\n";
    expect_error_in(hk_test_write_file("head.png", bin, sizeof bin - 1), HK_ERR_PARSE, 0,
                    "not a text file (binary data at line 3)");
    expect_error_in(hk_test_write_text("hairstyle.txt", "# hairstyle\nYoung 1e9\n"), HK_ERR_PARSE, 2,
                    "unknown shape 'Young'");
    /* A NULL hk_Error is allowed. */
    assert_int_equal(hk_collision_load(hk_test_write_text("c.txt", "Sphere 0 -1 0 0 0 1\n"), &s, &n, NULL),
                     HK_ERR_INVALID);
    assert_null(s);
}

/* Mutated copies of the sample: loads never crash, accepted shapes are sane, refusals
 * name the file. */
static void test_fuzz(void **state)
{
    (void)state;
    char base[1024];
    snprintf(base, sizeof base, "%s%sCuboid 0 1 0 0 0 1 1 1 1 0 0 0 1 0 0 0 1\n", thesis_collision, coupe_collision);
    static const char *const junk[12] = {"1e308 ",  "-",     "nan", "\"",        "#",    "\r\n",
                                         "Sphere ", "0x1p3", "\t",  "Elipsoid ", " 0 0", "99e999"};
    unsigned long long x = 0xD1B54A32D192ED03ULL;
    int rejected = 0, accepted = 0;
    for (int iter = 0; iter < 2000; iter++) {
        char buf[2048];
        size_t len = strlen(base);
        memcpy(buf, base, len);
        int edits = 1 + iter % 4;
        for (int e = 0; e < edits; e++)
            len = hk_test_mutate(buf, len, sizeof buf, " \t\n#\"-.e0123456789", junk, 12, &x);
        const char *path = hk_test_write_file("fuzz_collision.txt", buf, len);
        hk_Shape *s = (hk_Shape *)&s;
        int n = -1;
        hk_Error err;
        err.message[0] = '\0';
        hk_Status st = hk_collision_load(path, &s, &n, &err);
        if (st == HK_OK) {
            assert_true(n >= 0 && n <= HK_MAX_SHAPES);
            for (int i = 0; i < n; i++) {
                assert_true(isfinite(s[i].volume) && s[i].penalty >= 0 && isfinite(s[i].penalty));
                assert_true(s[i].half.x > 0 && s[i].half.y > 0 && s[i].half.z > 0);
                assert_true(isfinite(hk_shape_bound(&s[i])));
                for (int a = 0; a < 3; a++) {
                    hk_assert_near(hk_v3_norm(s[i].axis[a]), 1.0, 1e-12);
                    for (int b = a + 1; b < 3; b++) assert_true(fabs(hk_v3_dot(s[i].axis[a], s[i].axis[b])) <= 1e-3);
                }
            }
            hk_free(s);
            accepted++;
        } else {
            assert_true(st == HK_ERR_PARSE || st == HK_ERR_INVALID);
            assert_true(strncmp(err.message, path, strlen(path)) == 0);
            assert_true(strlen(err.message) > strlen(path) + 3);
            assert_null(s);
            assert_int_equal(n, 0);
            rejected++;
        }
    }
    print_message("collision fuzz: %d rejected, %d accepted\n", rejected, accepted);
    assert_true(rejected > 500 && accepted > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thesis_sample),
        cmocka_unit_test(test_spellings_and_layout),
        cmocka_unit_test(test_count_and_number_errors),
        cmocka_unit_test(test_range_errors),
        cmocka_unit_test(test_shape_limit),
        cmocka_unit_test(test_files),
        cmocka_unit_test(test_fuzz),
        cmocka_unit_test(test_roles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
