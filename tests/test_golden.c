/* Golden pictures of the renderer (issue 13, item 5): a small groomed head drawn with
 * Kajiya-Kay and Marschner shading, with and without shadows (with dual scattering, the
 * default), and with Kajiya-Kay and single scattering (the thesis's scatter floor),
 * compared with the pictures stored in tests/golden/.
 *
 * The reference is the stored pictures themselves: what the renderer drew when they
 * were made (scripts/refresh-golden.sh, which runs this test with HK_REFRESH_GOLDEN
 * naming the folder to write them to; tests/README.md says when to refresh), looked at
 * when stored. They catch changes of the shading, the shadows, the framing or the hair
 * that the formula-level tests (test_render, test_marschner, test_deep_opacity) do not
 * see. A picture that fails is written to the build folder (golden-NAME.png) to be
 * looked at.
 *
 * The scene: examples/default's hairstyle, collision shapes and colours on the
 * project's head, grown on the 201-guide wick (assets/wick-200.obj) at HairDensity 30,
 * about 15,000 strands of 41 points, seen from behind (the hair fills the picture) and
 * lit over the camera's shoulder; 160 x 120 pixels, a 512-texel shadow map; about
 * 13 kB a picture.
 *
 * Tolerance, per picture: a pixel differs when one of its channels is more than 2
 * levels (of 255) off; at most 0.2 % of the pixels (38) may differ, and the mean
 * absolute difference over all channels must stay under 0.1 level. Why: the pictures do
 * not depend on the thread count (test_render), but another compiler, optimisation
 * level, instruction set or libm changes floats in their last bits, which can move a
 * channel by a level here and there, or more on the few pixels where a fragment's
 * coverage or depth order flips. Measured: a clang 14 build at -O2 -march=native
 * -ffp-contract=fast (FMA instructions throughout the library) and gcc 12's -O1
 * sanitizer build (`make asan`), each against gcc 12 at -O2, gave the same pixels
 * (difference 0); the margin is left for other machines and libms. What fails, on the
 * Kajiya-Kay picture with shadows, measured before dual scattering (the picture now
 * kajiya-kay-single, which dual scattering left with the same pixels; pixels that
 * differ, mean difference in levels):
 * Marschner shading instead, 3416, 0.88 (checked below between the four pictures, as is
 * turning the shadows off: 7230, 5.9); the deep opacity layers equally deep
 * (light_maps.c), 4299, 0.66; the light turned by 1 degree, 333, 0.19; the scatter floor
 * 0.3 instead of 0.25, 208, 0.22; the shadow map at 256 or 1024 texels instead of 512,
 * 351 and 332; Glossiness 50 instead of 60, 24, 0.108. What passes: Glossiness 55 (0,
 * 0.051), the scatter floor 0.27 (2, 0.087), and each strand's own brightness
 * (strand_variation 0 instead of 0.15: 0, 0.065; at this size a pixel averages many
 * strands, so a variation from strand to strand averages out). */
#include "hk_test.h"

#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/groom.h"
#include "hairkit/render.h"

enum { WIDTH = 160, HEIGHT = 120 };

/* Tolerance (see the top). */
#define LEVELS_PER_PIXEL 2     /* a pixel differs when a channel is more than this off */
#define PIXEL_FRACTION   0.002 /* at most this fraction of the pixels may differ */
#define MEAN_LEVELS      0.1   /* mean absolute difference of the channels, below this */

typedef struct Scene {
    hk_HairFile hair;
    hk_Mesh head;
    hk_Visuality vis;
} Scene;

static int setup(void **state)
{
    Scene *sc = calloc(1, sizeof *sc);
    assert_non_null(sc);
    hk_Hairstyle style;
    hk_CollisionSet collision = {0};
    hk_Mesh wick;
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/default/hairstyle.txt", &style, &err), HK_OK);
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/default/collision.txt", &collision, &err), HK_OK);
    assert_int_equal(hk_visuality_load(HK_SOURCE_DIR "/examples/default/visuality.txt", &sc->vis, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/wick-200.obj", &wick, &err), HK_OK);
    assert_int_equal(hk_obj_load(HK_SOURCE_DIR "/assets/head.obj", &sc->head, &err), HK_OK);
    style.interpolation.hair_density = 30.0;
    hk_GroomDef o = hk_default_groom_def();
    hk_Groom g;
    assert_int_equal(
        hk_groom_grow(&style.strand, &style.interpolation, collision.shapes, collision.count, &wick, &o, &g, &err),
        HK_OK);
    assert_int_equal(hk_groom_to_hair(&g, &style.strand, &sc->hair, &err), HK_OK);
    hk_groom_free(&g);
    hk_mesh_free(&wick);
    hk_collision_free(&collision);
    hk_hairstyle_free(&style);
    *state = sc;
    return 0;
}

static int teardown(void **state)
{
    Scene *sc = *state;
    hk_hair_free(&sc->hair);
    hk_mesh_free(&sc->head);
    free(sc);
    return 0;
}

/* 8-bit RGB pixels of a PNG, read with libpng (NULL if it cannot be read). */
static uint8_t *read_png(const char *path, int *w, int *h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path)) return NULL;
    img.format = PNG_FORMAT_RGB;
    uint8_t *rgb = malloc(PNG_IMAGE_SIZE(img));
    if (!rgb || !png_image_finish_read(&img, NULL, rgb, 0, NULL)) {
        png_image_free(&img);
        free(rgb);
        return NULL;
    }
    *w = (int)img.width, *h = (int)img.height;
    return rgb;
}

static void write_png(const char *path, const uint8_t *rgb, int w, int h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = (png_uint_32)w, img.height = (png_uint_32)h;
    img.format = PNG_FORMAT_RGB;
    if (!png_image_write_to_file(&img, path, 0, rgb, 0, NULL)) fail_msg("cannot write %s: %s", path, img.message);
}

/* The picture as `hairkit render` writes it (hk_render_write_png: 8-bit sRGB), read
 * back. */
static uint8_t *render(const Scene *sc, const hk_RenderDef *o)
{
    hk_Canvas img;
    hk_Error err;
    if (hk_render(&sc->hair, &sc->head, &sc->vis, o, &img, NULL, &err) != HK_OK) fail_msg("render: %s", err.message);
    char path[4096];
    snprintf(path, sizeof path, "%s/picture.png", hk_test_tmpdir());
    assert_int_equal(hk_render_write_png(&img, path, &err), HK_OK);
    hk_canvas_free(&img);
    int w, h;
    uint8_t *rgb = read_png(path, &w, &h);
    assert_non_null(rgb);
    assert_true(w == WIDTH && h == HEIGHT);
    return rgb;
}

typedef struct Difference {
    int pixels;  /* pixels with a channel more than LEVELS_PER_PIXEL apart */
    double mean; /* mean absolute difference over all channels (levels) */
    int largest; /* largest difference of a channel (levels) */
} Difference;

static Difference compare(const uint8_t *a, const uint8_t *b)
{
    Difference d = {0, 0.0, 0};
    long sum = 0;
    for (int i = 0; i < WIDTH * HEIGHT; i++) {
        int most = 0;
        for (int c = 0; c < 3; c++) {
            const int x = abs((int)a[3 * i + c] - (int)b[3 * i + c]);
            sum += x;
            most = x > most ? x : most;
        }
        d.pixels += most > LEVELS_PER_PIXEL;
        d.largest = most > d.largest ? most : d.largest;
    }
    d.mean = (double)sum / (3.0 * WIDTH * HEIGHT);
    return d;
}

static int within_tolerance(Difference d)
{
    return d.pixels <= PIXEL_FRACTION * WIDTH * HEIGHT && d.mean < MEAN_LEVELS;
}

/* The picture of options o against tests/golden/NAME.png; with HK_REFRESH_GOLDEN set,
 * writes it there instead. *rgb receives the picture (to free); returns 0 when it is
 * not within the tolerance of the stored one (and writes it to the build folder). */
static int check_golden(const Scene *sc, const char *name, const hk_RenderDef *o, uint8_t **rgb)
{
    *rgb = render(sc, o);
    char path[4096];
    const char *refresh = getenv("HK_REFRESH_GOLDEN");
    if (refresh && *refresh) {
        snprintf(path, sizeof path, "%s/%s.png", refresh, name);
        write_png(path, *rgb, WIDTH, HEIGHT);
        print_message("wrote %s\n", path);
        return 1;
    }
    snprintf(path, sizeof path, "%s/tests/golden/%s.png", HK_SOURCE_DIR, name);
    int w = 0, h = 0;
    uint8_t *golden = read_png(path, &w, &h);
    if (!golden) fail_msg("cannot read %s (scripts/refresh-golden.sh makes it)", path);
    assert_true(w == WIDTH && h == HEIGHT);
    const Difference d = compare(*rgb, golden);
    free(golden);
    print_message("%-22s %4d pixels differ by more than %d levels (allowed %d), mean difference %.3f levels "
                  "(allowed %.2f), largest %d\n",
                  name, d.pixels, LEVELS_PER_PIXEL, (int)(PIXEL_FRACTION * WIDTH * HEIGHT), d.mean, MEAN_LEVELS,
                  d.largest);
    if (within_tolerance(d)) return 1;
    snprintf(path, sizeof path, "%s/golden-%s.png", HK_BINARY_DIR, name);
    write_png(path, *rgb, WIDTH, HEIGHT);
    print_error("%s differs from tests/golden/%s.png; the new picture is %s\n", name, name, path);
    return 0;
}

static hk_RenderDef options(hk_Shading shading, int shadows, hk_Scattering scattering)
{
    hk_RenderDef o = hk_default_render_def();
    o.width = WIDTH, o.height = HEIGHT;
    o.shading = shading;
    o.shadows = shadows;
    o.scattering = scattering;
    /* The 512-texel map the pictures were stored with (the default gives 96 at this
     * size since issue 18; these pictures watch the shading and the shadows, and
     * test_render the map's size). */
    o.shadow_map_size = 512;
    o.strand_lod = 0;                              /* every strand, as stored (the level of detail: test_render) */
    o.azimuth_deg = 140.0, o.elevation_deg = 15.0; /* from behind, on the hair */
    o.light_azimuth_deg = 160.0, o.light_elevation_deg = 40.0; /* over the camera's shoulder */
    return o;
}

static void test_golden_pictures(void **state)
{
    const Scene *sc = *state;
    enum { CASES = 5 };
    const struct {
        const char *name;
        hk_Shading shading;
        int shadows;
        hk_Scattering scattering;
    } cases[CASES] = {
        {"kajiya-kay", HK_SHADING_KAJIYA_KAY, 1, HK_SCATTERING_DUAL},
        {"kajiya-kay-no-shadows", HK_SHADING_KAJIYA_KAY, 0, HK_SCATTERING_DUAL},
        {"marschner", HK_SHADING_MARSCHNER, 1, HK_SCATTERING_DUAL},
        {"marschner-no-shadows", HK_SHADING_MARSCHNER, 0, HK_SCATTERING_DUAL},
        {"kajiya-kay-single", HK_SHADING_KAJIYA_KAY, 1, HK_SCATTERING_SINGLE}, /* the thesis's floor */
    };
    uint8_t *rgb[CASES];
    int failed = 0;
    for (int k = 0; k < CASES; k++) {
        hk_RenderDef o = options(cases[k].shading, cases[k].shadows, cases[k].scattering);
        failed += !check_golden(sc, cases[k].name, &o, &rgb[k]);
    }
    if (failed)
        fail_msg("%d of the %d pictures differ from tests/golden/; if the change is meant, look at the new "
                 "pictures and store them with scripts/refresh-golden.sh",
                 failed, CASES);
    /* The tolerance tells the pictures apart: another shading model, the shadows
     * turned off or single scattering instead of dual would fail. */
    for (int a = 0; a < CASES; a++)
        for (int b = a + 1; b < CASES; b++) {
            const Difference d = compare(rgb[a], rgb[b]);
            print_message("%s against %s: %d pixels differ, mean %.2f levels\n", cases[a].name, cases[b].name, d.pixels,
                          d.mean);
            assert_false(within_tolerance(d));
        }
    for (int k = 0; k < CASES; k++) free(rgb[k]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_golden_pictures),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
