/* The scene of a setup file (src/scene/scene.c): the parts asked for and only those,
 * the hair grown or loaded and saved as the setup says, errors that leave the scene
 * safe to free, and the same hair and picture as the pieces called one by one. */
#include "hk_test.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/scene.h"

static void test_parts(void **state)
{
    (void)state;
    hk_Scene s;
    hk_Error err;
    const char *setup = hk_test_light_setup();
    /* The setup alone, then the rendering parts, then the grooming parts. */
    assert_int_equal(hk_scene_load(setup, 0, &s, &err), HK_OK);
    assert_int_equal(s.parts, 0u);
    assert_int_equal(s.head.vertex_count, 0);
    assert_int_equal(s.wick.vertex_count, 0);
    assert_int_equal(s.collision.count, 0);
    assert_string_equal(s.setup_path, setup);
    assert_int_equal(hk_scene_load_parts(&s, HK_SCENE_RENDERING, &err), HK_OK);
    assert_true(s.head.vertex_count > 0);
    assert_int_equal(s.wick.vertex_count, 0);
    assert_int_equal(hk_scene_load_parts(&s, HK_SCENE_HAIR, &err), HK_OK); /* Load false: grooming */
    assert_int_equal(s.parts, (unsigned)HK_SCENE_ALL);
    assert_int_equal(s.wick.vertex_count, 201); /* assets/wick-200.obj */
    assert_true(s.collision.count > 0);
    hk_assert_near(s.style.interpolation.hair_density, 4.0, 0.0); /* hk_test_light_setup's hairstyle */
    hk_scene_free(&s);
    hk_scene_free(&s); /* freeing twice is harmless: the scene is empty after the first */
}

static void test_errors(void **state)
{
    (void)state;
    hk_Scene s;
    hk_Error err;
    /* Load true with no HairstyleInfo: the setup is fine, the hairstyle cannot be read. */
    char text[4096];
    snprintf(text, sizeof text, "Load true\nLoadFile \"%s/assets/wick-200.obj\"\n", HK_SOURCE_DIR);
    const char *path = hk_test_write_text("loadsetup.txt", text);
    assert_int_equal(hk_scene_load(path, HK_SCENE_HAIR, &s, &err), HK_OK); /* Load true: nothing to groom */
    assert_int_equal(hk_scene_load_parts(&s, HK_SCENE_HAIRSTYLE, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "loadsetup.txt");
    hk_assert_contains(err.message, "HairstyleInfo");
    assert_int_equal(s.parts, 0u); /* the scene keeps what it had */
    hk_scene_free(&s);
    assert_int_equal(hk_scene_load(path, HK_SCENE_WICK, &s, &err), HK_ERR_PARSE);
    hk_assert_contains(err.message, "WickModel");
    assert_null(s.setup_path); /* emptied */
    hk_scene_free(&s);
    /* A broken part: the error names its file and line, parts read before it in the same
     * call are dropped. */
    const char *bad_head = hk_test_write_text("badhead.obj", "v 0 0 0\nv 1 0\n");
    snprintf(
        text, sizeof text,
        "HairstyleInfo \"%s/examples/default/hairstyle.txt\"\nHeadModel \"%s\"\nWickModel \"%s/assets/wick-200.obj\"\n",
        HK_SOURCE_DIR, bad_head, HK_SOURCE_DIR);
    path = hk_test_write_text("badsetup.txt", text);
    assert_int_equal(hk_scene_load(path, 0, &s, &err), HK_OK);
    assert_true(hk_scene_load_parts(&s, HK_SCENE_ALL, &err) != HK_OK);
    hk_assert_contains(err.message, "badhead.obj:2");
    assert_int_equal(s.parts, 0u);
    assert_int_equal(s.style.strand.element_count, hk_default_hairstyle().strand.element_count);
    hk_scene_free(&s);
    /* Growing needs the grooming parts. */
    assert_int_equal(hk_scene_load(hk_test_light_setup(), HK_SCENE_RENDERING, &s, &err), HK_OK);
    hk_HairFile hair;
    assert_int_equal(hk_scene_hair(&s, NULL, &hair, NULL, &err), HK_ERR_INVALID);
    assert_int_equal(hair.strand_count, 0u);
    hk_scene_free(&s);
}

/* The scene's hair and picture are those of the calls it stands for, byte for byte, and
 * Save true writes the hair that a Load true setup reads back. */
static void test_same_as_pieces(void **state)
{
    (void)state;
    hk_Error err;
    hk_Scene s;
    assert_int_equal(hk_scene_load(hk_test_light_setup(), HK_SCENE_ALL, &s, &err), HK_OK);
    hk_GroomDef go = hk_default_groom_def();
    go.threads = 2;
    hk_HairFile a, b;
    hk_SceneHairReport report;
    assert_int_equal(hk_scene_hair(&s, &go, &a, &report, &err), HK_OK);
    assert_int_equal(report.grown, 1);
    assert_int_equal(report.guides, 201);
    assert_int_equal((uint32_t)(report.guides + report.strands), a.strand_count);
    hk_Groom g;
    assert_int_equal(hk_groom_grow(&s.style.strand, &s.style.interpolation, s.collision.shapes, s.collision.count,
                                   &s.wick, &go, &g, &err),
                     HK_OK);
    assert_int_equal(hk_groom_to_hair(&g, &s.style.strand, &b, &err), HK_OK);
    assert_int_equal(a.point_count, b.point_count);
    assert_memory_equal(a.points, b.points, sizeof(float) * 3 * a.point_count);
    hk_groom_free(&g);
    hk_RenderDef ro = hk_default_render_def();
    ro.width = 64, ro.height = 48;
    hk_Canvas pa, pb;
    assert_int_equal(hk_scene_render(&s, &a, &ro, &pa, NULL, &err), HK_OK);
    assert_int_equal(hk_render(&a, &s.head, &s.visuality, &ro, &pb, NULL, &err), HK_OK);
    assert_memory_equal(pa.rgb, pb.rgb, sizeof(float) * 3 * 64 * 48);
    hk_canvas_free(&pa);
    hk_canvas_free(&pb);
    hk_hair_free(&b);
    hk_scene_free(&s);

    /* Save true, then Load true reads the same hair. */
    char saved[512], text[4096];
    snprintf(saved, sizeof saved, "%s/saved.hair", hk_test_tmpdir());
    size_t size;
    char *light = hk_test_read_file(hk_test_light_setup(), &size);
    snprintf(text, sizeof text, "%sSave true\nSaveFile \"%s\"\n", light, saved);
    free(light);
    assert_int_equal(hk_scene_load(hk_test_write_text("savesetup.txt", text), HK_SCENE_HAIR, &s, &err), HK_OK);
    assert_int_equal(hk_scene_hair(&s, &go, &b, NULL, &err), HK_OK);
    hk_hair_free(&b);
    hk_scene_free(&s);
    snprintf(text, sizeof text, "Load true\nLoadFile \"%s\"\n", saved);
    assert_int_equal(hk_scene_load(hk_test_write_text("loadsaved.txt", text), HK_SCENE_HAIR, &s, &err), HK_OK);
    assert_int_equal(s.parts, 0u); /* nothing grown, nothing read but the setup */
    assert_int_equal(hk_scene_hair(&s, NULL, &b, &report, &err), HK_OK);
    assert_int_equal(report.grown, 0);
    assert_int_equal(a.point_count, b.point_count);
    assert_memory_equal(a.points, b.points, sizeof(float) * 3 * a.point_count);
    hk_hair_free(&a);
    hk_hair_free(&b);
    hk_scene_free(&s);
}

/* A collision file's Mesh line and the setup's HeadCollider: both fields belong to the
 * scene's collision set, in that order (the file's shapes, then the head's), and go
 * with it; a Mesh line that cannot be read fails the collision part with its file and
 * line. */
static void test_collision_meshes(void **state)
{
    (void)state;
    hk_test_write_text("tetra.obj", "v 0 0 0\nv 0.02 0 0\nv 0 0.02 0\nv 0 0 0.02\n"
                                    "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    hk_test_write_text("meshes.txt", "Sphere 0 1 0 0 0 1\nMesh 0.01 10 tetra.obj Styling\n");
    const char *path = hk_test_write_text("meshsetup.txt", "Load true\nLoadFile tetra.obj\n"
                                                           "CollisionInfo meshes.txt\nHeadModel tetra.obj\n"
                                                           "HeadCollider 0 5\n");
    hk_Scene s;
    hk_Error err;
    assert_int_equal(hk_scene_load(path, HK_SCENE_COLLISION, &s, &err), HK_OK);
    assert_int_equal(s.collision.count, 3);
    assert_int_equal(s.collision.field_count, 2);
    assert_int_equal(s.collision.shapes[0].kind, HK_SHAPE_SPHERE);
    assert_ptr_equal(s.collision.shapes[1].field, s.collision.fields[0]);
    assert_ptr_equal(s.collision.shapes[2].field, s.collision.fields[1]);
    assert_int_equal(s.collision.shapes[1].styling, 1);
    assert_int_equal(s.collision.shapes[2].styling, 0);
    hk_assert_near(s.collision.shapes[1].penalty, 10.0, 0.0);
    hk_assert_near(s.collision.shapes[2].penalty, 5.0, 0.0);
    hk_scene_free(&s);

    hk_test_write_text("meshes.txt", "Sphere 0 1 0 0 0 1\nMesh 0.01 10 nowhere.obj\n");
    assert_int_equal(hk_scene_load(path, 0, &s, &err), HK_OK);
    assert_int_equal(hk_scene_load_parts(&s, HK_SCENE_COLLISION, &err), HK_ERR_IO);
    hk_assert_contains(err.message, "meshes.txt:2: Mesh: ");
    hk_assert_contains(err.message, "nowhere.obj: cannot open");
    assert_int_equal(s.collision.count, 0);
    assert_int_equal(s.parts, 0u);
    hk_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parts),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_collision_meshes),
        cmocka_unit_test(test_same_as_pieces),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
