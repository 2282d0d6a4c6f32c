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
#include "io/io_internal.h"

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

/* The set load_ok read last (released by the next load_ok or hk_collision_free). */
static hk_CollisionSet loaded;

/* Loads `text`; fails the test unless it succeeds with `want` shapes, which it returns. */
static hk_Shape *load_ok(const char *text, int want)
{
    hk_collision_free(&loaded);
    hk_Error err;
    hk_Status st = hk_collision_load(hk_test_write_text("collision.txt", text), &loaded, &err);
    if (st != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(st, HK_OK);
    assert_int_equal(loaded.count, want);
    if (want == 0) assert_null(loaded.shapes);
    return loaded.shapes;
}

/* A set to be overwritten by the loader: garbage in every field. */
static hk_CollisionSet garbage_set(void)
{
    hk_CollisionSet set;
    memset(&set, 0x5a, sizeof set);
    return set;
}

static void assert_empty(const hk_CollisionSet *set)
{
    assert_null(set->shapes);
    assert_int_equal(set->count, 0);
    assert_null(set->fields);
    assert_int_equal(set->field_count, 0);
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
    hk_collision_free(&loaded);

    s = load_ok(coupe_collision, 2);
    assert_int_equal(s[0].kind, HK_SHAPE_ELLIPSOID);
    assert_vec(s[0].centre, -0.001, 0.068, 0.010, 0);
    hk_assert_near(s[1].volume, 0.15, 0);
    assert_vec(s[1].centre, 0.0, 0.033, 0.165, 0);
    hk_assert_near(s[1].half.x, 0.08, 0);
    hk_collision_free(&loaded);
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
    hk_collision_free(&loaded);

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
    hk_collision_free(&loaded);

    /* Comments and blanks only: valid, no shapes. */
    load_ok("# nothing\n\n   \t\n", 0);
    load_ok("# Collision List\r\n# (none)", 0);
}

/* Loading the file fails with `code` at `line`, with `phrase`, and returns nothing. */
static void expect_error_in(const char *path, hk_Status code, int line, const char *phrase)
{
    hk_CollisionSet set = garbage_set();
    hk_Error err;
    err.message[0] = '\0';
    hk_Status st = hk_collision_load(path, &set, &err);
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
    assert_empty(&set);
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
    hk_collision_free(&loaded);
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
    hk_collision_free(&loaded);
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
                 "unknown shape 'Box' (expected Sphere, Ellipsoid, Cuboid or Mesh)");
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
    load_ok(text, HK_MAX_SHAPES);
    hk_collision_free(&loaded);
    sprintf(p, "%s", line);
    expect_error(text, HK_ERR_INVALID, HK_MAX_SHAPES + 2, "more than 10000 collision shapes");
    free(text);
}

static void test_files(void **state)
{
    (void)state;
    hk_CollisionSet set = garbage_set();
    hk_Error err;
    assert_int_equal(hk_collision_load("/nonexistent/collision.txt", &set, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/collision.txt: cannot open");
    assert_empty(&set);
    expect_error_in(hk_test_write_text("empty.txt", ""), HK_ERR_PARSE, 0, "file is empty");
    static const char bin[] = "Sphere 0 1 0 0 0 1\r\n\x89PNG\r\n\x1a\n";
    expect_error_in(hk_test_write_file("head.png", bin, sizeof bin - 1), HK_ERR_PARSE, 0,
                    "not a text file (binary data at line 3)");
    expect_error_in(hk_test_write_text("hairstyle.txt", "# hairstyle\nYoung 1e9\n"), HK_ERR_PARSE, 2,
                    "unknown shape 'Young'");
    /* A NULL hk_Error is allowed. */
    set = garbage_set();
    assert_int_equal(hk_collision_load(hk_test_write_text("c.txt", "Sphere 0 -1 0 0 0 1\n"), &set, NULL),
                     HK_ERR_INVALID);
    assert_empty(&set);
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
        hk_CollisionSet set = garbage_set();
        hk_Error err;
        err.message[0] = '\0';
        hk_Status st = hk_collision_load(path, &set, &err);
        const hk_Shape *s = set.shapes;
        const int n = set.count;
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
            hk_collision_free(&set);
            accepted++;
        } else {
            assert_true(st == HK_ERR_PARSE || st == HK_ERR_INVALID);
            assert_true(strncmp(err.message, path, strlen(path)) == 0);
            assert_true(strlen(err.message) > strlen(path) + 3);
            assert_empty(&set);
            rejected++;
        }
    }
    print_message("collision fuzz: %d rejected, %d accepted\n", rejected, accepted);
    assert_true(rejected > 500 && accepted > 100);
}

/* A closed tetrahedron of 2 cm (a small collider: its field is quick to build). */
static const char *const tetra_obj = "v 0 0 0\nv 0.02 0 0\nv 0 0.02 0\nv 0 0 0.02\n"
                                     "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

/* Mesh lines (a hairkit addition): the mesh named relative to the collision file,
 * its field a body shape in the line's place; Scale, Up and the role; then every
 * error names the collision file and the line. */
static void test_mesh_lines(void **state)
{
    (void)state;
    hk_test_write_text("tetra.obj", tetra_obj);
    hk_Shape *s = load_ok("Sphere 0 1 0 0 0 1\n"
                          "Mesh 0.01 10 tetra.obj   # relative to this file\n"
                          "mesh -0.002 5 \"tetra.obj\" 10 +z Styling\n"
                          "Cuboid 0 1 0 0 0 1 2 3 1 0 0 0 1 0 0 0 1\n",
                          4);
    assert_int_equal(s[0].kind, HK_SHAPE_SPHERE);
    assert_int_equal(s[1].kind, HK_SHAPE_FIELD);
    assert_int_equal(s[2].kind, HK_SHAPE_FIELD);
    assert_int_equal(s[3].kind, HK_SHAPE_CUBOID);
    assert_int_equal(loaded.field_count, 2);
    assert_ptr_equal(s[1].field, loaded.fields[0]);
    assert_ptr_equal(s[2].field, loaded.fields[1]);
    hk_assert_near(s[1].volume, 0.01, 0);
    hk_assert_near(s[1].penalty, 10.0, 0);
    assert_int_equal(s[1].styling, 0);
    hk_assert_near(s[2].volume, -0.002, 0);
    assert_int_equal(s[2].styling, 1);
    /* inside the tetrahedron near its corner: dent > 0; far away: < 0 */
    assert_true(hk_shape_dent(&s[1], hk_v3(0.002, 0.002, 0.002), NULL, NULL) > 0.0);
    assert_true(hk_shape_dent(&s[1], hk_v3(0.05, 0.05, 0.05), NULL, NULL) < 0.0);
    /* Scale 10 and Up +z: (x, y, z) -> 10 (x, z, -y), the corner (0, 0.02, 0) at
     * (0, 0, -0.2) and (0, 0, 0.02) at (0, 0.2, 0). */
    assert_true(hk_shape_dent(&s[2], hk_v3(0.01, 0.01, -0.01), NULL, NULL) > 0.0);
    assert_true(hk_shape_dent(&s[2], hk_v3(0.01, -0.01, 0.01), NULL, NULL) < 0.0);
    hk_collision_free(&loaded);

    hk_test_write_text("flat.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
    hk_test_write_text("broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    expect_error("Sphere 0 1 0 0 0 1\nMesh 0 10 nowhere.obj\n", HK_ERR_IO, 2, "nowhere.obj: cannot open");
    expect_error("Mesh 0 10 .\n", HK_ERR_IO, 1, "not a regular file");
    expect_error("Mesh 0 10 broken.obj\n", HK_ERR_PARSE, 1, "broken.obj:4: index out of range in face corner '7'");
    expect_error("Mesh 0 10 flat.obj\n", HK_ERR_PARSE, 1, "no faces in this OBJ file");
    hk_test_write_text("flat.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                   "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                                   "end_header\n0 0 0\n1 0 0\n0 1 0\n");
    expect_error("Mesh 0 10 flat.ply\n", HK_ERR_PARSE, 1, "no faces in this PLY file");
    expect_error("Mesh 0 10\n", HK_ERR_PARSE, 1, "expected 'Mesh Volume Penalty PATH [Scale [Up]]");
    expect_error("Mesh 0 10 tetra.obj 1 +y Body extra\n", HK_ERR_PARSE, 1, "got 7 values");
    expect_error("Mesh zero 10 tetra.obj\n", HK_ERR_PARSE, 1, "'zero' is not a finite number (value 1 of 'Mesh')");
    expect_error("Mesh 0 -1 tetra.obj\n", HK_ERR_INVALID, 1, "Penalty must be >= 0, got -1");
    expect_error("Mesh 0 10 tetra.obj 0\n", HK_ERR_INVALID, 1, "Scale must be a number > 0, got '0'");
    expect_error("Mesh 0 10 tetra.obj 1e-3x +z\n", HK_ERR_INVALID, 1, "Scale must be a number > 0, got '1e-3x'");
    expect_error("Mesh 0 10 tetra.obj Stylng\n", HK_ERR_INVALID, 1, "unknown role 'Stylng' after the mesh's path");
    expect_error("Mesh 0 10 tetra.obj 1 up\n", HK_ERR_INVALID, 1, "unknown up axis 'up'");
    /* a mesh that would leave the coordinates hairkit reads */
    expect_error("Mesh 0 10 tetra.obj 1e9\n", HK_ERR_INVALID, 1, "Mesh: ");
    /* a mistake on a later line is told before any field is built */
    expect_error("Mesh 0 10 nowhere.obj\nSphere 0 1 0 0 0\n", HK_ERR_PARSE, 2, "expected 6 numbers");
}

/* A simulation's CollisionHash covers the meshes a collision file names: the file's
 * own fingerprint when it names none, another when a mesh it names changes. */
static void test_mesh_fingerprint(void **state)
{
    (void)state;
    hk_Error err;
    uint64_t plain = 0, with_file = 0, a = 0, b = 0;
    const char *path = hk_test_write_text("plain.txt", "Sphere 0 1 0 0 0 1\n");
    assert_int_equal(hk_collision_fingerprint(path, &plain, &err), HK_OK);
    assert_int_equal(hk_file_fingerprint(path, &with_file, &err), HK_OK);
    assert_true(plain == with_file);
    hk_test_write_text("tetra.obj", tetra_obj);
    path = hk_test_write_text("meshes.txt", "Sphere 0 1 0 0 0 1\nMesh 0 10 tetra.obj\n");
    assert_int_equal(hk_collision_fingerprint(path, &a, &err), HK_OK);
    assert_int_equal(hk_file_fingerprint(path, &with_file, &err), HK_OK);
    assert_true(a != with_file);
    hk_test_write_text("tetra.obj", "# moved\n"); /* the same collision file, another mesh */
    assert_int_equal(hk_collision_fingerprint(path, &b, &err), HK_OK);
    assert_true(a != b);
    path = hk_test_write_text("gone.txt", "Mesh 0 10 gone.obj\n");
    assert_int_equal(hk_collision_fingerprint(path, &b, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "gone.obj: cannot read");
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
        cmocka_unit_test(test_mesh_lines),
        cmocka_unit_test(test_mesh_fingerprint),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
