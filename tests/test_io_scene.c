/* Scene files: OBJ meshes (src/io/obj.c), setup and visuality files (src/io/setup.c,
 * visuality.c): accepted forms, relative paths, Load/Save rules, errors with file:line. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hairkit/io.h"
#include "hairkit/mesh.h"

static void test_obj_forms(void **state)
{
    (void)state;
    /* A unit square as one quad (v//vn), a triangle with v/vt/vn and negative indices,
     * comments, groups and texture coordinates ignored. */
    const char *text = "# square\no thing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 2\n"
                       "g group\nusemtl m\ns 1\nf 1//1 2//1 3//1 4//1\nv 2 0 0\nf -3/1/1 -4/1/1 -1/1/1\n";
    hk_Mesh m;
    hk_Error err;
    assert_int_equal(hk_obj_load(hk_test_write_text("square.obj", text), &m, &err), HK_OK);
    assert_int_equal(m.vertex_count, 5);
    assert_int_equal(m.triangle_count, 3); /* quad as a fan of two, plus one */
    const int expect[9] = {0, 1, 2, 0, 2, 3, 2, 1, 4};
    assert_memory_equal(m.triangles, expect, sizeof expect);
    hk_assert_near(m.normals[0].z, 1.0, 1e-15); /* from vn, normalised */
    hk_assert_near(hk_mesh_area(&m), 1.0 + 0.5, 1e-15);
    /* Vertex 5 gets its normal from the vn its face corner names. */
    hk_assert_near(m.normals[4].z, 1.0, 1e-15);
    /* Save and reload: same geometry. */
    char path[512];
    snprintf(path, sizeof path, "%s/again.obj", hk_test_tmpdir());
    assert_int_equal(hk_obj_save(path, &m, "test", &err), HK_OK);
    hk_Mesh m2;
    assert_int_equal(hk_obj_load(path, &m2, &err), HK_OK);
    assert_int_equal(m2.triangle_count, 3);
    assert_memory_equal(m2.triangles, expect, sizeof expect);
    hk_mesh_free(&m);
    hk_mesh_free(&m2);
}

static void test_obj_face_normals(void **state)
{
    (void)state;
    /* Without vn: area-weighted face normals, counter-clockwise is outward. */
    const char *text = "v 0 0 0\nv 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    hk_Mesh m;
    hk_Error err;
    assert_int_equal(hk_obj_load(hk_test_write_text("corner.obj", text), &m, &err), HK_OK);
    hk_assert_near(m.normals[1].y, 1.0, 1e-15);       /* only in face 1: normal +y */
    hk_assert_near(m.normals[3].z, 1.0, 1e-15);       /* only in face 2: normal +z */
    hk_assert_near(m.normals[0].y, sqrt(0.5), 1e-15); /* shared, equal areas */
    hk_mesh_free(&m);
}

static void expect_obj_error(const char *text, const char *phrase)
{
    hk_Mesh m;
    hk_Error err;
    hk_Status st = hk_obj_load(hk_test_write_text("bad.obj", text), &m, &err);
    assert_true(st != HK_OK);
    hk_assert_contains(err.message, phrase);
    assert_null(m.positions);
}

static void test_obj_errors(void **state)
{
    (void)state;
    expect_obj_error("v 0 0 0\nv 1 0 0\nf 1 2 3\n", "bad.obj:3: index out of range in face corner '3'");
    expect_obj_error("v 0 0\n", "bad.obj:1: 'v' needs three finite numbers");
    expect_obj_error("v 0 0 nan\n", "bad.obj:1:");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "bad.obj:4: a face needs at least 3 corners");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 x 3\n", "malformed face corner 'x'");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//7 2 3\n", "index out of range");
    expect_obj_error("# nothing\n", "bad.obj: no vertices");
    expect_obj_error("v 0 0 0\n", "bad.obj: no faces");
    expect_obj_error("", "bad.obj: no vertices");
    hk_Mesh m;
    hk_Error err;
    /* Numbers are decimal, as in the key files: hex floats read as 16 by strtod. */
    expect_obj_error("v 0 0 0\nv 0x10 0 0\nv 0 1 0\nf 1 2 3\n",
                     "bad.obj:2: '0x10' is not a decimal number (value 1 of 'v')");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 0x1p0\nf 1//1 2//1 3//1\n",
                     "bad.obj:4: '0x1p0' is not a decimal number (value 3 of 'vn')");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 inf\n", "bad.obj:4: 'inf' is not a decimal number");
    /* Out of any sane range: the wick vertex at 1e39 that overflowed the strand count. */
    expect_obj_error("v 0 0 0\nv 1e39 0.146 0.031\nv 0 1 0\nf 1 2 3\n",
                     "bad.obj:2: '1e39' is out of range (value 1 of 'v')");
    expect_obj_error("v 0 0 0\nv 0 -1e400 0\n", "bad.obj:2: '-1e400' is out of range");
    expect_obj_error("v 0 0 0\nv 0 0 1000001\n", "bad.obj:2: '1000001' is out of range");
    const char *big = "v 0 0 0\nv 1e6 0 0\nv 0 -1e6 0\nf 1 2 3\n"; /* the bound itself is fine */
    assert_int_equal(hk_obj_load(hk_test_write_text("big.obj", big), &m, &err), HK_OK);
    hk_mesh_free(&m);
    /* A normal index of 0 or -(count+1) is as wrong as a vertex index of 0 (they were
     * dropped silently), and so is a texture index of 0. */
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//0 2//1 3//1\n",
                     "bad.obj:5: index out of range in face corner '1//0'");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//-2 3//1\n",
                     "bad.obj:5: index out of range in face corner '2//-2'");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1/1/1 2/0/1 3/1/1\n",
                     "bad.obj:5: index out of range in face corner '2/0/1'");
    expect_obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "bad.obj:4: index out of range in face corner '0'");
    const char *neg = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-1 2//1 3//-1\n";
    assert_int_equal(hk_obj_load(hk_test_write_text("neg.obj", neg), &m, &err), HK_OK);
    hk_mesh_free(&m);
    const char bin[] = "v 0 0 0\nf\0\1\2";
    assert_int_equal(hk_obj_load(hk_test_write_file("bin.obj", bin, sizeof bin), &m, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "bin.obj:2: not a text file");
    assert_int_equal(hk_obj_load("/nonexistent.obj", &m, &err), HK_ERR_IO);
}

static void test_visuality(void **state)
{
    (void)state;
    /* Thesis Appendix B sample. */
    const char *text = "# Blond 0.863 0.549 0.000\nAmbientColor 0.392 0.584 0.929\nDiffuseColor 0.471 0.235 0.000\n"
                       "SpecularColor 0.200 0.200 0.200\nGlossiness 60\n";
    hk_Visuality v;
    hk_Error err;
    assert_int_equal(hk_visuality_load(hk_test_write_text("visuality.txt", text), &v, &err), HK_OK);
    hk_assert_near(v.ambient.z, 0.929, 0);
    hk_assert_near(v.diffuse.x, 0.471, 0);
    hk_assert_near(v.glossiness, 60, 0);
    assert_int_equal(hk_visuality_load(hk_test_write_text("v.txt", "Glossiness 0\n"), &v, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "v.txt:1: Glossiness must be in (0, 100000]");
    assert_int_equal(hk_visuality_load(hk_test_write_text("v.txt", "DiffuseColor 1 -1 0\n"), &v, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "v.txt:1: DiffuseColor components");
    assert_int_equal(hk_visuality_load(hk_test_write_text("v.txt", "Shine 3\n"), &v, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "unknown key 'Shine'");
}

static void test_setup(void **state)
{
    (void)state;
    /* Files next to the setup, named relative to it. */
    hk_test_write_text("hairstyle.txt", "x");
    hk_test_write_text("wick.obj", "x");
    hk_test_write_text("collision.txt", "x");
    const char *text = "# thesis Appendix B style\nLoad false\nSave TRUE\nSaveFile \"out dir/h1.hair\"\n"
                       "HairstyleInfo hairstyle.txt\nCollisionInfo collision.txt\nWickModel wick.obj\n"
                       "HeadVert Assets/Shaders/Phong_Shadow.vert\n";
    hk_Setup s;
    hk_Error err;
    assert_int_equal(hk_setup_load(hk_test_write_text("setup.txt", text), &s, &err), HK_OK);
    assert_false(s.load);
    assert_true(s.save);
    char expect[600];
    snprintf(expect, sizeof expect, "%s/out dir/h1.hair", hk_test_tmpdir());
    assert_string_equal(s.save_file, expect);
    snprintf(expect, sizeof expect, "%s/wick.obj", hk_test_tmpdir());
    assert_string_equal(s.wick_model, expect);
    assert_null(s.visuality);
    /* The viewer's shaders: resolved, not required to exist (the CPU jobs ignore them). */
    snprintf(expect, sizeof expect, "%s/Assets/Shaders/Phong_Shadow.vert", hk_test_tmpdir());
    assert_string_equal(s.head_vert, expect);
    assert_null(s.hair_frag);
    hk_setup_free(&s);
    /* The rules, each with the setup file's line. */
    struct {
        const char *text, *phrase;
    } bad[] = {
        {"Load true\n", "setup.txt:1: Load is true but no LoadFile is given"},
        {"Load true\nLoadFile missing.hair\n", "setup.txt:2: LoadFile '"},
        {"HairstyleInfo hairstyle.txt\n", "setup.txt: missing key 'WickModel'"},
        {"WickModel wick.obj\nHairstyleInfo nowhere.txt\n", "setup.txt:2: HairstyleInfo '"},
        {"HairModel wick.obj\nHairstyleInfo hairstyle.txt\nSave yes\n", "setup.txt:3: Save is true but no SaveFile"},
        {"Load maybe\n", "setup.txt:1: 'Load' must be true or false"},
        {"Colour red\n", "setup.txt:1: unknown key 'Colour'"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        hk_Status st = hk_setup_load(hk_test_write_text("setup.txt", bad[i].text), &s, &err);
        assert_true(st != HK_OK);
        hk_assert_contains(err.message, bad[i].phrase);
        assert_null(s.wick_model);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obj_forms),  cmocka_unit_test(test_obj_face_normals),
        cmocka_unit_test(test_obj_errors), cmocka_unit_test(test_visuality),
        cmocka_unit_test(test_setup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
