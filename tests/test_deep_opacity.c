/* The deep opacity map of the light (src/render/light_maps.c; Yuksel & Keyser, "Deep
 * Opacity Maps", 2008; thesis 004 §4.1.6), against its documented layout (issue 13,
 * item 5). The references are docs/rendering.md ("The passes", 1) and the options in
 * include/hairkit/render.h: per texel, z0 is the depth where the hair begins; layer k
 * spans [z0 + S(k-1), z0 + S(k)) with S the running sum of the layer depths, the first
 * layer_size deep (2 mm when <= 0) and each next one twice as deep as the one before
 * (2, 4, 8, 16 mm by default, so S = 2, 6, 14, 30 mm); every fragment adds its opacity
 * to its layer, the last layer taking everything beyond; a lookup interpolates the
 * running sums linearly within a layer.
 *
 *  - test_layer_layout: the layer ends of a built map are S(k), for the default layer
 *    size and count, a 1 mm first layer, and 6 layers.
 *  - test_transmittance_behind_sheets: four sheets of hair seen from a light straight
 *    above, 0, 3, 9 and 20 mm below the first (one in each layer of the default
 *    layout). What reaches a point is the transmittance exp(-Omega) of the opacity
 *    Omega in front of it (docs/rendering.md, "Shading"). A point at the end of a layer
 *    lies behind exactly the sheets in that layer and the ones before, so it must
 *    receive their opacity: at 6, 14 and 30 mm behind the first sheet, that of the
 *    first 2, 3 and 4 sheets, each measured alone from far behind them (40 mm, beyond
 *    the last layer) in a map of those sheets only (the same framing). Transmittance
 *    therefore falls with every sheet passed: 6 mm > 14 mm > 30 mm. Equally deep layers
 *    (2, 4, 6, 8 mm) put the sheets at 9 and 20 mm both in the last layer, and the
 *    point at 14 mm, in front of the sheet at 20 mm, in its shadow. */
#include "hk_test.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/render.h"
#include "render/render_internal.h"

enum { POINTS = 11 };

/* Sheets of straight strands along x, 0.5 mm apart in z over 10 cm x 10 cm, in the
 * planes y = -depth[i] (the first `count` of them). */
static void make_sheets(hk_HairFile *h, const double *depth, int count)
{
    const int per_sheet = 201;
    uint32_t *counts = malloc(sizeof *counts * (size_t)(per_sheet * count));
    assert_non_null(counts);
    for (int s = 0; s < per_sheet * count; s++) counts[s] = POINTS;
    assert_int_equal(hk_hair_alloc(h, (uint32_t)(per_sheet * count), counts, NULL), HK_OK);
    free(counts);
    h->default_thickness = 1e-4f;
    for (int s = 0; s < per_sheet * count; s++)
        for (int p = 0; p < POINTS; p++) {
            float *q = h->points + 3 * ((size_t)s * POINTS + (size_t)p);
            q[0] = (float)(-0.05 + 0.1 * p / (POINTS - 1));
            q[1] = (float)(-depth[s / per_sheet]);
            q[2] = (float)(-0.05 + 0.0005 * (s % per_sheet));
        }
}

/* The light's maps of hair h lit from straight above (the scene's box fixed, so that
 * every map has the same texels whichever sheets it holds), as hk_render builds them. */
static void build_maps(const hk_HairFile *h, const hk_RenderDef *o, hk_LightMaps *m)
{
    const hk_Visuality v = hk_default_visuality();
    hk_Scene sc;
    memset(&sc, 0, sizeof sc);
    sc.hair = h, sc.head = NULL, sc.vis = &v, sc.opt = o;
    sc.light_dir = hk_v3(0, 1, 0);
    sc.lo = hk_v3(-0.05, -0.02, -0.05), sc.hi = hk_v3(0.05, 0.0, 0.05);
    sc.thickness = h->default_thickness;
    sc.threads = hk_render_threads(o);
    hk_scene_thickness(&sc, 1);
    uint8_t *seg = malloc(h->point_count);
    assert_non_null(seg);
    sc.segment_count = hk_segment_starts(h, 1, seg, sc.threads);
    memset(m, 0, sizeof *m);
    hk_Error err;
    assert_int_equal(hk_light_maps_build(&sc, seg, m, NULL, &err), HK_OK);
    free(seg);
}

static hk_RenderDef light_options(void)
{
    hk_RenderDef o = hk_default_render_def();
    o.shadow_map_size = 128; /* texels of 1.1 mm: two or three strands of a sheet each */
    o.light_azimuth_deg = 0.0, o.light_elevation_deg = 90.0;
    return o;
}

static void test_layer_layout(void **state)
{
    (void)state;
    const double depth[1] = {0.0};
    hk_HairFile h;
    make_sheets(&h, depth, 1);
    struct {
        double layer_size;
        int layers;
        double ends_mm[6];
    } cases[3] = {
        {0.0, 4, {2, 6, 14, 30}},          /* default: 2, 4, 8, 16 mm deep */
        {0.001, 4, {1, 3, 7, 15}},         /* 1, 2, 4, 8 mm */
        {0.0, 6, {2, 6, 14, 30, 62, 126}}, /* 2 ... 64 mm */
    };
    for (int c = 0; c < 3; c++) {
        hk_RenderDef o = light_options();
        o.layer_size = cases[c].layer_size, o.opacity_layers = cases[c].layers;
        hk_LightMaps m;
        build_maps(&h, &o, &m);
        assert_int_equal(m.layers, cases[c].layers);
        for (int k = 0; k < cases[c].layers; k++) hk_assert_rel(m.layer_end[k], 1e-3 * cases[c].ends_mm[k], 1e-6, 0.0);
        hk_light_maps_free(&m);
    }
    hk_hair_free(&h);
}

/* Opacity in front of the point `depth_mm` below the first sheet (at a fixed spot away
 * from the sheets' edges and not on a texel centre). */
static double opacity_at(const hk_LightMaps *m, double depth_mm)
{
    double visible, opacity;
    hk_light_lookup(m, hk_v3(0.0123, -1e-3 * depth_mm, 0.0077), &visible, &opacity);
    hk_assert_near(visible, 1.0, 1e-6); /* no head: the bilinear weights of the lit texels */
    return opacity;
}

static void test_transmittance_behind_sheets(void **state)
{
    (void)state;
    const double depth[4] = {0.0, 0.003, 0.009, 0.020};
    const hk_RenderDef o = light_options();
    /* Opacity of the first k sheets, from behind them all. */
    double alone[5] = {0, 0, 0, 0, 0};
    for (int k = 1; k <= 4; k++) {
        hk_HairFile h;
        make_sheets(&h, depth, k);
        hk_LightMaps m;
        build_maps(&h, &o, &m);
        alone[k] = opacity_at(&m, 40.0);
        hk_light_maps_free(&m);
        hk_hair_free(&h);
        assert_true(alone[k] > alone[k - 1] + 0.05); /* each sheet is seen */
    }
    hk_HairFile h;
    make_sheets(&h, depth, 4);
    hk_LightMaps m;
    build_maps(&h, &o, &m);
    const double probe_mm[3] = {6.0, 14.0, 30.0};
    double transmittance[3];
    for (int i = 0; i < 3; i++) {
        const double omega = opacity_at(&m, probe_mm[i]);
        transmittance[i] = exp(-omega);
        print_message("%4.1f mm behind the first sheet, behind %d sheets: opacity %.4f (the %d sheets alone %.4f), "
                      "transmittance %.4f\n",
                      probe_mm[i], i + 2, omega, i + 2, alone[i + 2], transmittance[i]);
        hk_assert_rel(omega, alone[i + 2], 1e-5, 1e-9);
    }
    /* Every sheet passed takes light away. */
    assert_true(transmittance[1] < 0.97 * transmittance[0]);
    assert_true(transmittance[2] < 0.97 * transmittance[1]);
    hk_light_maps_free(&m);
    hk_hair_free(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layer_layout),
        cmocka_unit_test(test_transmittance_behind_sheets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
