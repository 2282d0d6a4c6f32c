/* Hair file formats (hairkit/hair_formats.h, src/io/hair_*.c): a round trip through every
 * format gives the same float32 bits and strand counts; TressFX resampling by arc length;
 * PLY edges chained into strands; OBJ polylines; the USD subset; the up-axis rotations
 * and scaling; malformed, truncated and lying files refused with the file named. Files
 * of other tools in these tests are written out by hand from the formats' descriptions,
 * not by our writers. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"

static const char *tmp_path(const char *name)
{
    static char buf[8][512];
    static int slot;
    char *p = buf[slot++ % 8];
    snprintf(p, 512, "%s/%s", hk_test_tmpdir(), name);
    return p;
}

static double uniform(double a, double b) { return a + (b - a) * hk_test_uniform(); }

/* A groom of `n` strands with 2..40 points (or exactly `fixed` points when non-zero),
 * coordinates spanning many binades plus a few awkward floats. */
static void make_hair(hk_HairFile *h, uint32_t n, uint32_t fixed)
{
    uint32_t *counts = malloc(n * sizeof *counts);
    for (uint32_t s = 0; s < n; s++) counts[s] = fixed ? fixed : 2 + (uint32_t)(hk_test_uniform() * 39);
    hk_Error err;
    assert_int_equal(hk_hair_alloc(h, n, counts, &err), HK_OK);
    free(counts);
    for (size_t i = 0; i < 3 * (size_t)h->point_count; i++) {
        double v = uniform(-1.0, 1.0) * pow(10.0, uniform(-6.0, 3.0));
        h->points[i] = (float)v;
    }
    if (h->point_count >= 8) {
        h->points[0] = 0.1f;
        h->points[1] = -0.0f;
        h->points[2] = 1e-40f; /* denormal */
        h->points[3] = 3.4e38f;
        h->points[4] = -1.17549435e-38f;
        h->points[5] = 16777217.0f;
        h->points[6] = 1.0f / 3.0f;
        h->points[7] = 123456.789f;
    }
}

static void assert_same_strands(const hk_HairFile *a, const hk_HairFile *b)
{
    assert_int_equal(a->strand_count, b->strand_count);
    assert_int_equal(a->point_count, b->point_count);
    for (uint32_t s = 0; s < a->strand_count; s++)
        assert_int_equal(hk_hair_strand_points(a, s), hk_hair_strand_points(b, s));
    assert_memory_equal(a->points, b->points, 3 * sizeof(float) * a->point_count);
}

static void round_trip(const hk_HairFile *h, const char *name, hk_HairFormat format, int ascii)
{
    hk_HairWriteDef def = hk_hair_write_defaults();
    def.ascii = ascii;
    hk_Error err;
    const char *path = tmp_path(name);
    if (hk_hair_write(path, h, &def, &err) != HK_OK) fail_msg("writing %s: %s", name, err.message);
    hk_HairFile back;
    if (hk_hair_read(path, HK_HAIR_FORMAT_AUTO, &back, &err) != HK_OK) fail_msg("reading %s: %s", name, err.message);
    assert_same_strands(h, &back);
    hk_hair_free(&back);
    /* The format named explicitly whatever the extension. */
    char other[600];
    snprintf(other, sizeof other, "%s.bin", path);
    def.format = format;
    assert_int_equal(hk_hair_write(other, h, &def, &err), HK_OK);
    assert_int_equal(hk_hair_read(other, format, &back, &err), HK_OK);
    assert_same_strands(h, &back);
    hk_hair_free(&back);
    remove(other);
}

static void test_round_trip_every_format(void **state)
{
    (void)state;
    hk_HairFile h;
    make_hair(&h, 57, 0);
    round_trip(&h, "rt.hair", HK_HAIR_FORMAT_CYHAIR, 0);
    round_trip(&h, "rt.data", HK_HAIR_FORMAT_USC, 0);
    round_trip(&h, "rt.ply", HK_HAIR_FORMAT_PLY, 0);
    round_trip(&h, "rt-ascii.ply", HK_HAIR_FORMAT_PLY, 1);
    round_trip(&h, "rt.obj", HK_HAIR_FORMAT_OBJ, 0);
    round_trip(&h, "rt.usda", HK_HAIR_FORMAT_USDA, 0);
    hk_hair_free(&h);
    /* TressFX: the same count in every strand. */
    make_hair(&h, 33, 16);
    round_trip(&h, "rt.tfx", HK_HAIR_FORMAT_TFX, 0);
    hk_hair_free(&h);
    /* One-point strands and an empty groom where the format allows them. */
    uint32_t counts[3] = {1, 5, 1};
    hk_Error err;
    assert_int_equal(hk_hair_alloc(&h, 3, counts, &err), HK_OK);
    for (size_t i = 0; i < 21; i++) h.points[i] = (float)i * 0.25f;
    round_trip(&h, "one.hair", HK_HAIR_FORMAT_CYHAIR, 0);
    round_trip(&h, "one.data", HK_HAIR_FORMAT_USC, 0);
    round_trip(&h, "one.ply", HK_HAIR_FORMAT_PLY, 0);
    round_trip(&h, "one-ascii.ply", HK_HAIR_FORMAT_PLY, 1);
    round_trip(&h, "one.obj", HK_HAIR_FORMAT_OBJ, 0);
    round_trip(&h, "one.usda", HK_HAIR_FORMAT_USDA, 0);
    hk_hair_free(&h);
}

static void test_text_is_shortest_and_exact(void **state)
{
    (void)state;
    uint32_t counts[1] = {2};
    hk_HairFile h;
    hk_Error err;
    assert_int_equal(hk_hair_alloc(&h, 1, counts, &err), HK_OK);
    const float v[6] = {0.1f, 1.5f, -2.0f, 1e-7f, 0.3f, 100.0f};
    memcpy(h.points, v, sizeof v);
    const char *path = tmp_path("short.obj");
    assert_int_equal(hk_obj_hair_save(path, &h, &err), HK_OK);
    size_t n;
    char *text = hk_test_read_file(path, &n);
    hk_assert_contains(text, "v 0.1 1.5 -2\n");
    hk_assert_contains(text, "v 1e-07 0.3 100\n");
    hk_assert_contains(text, "l 1 2\n");
    free(text);
    hk_hair_free(&h);
}

static void test_ply_colours_and_usd_widths(void **state)
{
    (void)state;
    hk_HairFile h, back;
    hk_Error err;
    make_hair(&h, 5, 0);
    h.colors = malloc(3 * sizeof(float) * h.point_count);
    h.flags |= HK_HAIR_COLORS;
    for (size_t i = 0; i < 3 * (size_t)h.point_count; i++) h.colors[i] = (float)(i % 256) / 255.0f;
    for (int ascii = 0; ascii < 2; ascii++) {
        const char *path = tmp_path(ascii ? "colours-ascii.ply" : "colours.ply");
        assert_int_equal(hk_ply_hair_save(path, &h, ascii, &err), HK_OK);
        assert_int_equal(hk_ply_hair_load(path, &back, &err), HK_OK);
        assert_true(back.flags & HK_HAIR_COLORS);
        assert_memory_equal(back.colors, h.colors, 3 * sizeof(float) * h.point_count);
        hk_hair_free(&back);
    }
    /* USD: per-vertex widths are the thickness array; a constant width the default. */
    h.thickness = malloc(sizeof(float) * h.point_count);
    h.flags |= HK_HAIR_THICKNESS;
    for (size_t i = 0; i < h.point_count; i++) h.thickness[i] = 7e-5f * (float)(1 + i % 3);
    const char *path = tmp_path("widths.usda");
    assert_int_equal(hk_usda_hair_save(path, &h, 1.0, &err), HK_OK);
    assert_int_equal(hk_usda_hair_load(path, &back, &err), HK_OK);
    assert_true(back.flags & HK_HAIR_THICKNESS);
    assert_memory_equal(back.thickness, h.thickness, sizeof(float) * h.point_count);
    hk_hair_free(&back);
    h.flags &= ~HK_HAIR_THICKNESS;
    h.default_thickness = 8e-5f;
    assert_int_equal(hk_usda_hair_save(path, &h, 1.0, &err), HK_OK);
    size_t n;
    char *text = hk_test_read_file(path, &n);
    hk_assert_contains(text, "upAxis = \"Y\"");
    hk_assert_contains(text, "metersPerUnit = 1\n");
    hk_assert_contains(text, "def BasisCurves \"hair\"");
    hk_assert_contains(text, "uniform token type = \"linear\"");
    hk_assert_contains(text, "float[] widths = [8e-05] (\n        interpolation = \"constant\"");
    free(text);
    assert_int_equal(hk_usda_hair_load(path, &back, &err), HK_OK);
    assert_null(back.thickness);
    assert_true(back.default_thickness == 8e-5f);
    hk_hair_free(&back);
    /* metersPerUnit 0.01: the points come back in metres. */
    assert_int_equal(hk_usda_hair_save(path, &h, 0.01, &err), HK_OK);
    assert_int_equal(hk_usda_hair_load(path, &back, &err), HK_OK);
    for (size_t i = 0; i < 3 * (size_t)h.point_count; i++)
        assert_true(back.points[i] == (float)((double)h.points[i] * 0.01));
    hk_hair_free(&back);
    hk_hair_free(&h);
}

/* Arc length of the polyline p[0..n) up to the point q, which lies on it; -1 if not. */
static double arc_position(const float *p, uint32_t n, const float *q, double tol)
{
    double s = 0.0;
    for (uint32_t i = 0; i + 1 < n; i++) {
        const float *a = p + 3 * i, *b = a + 3;
        double ab[3], aq[3], len2 = 0.0, t = 0.0;
        for (int k = 0; k < 3; k++) ab[k] = (double)b[k] - a[k], aq[k] = (double)q[k] - a[k], len2 += ab[k] * ab[k];
        if (len2 > 0.0) t = (ab[0] * aq[0] + ab[1] * aq[1] + ab[2] * aq[2]) / len2;
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) d2 += pow(aq[k] - t * ab[k], 2);
        if (t >= -1e-9 && t <= 1 + 1e-9 && d2 <= tol * tol) return s + t * sqrt(len2);
        s += sqrt(len2);
    }
    return -1.0;
}

static void test_tfx_resampling(void **state)
{
    (void)state;
    hk_HairFile h, back;
    hk_Error err;
    make_hair(&h, 40, 0);
    /* Strands of moderate size: a random walk. */
    for (uint32_t s = 0; s < h.strand_count; s++)
        for (uint32_t i = h.first_point[s]; i < h.first_point[s + 1]; i++)
            for (int k = 0; k < 3; k++)
                h.points[3 * i + (uint32_t)k] = i == h.first_point[s]
                                                    ? (float)uniform(-0.1, 0.1)
                                                    : h.points[3 * (i - 1) + (uint32_t)k] + (float)uniform(-0.01, 0.01);
    const char *path = tmp_path("resample.tfx");
    /* Strands of different counts and no count given: refused, saying what to do. */
    assert_int_equal(hk_tfx_save(path, &h, 0, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "resample.tfx");
    hk_assert_contains(err.message, "same number of points");
    hk_assert_contains(err.message, "--points");
    hk_HairWriteDef def = hk_hair_write_defaults();
    assert_int_equal(hk_hair_write(path, &h, &def, &err), HK_ERR_INVALID);
    def.points = 12;
    assert_int_equal(hk_hair_write(path, &h, &def, &err), HK_OK);
    assert_int_equal(hk_tfx_load(path, &back, &err), HK_OK);
    assert_int_equal(back.strand_count, h.strand_count);
    assert_int_equal(back.point_count, 12 * h.strand_count);
    for (uint32_t s = 0; s < h.strand_count; s++) {
        const float *p = h.points + 3 * (size_t)h.first_point[s];
        const uint32_t n = hk_hair_strand_points(&h, s);
        const float *q = back.points + 3 * (size_t)back.first_point[s];
        double length = 0.0;
        for (uint32_t i = 1; i < n; i++)
            length += sqrt(pow((double)p[3 * i] - p[3 * i - 3], 2) + pow((double)p[3 * i + 1] - p[3 * i - 2], 2) +
                           pow((double)p[3 * i + 2] - p[3 * i - 1], 2));
        if (n == 12) { /* already 12 points: kept exactly */
            assert_memory_equal(q, p, 12 * 3 * sizeof(float));
            continue;
        }
        assert_memory_equal(q, p, 3 * sizeof(float));                            /* the root */
        assert_memory_equal(q + 33, p + 3 * (size_t)(n - 1), 3 * sizeof(float)); /* the tip */
        for (uint32_t k = 0; k < 12; k++) {
            const double at = arc_position(p, n, q + 3 * k, 1e-6);
            assert_true(at >= 0.0);
            hk_assert_near(at, length * k / 11.0, 2e-6);
        }
    }
    hk_hair_free(&back);
    /* Uniform strands with another count given are resampled too. */
    hk_HairFile u;
    make_hair(&u, 3, 4);
    assert_int_equal(hk_tfx_save(path, &u, 7, &err), HK_OK);
    assert_int_equal(hk_tfx_load(path, &back, &err), HK_OK);
    assert_int_equal(back.point_count, 21);
    hk_hair_free(&back);
    hk_hair_free(&u);
    /* A strand of zero length repeats its root. */
    uint32_t one[2] = {1, 3};
    assert_int_equal(hk_hair_alloc(&u, 2, one, &err), HK_OK);
    for (size_t i = 0; i < 12; i++) u.points[i] = 0.5f;
    assert_int_equal(hk_hair_resample(&u, 4, &back, &err), HK_OK);
    for (size_t i = 0; i < 24; i++) assert_true(back.points[i] == 0.5f);
    hk_hair_free(&back);
    assert_int_equal(hk_hair_resample(&u, 1, &back, &err), HK_ERR_INVALID);
    hk_hair_free(&u);
    hk_hair_free(&h);
}

static void test_up_axis_and_scale(void **state)
{
    (void)state;
    uint32_t counts[1] = {4};
    hk_HairFile h;
    hk_Error err;
    for (int a = 0; a < 6; a++) {
        assert_int_equal(hk_hair_alloc(&h, 1, counts, &err), HK_OK);
        /* the up axis, then x, y and z */
        const float in[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        memcpy(h.points, in, sizeof in);
        const float up[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        memcpy(h.points, up[a], sizeof up[a]);
        hk_hair_up_to_y(&h, (hk_Axis)a);
        /* the named axis onto +y */
        assert_true(h.points[0] == 0.0f && h.points[1] == 1.0f && h.points[2] == 0.0f);
        /* a rotation: the images of x, y, z are orthonormal and right-handed */
        const float *x = h.points + 3, *y = h.points + 6, *z = h.points + 9;
        const float c[3] = {x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
        for (int k = 0; k < 3; k++) assert_true(c[k] == z[k]);
        /* the smallest rotation: the angle is 90 degrees (trace 1) but 180 for -y, 0 for +y */
        const double trace = (double)x[0] + y[1] + z[2];
        hk_assert_near(trace, a == HK_AXIS_POS_Y ? 3.0 : a == HK_AXIS_NEG_Y ? -1.0 : 1.0, 0);
        hk_hair_free(&h);
    }
    assert_int_equal(hk_axis_from_name("+x"), HK_AXIS_POS_X);
    assert_int_equal(hk_axis_from_name("-Z"), HK_AXIS_NEG_Z);
    assert_int_equal(hk_axis_from_name("y"), HK_AXIS_POS_Y);
    assert_int_equal(hk_axis_from_name("up"), -1);
    assert_int_equal(hk_axis_from_name("+w"), -1);
    assert_string_equal(hk_axis_name(HK_AXIS_NEG_Y), "-y");

    make_hair(&h, 4, 0);
    h.thickness = malloc(sizeof(float) * h.point_count);
    h.flags |= HK_HAIR_THICKNESS;
    for (size_t i = 0; i < h.point_count; i++) h.thickness[i] = 2.0f;
    h.default_thickness = 1.0f;
    h.points[3] = 237.0f; /* no overflow from the 3.4e38 of make_hair with 0.001 */
    const float before = h.points[9];
    assert_int_equal(hk_hair_scale(&h, 0.001, &err), HK_OK);
    assert_true(h.points[9] == (float)((double)before * 0.001));
    assert_true(h.points[3] == (float)(237.0 * 0.001));
    assert_true(h.thickness[0] == (float)0.002);
    assert_true(h.default_thickness == (float)0.001);
    assert_int_equal(hk_hair_scale(&h, 0.0, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_scale(&h, -1.0, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_scale(&h, NAN, &err), HK_ERR_INVALID);
    hk_hair_free(&h);
}

static void test_format_names(void **state)
{
    (void)state;
    assert_int_equal(hk_hair_format_from_path("a/b/c.TFX"), HK_HAIR_FORMAT_TFX);
    assert_int_equal(hk_hair_format_from_path("x.hair"), HK_HAIR_FORMAT_CYHAIR);
    assert_int_equal(hk_hair_format_from_path("x.data"), HK_HAIR_FORMAT_USC);
    assert_int_equal(hk_hair_format_from_path("x.ply"), HK_HAIR_FORMAT_PLY);
    assert_int_equal(hk_hair_format_from_path("x.obj"), HK_HAIR_FORMAT_OBJ);
    assert_int_equal(hk_hair_format_from_path("x.usda"), HK_HAIR_FORMAT_USDA);
    assert_int_equal(hk_hair_format_from_path("x.usd"), HK_HAIR_FORMAT_AUTO);
    assert_int_equal(hk_hair_format_from_path("dir.tfx/file"), HK_HAIR_FORMAT_AUTO);
    assert_int_equal(hk_hair_format_from_path("noext"), HK_HAIR_FORMAT_AUTO);
    assert_int_equal(hk_hair_format_from_name("TressFX"), HK_HAIR_FORMAT_TFX);
    assert_int_equal(hk_hair_format_from_name("hair"), HK_HAIR_FORMAT_CYHAIR);
    assert_int_equal(hk_hair_format_from_name("cyhair"), HK_HAIR_FORMAT_CYHAIR);
    assert_int_equal(hk_hair_format_from_name("usd"), HK_HAIR_FORMAT_USDA);
    assert_int_equal(hk_hair_format_from_name("abc"), -1);
    assert_string_equal(hk_hair_format_name(HK_HAIR_FORMAT_USC), "usc");
    /* An unknown extension: the content decides, or the message says what to do. */
    hk_HairFile h, back;
    hk_Error err;
    make_hair(&h, 3, 0);
    const char *path = tmp_path("noext");
    hk_HairWriteDef def = hk_hair_write_defaults();
    assert_int_equal(hk_hair_write(path, &h, &def, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "--to");
    const hk_HairFormat sniffed[3] = {HK_HAIR_FORMAT_CYHAIR, HK_HAIR_FORMAT_PLY, HK_HAIR_FORMAT_USDA};
    for (int i = 0; i < 3; i++) {
        def.format = sniffed[i];
        assert_int_equal(hk_hair_write(path, &h, &def, &err), HK_OK);
        assert_int_equal(hk_hair_read(path, HK_HAIR_FORMAT_AUTO, &back, &err), HK_OK);
        assert_same_strands(&h, &back);
        hk_hair_free(&back);
    }
    def.format = HK_HAIR_FORMAT_USC;
    assert_int_equal(hk_hair_write(path, &h, &def, &err), HK_OK);
    assert_int_equal(hk_hair_read(path, HK_HAIR_FORMAT_AUTO, &back, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "noext");
    hk_assert_contains(err.message, "--from");
    assert_int_equal(hk_hair_read(tmp_path("missing.tfx"), HK_HAIR_FORMAT_AUTO, &back, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "missing.tfx");
    hk_hair_free(&h);
}

/* ---- files of other tools, by hand ---- */

static void test_ply_edges(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Error err;
    /* Two strands given as edges out of order, one written tip to root (edges pointing
     * into its first vertex), and an isolated vertex: a one-point strand. */
    const char *ply = "ply\r\nformat ascii 1.0\r\ncomment by hand\r\nelement vertex 7\r\n"
                      "property double x\r\nproperty float y\r\nproperty float z\r\nproperty uchar alpha\r\n"
                      "element edge 4\r\nproperty int vertex1\r\nproperty uint vertex2\r\n"
                      "element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                      "0 0 0 1\r\n0 1 0 1\r\n0 2 0 1\r\n5 0 0 1\r\n5 1 0 1\r\n5 2 0 1\r\n9 9 9 1\r\n"
                      "1 2\r\n0 1\r\n4 3\r\n5 4\r\n3 0 1 2\r\n";
    assert_int_equal(hk_ply_hair_load(hk_test_write_text("edges.ply", ply), &h, &err), HK_OK);
    assert_int_equal(h.strand_count, 3);
    assert_int_equal(hk_hair_strand_points(&h, 0), 3);
    assert_int_equal(hk_hair_strand_points(&h, 1), 3);
    assert_int_equal(hk_hair_strand_points(&h, 2), 1);
    const float want[21] = {0, 0, 0, 0, 1, 0, 0, 2, 0, 5, 2, 0, 5, 1, 0, 5, 0, 0, 9, 9, 9};
    assert_memory_equal(h.points, want, sizeof want);
    assert_null(h.colors);
    hk_hair_free(&h);

    /* The same in binary, with the strand element too (it wins over the edges). */
    unsigned char bin[1024];
    const char *head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                       "property float y\nproperty float z\nproperty uchar red\nproperty uchar green\n"
                       "property uchar blue\nelement strand 1\nproperty ushort nsegs\nelement edge 2\n"
                       "property int vertex1\nproperty int vertex2\nend_header\n";
    size_t n = strlen(head);
    memcpy(bin, head, n);
    for (int v = 0; v < 3; v++) {
        const float p[3] = {(float)v, 0.5f, -0.25f};
        memcpy(bin + n, p, 12);
        n += 12;
        bin[n++] = 255, bin[n++] = 0, bin[n++] = 51;
    }
    bin[n++] = 2, bin[n++] = 0;
    const int32_t e[4] = {0, 1, 1, 2};
    memcpy(bin + n, e, sizeof e);
    n += sizeof e;
    const char *path = hk_test_write_file("curly-like.ply", bin, n);
    assert_int_equal(hk_ply_hair_load(path, &h, &err), HK_OK);
    assert_int_equal(h.strand_count, 1);
    assert_int_equal(h.point_count, 3);
    assert_true(h.points[3] == 1.0f && h.points[4] == 0.5f);
    assert_true(h.colors[0] == 1.0f && h.colors[1] == 0.0f && h.colors[2] == 0.2f);
    hk_hair_free(&h);
    /* Every truncation of it is refused, naming the file. */
    for (size_t len = 0; len < n; len++) {
        path = hk_test_write_file("cut.ply", bin, len);
        assert_int_not_equal(hk_ply_hair_load(path, &h, &err), HK_OK);
        hk_assert_contains(err.message, "cut.ply");
    }

    /* Branches, loops, bad indices. */
    const struct {
        const char *edges, *msg;
        int nedges;
    } bad[] = {{"0 1\n1 2\n1 3\n", "branch", 3},
               {"0 1\n1 2\n2 0\n", "closed loop", 3},
               {"0 1\n1 9\n", "edge 1 joins vertices 1 and 9", 2},
               {"0 0\n", "edge 0 joins", 1},
               {"0 1\n1 -2\n", "'-2' is not a uint", 2}};
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char text[512];
        snprintf(text, sizeof text,
                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                 "property float z\nelement edge %d\nproperty int vertex1\nproperty uint vertex2\nend_header\n"
                 "0 0 0\n1 0 0\n2 0 0\n3 0 0\n%s",
                 bad[i].nedges, bad[i].edges);
        assert_int_equal(hk_ply_hair_load(hk_test_write_text("bad-edges.ply", text), &h, &err), HK_ERR_PARSE);
        hk_assert_contains(err.message, "bad-edges.ply");
        hk_assert_contains(err.message, bad[i].msg);
    }
}

static void test_ply_malformed(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Error err;
    const char *head = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                       "property float z\nelement strand 1\nproperty ushort nsegs\nend_header\n";
    const struct {
        const char *text, *msg;
    } bad[] = {
        {"", "no 'ply' line"},
        {"PLY\n", "no 'ply' line"},
        {"ply\nformat binary_big_endian 1.0\nend_header\n", "big-endian"},
        {"ply\nformat ascii 2.0\nend_header\n", "version"},
        {"ply\nformat ascii 1.0\nelement vertex 1\n", ":4: the header has no end_header"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", ":4: unknown property type"},
        {"ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", ":3: malformed element"},
        {"ply\nformat ascii 1.0\nelement vertex 4294967295\nproperty float x\nproperty float y\n"
         "property float z\nend_header\n1 2 3\n",
         "truncated: element 'vertex' announces 4294967295 records"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
         ":3: the vertex element has no property z"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty int z\n"
         "element strand 1\nproperty ushort nsegs\nend_header\n1 2 3\n0\n",
         "vertex z is int"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
         "end_header\n1 2 3\n",
         "neither a strand element"},
        {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
         "element face 0\nproperty list uchar int vertex_indices\nend_header\n1 2 3\n",
         "a mesh, not hair"},
        {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "element strand 1\nproperty ushort nsegs\nend_header\n1 2 3\n4 5 nan\n1\n",
         ":11: 'nan' is not a float"},
        {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "element strand 1\nproperty ushort nsegs\nend_header\n1 2 3\n4 5 6\n2\n",
         "add up to 3 points, the file has 2 vertices"},
        {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "element strand 1\nproperty ushort nsegs\nend_header\n1 2 3\n4 5 6\n1\n7\n",
         "data after the last element"},
        {"ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
         "element strand 1\nproperty ushort nsegs\nend_header\n1 2 3\n4 5 1e39\n1\n",
         "'1e39' is not a float"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        if (hk_ply_hair_load(hk_test_write_text("bad.ply", bad[i].text), &h, &err) == HK_OK)
            fail_msg("case %zu was read", i);
        hk_assert_contains(err.message, "bad.ply");
        hk_assert_contains(err.message, bad[i].msg);
    }
    /* ASCII truncated anywhere: refused (a cut inside the last number may still read). */
    char text[512];
    snprintf(text, sizeof text, "%s0.5 1.5 2.5\n3.5 4.5 5.5\n1\n", head);
    const size_t n = strlen(text);
    assert_int_equal(hk_ply_hair_load(hk_test_write_text("ok.ply", text), &h, &err), HK_OK);
    hk_hair_free(&h);
    for (size_t len = 0; len + 2 < n; len++) {
        if (hk_ply_hair_load(hk_test_write_file("cut-ascii.ply", text, len), &h, &err) == HK_OK)
            fail_msg("cut at %zu was read", len);
        hk_assert_contains(err.message, "cut-ascii.ply");
    }
    /* Binary with a lying vertex count: refused before allocating. */
    hk_HairFile g;
    make_hair(&g, 4, 0);
    const char *path = tmp_path("lying.ply");
    assert_int_equal(hk_ply_hair_save(path, &g, 0, &err), HK_OK);
    size_t size;
    char *bin = hk_test_read_file(path, &size);
    char *count = strstr(bin, "element vertex ") + 15;
    const size_t digits = strspn(count, "0123456789");
    char *lie = malloc(size + 16);
    const size_t at = (size_t)(count - bin);
    memcpy(lie, bin, at);
    memcpy(lie + at, "9999999", 7);
    memcpy(lie + at + 7, count + digits, size - at - digits);
    assert_int_equal(hk_ply_hair_load(hk_test_write_file("lying2.ply", lie, size - digits + 7), &h, &err),
                     HK_ERR_PARSE);
    hk_assert_contains(err.message, "lying2.ply");
    hk_assert_contains(err.message, "truncated: element 'vertex' announces 9999999 records");
    free(lie);
    free(bin);
    hk_hair_free(&g);
}

static void test_obj_polylines(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Error err;
    /* Blender-like: one segment per line (joined), a head's faces ignored, v/vt indices,
     * negative indices, comments, a colour after the coordinates. */
    const char *obj = "# from some tool\nmtllib x.mtl\no hair\nv 0 0 0\nv 0 1 0\nv 0 2 0 # tip\n"
                      "v 1 0 0 0.5 0.5 0.5\nv 1 1 0\nvt 0 0\nl 1 2\nl 2 3\ns off\nl -2/1 -1\nl 4\n"
                      "f 1 2 3\ng head\nusemtl skin\n";
    assert_int_equal(hk_obj_hair_load(hk_test_write_text("lines.obj", obj), &h, &err), HK_OK);
    assert_int_equal(h.strand_count, 3);
    assert_int_equal(hk_hair_strand_points(&h, 0), 3);
    assert_int_equal(hk_hair_strand_points(&h, 1), 2);
    assert_int_equal(hk_hair_strand_points(&h, 2), 1);
    const float want[18] = {0, 0, 0, 0, 1, 0, 0, 2, 0, 1, 0, 0, 1, 1, 0, 1, 0, 0};
    assert_memory_equal(h.points, want, sizeof want);
    hk_hair_free(&h);
    const struct {
        const char *text, *msg;
    } bad[] = {
        {"v 0 0 0\n", "no polylines"},
        {"v 0 0 0\nv 1 1 1\nl 1 3\n", "lines-bad.obj:3: '3' is not a vertex index"},
        {"v 0 0 0\nl 1 0\n", ":2: '0' is not a vertex index"},
        {"v 0 0\nl 1\n", ":1: a vertex has 3 coordinates"},
        {"v 0 0 x\nl 1\n", ":1: 'x' is not a number"},
        {"v 0 0 0\nl\n", ":2: an 'l' line without vertex indices"},
        {"v 0 0 0\ncstype bspline\nl 1\n", ":2: free-form curves"},
        {"v 0 0 0\nbogus 1\nl 1\n", ":2: unknown statement 'bogus'"},
        {"v 0 0 0\nl 1\n\0junk", "binary data"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        const size_t len = strlen(bad[i].text) + (strstr(bad[i].msg, "binary") ? 5 : 0);
        if (hk_obj_hair_load(hk_test_write_file("lines-bad.obj", bad[i].text, len), &h, &err) == HK_OK)
            fail_msg("case %zu was read", i);
        hk_assert_contains(err.message, "lines-bad.obj");
        hk_assert_contains(err.message, bad[i].msg);
    }
}

static void test_usda_subset(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Error err;
    /* Z up, centimetres, nested prims, identity transforms, uniform widths as a primvar,
     * a second curves prim, metadata and comments a DCC writes. */
    const char *usda =
        "#usda 1.0\n(\n    \"\"\"a doc\n string\"\"\"\n    upAxis = \"Z\"\n"
        "    metersPerUnit = 0.01\n    customLayerData = { string creator = \"x\" }\n)\n\n"
        "def Xform \"root\" (\n    kind = \"component\"\n)\n{\n"
        "    double3 xformOp:translate = (0, 0, 0)\n    float3 xformOp:scale = (1, 1, 1)\n"
        "    uniform token[] xformOpOrder = [\"xformOp:translate\", \"xformOp:scale\"]\n"
        "    def BasisCurves \"a\" # comment\n    {\n        uniform token type = \"linear\"\n"
        "        int[] curveVertexCounts = [2, 3]\n"
        "        point3f[] points = [(0, 0, 100), (0, 0, 200), (1, 2, 3), (4, 5, 6), (7, 8, 9)]\n"
        "        float[] primvars:widths = [0.5, 0.25] (\n            interpolation = \"uniform\"\n        )\n"
        "        rel material:binding = </Mat>\n        color3f[] primvars:displayColor = [(1, 0, 0)]\n"
        "    }\n    def BasisCurves \"b\"\n    {\n        uniform token type = \"linear\"\n"
        "        uniform token wrap = \"nonperiodic\"\n        int[] curveVertexCounts = [1]\n"
        "        point3f[] points = [(10, 20, 30),]\n    }\n}\n";
    assert_int_equal(hk_usda_hair_load(hk_test_write_text("dcc.usda", usda), &h, &err), HK_OK);
    assert_int_equal(h.strand_count, 3);
    assert_int_equal(hk_hair_strand_points(&h, 0), 2);
    assert_int_equal(hk_hair_strand_points(&h, 1), 3);
    assert_int_equal(hk_hair_strand_points(&h, 2), 1);
    /* Z up: (x, y, z) -> (x, z, -y); then centimetres to metres. */
    assert_true(h.points[0] == 0.0f && h.points[1] == 1.0f && h.points[2] == 0.0f);
    assert_true(h.points[6] == 0.01f && h.points[7] == 0.03f && h.points[8] == -0.02f);
    assert_true(h.points[15] == 0.1f && h.points[16] == 0.3f && h.points[17] == -0.2f);
    assert_non_null(h.thickness);
    assert_true(h.thickness[0] == 0.005f && h.thickness[1] == 0.005f && h.thickness[2] == 0.0025f);
    assert_true(h.thickness[5] == 0.005f); /* prim b gives no widths: the first width */
    hk_hair_free(&h);
    const char *curves = "def BasisCurves \"c\"\n{\n    uniform token type = \"linear\"\n"
                         "    int[] curveVertexCounts = [2]\n    point3f[] points = [(0, 0, 0), (1, 1, 1)]\n";
    const struct {
        const char *pre, *body, *msg;
    } bad[] = {
        {"", "}\n", ":1: not a USD ascii file"},
        {"#usda 1.0\n", "}\n", NULL},
        {"#usda 1.0\n", "    uniform token wrap = \"periodic\"\n}\n", ":7: wrap = \"periodic\""},
        {"#usda 1.0\n", "    uniform token type = \"cubic\"\n}\n", ":7: type = \"cubic\": only linear"},
        {"#usda 1.0\n", "    int[] curveVertexCounts = [3]\n}\n",
         ":2: curveVertexCounts add up to 3 points, points has 2"},
        {"#usda 1.0\n", "    int[] curveVertexCounts = [0, 2]\n}\n", ":7: curve 0 has 0 vertices"},
        {"#usda 1.0\n", "    float[] widths = [1, 2, 3]\n}\n", "3 widths with interpolation \"vertex\""},
        {"#usda 1.0\n", "    double3 xformOp:translate = (1, 0, 0)\n}\n",
         ":7: xformOp:translate: transforms are not applied"},
        {"#usda 1.0\n", "    point3f[] points = [(0, 0, 0), (1, 1)]\n}\n", ":7: expected ','"},
        {"#usda 1.0\n", "    point3f[] points = [(0, 0, 0), (1, 1, inf)]\n}\n", ":7: 'inf' is not a number"},
        {"#usda 1.0\n", "", "missing '}'"},
        {"#usda 1.0\n", "    string s = \"open\n}\n", ":7: unterminated string"},
        {"#usda 1.0\n(\n    upAxis = \"X\"\n)\n", "}\n", ":3: upAxis must be"},
        {"#usda 1.0\n(\n    metersPerUnit = -1\n)\n", "}\n", ":3: metersPerUnit must be > 0"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char text[1024];
        snprintf(text, sizeof text, "%s%s%s", bad[i].pre, bad[i].pre[0] ? curves : "def", bad[i].body);
        const hk_Status st = hk_usda_hair_load(hk_test_write_text("bad.usda", text), &h, &err);
        if (!bad[i].msg) { /* the well-formed base case */
            assert_int_equal(st, HK_OK);
            hk_hair_free(&h);
            continue;
        }
        if (st == HK_OK) fail_msg("case %zu was read", i);
        hk_assert_contains(err.message, "bad.usda");
        hk_assert_contains(err.message, bad[i].msg);
    }
    /* Without type (the schema's default is cubic), with time samples only. */
    assert_int_equal(
        hk_usda_hair_load(hk_test_write_text("notype.usda",
                                             "#usda 1.0\ndef BasisCurves \"c\" {\n"
                                             "int[] curveVertexCounts = [1]\npoint3f[] points = [(0,0,0)]\n}\n"),
                          &h, &err),
        HK_ERR_PARSE);
    hk_assert_contains(err.message, "notype.usda:2: BasisCurves without 'type'");
    assert_int_equal(
        hk_usda_hair_load(hk_test_write_text("anim.usda",
                                             "#usda 1.0\ndef BasisCurves \"c\" {\nuniform token type = \"linear\"\n"
                                             "int[] curveVertexCounts = [1]\npoint3f[] points.timeSamples = {\n"
                                             "  1: [(0,0,0)],\n}\n}\n"),
                          &h, &err),
        HK_ERR_PARSE);
    hk_assert_contains(err.message, "time samples");
    assert_int_equal(
        hk_usda_hair_load(hk_test_write_text("nocurves.usda", "#usda 1.0\ndef Mesh \"m\" {\n}\n"), &h, &err),
        HK_ERR_PARSE);
    hk_assert_contains(err.message, "no BasisCurves prim");
}

/* Cuts a valid file at every length up to `upto` (and at a few more) and checks each cut
 * is refused with the file named. */
static void refuse_truncations(const char *path, size_t upto, hk_HairFormat format)
{
    size_t size;
    char *data = hk_test_read_file(path, &size);
    hk_HairFile h;
    hk_Error err;
    char name[64];
    snprintf(name, sizeof name, "truncated.%s", hk_hair_format_name(format));
    for (size_t len = 0; len < size; len += len < upto ? 1 : (size - upto) / 7 + 1) {
        const char *cut = hk_test_write_file(name, data, len);
        if (hk_hair_read(cut, format, &h, &err) == HK_OK) fail_msg("%s cut at %zu of %zu was read", path, len, size);
        hk_assert_contains(err.message, name);
    }
    free(data);
}

static void test_binary_truncated_and_lying(void **state)
{
    (void)state;
    hk_HairFile h, g;
    hk_Error err;
    make_hair(&g, 6, 8);
    const char *tfx = tmp_path("good.tfx"), *data = tmp_path("good.data"), *ply = tmp_path("good.ply");
    assert_int_equal(hk_tfx_save(tfx, &g, 0, &err), HK_OK);
    assert_int_equal(hk_usc_save(data, &g, &err), HK_OK);
    assert_int_equal(hk_ply_hair_save(ply, &g, 0, &err), HK_OK);
    refuse_truncations(tfx, 160 + 64, HK_HAIR_FORMAT_TFX);
    refuse_truncations(data, 4 + 2 * (4 + 8 * 12), HK_HAIR_FORMAT_USC);
    refuse_truncations(ply, 400, HK_HAIR_FORMAT_PLY);

    size_t size;
    unsigned char *b = (unsigned char *)hk_test_read_file(tfx, &size);
    /* TressFX: flipped counts, offsets and versions. */
    const struct {
        size_t at;
        uint32_t value;
        const char *msg;
    } tfx_bad[] = {
        {4, 0xFFFFFFFFu, "more than 2^32 points"},
        {4, 1000, "good-lie.tfx:4: truncated: the header announces 1000 strands of 8 vertices"},
        {8, 0, "good-lie.tfx:8: 0 vertices per strand"},
        {8, 70000, "70000 vertices per strand"},
        {8, 9, "truncated"},
        {12, 100, "good-lie.tfx:12: the vertices' offset 100 lies inside the 160-byte header"},
        {12, 0xFFFFFF00u, "truncated"},
        {0, 0x40400001u, "good-lie.tfx:0: not a TressFX file: version 3"},
        {0, 0x40400000u, "TressFX 3 header"}, /* 3.0, in a file of 200 bytes: v3's header is 296 */
    };
    for (size_t i = 0; i < sizeof tfx_bad / sizeof *tfx_bad; i++) {
        unsigned char copy[4096];
        assert_true(size <= sizeof copy);
        memcpy(copy, b, size);
        for (int k = 0; k < 4; k++) copy[tfx_bad[i].at + (size_t)k] = (unsigned char)(tfx_bad[i].value >> (8 * k));
        const char *path =
            hk_test_write_file("good-lie.tfx", copy, i + 1 == sizeof tfx_bad / sizeof *tfx_bad ? 200 : size);
        if (hk_tfx_load(path, &h, &err) == HK_OK) fail_msg("tfx case %zu was read", i);
        hk_assert_contains(err.message, "good-lie.tfx");
        hk_assert_contains(err.message, tfx_bad[i].msg);
    }
    /* a NaN point */
    {
        unsigned char copy[4096];
        memcpy(copy, b, size);
        const float nan = NAN;
        memcpy(copy + 160 + 16 * 9, &nan, 4);
        assert_int_equal(hk_tfx_load(hk_test_write_file("nan.tfx", copy, size), &h, &err), HK_ERR_PARSE);
        hk_assert_contains(err.message, "nan.tfx: point 9 (strand 1) has a non-finite coordinate");
    }
    free(b);
    /* A v3 file by hand: 296-byte header, float3 vertices. */
    {
        unsigned char v3[296 + 2 * 3 * 12];
        memset(v3, 0, sizeof v3);
        const float version = 3.0f;
        memcpy(v3, &version, 4);
        const uint32_t ns = 2, nv = 3, off = 296;
        memcpy(v3 + 4, &ns, 4);
        memcpy(v3 + 8, &nv, 4);
        memcpy(v3 + 144, &off, 4);
        for (int i = 0; i < 18; i++) {
            const float f = (float)i * 1.25f;
            memcpy(v3 + 296 + 4 * i, &f, 4);
        }
        assert_int_equal(hk_tfx_load(hk_test_write_file("v3.tfx", v3, sizeof v3), &h, &err), HK_OK);
        assert_int_equal(h.strand_count, 2);
        assert_int_equal(h.point_count, 6);
        assert_true(h.points[17] == 17 * 1.25f);
        hk_hair_free(&h);
        refuse_truncations(tmp_path("v3.tfx"), sizeof v3, HK_HAIR_FORMAT_TFX);
    }
    /* USC: lying counts. */
    b = (unsigned char *)hk_test_read_file(data, &size);
    const struct {
        size_t at;
        uint32_t value;
        const char *msg;
    } usc_bad[] = {
        {0, 0x7FFFFFFFu, "good-lie.data:0: 2147483647 strands cannot fit"},
        {0, 0xFFFFFFFFu, "-1 strands"},
        {0, 7, "truncated in a strand's vertex count"},
        {0, 5, "bytes after the last strand"},
        {4, 0, "good-lie.data:4: strand 0 has 0 vertices"},
        {4, 0x80000000u, "strand 0 has -2147483648 vertices"},
        {4, 60000, "good-lie.data:4: truncated: strand 0 announces 60000 vertices"},
        {4, 9, "good-lie.data"},
    };
    for (size_t i = 0; i < sizeof usc_bad / sizeof *usc_bad; i++) {
        unsigned char copy[4096];
        assert_true(size <= sizeof copy);
        memcpy(copy, b, size);
        for (int k = 0; k < 4; k++) copy[usc_bad[i].at + (size_t)k] = (unsigned char)(usc_bad[i].value >> (8 * k));
        const char *path = hk_test_write_file("good-lie.data", copy, size);
        if (hk_usc_load(path, &h, &err) == HK_OK) fail_msg("usc case %zu was read", i);
        hk_assert_contains(err.message, usc_bad[i].msg);
    }
    free(b);
    hk_hair_free(&g);
}

static void test_text_truncated(void **state)
{
    (void)state;
    hk_HairFile g, h;
    hk_Error err;
    make_hair(&g, 3, 0);
    const char *usda = tmp_path("good.usda"), *ply = tmp_path("good-ascii.ply"), *obj = tmp_path("good.obj");
    assert_int_equal(hk_usda_hair_save(usda, &g, 1.0, &err), HK_OK);
    assert_int_equal(hk_ply_hair_save(ply, &g, 1, &err), HK_OK);
    assert_int_equal(hk_obj_hair_save(obj, &g, &err), HK_OK);
    /* USD: every cut before the closing brace is refused. */
    size_t size;
    char *text = hk_test_read_file(usda, &size);
    for (size_t len = 0; len + 2 < size; len++) {
        const char *cut = hk_test_write_file("cut.usda", text, len);
        if (hk_usda_hair_load(cut, &h, &err) == HK_OK) fail_msg("usda cut at %zu was read", len);
        hk_assert_contains(err.message, "cut.usda");
    }
    free(text);
    /* PLY ASCII: refused unless only the last number's end is lost. */
    text = hk_test_read_file(ply, &size);
    for (size_t len = 0; len < size; len++) {
        const char *cut = hk_test_write_file("cut-a.ply", text, len);
        const hk_Status st = hk_ply_hair_load(cut, &h, &err);
        if (st == HK_OK) {
            assert_true(len + 3 >= size);
            hk_hair_free(&h);
        } else {
            hk_assert_contains(err.message, "cut-a.ply");
        }
    }
    free(text);
    /* OBJ: a cut either fails naming the file or reads a prefix of the strands. */
    text = hk_test_read_file(obj, &size);
    for (size_t len = 0; len < size; len++) {
        const char *cut = hk_test_write_file("cut.obj", text, len);
        if (hk_obj_hair_load(cut, &h, &err) == HK_OK) {
            assert_true(h.strand_count <= g.strand_count);
            hk_hair_free(&h);
        } else {
            hk_assert_contains(err.message, "cut.obj");
        }
    }
    free(text);
    hk_hair_free(&g);
}

/* Random edits of small valid files of every format: never a crash or a leak (the
 * sanitizer build runs this), and every refusal names the file. */
static void test_fuzz_small(void **state)
{
    (void)state;
    hk_HairFile g, h;
    hk_Error err;
    make_hair(&g, 3, 4);
    const hk_HairFormat formats[] = {HK_HAIR_FORMAT_TFX, HK_HAIR_FORMAT_USC, HK_HAIR_FORMAT_PLY,
                                     HK_HAIR_FORMAT_PLY, HK_HAIR_FORMAT_OBJ, HK_HAIR_FORMAT_USDA};
    static const char *const junk[] = {"element vertex 99\n",
                                       "property list uchar int x\n",
                                       "l 1 2 3\n",
                                       "v 1 2 3\n",
                                       "def BasisCurves \"x\" {",
                                       "[(",
                                       "\"\"\"",
                                       "}",
                                       "\xff\xff\xff\x7f",
                                       "\0\0\0\0",
                                       "-1",
                                       "1e30"};
    unsigned long long x = 12345;
    for (size_t f = 0; f < sizeof formats / sizeof *formats; f++) {
        hk_HairWriteDef def = hk_hair_write_defaults();
        def.format = formats[f];
        def.ascii = f == 3;
        const char *path = tmp_path("seed.bin");
        assert_int_equal(hk_hair_write(path, &g, &def, &err), HK_OK);
        size_t size;
        char *seed = hk_test_read_file(path, &size);
        for (int round = 0; round < 300; round++) {
            char buf[8192];
            assert_true(size <= sizeof buf);
            memcpy(buf, seed, size);
            size_t len = size;
            for (int k = 0; k < 1 + round % 4; k++)
                len = hk_test_mutate(buf, len, sizeof buf, " \n0123456789.-e()[],\"", junk, 12, &x);
            const char *cut = hk_test_write_file("fuzz.bin", buf, len);
            if (hk_hair_read(cut, formats[f], &h, &err) == HK_OK)
                hk_hair_free(&h);
            else
                hk_assert_contains(err.message, "fuzz.bin");
        }
        free(seed);
    }
    hk_hair_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_every_format),
        cmocka_unit_test(test_text_is_shortest_and_exact),
        cmocka_unit_test(test_ply_colours_and_usd_widths),
        cmocka_unit_test(test_tfx_resampling),
        cmocka_unit_test(test_up_axis_and_scale),
        cmocka_unit_test(test_format_names),
        cmocka_unit_test(test_ply_edges),
        cmocka_unit_test(test_ply_malformed),
        cmocka_unit_test(test_obj_polylines),
        cmocka_unit_test(test_usda_subset),
        cmocka_unit_test(test_binary_truncated_and_lying),
        cmocka_unit_test(test_text_truncated),
        cmocka_unit_test(test_fuzz_small),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
