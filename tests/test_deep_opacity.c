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
 *    point at 14 mm, in front of the sheet at 20 mm, in its shadow.
 *  - test_thin_columns: the map's rasteriser (hk_raster_segment_thin) visits only the
 *    columns its test on t can accept; it must emit the same fragments, bit for bit,
 *    as the walk over the wider range it had before (copied here as the reference),
 *    for random segments, ends on pixel centres and edges, and clips; and every
 *    fragment must lie in the segment's box for the map's bins
 *    (hk_segment_box_thin_inline). */
#include "hk_test.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/render.h"
#include "render/raster_inline.h"
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

/* Fragments of one segment, as emitted. */
typedef struct Emitted {
    int count;
    int x[512], y[512];
    float t[512], alpha[512];
} Emitted;

static void record(void *user, int x, int y, float t, float alpha)
{
    Emitted *e = user;
    assert_true(e->count < 512);
    e->x[e->count] = x, e->y[e->count] = y, e->t[e->count] = t, e->alpha[e->count] = alpha;
    e->count++;
}

/* hk_raster_segment_thin before its columns were narrowed (a copy): every column from
 * the segment's lower end less 1/2 to its upper end rounded up, each tested on t. */
static void thin_reference(hk_RasterPoint a, hk_RasterPoint b, float width, hk_Rect clip, Emitted *out)
{
    const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    if (!(len2 > 1e-12f) || !(width > 0.0f)) return;
    const int x_major = fabsf(dx) >= fabsf(dy);
    const float major_a = x_major ? a.x : a.y, d_major = x_major ? dx : dy;
    const float minor_a = x_major ? a.y : a.x, d_minor = x_major ? dy : dx;
    float alpha = width * sqrtf(len2) / fabsf(d_major);
    if (alpha > 1.0f) alpha = 1.0f;
    const int lo_major = x_major ? clip.x0 : clip.y0, hi_major = x_major ? clip.x1 : clip.y1;
    const int lo_minor = x_major ? clip.y0 : clip.x0, hi_minor = x_major ? clip.y1 : clip.x1;
    const int m0 = ifloor(clampf(minf(major_a, major_a + d_major) - 0.5f, (float)lo_major, (float)hi_major));
    const int m1 = iceil(clampf(maxf(major_a, major_a + d_major), (float)lo_major - 1.0f, (float)hi_major - 1.0f));
    for (int m = m0; m <= m1; m++) {
        const float t = ((float)m + 0.5f - major_a) / d_major;
        if (!(t >= 0.0f && t < 1.0f)) continue;
        const float minor = minor_a + t * d_minor;
        if (!(minor >= (float)lo_minor && minor < (float)hi_minor)) continue;
        const int n = (int)minor;
        if (n < lo_minor || n >= hi_minor) continue;
        record(out, x_major ? m : n, x_major ? n : m, t, alpha);
    }
}

/* A coordinate: anywhere in [-20, 140), or on a pixel centre or edge (where the test
 * on t decides at its bounds), or just beside one. */
static float coordinate(void)
{
    const double u = hk_test_uniform(), v = -20.0 + 160.0 * hk_test_uniform();
    if (u < 0.4) return (float)v;
    const float whole = (float)floor(v);
    if (u < 0.6) return whole + 0.5f;
    if (u < 0.8) return whole;
    return nextafterf(whole + 0.5f, u < 0.9 ? 1e9f : -1e9f);
}

static void test_thin_columns(void **state)
{
    (void)state;
    static Emitted got, want;
    long fragments = 0, boxed_area = 0;
    for (int k = 0; k < 200000; k++) {
        const int x0 = (int)(100.0 * hk_test_uniform()), y0 = (int)(100.0 * hk_test_uniform());
        const hk_Rect clip = {x0, y0, x0 + 1 + (int)(32.0 * hk_test_uniform()),
                              y0 + 1 + (int)(32.0 * hk_test_uniform())};
        hk_RasterPoint a = {coordinate(), coordinate(), 1.0f, 1.0f}, b = a;
        const double kind = hk_test_uniform();
        if (kind < 0.7) { /* short ones start near the clip (its pixel grid kept) */
            a.x += (float)(x0 - (int)floorf(a.x) + (int)(40.0 * hk_test_uniform()) - 4);
            a.y += (float)(y0 - (int)floorf(a.y) + (int)(40.0 * hk_test_uniform()) - 4);
        }
        if (kind < 0.5) { /* short, as a hair's segments in the map: a few texels */
            b.x = a.x + (float)(12.0 * hk_test_uniform() - 6.0), b.y = a.y + (float)(12.0 * hk_test_uniform() - 6.0);
        } else if (kind < 0.7) { /* very short */
            b.x = a.x + (float)(1e-3 * (hk_test_uniform() - 0.5)),
            b.y = a.y + (float)(1e-3 * (hk_test_uniform() - 0.5));
        } else if (kind < 0.8) { /* along an axis */
            if (hk_test_uniform() < 0.5)
                b.x = coordinate();
            else
                b.y = coordinate();
        } else {
            b.x = coordinate(), b.y = coordinate();
        }
        const float width = (float)(2.0 * hk_test_uniform());
        got.count = want.count = 0;
        hk_raster_segment_thin(a, b, width, clip, record, &got);
        thin_reference(a, b, width, clip, &want);
        assert_int_equal(got.count, want.count);
        for (int i = 0; i < got.count; i++) {
            assert_int_equal(got.x[i], want.x[i]);
            assert_int_equal(got.y[i], want.y[i]);
            assert_memory_equal(&got.t[i], &want.t[i], sizeof(float));
            assert_memory_equal(&got.alpha[i], &want.alpha[i], sizeof(float));
        }
        fragments += got.count;
        /* The box the map's bins take (hk_segment_box_thin_inline) holds every
         * fragment drawn anywhere in the image: a tile outside it gets none. */
        const hk_Rect image = {0, 0, 128, 128};
        got.count = 0;
        hk_raster_segment_thin(a, b, width, image, record, &got);
        hk_Rect box = {0, 0, 0, 0};
        const int boxed = hk_segment_box_thin_inline(a, b, image.x1, image.y1, &box);
        if (got.count > 0) assert_true(boxed);
        for (int i = 0; i < got.count; i++) {
            assert_true(got.x[i] >= box.x0 && got.x[i] < box.x1);
            assert_true(got.y[i] >= box.y0 && got.y[i] < box.y1);
        }
        boxed_area += boxed ? (long)(box.x1 - box.x0) * (box.y1 - box.y0) : 0;
    }
    print_message("boxes of %ld pixels in all\n", boxed_area);
    print_message("%ld fragments, the same\n", fragments);
    assert_true(fragments > 100000); /* the segments reach their clips (137,000) */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_layer_layout),
        cmocka_unit_test(test_transmittance_behind_sheets),
        cmocka_unit_test(test_thin_columns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
