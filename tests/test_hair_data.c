/* Real grooms made by others (../shared/hair-data, described in its SOURCES.md; never
 * copied into this repository): every file read with the strand and point counts
 * SOURCES.md gives, and its points checked against a second reader: Bangs_100.hair
 * against Bangs_100.data (the same strands in two formats), the TressFX files against a
 * small reader written here from SOURCES.md's layout, Curly_100.ply's strand element
 * against its edge element. Each groom also goes through every writable format and back
 * unchanged. Skipped, saying so, when the folder is absent. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"

static void read_ok(const char *name, hk_HairFile *h)
{
    hk_Error err;
    if (hk_hair_read(hk_test_shared_path(name), HK_HAIR_FORMAT_AUTO, h, &err) != HK_OK)
        fail_msg("%s: %s", name, err.message);
}

static void assert_same(const hk_HairFile *a, const hk_HairFile *b)
{
    assert_int_equal(a->strand_count, b->strand_count);
    assert_int_equal(a->point_count, b->point_count);
    for (uint32_t s = 0; s < a->strand_count; s++)
        assert_int_equal(hk_hair_strand_points(a, s), hk_hair_strand_points(b, s));
    assert_memory_equal(a->points, b->points, 3 * sizeof(float) * a->point_count);
}

/* Writes h in every format (TressFX only when the strands allow) and reads it back. */
static void through_every_format(const hk_HairFile *h)
{
    static const char *const names[] = {"x.hair", "x.data", "x.ply", "x.obj", "x.usda", "x.tfx"};
    char path[600];
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        if (!strcmp(names[i], "x.tfx") && !hk_hair_uniform_strands(h)) continue;
        for (int ascii = 0; ascii < (strcmp(names[i], "x.ply") ? 1 : 2); ascii++) {
            snprintf(path, sizeof path, "%s/%s", hk_test_tmpdir(), names[i]);
            hk_HairWriteDef def = hk_hair_write_defaults();
            def.ascii = ascii;
            hk_Error err;
            hk_HairFile back;
            if (hk_hair_write(path, h, &def, &err) != HK_OK) fail_msg("%s: %s", names[i], err.message);
            if (hk_hair_read(path, HK_HAIR_FORMAT_AUTO, &back, &err) != HK_OK)
                fail_msg("%s: %s", names[i], err.message);
            assert_same(h, &back);
            hk_hair_free(&back);
        }
    }
}

static void test_bangs_hair_and_data(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    hk_HairFile a, b;
    read_ok("Bangs_100.hair", &a);
    read_ok("Bangs_100.data", &b);
    assert_int_equal(a.strand_count, 100);
    assert_int_equal(a.point_count, 1165);
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t s = 0; s < a.strand_count; s++) {
        const uint32_t n = hk_hair_strand_points(&a, s);
        lo = n < lo ? n : lo, hi = n > hi ? n : hi;
    }
    assert_int_equal(lo, 5); /* SOURCES.md: 4..20 segments, 5..21 vertices */
    assert_int_equal(hi, 21);
    assert_same(&a, &b); /* the same strands, bit for bit */
    /* bbox x[11.9, 247.9] y[17.1, 236.9] z[31.8, 204.9]: millimetres */
    float l[3] = {INFINITY, INFINITY, INFINITY}, u[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < a.point_count; i++)
        for (int k = 0; k < 3; k++)
            l[k] = fminf(l[k], a.points[3 * i + (size_t)k]), u[k] = fmaxf(u[k], a.points[3 * i + (size_t)k]);
    hk_assert_near(l[0], 11.9, 0.05), hk_assert_near(u[0], 247.9, 0.05);
    hk_assert_near(l[1], 17.1, 0.05), hk_assert_near(u[1], 236.9, 0.05);
    hk_assert_near(l[2], 31.8, 0.05), hk_assert_near(u[2], 204.9, 0.05);
    through_every_format(&a);
    hk_hair_free(&a);
    hk_hair_free(&b);
}

/* ---- a second reader of Curly_100.ply, from SOURCES.md's description: vertex x, y, z
 * float + r, g, b uchar (15 bytes); strand ushort nsegs; edge int vertex1, vertex2 ---- */
static void test_curly_ply(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    hk_HairFile h;
    read_ok("Curly_100.ply", &h);
    assert_int_equal(h.strand_count, 100);
    assert_int_equal(h.point_count, 2528);
    assert_true(h.flags & HK_HAIR_COLORS);
    size_t size;
    unsigned char *d = (unsigned char *)hk_test_read_file(hk_test_shared_path("Curly_100.ply"), &size);
    const char *end = strstr((const char *)d, "end_header\n");
    assert_non_null(end);
    size_t at = (size_t)(end - (const char *)d) + strlen("end_header\n");
    assert_int_equal(size, at + 2528 * 15 + 100 * 2 + 2428 * 8);
    const unsigned char *vert = d + at, *strand = vert + 2528 * 15, *edge = strand + 200;
    uint32_t first = 0, segs = 0;
    for (uint32_t s = 0; s < 100; s++) {
        const uint32_t nsegs = (uint32_t)(strand[2 * s] | strand[2 * s + 1] << 8);
        assert_int_equal(hk_hair_strand_points(&h, s), nsegs + 1);
        assert_true(nsegs >= 9 && nsegs <= 46);
        assert_int_equal(h.first_point[s], first);
        first += nsegs + 1;
        segs += nsegs;
    }
    assert_int_equal(segs, 2428);
    for (uint32_t i = 0; i < 2528; i++) {
        assert_memory_equal(h.points + 3 * (size_t)i, vert + 15 * (size_t)i, 12); /* little-endian host */
        for (int k = 0; k < 3; k++)
            assert_true(h.colors[3 * i + (uint32_t)k] == (float)vert[15 * i + 12 + (uint32_t)k] / 255.0f);
    }
    /* The edges chain each strand's points, root first. */
    uint32_t e = 0;
    for (uint32_t s = 0; s < 100; s++)
        for (uint32_t p = h.first_point[s]; p + 1 < h.first_point[s + 1]; p++, e++) {
            int32_t a, b;
            memcpy(&a, edge + 8 * e, 4);
            memcpy(&b, edge + 8 * e + 4, 4);
            assert_int_equal(a, p);
            assert_int_equal(b, p + 1);
        }
    /* The edges alone give the same strands: the file with its strand element removed. */
    char *copy = malloc(size);
    const char *strand_line = strstr((const char *)d, "element strand 100\nproperty ushort nsegs\n");
    assert_non_null(strand_line);
    const size_t cut = (size_t)(strand_line - (const char *)d),
                 cut_len = strlen("element strand 100\nproperty ushort nsegs\n");
    memcpy(copy, d, cut);
    memcpy(copy + cut, d + cut + cut_len, at - cut - cut_len);
    size_t n = at - cut_len;
    memcpy(copy + n, vert, 2528 * 15);
    n += 2528 * 15;
    memcpy(copy + n, edge, 2428 * 8);
    n += 2428 * 8;
    hk_HairFile g;
    hk_Error err;
    assert_int_equal(hk_ply_hair_load(hk_test_write_file("curly-edges.ply", copy, n), &g, &err), HK_OK);
    assert_same(&h, &g);
    hk_hair_free(&g);
    free(copy);
    free(d);
    through_every_format(&h);
    hk_hair_free(&h);
}

/* ---- a second reader of TressFX files, from SOURCES.md's layout ---- */
static void check_tfx(const char *name, uint32_t strands, uint32_t verts, float ymin, float ymax)
{
    hk_HairFile h;
    read_ok(name, &h);
    assert_int_equal(h.strand_count, strands);
    assert_int_equal(h.point_count, strands * verts);
    assert_true(hk_hair_uniform_strands(&h));
    assert_int_equal(hk_hair_strand_points(&h, 0), verts);
    size_t size;
    unsigned char *d = (unsigned char *)hk_test_read_file(hk_test_shared_path(name), &size);
    float version;
    uint32_t ns, nv, offset;
    memcpy(&version, d, 4);
    memcpy(&ns, d + 4, 4);
    memcpy(&nv, d + 8, 4);
    const int v3 = version == 3.0f;
    assert_true(v3 || version == 4.0f);
    memcpy(&offset, d + (v3 ? 144 : 12), 4);
    assert_int_equal(offset, v3 ? 296 : 160);
    assert_int_equal(ns, strands);
    assert_int_equal(nv, verts);
    const size_t stride = v3 ? 12 : 16;
    assert_true(offset + (size_t)ns * nv * stride <= size);
    float y0 = INFINITY, y1 = -INFINITY;
    for (size_t i = 0; i < (size_t)ns * nv; i++) {
        assert_memory_equal(h.points + 3 * i, d + offset + stride * i, 12);
        y0 = fminf(y0, h.points[3 * i + 1]), y1 = fmaxf(y1, h.points[3 * i + 1]);
    }
    hk_assert_near(y0, ymin, 0.006 * fabs(ymax - ymin) + 0.01);
    hk_assert_near(y1, ymax, 0.006 * fabs(ymax - ymin) + 0.01);
    free(d);
    if (strands < 5000) through_every_format(&h);
    hk_hair_free(&h);
}

static void test_tressfx(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    check_tfx("SintelHairOriginal-sintel_hair.16points.tfx", 11400, 16, 1.40f, 1.67f);
    check_tfx("Ratboy_mohawk.tfx", 2228, 32, 0.21f, 1.11f);
    check_tfx("tressfx_ponytail/front_top.tfx", 876, 16, 63.2f, 123.6f);
    check_tfx("tressfx_ponytail/side.tfx", 3066, 16, 16.9f, 123.7f);
    check_tfx("tressfx_ponytail/back.tfx", 517, 16, 62.4f, 103.9f);
    check_tfx("tressfx_ponytail/tail.tfx", 474, 16, -3.1f, 83.3f);
    check_tfx("bear.tfx", 48113, 4, -0.8f, 114.1f);
    /* Sintel written back as TressFX 4 gives the file's bytes (w: 0 at the root, 1 after). */
    hk_HairFile h;
    read_ok("SintelHairOriginal-sintel_hair.16points.tfx", &h);
    char path[600];
    snprintf(path, sizeof path, "%s/sintel-again.tfx", hk_test_tmpdir());
    hk_Error err;
    assert_int_equal(hk_hair_write(path, &h, NULL, &err), HK_OK);
    size_t a, b;
    char *x = hk_test_read_file(path, &a),
         *y = hk_test_read_file(hk_test_shared_path("SintelHairOriginal-sintel_hair.16points.tfx"), &b);
    assert_int_equal(a, b);
    assert_memory_equal(x, y, a);
    free(x);
    free(y);
    hk_hair_free(&h);
}

static void test_head_mesh_is_not_hair(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    hk_HairFile h;
    hk_Error err;
    assert_int_equal(hk_hair_read(hk_test_shared_path("Bangs_head.ply"), HK_HAIR_FORMAT_AUTO, &h, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "Bangs_head.ply");
    hk_assert_contains(err.message, "a mesh, not hair strands");
    assert_int_equal(hk_hair_read(hk_test_shared_path("sintel.obj"), HK_HAIR_FORMAT_AUTO, &h, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "sintel.obj: no polylines");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bangs_hair_and_data),
        cmocka_unit_test(test_curly_ply),
        cmocka_unit_test(test_tressfx),
        cmocka_unit_test(test_head_mesh_is_not_hair),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
