/* PLY meshes (src/io/mesh_ply.c): the same mesh read from OBJ, ASCII PLY and binary PLY
 * (triangles and polygons fanned, with and without normals, extra properties and
 * elements skipped); hk_mesh_load's choice by extension and content; the head mesh of
 * ../shared/hair-data (Bangs_head.ply) read with the counts SOURCES.md gives and its
 * vertices checked against the bytes (skipped, saying so, when the folder is absent);
 * truncated files and lying headers refused with file:line or file:offset before any
 * allocation; the transforms hk_mesh_scale and hk_mesh_up_to_y. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/mesh.h"


/* A unit cube's corners and its six faces as quads (fanned into two triangles each). */
static const float cube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                 {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};

static const char *cube_obj(int normals)
{
    static char text[2048];
    size_t n = 0;
    for (int i = 0; i < 8; i++)
        n += (size_t)snprintf(text + n, sizeof text - n, "v %g %g %g\n", cube[i][0], cube[i][1], cube[i][2]);
    if (normals)
        for (int i = 0; i < 8; i++)
            n += (size_t)snprintf(text + n, sizeof text - n, "vn %g %g %g\n", 2 * cube[i][0] - 1, 2 * cube[i][1] - 1,
                                  2 * cube[i][2] - 1);
    for (int f = 0; f < 6; f++) {
        n += (size_t)snprintf(text + n, sizeof text - n, "f");
        for (int k = 0; k < 4; k++)
            n += normals ? (size_t)snprintf(text + n, sizeof text - n, " %d//%d", quads[f][k] + 1, quads[f][k] + 1)
                         : (size_t)snprintf(text + n, sizeof text - n, " %d", quads[f][k] + 1);
        n += (size_t)snprintf(text + n, sizeof text - n, "\n");
    }
    return hk_test_write_text(normals ? "cube-n.obj" : "cube.obj", text);
}

/* The cube as PLY: ASCII or binary; with normals (as double) or not; a colour and an
 * s, t pair on each vertex and an extra element, which the reader skips. */
static const char *cube_ply(int ascii, int normals, const char *name)
{
    static unsigned char buf[8192];
    size_t n = (size_t)snprintf((char *)buf, sizeof buf,
                                "ply\nformat %s 1.0\ncomment a cube\nelement vertex 8\nproperty float x\n"
                                "property float y\nproperty float z\n%sproperty uchar red\nproperty double s\n"
                                "element material 1\nproperty list uchar float tint\n"
                                "element face 6\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
                                "end_header\n",
                                ascii ? "ascii" : "binary_little_endian",
                                normals ? "property double nx\nproperty double ny\nproperty double nz\n" : "");
    for (int i = 0; i < 8; i++) {
        if (ascii) {
            n += (size_t)snprintf((char *)buf + n, sizeof buf - n, "%g %g %g", cube[i][0], cube[i][1], cube[i][2]);
            if (normals)
                n += (size_t)snprintf((char *)buf + n, sizeof buf - n, " %g %g %g", 2 * cube[i][0] - 1,
                                      2 * cube[i][1] - 1, 2 * cube[i][2] - 1);
            n += (size_t)snprintf((char *)buf + n, sizeof buf - n, " 200 0.5\n");
        } else {
            memcpy(buf + n, cube[i], 12);
            n += 12;
            if (normals)
                for (int k = 0; k < 3; k++) {
                    const double v = 2 * cube[i][k] - 1;
                    memcpy(buf + n, &v, 8);
                    n += 8;
                }
            buf[n++] = 200;
            const double s = 0.5;
            memcpy(buf + n, &s, 8);
            n += 8;
        }
    }
    if (ascii) {
        n += (size_t)snprintf((char *)buf + n, sizeof buf - n, "2 0.25 0.5\n");
    } else {
        buf[n++] = 2;
        const float t[2] = {0.25f, 0.5f};
        memcpy(buf + n, t, 8);
        n += 8;
    }
    for (int f = 0; f < 6; f++) {
        if (ascii) {
            n += (size_t)snprintf((char *)buf + n, sizeof buf - n, "7 4 %d %d %d %d\n", quads[f][0], quads[f][1],
                                  quads[f][2], quads[f][3]);
        } else {
            buf[n++] = 7;
            buf[n++] = 4;
            for (int k = 0; k < 4; k++) {
                const int32_t v = quads[f][k];
                memcpy(buf + n, &v, 4);
                n += 4;
            }
        }
    }
    return hk_test_write_file(name, buf, n);
}

static void assert_same_mesh(const hk_Mesh *a, const hk_Mesh *b)
{
    assert_int_equal(a->vertex_count, b->vertex_count);
    assert_int_equal(a->triangle_count, b->triangle_count);
    assert_memory_equal(a->triangles, b->triangles, 3 * sizeof(int) * (size_t)a->triangle_count);
    for (int i = 0; i < a->vertex_count; i++) {
        assert_true(a->positions[i].x == b->positions[i].x && a->positions[i].y == b->positions[i].y &&
                    a->positions[i].z == b->positions[i].z);
        hk_assert_near(a->normals[i].x, b->normals[i].x, 1e-15);
        hk_assert_near(a->normals[i].y, b->normals[i].y, 1e-15);
        hk_assert_near(a->normals[i].z, b->normals[i].z, 1e-15);
    }
}

static void test_same_mesh_as_obj(void **state)
{
    (void)state;
    hk_Error err;
    for (int normals = 0; normals < 2; normals++) {
        hk_Mesh obj;
        if (hk_obj_load(cube_obj(normals), &obj, &err) != HK_OK) fail_msg("%s", err.message);
        assert_int_equal(obj.triangle_count, 12);
        for (int ascii = 0; ascii < 2; ascii++) {
            hk_Mesh ply, any;
            const char *path = cube_ply(ascii, normals, ascii ? "cube-a.ply" : "cube-b.ply");
            if (hk_ply_mesh_load(path, &ply, &err) != HK_OK) fail_msg("%s", err.message);
            assert_same_mesh(&obj, &ply);
            /* hk_mesh_load picks PLY by the extension */
            assert_int_equal(hk_mesh_load(path, &any, &err), HK_OK);
            assert_same_mesh(&obj, &any);
            hk_mesh_free(&ply);
            hk_mesh_free(&any);
        }
        /* Normals given: the file's (made unit), corners of the cube point outwards. */
        if (normals) hk_assert_near(obj.normals[6].x, 1.0 / sqrt(3.0), 1e-15);
        hk_mesh_free(&obj);
    }
    /* ... by the content when the name says nothing, and OBJ otherwise. */
    size_t size;
    char *bytes = hk_test_read_file(cube_ply(0, 0, "cube-b.ply"), &size);
    hk_Mesh m;
    assert_int_equal(hk_mesh_load(hk_test_write_file("cube.mesh", bytes, size), &m, &err), HK_OK);
    assert_int_equal(m.triangle_count, 12);
    hk_mesh_free(&m);
    assert_int_equal(hk_mesh_load(hk_test_write_file("CUBE.PLY", bytes, size), &m, &err), HK_OK);
    hk_mesh_free(&m);
    free(bytes);
    assert_int_equal(hk_mesh_load(cube_obj(0), &m, &err), HK_OK);
    assert_int_equal(m.triangle_count, 12);
    hk_mesh_free(&m);
    assert_int_equal(hk_mesh_load(NULL, &m, &err), HK_ERR_INVALID);
    assert_int_equal(hk_mesh_load("/nonexistent.ply", &m, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "/nonexistent.ply");
}

/* A triangle (0 0 0, 1 0 0, 0 1 0) in ASCII with the given face lines. */
static void expect_error(const char *name, const char *text, size_t size, const char *phrase)
{
    hk_Mesh m;
    hk_Error err;
    const char *path = size ? hk_test_write_file(name, text, size) : hk_test_write_text(name, text);
    hk_Status st = hk_ply_mesh_load(path, &m, &err);
    if (st == HK_OK) fail_msg("%s was accepted", name);
    hk_assert_contains(err.message, name);
    hk_assert_contains(err.message, phrase);
    assert_null(m.positions);
}

static void test_refused(void **state)
{
    (void)state;
    const char *head =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    char text[1024];
    /* Face with two corners, index out of range, negative, a float index list. */
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n2 0 1\n",
             head);
    expect_error("two.ply", text, 0, "two.ply:13: face 0 has 2 corners");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
             head);
    expect_error("range.ply", text, 0, "range.ply:13: face 0: corner 2 is vertex 3 (3 vertices)");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n",
             head);
    expect_error("neg.ply", text, 0, "corner 2 is vertex -1");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar float vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
             head);
    expect_error("float.ply", text, 0, "float.ply:7: face indices are float");
    /* Not a number, a coordinate past the bound, nan. */
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n",
             head);
    expect_error("word.ply", text, 0, "word.ply:11: 'x' is not a float in vertex 1");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1e9 0\n3 0 1 2\n",
             head);
    expect_error("far.ply", text, 0, "out of range in vertex 2");
    /* Lying counts: more vertices or faces than the file holds, refused before any
     * allocation ("truncated" at the header's element). */
    snprintf(text, sizeof text,
             "ply\nformat ascii 1.0\nelement vertex 4000000000\nproperty float x\n"
             "property float y\nproperty float z\nelement face 1\n"
             "property list uchar int vertex_indices\nend_header\n0 0 0\n");
    expect_error("many.ply", text, 0, "vertices (1 to");
    snprintf(text, sizeof text,
             "%selement face 1000000\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
             head);
    expect_error("faces.ply", text, 0, "truncated: element 'face' announces 1000000 records");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1\n",
             head);
    expect_error("short.ply", text, 0, "short.ply:14: truncated in face 0 (the file ends)");
    snprintf(text, sizeof text,
             "%selement face 1\nproperty list uchar int vertex_indices\nend_header\n"
             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n4\n",
             head);
    expect_error("after.ply", text, 0, "data after the last element");
    /* Binary: truncated inside the faces, at its offset. */
    unsigned char bin[512];
    size_t n = (size_t)snprintf((char *)bin, sizeof bin,
                                "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
                                "property float y\nproperty float z\nelement face 2\n"
                                "property list uchar int vertex_indices\nend_header\n");
    const size_t body = n;
    memset(bin + n, 0, 36);
    n += 36;
    bin[n++] = 3;
    for (int k = 0; k < 3; k++) {
        const int32_t v = k;
        memcpy(bin + n, &v, 4);
        n += 4;
    }
    bin[n++] = 4; /* the second face: a quad, cut after three of its corners */
    memset(bin + n, 0, 12);
    n += 12;
    char want[64];
    snprintf(want, sizeof want, "bin.ply:%zu: truncated in face 1", body + 36 + 13 + 13);
    /* the check before allocating sees that 2 faces of at least 13 bytes fit, so the
     * reader reaches the short face */
    expect_error("bin.ply", (const char *)bin, n, want);
    bin[body + 36 + 13] = 200; /* a list longer than the file */
    expect_error("bin.ply", (const char *)bin, n, want);
    /* Headers: no faces (hair), big-endian, no end_header, not PLY at all. */
    expect_error("strands.ply",
                 "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                 "element strand 1\nproperty ushort nsegs\nend_header\n0 0 0\n1 0 0\n1\n",
                 0, "no face element in this PLY file (it has strands or edges: hair, not a mesh)");
    expect_error("big.ply", "ply\nformat binary_big_endian 1.0\nend_header\n", 0, "big.ply:2: big-endian PLY");
    expect_error("open.ply", "ply\nformat ascii 1.0\nelement vertex 3\n", 0, "no end_header");
    expect_error("obj.ply", "v 0 0 0\n", 0, "obj.ply:1: not a PLY file");
    expect_error("novert.ply",
                 "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                 "element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n",
                 0, "novert.ply:3: the vertex element has no property z");
}

static void test_transforms(void **state)
{
    (void)state;
    hk_Mesh m;
    hk_Error err;
    assert_int_equal(hk_ply_mesh_load(cube_ply(1, 1, "cube-t.ply"), &m, &err), HK_OK);
    /* x up: the vertex (1, 0, 0) goes to (0, 1, 0); normals turn with it. */
    const hk_Vec3 n1 = m.normals[1];
    hk_mesh_up_to_y(&m, HK_AXIS_POS_X);
    assert_true(m.positions[1].x == 0 && m.positions[1].y == 1 && m.positions[1].z == 0);
    assert_true(m.normals[1].x == -n1.y && m.normals[1].y == n1.x && m.normals[1].z == n1.z);
    /* The same rotation as the hair's (hk_hair_up_to_y, `convert --up`). */
    for (int a = 0; a < 6; a++) {
        hk_HairFile h;
        const uint32_t counts[1] = {1};
        assert_int_equal(hk_hair_alloc(&h, 1, counts, &err), HK_OK);
        h.points[0] = 1, h.points[1] = 2, h.points[2] = 3;
        hk_hair_up_to_y(&h, (hk_Axis)a);
        const hk_Vec3 q = hk_v3_up_to_y(hk_v3(1, 2, 3), (hk_Axis)a);
        assert_true(h.points[0] == (float)q.x && h.points[1] == (float)q.y && h.points[2] == (float)q.z);
        hk_hair_free(&h);
    }
    const hk_Vec3 up = hk_v3_up_to_y(hk_v3(0, 0, 1), HK_AXIS_POS_Z);
    assert_true(up.x == 0 && up.y == 1 && up.z == 0);
    assert_int_equal(hk_mesh_scale(&m, 0.001, &err), HK_OK);
    hk_assert_near(m.positions[1].y, 0.001, 1e-18);
    hk_assert_near(hk_v3_norm(m.normals[1]), 1.0, 1e-15);
    assert_int_equal(hk_mesh_scale(&m, 0.0, &err), HK_ERR_INVALID);
    assert_int_equal(hk_mesh_scale(&m, 1e12, &err), HK_ERR_INVALID);
    hk_assert_near(m.positions[1].y, 0.001, 1e-18); /* refused: unchanged */
    hk_mesh_free(&m);
}

/* Bangs_head.ply: binary little-endian (trimesh), vertex x, y, z float and s, t double
 * (28 bytes), face list uchar int: 3,943 vertices and 7,694 triangles (SOURCES.md). */
static void test_bangs_head(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    const char *path = hk_test_shared_path("Bangs_head.ply");
    hk_Mesh m;
    hk_Error err;
    if (hk_mesh_load(path, &m, &err) != HK_OK) fail_msg("%s", err.message);
    assert_int_equal(m.vertex_count, 3943);
    assert_int_equal(m.triangle_count, 7694);
    size_t size;
    unsigned char *d = (unsigned char *)hk_test_read_file(path, &size);
    const char *end = strstr((const char *)d, "end_header\n");
    assert_non_null(end);
    const size_t at = (size_t)(end - (const char *)d) + strlen("end_header\n");
    assert_int_equal(size, at + 3943 * 28 + 7694 * 13);
    for (int i = 0; i < 3943; i++) {
        float p[3];
        memcpy(p, d + at + 28 * (size_t)i, 12);
        assert_true(m.positions[i].x == p[0] && m.positions[i].y == p[1] && m.positions[i].z == p[2]);
    }
    const unsigned char *f = d + at + 3943 * 28;
    for (int t = 0; t < 7694; t++) {
        assert_int_equal(f[13 * (size_t)t], 3);
        int32_t v[3];
        memcpy(v, f + 13 * (size_t)t + 1, 12);
        for (int k = 0; k < 3; k++) assert_int_equal(m.triangles[3 * t + k], v[k]);
    }
    free(d);
    /* Millimetres and x up (the Bangs groom's frame): in metres and y up it is a head,
     * taller than wide, a few tens of centimetres. */
    assert_int_equal(hk_mesh_scale(&m, 0.001, &err), HK_OK);
    hk_mesh_up_to_y(&m, HK_AXIS_POS_X);
    double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
    for (int i = 0; i < m.vertex_count; i++) {
        const double p[3] = {m.positions[i].x, m.positions[i].y, m.positions[i].z};
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], p[k]), hi[k] = fmax(hi[k], p[k]);
    }
    print_message("Bangs_head in metres, y up: x [%.3f, %.3f] y [%.3f, %.3f] z [%.3f, %.3f]\n", lo[0], hi[0], lo[1],
                  hi[1], lo[2], hi[2]);
    for (int k = 0; k < 3; k++) assert_true(hi[k] - lo[k] > 0.1 && hi[k] - lo[k] < 0.5);
    hk_mesh_free(&m);
    /* The OBJ heads read through the same entry point. */
    assert_int_equal(hk_mesh_load(hk_test_shared_path("sintel.obj"), &m, &err), HK_OK);
    assert_int_equal(m.vertex_count, 3046);
    assert_int_equal(m.triangle_count, 5952);
    hk_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_same_mesh_as_obj),
        cmocka_unit_test(test_refused),
        cmocka_unit_test(test_transforms),
        cmocka_unit_test(test_bangs_head),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
