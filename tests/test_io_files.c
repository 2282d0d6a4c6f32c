/* Input files (src/io/keyfile.c, hairstyle.c, collision_file.c): the thesis's sample
 * files of Appendix B, tokenising rules, every error class with its file:line message,
 * and a fuzz loop that must never crash, leak or accept garbage silently. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/io.h"
#include "io/keyfile.h"

/* Thesis 004 Appendix B, "Hairstyle Info" (Maxiter spelled as printed). */
static const char *const thesis_hairstyle =
    "##############################\n"
    "## Hairstyle File: Medium Straight ##\n"
    "# Precision\n"
    "VisualityStep   0.0025\n"
    "CollisionStep   0.0050\n"
    "# Minimization\n"
    "Maxiter         5\n"
    "Epsilon         0.0001\n"
    "# Hair Shape\n"
    "HairLengths     0.01 0.01 0.01 0.01 0.01 0.01 0.01 0.01\n"
    "HairDensity     80\n"
    "# Elasticity\n"
    "HairRadius1     0.000035\n"
    "HairRadius2     0.000050\n"
    "HelixRadius     0.050\n"
    "HelixStep       0.050\n"
    "Poisson         0.48\n"
    "Young           1000000000\n"
    "# Gravity\n"
    "Density         13000\n"
    "Gravity         9.81\n";

/* Thesis 004 Appendix B, "Collision Info" ("Elipsoid" as printed), plus the '+'
 * signs of Appendix C's tables. */
static const char *const thesis_collision =
    "# Elipsoid [Volume:1] [Penalty:1] [Centre:3] [Dimensions:3] [Axis:9]\n"
    "# Collision List\n"
    "Elipsoid 0.04 10.00 0.00 0.07 0.01 0.08 0.08 0.11 1 0 0 0 1 0 0 0 1\n"
    "Sphere -0.02 0.01 0.00 0.04 0.16 0.10\n"
    "Ellipsoid 0.00 10.0 -0.001 +0.068 +0.010 0.080 0.080 0.110 1 0 0 0 1 0 0 0 1\n"
    "cuboid 0 1 0 0 0 0.1 0.2 0.3 0 0 2 0 3 0 4 0 0\n";

static void test_thesis_hairstyle(void **state)
{
    (void)state;
    hk_HairstyleDef d;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(hk_test_write_text("hairstyle.txt", thesis_hairstyle), &d, &err), HK_OK);
    hk_assert_near(d.visuality_step, 0.0025, 0);
    hk_assert_near(d.collision_step, 0.005, 0);
    assert_int_equal(d.max_iter, 5);
    hk_assert_near(d.epsilon, 1e-4, 0);
    assert_int_equal(d.element_count, 8);
    hk_assert_near(hk_hairstyle_length(&d), 0.08, 1e-15);
    hk_assert_near(d.hair_density, 80, 0);
    hk_assert_near(d.radius1, 35e-6, 0);
    hk_assert_near(d.radius2, 50e-6, 0);
    hk_assert_near(d.helix_radius, 0.05, 0);
    hk_assert_near(d.helix_step, 0.05, 0);
    hk_assert_near(d.poisson, 0.48, 0);
    hk_assert_near(d.young, 1e9, 0);
    hk_assert_near(d.density, 13000, 0);
    hk_assert_near(d.gravity, 9.81, 0);
    hk_assert_near(d.gravity_dir.y, -1, 0);
    hk_HairstyleDef c;
    assert_int_equal(hk_hairstyle_copy(&d, &c, &err), HK_OK);
    assert_ptr_not_equal(c.element_lengths, d.element_lengths);
    hk_assert_near(c.element_lengths[7], 0.01, 0);
    hk_hairstyle_free(&c);
    hk_hairstyle_free(&d);
    assert_null(d.element_lengths);
}

static void test_defaults_and_spellings(void **state)
{
    (void)state;
    /* Only the required keys, any case, the HairLength alias, CRLF, no final newline,
     * comments after values, GravityDirection normalised. */
    const char *text = "hairlength 0.1 0.1\r\nHAIRRADIUS1 5e-5 # a\r\nhairRadius2 5e-5\r\n"
                       "helixradius 0\r\nHelixStep 0\r\nYOUNG 2e9\r\nGravityDirection 0 0 -2";
    hk_HairstyleDef d;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(hk_test_write_text("minimal.txt", text), &d, &err), HK_OK);
    assert_int_equal(d.element_count, 2);
    hk_assert_near(d.density, 1300, 0);
    hk_assert_near(d.poisson, 0.48, 0);
    assert_int_equal(d.max_iter, 20);
    hk_assert_near(d.gravity_dir.z, -1, 0);
    hk_hairstyle_free(&d);
}

static void test_thesis_collision(void **state)
{
    (void)state;
    hk_Shape *s;
    int n;
    hk_Error err;
    assert_int_equal(hk_collision_load(hk_test_write_text("collision.txt", thesis_collision), &s, &n, &err), HK_OK);
    assert_int_equal(n, 4);
    assert_int_equal(s[0].kind, HK_SHAPE_ELLIPSOID);
    hk_assert_near(s[0].volume, 0.04, 0);
    hk_assert_near(s[0].penalty, 10, 0);
    hk_assert_near(s[0].centre.y, 0.07, 0);
    hk_assert_near(s[0].half.z, 0.11, 0);
    assert_int_equal(s[1].kind, HK_SHAPE_SPHERE);
    hk_assert_near(s[1].volume, -0.02, 0);
    hk_assert_near(s[1].half.x, 0.10, 0);
    hk_assert_near(s[2].centre.y, 0.068, 0);
    assert_int_equal(s[3].kind, HK_SHAPE_CUBOID);
    hk_assert_near(s[3].axis[0].z, 1.0, 0); /* axes normalised */
    hk_assert_near(s[3].axis[1].y, 1.0, 0);
    hk_free(s);
    /* A file of comments only lists no shapes. */
    assert_int_equal(hk_collision_load(hk_test_write_text("none.txt", "# nothing\n\n"), &s, &n, &err), HK_OK);
    assert_int_equal(n, 0);
    assert_null(s);
}

static void test_keyfile_tokens(void **state)
{
    (void)state;
    const char *text = "Path \"my hair/file #1.hair\"  # comment\nValues\t1 2\t3#c\n\n   # only a comment\nFlag yes\n";
    hk_KeyFile kf;
    hk_Error err;
    assert_int_equal(hk_keyfile_read(hk_test_write_text("setup.txt", text), &kf, &err), HK_OK);
    assert_int_equal(kf.line_count, 3);
    assert_string_equal(kf.lines[0].key, "Path");
    assert_int_equal(kf.lines[0].count, 1);
    assert_string_equal(kf.lines[0].values[0], "my hair/file #1.hair");
    assert_int_equal(kf.lines[1].line, 2);
    assert_int_equal(kf.lines[1].count, 3);
    assert_string_equal(kf.lines[1].values[2], "3");
    assert_int_equal(kf.lines[2].line, 5);
    int flag = 0;
    assert_int_equal(hk_keyline_bool(&kf, &kf.lines[2], &flag, &err), HK_OK);
    assert_true(flag);
    char *resolved = hk_keyfile_resolve_path(&kf, "hair/a.hair", &err);
    assert_non_null(resolved);
    assert_true(strstr(resolved, "/hair/a.hair") != NULL && resolved[0] == '/');
    hk_free(resolved);
    char *absolute = hk_keyfile_resolve_path(&kf, "/abs/b.obj", &err);
    assert_string_equal(absolute, "/abs/b.obj");
    hk_free(absolute);
    hk_keyfile_free(&kf);
    assert_int_equal(hk_keyfile_read(hk_test_write_text("quote.txt", "A \"unterminated\n"), &kf, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "quote.txt:1: unterminated");
}

/* Replaces (or appends) the line of `key` in the thesis file with `line`. */
static const char *hairstyle_with(const char *key, const char *line)
{
    static char buf[16384];
    buf[0] = '\0';
    const char *p = thesis_hairstyle;
    int replaced = 0;
    while (*p) {
        const char *nl = strchr(p, '\n');
        size_t len = (size_t)(nl - p) + 1;
        if (!strncmp(p, key, strlen(key)) && p[strlen(key)] == ' ') {
            if (line) strcat(buf, line), strcat(buf, "\n");
            replaced = 1;
        } else {
            strncat(buf, p, len);
        }
        p += len;
    }
    if (!replaced && line) strcat(buf, line), strcat(buf, "\n");
    return hk_test_write_text("hairstyle.txt", buf);
}

static void expect_hairstyle_error(const char *key, const char *line, hk_Status code, const char *where,
                                   const char *phrase)
{
    hk_HairstyleDef d;
    hk_Error err;
    hk_Status st = hk_hairstyle_load(hairstyle_with(key, line), &d, &err);
    if (st != code) print_error("for '%s': status %d, message %s\n", line ? line : key, st, err.message);
    assert_int_equal(st, code);
    hk_assert_contains(err.message, where);
    hk_assert_contains(err.message, phrase);
    assert_null(d.element_lengths); /* nothing to free after an error */
}

static void test_hairstyle_errors(void **state)
{
    (void)state;
    /* The line numbers refer to the thesis file above (Young is on line 18). */
    expect_hairstyle_error("Young", "Young -3", HK_ERR_INVALID, "hairstyle.txt:18:", "Young must be > 0, got -3");
    expect_hairstyle_error("Young", NULL, HK_ERR_PARSE, "hairstyle.txt: ", "missing required key 'Young'");
    expect_hairstyle_error("Foo", "Foo 1", HK_ERR_PARSE, "hairstyle.txt:22:", "unknown key 'Foo'");
    expect_hairstyle_error("Extra", "young 1e9", HK_ERR_PARSE, ":22:", "duplicate key 'Young' (first given at line 18)");
    expect_hairstyle_error("Poisson", "Poisson 0.5", HK_ERR_INVALID, ":17:", "Poisson must be in (-1, 0.5)");
    expect_hairstyle_error("Poisson", "Poisson -1", HK_ERR_INVALID, ":17:", "Poisson");
    expect_hairstyle_error("Density", "Density 1e3x", HK_ERR_PARSE, ":20:", "'1e3x' is not a finite number");
    expect_hairstyle_error("Density", "Density nan", HK_ERR_PARSE, ":20:", "not a finite number");
    expect_hairstyle_error("Density", "Density 0", HK_ERR_INVALID, ":20:", "Density must be > 0");
    expect_hairstyle_error("Gravity", "Gravity 9.81 1", HK_ERR_PARSE, ":21:", "expected 1 number after 'Gravity', got 2");
    expect_hairstyle_error("HairRadius1", "HairRadius1", HK_ERR_PARSE, ":13:", "expected 1 number");
    expect_hairstyle_error("HairRadius2", "HairRadius2 0", HK_ERR_INVALID, ":14:", "HairRadius2 must be in (0, 0.01) m");
    expect_hairstyle_error("HelixRadius", "HelixRadius -0.1", HK_ERR_INVALID, ":15:", "HelixRadius must be >= 0");
    expect_hairstyle_error("HairLengths", "HairLengths 0.01 0 0.02", HK_ERR_INVALID, ":10:", "element length 2");
    expect_hairstyle_error("HairLengths", "HairLengths", HK_ERR_PARSE, ":10:", "at least one number");
    expect_hairstyle_error("Maxiter", "MaxIter 2.5", HK_ERR_PARSE, ":7:", "not a whole number");
    expect_hairstyle_error("Maxiter", "MaxIter 0", HK_ERR_INVALID, ":7:", "MaxIter must be in [1,");
    expect_hairstyle_error("Epsilon", "Epsilon -1", HK_ERR_INVALID, ":8:", "Epsilon must be > 0");
    expect_hairstyle_error("VisualityStep", "VisualityStep 1e-12", HK_ERR_INVALID, ":4:", "VisualityStep 1e-12 gives");
    expect_hairstyle_error("CollisionStep", "CollisionStep 0", HK_ERR_INVALID, ":5:", "CollisionStep must be > 0");
    expect_hairstyle_error("HairDensity", "HairDensity -5", HK_ERR_INVALID, ":11:", "HairDensity");
    expect_hairstyle_error("GravityDirection", "GravityDirection 0 0 0", HK_ERR_INVALID, ":22:", "must not be zero");
    /* Too many elements for HK_MAX_ELEMENTS. */
    char *many = malloc(20 * 1200);
    strcpy(many, "HairLengths");
    for (int i = 0; i < HK_MAX_ELEMENTS + 1; i++) strcat(many, " 0.001");
    expect_hairstyle_error("HairLengths", many, HK_ERR_INVALID, ":10:", "at most 1000 allowed");
    free(many);
}

static void expect_collision_error(const char *text, hk_Status code, const char *where, const char *phrase)
{
    hk_Shape *s = (hk_Shape *)1;
    int n = -1;
    hk_Error err;
    hk_Status st = hk_collision_load(hk_test_write_text("collision.txt", text), &s, &n, &err);
    if (st != code) print_error("for '%s': status %d, message %s\n", text, st, err.message);
    assert_int_equal(st, code);
    hk_assert_contains(err.message, where);
    hk_assert_contains(err.message, phrase);
    assert_null(s);
    assert_int_equal(n, 0);
}

static void test_collision_errors(void **state)
{
    (void)state;
    expect_collision_error("# c\nSphere 0 10 0 0 0\n", HK_ERR_PARSE, "collision.txt:2:", "expected 6 numbers after 'Sphere', got 5");
    expect_collision_error("Sphere 0 10 0 0 0 -1\n", HK_ERR_INVALID, ":1:", "sphere radius must be > 0");
    expect_collision_error("Sphere 0 -1 0 0 0 1\n", HK_ERR_INVALID, ":1:", "Penalty must be >= 0");
    expect_collision_error("Sphere 0 1 0 0 0 1\nBox 1 2\n", HK_ERR_PARSE, ":2:", "unknown shape 'Box'");
    expect_collision_error("Ellipsoid 0 1 0 0 0 1 1 1 1 0 0 1 1 0 0 0 1\n", HK_ERR_INVALID, ":1:", "axes U and V");
    expect_collision_error("Cuboid 0 1 0 0 0 1 1 1 0 0 0 0 1 0 0 0 1\n", HK_ERR_INVALID, ":1:", "axis U of the Cuboid is zero");
    expect_collision_error("Cuboid 0 1 0 0 0 1 0 1 1 0 0 0 1 0 0 0 1\n", HK_ERR_INVALID, ":1:", "dimensions must be > 0");
    expect_collision_error("Sphere 0 1 0 zero 0 1\n", HK_ERR_PARSE, ":1:", "'zero' is not a finite number");
}

static void test_bad_files(void **state)
{
    (void)state;
    hk_HairstyleDef d;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load("/nonexistent/dir/hairstyle.txt", &d, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent/dir/hairstyle.txt: cannot open");
    assert_int_equal(hk_hairstyle_load(hk_test_write_text("empty.txt", ""), &d, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "empty.txt: file is empty");
    const char binary[] = "Young 1\nHair\0\1\2\3";
    assert_int_equal(hk_hairstyle_load(hk_test_write_file("bin.txt", binary, sizeof binary), &d, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "bin.txt: not a text file (binary data at line 2)");
    assert_int_equal(hk_hairstyle_load(hk_test_tmpdir(), &d, &err), HK_ERR_IO); /* a folder */
    /* Larger than the limit: a sparse file, no need to write 16 MiB. */
    char path[512];
    snprintf(path, sizeof path, "%s/huge.txt", hk_test_tmpdir());
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fseek(f, HK_MAX_INPUT_FILE_BYTES + 1, SEEK_SET), 0);
    fputc('\n', f);
    fclose(f);
    assert_int_equal(hk_hairstyle_load(path, &d, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "larger than");
}

/* Mutated copies of the valid files: each load either succeeds with sane values or
 * fails with a message; the sanitizer build checks for crashes and leaks. */
static void test_fuzz(void **state)
{
    (void)state;
    unsigned long long x = 0x2545F4914F6CDD1DULL;
    const char *sources[2] = {thesis_hairstyle, thesis_collision};
    int failures = 0, successes = 0;
    for (int iter = 0; iter < 3000; iter++) {
        const char *src = sources[iter % 2];
        char buf[2048];
        size_t len = strlen(src);
        memcpy(buf, src, len);
        int edits = 1 + (int)(x % 4);
        for (int e = 0; e < edits && len > 0; e++) {
            x ^= x << 13, x ^= x >> 7, x ^= x << 17;
            size_t at = (size_t)(x % len);
            switch ((x >> 20) % 4) {
            case 0: buf[at] = (char)(x >> 32); break;                                  /* any byte */
            case 1: len = at; break;                                                  /* truncate */
            case 2: buf[at] = " \t\n#\"-.e0123456789"[(x >> 40) % 18]; break;           /* plausible */
            default:
                if (len + 8 < sizeof buf) memmove(buf + at + 8, buf + at, len - at), memcpy(buf + at, "1e308 x ", 8), len += 8;
            }
        }
        const char *path = hk_test_write_file(iter % 2 ? "fuzz_collision.txt" : "fuzz_hairstyle.txt", buf, len);
        hk_Error err;
        err.message[0] = '\0';
        hk_Status st;
        if (iter % 2) {
            hk_Shape *s;
            int n;
            st = hk_collision_load(path, &s, &n, &err);
            if (st == HK_OK) {
                for (int i = 0; i < n; i++) assert_true(s[i].half.x > 0 && s[i].penalty >= 0);
                hk_free(s);
            }
        } else {
            hk_HairstyleDef d;
            st = hk_hairstyle_load(path, &d, &err);
            if (st == HK_OK) {
                assert_true(d.element_count >= 1 && d.young > 0 && d.poisson > -1 && d.poisson < 0.5);
                hk_hairstyle_free(&d);
            }
        }
        if (st != HK_OK) {
            assert_true(strlen(err.message) > 0);
            assert_true(strstr(err.message, "fuzz_") != NULL); /* names the file */
            failures++;
        } else {
            successes++;
        }
    }
    print_message("fuzz: %d rejected, %d accepted\n", failures, successes);
    assert_true(failures > 500 && successes > 100);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_thesis_hairstyle),
        cmocka_unit_test(test_defaults_and_spellings),
        cmocka_unit_test(test_thesis_collision),
        cmocka_unit_test(test_keyfile_tokens),
        cmocka_unit_test(test_hairstyle_errors),
        cmocka_unit_test(test_collision_errors),
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_fuzz),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
