/* cyHair .hair files (src/io/hair_file.c): byte-exact round trips, files written by
 * other tools (optional arrays absent, default segment counts), and clear errors for
 * truncated or corrupt files. The byte layout in these tests is written out by hand
 * from the format's description (Cem Yuksel's cyHairFile.h), not by our writer. */
#include "hk_test.h"

#include <sys/resource.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/core_internal.h"
#include "hairkit/hairfile.h"

/* Little-endian byte builder. */
typedef struct Bytes {
    unsigned char data[4096];
    size_t n;
} Bytes;

static void put32(Bytes *b, uint32_t v)
{
    for (int i = 0; i < 4; i++) b->data[b->n++] = (unsigned char)(v >> (8 * i));
}
static void putf(Bytes *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put32(b, u);
}
static void put16(Bytes *b, uint16_t v)
{
    b->data[b->n++] = (unsigned char)v;
    b->data[b->n++] = (unsigned char)(v >> 8);
}

static void header(Bytes *b, uint32_t strands, uint32_t points, uint32_t flags, uint32_t def_seg, const char *info)
{
    memcpy(b->data, "HAIR", 4);
    b->n = 4;
    put32(b, strands);
    put32(b, points);
    put32(b, flags);
    put32(b, def_seg);
    putf(b, 0.5f);  /* thickness */
    putf(b, 0.25f); /* transparency */
    putf(b, 0.1f), putf(b, 0.2f), putf(b, 0.3f);
    memset(b->data + b->n, 0, 88);
    memcpy(b->data + b->n, info, strlen(info));
    b->n += 88;
}

static void test_other_tools_file_without_segments(void **state)
{
    (void)state;
    /* Two strands of default 2 segments (3 points), points only: flags 0x2. */
    Bytes b;
    header(&b, 2, 6, 0x2, 2, "made by hand");
    for (int i = 0; i < 18; i++) putf(&b, (float)i * 0.5f);
    hk_HairFile h;
    hk_Error err;
    assert_int_equal(hk_hair_load(hk_test_write_file("noseg.hair", b.data, b.n), &h, &err), HK_OK);
    assert_int_equal(h.strand_count, 2);
    assert_int_equal(hk_hair_strand_points(&h, 0), 3);
    assert_int_equal(hk_hair_strand_points(&h, 1), 3);
    assert_null(h.segments);
    assert_null(h.thickness);
    hk_assert_near(h.points[17], 8.5, 0);
    hk_assert_near(h.default_thickness, 0.5, 0);
    hk_assert_near(h.default_color[2], 0.3f, 0);
    assert_memory_equal(h.info, "made by hand", 12);
    /* Saving it again gives back the same bytes. */
    char path[512];
    snprintf(path, sizeof path, "%s/noseg-again.hair", hk_test_tmpdir());
    assert_int_equal(hk_hair_save(path, &h, &err), HK_OK);
    FILE *f = fopen(path, "rb");
    unsigned char back[4096];
    size_t n = fread(back, 1, sizeof back, f);
    fclose(f);
    assert_int_equal(n, b.n);
    assert_memory_equal(back, b.data, n);
    hk_hair_free(&h);
}

static void test_all_arrays_round_trip(void **state)
{
    (void)state;
    /* Segments 1 and 2 (2 + 3 points) with thickness, transparency and colours. */
    Bytes b;
    header(&b, 2, 5, 0x1F, 0, "all arrays");
    put16(&b, 1), put16(&b, 2);
    for (int i = 0; i < 15; i++) putf(&b, 0.01f * i);
    for (int i = 0; i < 5; i++) putf(&b, 1e-4f * i);
    for (int i = 0; i < 5; i++) putf(&b, 0.1f * i);
    for (int i = 0; i < 15; i++) putf(&b, 0.05f * i);
    const char *p1 = hk_test_write_file("all.hair", b.data, b.n);
    hk_HairFile h;
    hk_Error err;
    assert_int_equal(hk_hair_load(p1, &h, &err), HK_OK);
    assert_int_equal(hk_hair_strand_points(&h, 1), 3);
    hk_assert_near(h.thickness[4], 4e-4f, 0);
    hk_assert_near(h.colors[14], 0.7f, 0);
    /* save -> load -> save is byte-identical. */
    char p2[512], p3[512];
    snprintf(p2, sizeof p2, "%s/all2.hair", hk_test_tmpdir());
    snprintf(p3, sizeof p3, "%s/all3.hair", hk_test_tmpdir());
    assert_int_equal(hk_hair_save(p2, &h, &err), HK_OK);
    hk_HairFile h2;
    assert_int_equal(hk_hair_load(p2, &h2, &err), HK_OK);
    assert_int_equal(hk_hair_save(p3, &h2, &err), HK_OK);
    unsigned char x[4096], y[4096];
    FILE *f = fopen(p2, "rb");
    size_t nx = fread(x, 1, sizeof x, f);
    fclose(f);
    f = fopen(p3, "rb");
    size_t ny = fread(y, 1, sizeof y, f);
    fclose(f);
    assert_int_equal(nx, b.n);
    assert_int_equal(ny, b.n);
    assert_memory_equal(x, b.data, b.n);
    assert_memory_equal(y, b.data, b.n);
    hk_hair_free(&h);
    hk_hair_free(&h2);
}

static void expect_error(const Bytes *b, size_t cut, const char *phrase)
{
    hk_HairFile h;
    hk_Error err;
    const char *path = hk_test_write_file("bad.hair", b->data, cut);
    hk_Status st = hk_hair_load(path, &h, &err);
    assert_true(st == HK_ERR_PARSE);
    hk_assert_contains(err.message, "bad.hair: ");
    hk_assert_contains(err.message, phrase);
    assert_null(h.points);
}

static void test_corrupt_files(void **state)
{
    (void)state;
    Bytes b;
    header(&b, 2, 5, 0x3, 0, "");
    put16(&b, 1), put16(&b, 2);
    for (int i = 0; i < 15; i++) putf(&b, 0.01f * i);
    expect_error(&b, 100, "too short");
    expect_error(&b, b.n - 1, "truncated");
    expect_error(&b, 128, "truncated");
    Bytes c = b;
    memcpy(c.data, "HIAR", 4);
    expect_error(&c, c.n, "no HAIR signature");
    c = b;
    c.data[8] = 6; /* header says 6 points, the segments give 5 (and the size is short) */
    expect_error(&c, c.n, "truncated");
    c = b;
    c.data[8] = 4; /* 4 points announced, segments say 5 */
    expect_error(&c, c.n, "add up to 5 points");
    c = b;
    c.data[12] = 0x1; /* no points array */
    expect_error(&c, c.n, "no points array");
    c = b;
    c.data[12] = 0x43; /* unknown flag */
    expect_error(&c, c.n, "unknown flags");
    c = b;
    c.data[4] = 0xFF, c.data[5] = 0xFF, c.data[6] = 0xFF, c.data[7] = 0x7F; /* 2^31 strands */
    expect_error(&c, c.n, "truncated");
    c = b;
    float nan = NAN;
    memcpy(c.data + 128 + 4 + 8, &nan, 4);
    expect_error(&c, c.n, "non-finite");
    hk_HairFile h;
    hk_Error err;
    assert_int_equal(hk_hair_load(hk_test_tmpdir(), &h, &err), HK_ERR_IO);
}

/* A header that lies about its counts is refused from the header and the file's size
 * alone, at once, with the field that is wrong: 2,147,483,646 strands and 0 points
 * without a segments array made the loader allocate and fill 8.4 GB for 24 s before
 * failing; 0xFFFFFFFF strands said "refusing to allocate 17179869184 bytes". */
static void test_lying_header(void **state)
{
    (void)state;
    Bytes b;
    hk_HairFile h;
    hk_Error err;
    header(&b, 2147483646u, 0, 0x2, 0, "");
    assert_int_equal(b.n, 128);
    /* Refused before any allocation: the process's peak memory does not grow by the
     * gigabytes the counts ask for (a check of memory, not of time, so a busy machine
     * cannot fail it). */
    struct rusage before, after;
    getrusage(RUSAGE_SELF, &before);
    expect_error(&b, b.n,
                 "strand count 2147483646 in the header needs at least 25769803880 bytes but the file has 128");
    getrusage(RUSAGE_SELF, &after);
    assert_true(after.ru_maxrss - before.ru_maxrss < 100 * 1024); /* kilobytes */
    header(&b, 0xFFFFFFFFu, 0, 0x2, 0, "");
    expect_error(&b, b.n, "strand count 4294967295 in the header needs at least");
    header(&b, 0xFFFFFFFFu, 0, 0x3, 0, "");
    expect_error(&b, b.n, "strand count 4294967295 in the header needs at least 60129542258 bytes");
    /* Counts that fit the size but not each other. */
    header(&b, 2, 7, 0x2, 2, ""); /* 2 strands of 3 points are 6 points, not 7 */
    for (int i = 0; i < 21; i++) putf(&b, 0.0f);
    expect_error(&b, b.n, "2 strands of default segment count 2 in the header make 6 points, its point count says 7");
    header(&b, 9, 2, 0x3, 0, "");
    for (int i = 0; i < 9; i++) put16(&b, 0);
    for (int i = 0; i < 40; i++) putf(&b, 0.0f);
    expect_error(&b, b.n, "strand count 9 in the header is more than its point count 2");
    header(&b, 1, 0xFFFFFFFFu, 0x3, 0, "");
    put16(&b, 0);
    for (int i = 0; i < 3; i++) putf(&b, 0.0f);
    expect_error(&b, b.n, "point count 4294967295 in the header needs 51539607670 bytes");
    /* A good file over the memory budget (HAIRKIT_MEMORY_LIMIT): refused before the
     * arrays are allocated, with the need and the limit. */
    header(&b, 2, 6, 0x2, 2, "");
    for (int i = 0; i < 18; i++) putf(&b, 0.5f);
    const char *path = hk_test_write_file("budget.hair", b.data, b.n);
    setenv(HK_MEMORY_LIMIT_ENV, "80", 1);
    assert_int_equal(hk_hair_load(path, &h, &err), HK_ERR_NOMEM);
    hk_assert_contains(err.message, "budget.hair (2 strands, 6 points) would take about 8.4e-08 GB of memory, over "
                                    "the limit of 8e-08 GB");
    assert_null(h.points);
    setenv(HK_MEMORY_LIMIT_ENV, "84", 1); /* 72 bytes of points and 3 offsets of 4 */
    assert_int_equal(hk_hair_load(path, &h, &err), HK_OK);
    hk_hair_free(&h);
    unsetenv(HK_MEMORY_LIMIT_ENV);
    /* hk_hair_index refuses impossible counts before allocating its offsets too. */
    memset(&h, 0, sizeof h);
    h.strand_count = 2147483646u, h.point_count = 0, h.flags = HK_HAIR_POINTS;
    assert_int_equal(hk_hair_index(&h, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "2147483646 strands of default segment count 0 make 2147483646 points");
    assert_null(h.first_point);
}

static void test_alloc_and_info(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Error err;
    const uint32_t counts[3] = {2, 5, 1};
    assert_int_equal(hk_hair_alloc(&h, 3, counts, &err), HK_OK);
    assert_int_equal(h.point_count, 8);
    assert_int_equal(h.first_point[2], 7);
    const char *text = "a very long information string that goes on and on beyond the eighty-eight bytes of the field";
    hk_hair_set_info(&h, text);
    assert_memory_equal(h.info, text, 88); /* truncated to the field */
    hk_hair_set_info(&h, "short");
    assert_memory_equal(h.info, "short\0\0\0", 8); /* NUL-padded */
    hk_hair_free(&h);
    const uint32_t bad[1] = {0};
    assert_int_equal(hk_hair_alloc(&h, 1, bad, &err), HK_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_other_tools_file_without_segments),
        cmocka_unit_test(test_all_arrays_round_trip),
        cmocka_unit_test(test_corrupt_files),
        cmocka_unit_test(test_lying_header),
        cmocka_unit_test(test_alloc_and_info),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
