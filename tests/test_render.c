/* The renderer: the pixel of a lit strand against the Kajiya-Kay formula written out
 * here from the paper (Kajiya & Kay 1989, Lansink 2010 §4.1.5), shadows from an
 * occluder in the light's view, sub-pixel coverage against the analytic area of a
 * thin line, determinism across thread counts, no NaN or black frames, a PNG that
 * libpng reads back, and its bytes against the sRGB curve. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hk_test.h"
#include "hairkit/canvas.h"
#include "hairkit/image.h"
#include "hairkit/render.h"
#include "hairkit/rng.h"
#include "render/raster_inline.h"
#include "render/render_internal.h"


/* Straight strands along x in the plane z = z0, `points` points each. */
static void make_strands(hk_HairFile *h, int strands, int points, double half_length, double spacing, double z0)
{
    uint32_t *counts = hk_alloc_array((size_t)strands, sizeof *counts, NULL);
    for (int s = 0; s < strands; s++) counts[s] = (uint32_t)points;
    assert_int_equal(hk_hair_alloc(h, (uint32_t)strands, counts, NULL), HK_OK);
    hk_free(counts);
    for (int s = 0; s < strands; s++)
        for (int p = 0; p < points; p++) {
            float *q = h->points + 3 * ((size_t)s * points + p);
            q[0] = (float)(-half_length + 2.0 * half_length * p / (points - 1));
            q[1] = (float)((s - 0.5 * (strands - 1)) * spacing);
            q[2] = (float)z0;
        }
}

static hk_RenderDef plain_options(int size)
{
    hk_RenderDef o = hk_default_render_def();
    o.width = o.height = size;
    o.shadows = 0;
    o.azimuth_deg = 0.0, o.elevation_deg = 0.0; /* camera on +z looking along -z */
    o.ambient_intensity = 0.0;
    o.strand_variation = 0.0;
    o.background_top = o.background_bottom = hk_v3(0, 0, 0);
    return o;
}

/* The pixel where the renderer's camera sees the origin (the middle of the strand). */
static hk_Vec3 last_eye; /* the camera's position, from the last call */
static size_t origin_pixel(const hk_HairFile *h, const hk_Mesh *head, const hk_RenderDef *o)
{
    hk_Visuality v = hk_default_visuality();
    hk_Scene sc;
    memset(&sc, 0, sizeof sc);
    sc.hair = h, sc.head = head, sc.vis = &v, sc.opt = o;
    sc.threads = hk_render_threads(o);
    sc.lo = hk_v3(1e9, 1e9, 1e9), sc.hi = hk_v3(-1e9, -1e9, -1e9);
    for (uint32_t i = 0; i < h->point_count; i++) {
        hk_Vec3 q = hk_hair_point(h, i);
        sc.lo = hk_v3(fmin(sc.lo.x, q.x), fmin(sc.lo.y, q.y), fmin(sc.lo.z, q.z));
        sc.hi = hk_v3(fmax(sc.hi.x, q.x), fmax(sc.hi.y, q.y), fmax(sc.hi.z, q.z));
    }
    for (int i = 0; head && i < head->vertex_count; i++) {
        hk_Vec3 q = head->positions[i];
        sc.lo = hk_v3(fmin(sc.lo.x, q.x), fmin(sc.lo.y, q.y), fmin(sc.lo.z, q.z));
        sc.hi = hk_v3(fmax(sc.hi.x, q.x), fmax(sc.hi.y, q.y), fmax(sc.hi.z, q.z));
    }
    const hk_View cam = hk_camera_frame(&sc);
    last_eye = cam.origin;
    const hk_RasterPoint q = hk_view_project(&cam, hk_v3(0, 0, 0));
    return (size_t)floor(q.y) * (size_t)o->width + (size_t)floor(q.x);
}

static double srgb_to_linear(double c) { return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4); }

/* One thick strand across the picture along t = +x, its middle on the camera axis,
 * lit by one light of direction l (as the options document it). Returns the linear
 * colour of the pixel there; ambient is off and the background black. */
static void lit_strand(double cam_azimuth, double light_az, double light_el, hk_Vec3 kd, hk_Vec3 ks, double p,
                       float out[3])
{
    hk_HairFile h;
    make_strands(&h, 1, 401, 0.1, 0.0, 0.0);
    h.default_thickness = 0.01f; /* four pixels wide: the pixels near its axis are covered */
    hk_RenderDef o = plain_options(96);
    o.azimuth_deg = cam_azimuth;
    o.light_azimuth_deg = light_az, o.light_elevation_deg = light_el;
    hk_Visuality v = hk_default_visuality();
    v.diffuse = kd, v.specular = ks, v.glossiness = p;
    hk_Canvas img;
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, NULL), HK_OK);
    memcpy(out, img.rgb + 3 * origin_pixel(&h, NULL, &o), 3 * sizeof(float));
    hk_canvas_free(&img);
    hk_hair_free(&h);
}

/* Kajiya-Kay (Kajiya & Kay 1989; Lansink 2010 §4.1.5), written out here:
 *   I = K_d sin(t, l) + K_s (sin(t,l) sin(t,e) - (t.l)(t.e))^p,
 * with the visuality colours read as sRGB. (1) Diffuse only, three light directions:
 * I = K_d sin(t, l), with t.l = sin(az) cos(el). (2) Light perpendicular to the
 * strand (t.l = 0) seen from the front (t.e = 0): I = K_d + K_s. (3) The specular
 * cone: seen from about 30 degrees (t.e near 0.5), a light with t.l = -0.5 is near
 * the mirror cone and one with t.l = +0.5 is not; the thesis shader's abs() would
 * light both alike. Tolerances: float arithmetic in (1) and (2); in (3) the eye
 * direction changes by ~1e-3 over the half pixel between the origin and the pixel's
 * centre, which moves cone^p by p x 0.2% at most. */
static void test_kajiya_kay_pixel(void **state)
{
    (void)state;
    const hk_Vec3 kd = hk_v3(0.6, 0.4, 0.2), none = hk_v3(0, 0, 0), ks = hk_v3(0.3, 0.3, 0.3);
    const double kd_lin[3] = {srgb_to_linear(0.6), srgb_to_linear(0.4), srgb_to_linear(0.2)};
    const double ks_lin = srgb_to_linear(0.3);
    const double elevations[] = {10.0, 35.0, 60.0}, azimuths[] = {-50.0, 20.0, 80.0};
    float px[3], other[3];
    for (int k = 0; k < 3; k++) {
        lit_strand(0.0, azimuths[k], elevations[k], kd, none, 12.0, px);
        const double tl = sin(azimuths[k] * HK_PI / 180) * cos(elevations[k] * HK_PI / 180);
        for (int c = 0; c < 3; c++) hk_assert_rel(px[c], kd_lin[c] * sqrt(1.0 - tl * tl), 1e-4, 1e-7);
    }
    lit_strand(0.0, 0.0, 30.0, kd, ks, 12.0, px);
    for (int c = 0; c < 3; c++) hk_assert_rel(px[c], kd_lin[c] + ks_lin, 1e-4, 1e-7);
    /* Light directions with t.l = -0.5 and +0.5 at elevation 0: azimuth -30 and 30.
     * The camera re-centres the picture, so the eye direction at the origin is taken
     * from the camera's actual position. */
    lit_strand(30.0, -30.0, 0.0, none, ks, 4.0, px);
    const hk_Vec3 e = hk_v3_normalize(last_eye);
    const double te = e.x, sin_te = sqrt(1.0 - te * te), sin_tl = sqrt(0.75);
    assert_true(te > 0.3 && te < 0.7); /* seen from about 30 degrees */
    lit_strand(30.0, 30.0, 0.0, none, ks, 4.0, other);
    hk_assert_rel(px[0], ks_lin * pow(sin_tl * sin_te + 0.5 * te, 4.0), 0.01, 1e-7);
    hk_assert_rel(other[0], ks_lin * pow(sin_tl * sin_te - 0.5 * te, 4.0), 0.01, 1e-7);
    assert_true(px[0] > 5.0 * other[0]); /* the mirror cone, not its transmitted image */
}

/* A horizontal square above a strand hides it from a light straight overhead; seen
 * from the front (edge-on) the square hides nothing. The strand must be darker with
 * the square than without, and unchanged with --no-shadows. Likewise a layer of hair
 * between the light and the strand darkens it, but not to black (the scatter floor). */
static double strand_brightness_with(const hk_HairFile *h, const hk_Mesh *occluder, int shadows,
                                     hk_Scattering scattering)
{
    hk_RenderDef o = plain_options(96);
    o.shadows = shadows;
    o.scattering = scattering;
    o.light_azimuth_deg = 0.0, o.light_elevation_deg = 90.0;
    hk_Visuality v = hk_default_visuality();
    hk_Canvas img;
    assert_int_equal(hk_render(h, occluder, &v, &o, &img, NULL, NULL), HK_OK);
    const float *px = img.rgb + 3 * origin_pixel(h, occluder, &o);
    const double b = px[0] + px[1] + px[2];
    hk_canvas_free(&img);
    return b;
}

static double strand_brightness(const hk_HairFile *h, const hk_Mesh *occluder, int shadows)
{
    return strand_brightness_with(h, occluder, shadows, HK_SCATTERING_DUAL);
}

static void make_quad(hk_Mesh *quad, double y)
{
    assert_int_equal(hk_mesh_alloc(quad, 4, 2, NULL), HK_OK);
    const double r = 0.2;
    quad->positions[0] = hk_v3(-r, y, -r), quad->positions[1] = hk_v3(-r, y, r);
    quad->positions[2] = hk_v3(r, y, r), quad->positions[3] = hk_v3(r, y, -r);
    const int tris[6] = {0, 1, 2, 0, 2, 3};
    memcpy(quad->triangles, tris, sizeof tris);
    hk_mesh_compute_normals(quad);
}

static void test_shadow_from_occluder(void **state)
{
    (void)state;
    hk_HairFile h;
    make_strands(&h, 1, 101, 0.1, 0.0, 0.0);
    h.default_thickness = 0.01f;
    /* The square 3 cm above the strand or 3 cm below it: the same framing (the
     * scene's extent is mirrored), the light from straight above. */
    hk_Mesh above, below;
    make_quad(&above, 0.03);
    make_quad(&below, -0.03);
    const double shadowed = strand_brightness(&h, &above, 1);
    const double lit = strand_brightness(&h, &below, 1);
    const double no_shadows = strand_brightness(&h, &above, 0);
    assert_true(lit > 0.05);
    assert_true(shadowed < 0.01 * lit); /* ambient is off: nothing is left */
    hk_assert_rel(no_shadows, lit, 1e-5, 1e-9);
    hk_mesh_free(&above);
    hk_mesh_free(&below);
    hk_hair_free(&h);

    /* Hair between the light and the strand: the strand at y = 0 and a sheet of 40
     * strands 1 cm above it, side by side in z. With shadows the strand gets the
     * light through the sheet's opacity: much darker, but not below the thesis's
     * floor of 25% of the direct light (thesis §4.1.6, shadow mapped to [1, 0.25]). */
    hk_HairFile cover;
    make_strands(&cover, 41, 101, 0.1, 0.0005, 0.0);
    for (uint32_t s = 0; s < cover.strand_count; s++)
        for (uint32_t p = cover.first_point[s]; p < cover.first_point[s + 1]; p++) {
            float *q = cover.points + 3 * (size_t)p;
            if (s == 0) {
                q[1] = 0.0f, q[2] = 0.0f;
            } else {
                q[2] = q[1] - 0.01f; /* spread in z ... */
                q[1] = 0.01f;        /* ... 1 cm above the first strand */
            }
        }
    cover.default_thickness = 0.01f;
    const double under_hair = strand_brightness_with(&cover, NULL, 1, HK_SCATTERING_SINGLE);
    const double unshaded = strand_brightness_with(&cover, NULL, 0, HK_SCATTERING_SINGLE);
    assert_true(under_hair < 0.5 * unshaded);
    assert_true(under_hair >= 0.24 * unshaded);
    /* Dual scattering (the default): no floor, the sheet's fibres pass on what they
     * scatter forward; the strand is darker than in full light, lighter than the
     * unscattered light alone, exp(-opacity), and the same without shadows. */
    const double dual_under = strand_brightness(&cover, NULL, 1), dual_lit = strand_brightness(&cover, NULL, 0);
    hk_assert_rel(dual_lit, unshaded, 1e-5, 1e-9);
    assert_true(dual_under < dual_lit);
    hk_RenderDef o = plain_options(96);
    o.light_azimuth_deg = 0.0, o.light_elevation_deg = 90.0;
    hk_LightMaps maps = {0};
    hk_Scene scene = {&cover, NULL, NULL, &o, hk_v3(0, 1, 0), hk_v3_zero(), hk_v3_zero(), 0.01, 0, NULL, 0.0, 1, 1.0};
    assert_int_equal(hk_scene_bounds(&scene, NULL), HK_OK);
    hk_scene_thickness(&scene, 1);
    uint8_t *starts = malloc(cover.point_count);
    assert_non_null(starts);
    hk_segment_starts(&cover, 1, starts, 1);
    assert_int_equal(hk_light_maps_build(&scene, starts, &maps, NULL, NULL), HK_OK);
    double head_visible, opacity;
    hk_light_lookup(&maps, hk_v3(0, 0, 0), &head_visible, &opacity);
    assert_true(opacity > 0.5); /* the sheet is in front */
    assert_true(dual_under > 1.2 * exp(-opacity) * dual_lit);
    hk_light_maps_free(&maps);
    free(starts);
    hk_hair_free(&cover);
}

/* A thin line's fragments carry its area: sum of opacities = width x length. */
static float coverage_sum;
static void sum_alpha(void *user, int x, int y, float t, float alpha)
{
    (void)user, (void)x, (void)y, (void)t;
    coverage_sum += alpha;
}

static void test_subpixel_coverage(void **state)
{
    (void)state;
    const hk_Rect clip = {0, 0, 200, 200};
    const double widths[] = {0.05, 0.3, 0.9};
    for (int k = 0; k < 3; k++)
        for (int dir = 0; dir < 4; dir++) {
            /* Lengths of 80 pixels in four directions, away from the edges. */
            const double ang = 0.1 + dir * 0.4;
            hk_RasterPoint a = {50.3f, 60.7f, 1.0f, 1.0f}, b = a;
            b.x = (float)(a.x + 80.0 * cos(ang)), b.y = (float)(a.y + 80.0 * sin(ang));
            coverage_sum = 0.0f;
            hk_raster_segment(a, b, (float)widths[k], clip, NULL, sum_alpha, NULL);
            /* Exact for the tent footprint, up to the half-open ends (one column). */
            hk_assert_near(coverage_sum, widths[k] * 80.0, widths[k] * 1.5);
            /* The thin version clamps a column's opacity at 1 (w / cos(angle) > 1). */
            if (widths[k] / fmax(fabs(cos(ang)), fabs(sin(ang))) > 1.0) continue;
            coverage_sum = 0.0f;
            hk_raster_segment_thin(a, b, (float)widths[k], clip, sum_alpha, NULL);
            hk_assert_near(coverage_sum, widths[k] * 80.0, widths[k] * 1.5);
        }
}

/* The fragments a rasteriser emits, in order. */
typedef struct Emitted {
    int count;
    struct {
        int x, y;
        float t, alpha;
    } at[4096];
} Emitted;
static void record_fragment(void *user, int x, int y, float t, float alpha)
{
    Emitted *e = user;
    if (e->count == 4096) return;
    e->at[e->count].x = x, e->at[e->count].y = y, e->at[e->count].t = t, e->at[e->count].alpha = alpha;
    e->count++;
}

/* hk_raster_segment, which walks only the columns a pixel drawn can be in, emits what
 * the walk of every column within reach of the ends does, bit for bit and in the same
 * order: random segments in and around a tile, at every angle, thin and wide, long and
 * next to nothing, some pixels closed. */
static void test_segment_columns(void **state)
{
    (void)state;
    static Emitted narrow, wide;
    const hk_Rect clip = {64, 32, 96, 64};
    uint8_t closed[HK_TILE * HK_TILE];
    long long fragments = 0;
    for (uint64_t k = 0; k < 20000; k++) {
        for (int p = 0; p < HK_TILE * HK_TILE; p++) closed[p] = k % 3 == 0 && hk_rng_uniform(7, k, (uint64_t)p) < 0.3;
        /* some long segments across the tile, a few from far outside it */
        const float reach = k % 11 == 0 ? 3000.0f : k % 5 == 0 ? 40.0f : 4.0f;
        hk_RasterPoint a = {(float)(60.0 + 40.0 * hk_rng_uniform(1, k, 0)),
                            (float)(28.0 + 40.0 * hk_rng_uniform(1, k, 1)), 1.0f, 1.0f};
        hk_RasterPoint b = a;
        b.x += (float)(reach * (2.0 * hk_rng_uniform(1, k, 2) - 1.0));
        b.y += (float)(reach * (2.0 * hk_rng_uniform(1, k, 3) - 1.0));
        if (k % 97 == 0) b.x = a.x, b.y = a.y + 1e-7f; /* next to nothing */
        const float width = (float)(k % 7 == 0 ? 6.0 * hk_rng_uniform(1, k, 4) : hk_rng_uniform(1, k, 4));
        narrow.count = wide.count = 0;
        hk_raster_segment(a, b, width, clip, k % 3 == 0 ? closed : NULL, record_fragment, &narrow);
        hk_raster_segment_columns(a, b, width, clip, k % 3 == 0 ? closed : NULL, record_fragment, &wide, 0);
        assert_int_equal(narrow.count, wide.count);
        assert_true(narrow.count < 4096);
        assert_memory_equal(narrow.at, wide.at, (size_t)narrow.count * sizeof narrow.at[0]);
        fragments += narrow.count;
    }
    printf("segments drawn as with every column: %lld fragments\n", fragments);
    assert_true(fragments > 100000); /* the segments did draw (158,301 when written) */
}

/* The samples a triangle rasteriser emits, in (row, column, sample) order. */
typedef struct Sampled {
    int count;
    struct {
        int x, y, s;
        float l[3];
    } at[8192];
} Sampled;
static void record_sample(void *user, int x, int y, int s, float l0, float l1, float l2)
{
    Sampled *e = user;
    if (e->count == 8192) return;
    e->at[e->count].x = x, e->at[e->count].y = y, e->at[e->count].s = s;
    e->at[e->count].l[0] = l0, e->at[e->count].l[1] = l1, e->at[e->count].l[2] = l2;
    e->count++;
}
static int sample_before(const void *a, const void *b)
{
    const int *p = a, *q = b; /* x, y, s */
    return p[1] != q[1] ? p[1] - q[1] : p[0] != q[0] ? p[0] - q[0] : p[2] - q[2];
}

/* hk_raster_triangle emits the samples, and their barycentric coordinates bit for bit,
 * of the formula written per sample (as it was before the factors of a row of samples
 * were taken once), in any order: random triangles in and around a tile, small and
 * large, thin, with corners on sample positions, 1 and 2 x 2 samples a pixel. */
static void test_triangle_samples(void **state)
{
    (void)state;
    static Sampled got, want;
    const hk_Rect clip = {64, 32, 96, 64};
    long long samples = 0;
    for (uint64_t k = 0; k < 20000; k++) {
        const double size = k % 3 == 0 ? 3.0 : k % 3 == 1 ? 20.0 : 200.0;
        hk_RasterPoint v[3];
        for (int c = 0; c < 3; c++) {
            v[c].x = (float)(80.0 + size * (hk_rng_uniform(2, k, (uint64_t)(2 * c)) - 0.5));
            v[c].y = (float)(48.0 + size * (hk_rng_uniform(2, k, (uint64_t)(2 * c + 1)) - 0.5));
            v[c].z = v[c].px_per_unit = 1.0f;
        }
        if (k % 7 == 0) /* thin */
            v[2].x = v[0].x + 1e-3f * (v[1].x - v[0].x), v[2].y = v[0].y + 1e-3f * (v[1].y - v[0].y) + 1e-4f;
        if (k % 11 == 0) v[0].x = floorf(v[0].x) + 0.25f, v[1].y = floorf(v[1].y) + 0.75f;
        const int n = k % 2 ? 2 : 1;
        got.count = want.count = 0;
        hk_raster_triangle(v, clip, n, record_sample, &got);
        const float area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
        if (fabsf(area) > 1e-12f) {
            const float inv = 1.0f / area;
            for (int y = clip.y0; y < clip.y1; y++)
                for (int x = clip.x0; x < clip.x1; x++)
                    for (int s = 0; s < n * n; s++) {
                        const float px = (float)x + (n == 2 ? 0.25f + 0.5f * (float)(s & 1) : 0.5f);
                        const float py = (float)y + (n == 2 ? 0.25f + 0.5f * (float)(s >> 1) : 0.5f);
                        const float l0 = ((v[1].x - px) * (v[2].y - py) - (v[2].x - px) * (v[1].y - py)) * inv;
                        const float l1 = ((v[2].x - px) * (v[0].y - py) - (v[0].x - px) * (v[2].y - py)) * inv;
                        const float l2 = 1.0f - l0 - l1;
                        if (l0 >= 0.0f && l1 >= 0.0f && l2 >= 0.0f) record_sample(&want, x, y, s, l0, l1, l2);
                    }
        }
        assert_int_equal(got.count, want.count);
        assert_true(got.count < 8192);
        qsort(got.at, (size_t)got.count, sizeof got.at[0], sample_before);
        assert_memory_equal(got.at, want.at, (size_t)got.count * sizeof got.at[0]);
        samples += got.count;
    }
    printf("triangles drawn as by the formula per sample: %lld samples\n", samples);
    assert_true(samples > 1000000); /* the triangles did draw */
}

/* A small random head of hair over a sphere: same bytes with 1 and 2 threads, every
 * pixel finite, hair visible, and a PNG that libpng reads back. */
static void make_scene(hk_HairFile *h, hk_Mesh *ball)
{
    const int strands = 3000, points = 12;
    uint32_t counts[3000];
    for (int s = 0; s < strands; s++) counts[s] = points;
    assert_int_equal(hk_hair_alloc(h, strands, counts, NULL), HK_OK);
    h->default_thickness = 8e-5f;
    for (int s = 0; s < strands; s++) {
        const double u = hk_test_uniform() * 2 * HK_PI, v = acos(2 * hk_test_uniform() - 1);
        hk_Vec3 n = hk_v3(sin(v) * cos(u), cos(v), sin(v) * sin(u)), p = hk_v3_scale(n, 0.08);
        for (int k = 0; k < points; k++) {
            float *q = h->points + 3 * ((size_t)s * points + k);
            q[0] = (float)p.x, q[1] = (float)p.y, q[2] = (float)p.z;
            p = hk_v3_add(p, hk_v3_scale(hk_v3_normalize(hk_v3_add(n, hk_v3(0, -0.3 * k, 0))), 0.01));
        }
    }
    const int rings = 16, segs = 24;
    assert_int_equal(hk_mesh_alloc(ball, (rings + 1) * segs, rings * segs * 2, NULL), HK_OK);
    for (int i = 0; i <= rings; i++)
        for (int j = 0; j < segs; j++) {
            const double v = HK_PI * i / rings, u = 2 * HK_PI * j / segs;
            ball->positions[i * segs + j] = hk_v3(0.078 * sin(v) * cos(u), 0.078 * cos(v), -0.078 * sin(v) * sin(u));
        }
    int t = 0;
    for (int i = 0; i < rings; i++)
        for (int j = 0; j < segs; j++) {
            const int a = i * segs + j, b = i * segs + (j + 1) % segs, c = a + segs, d = b + segs;
            ball->triangles[3 * t] = a, ball->triangles[3 * t + 1] = c, ball->triangles[3 * t + 2] = b, t++;
            ball->triangles[3 * t] = b, ball->triangles[3 * t + 1] = c, ball->triangles[3 * t + 2] = d, t++;
        }
    hk_mesh_compute_normals(ball);
}

static void test_scene_deterministic_finite_png(void **state)
{
    (void)state;
    hk_HairFile h;
    hk_Mesh ball;
    make_scene(&h, &ball);
    hk_Visuality v = hk_default_visuality();
    hk_Canvas img[2];
    for (int k = 0; k < 2; k++) {
        hk_RenderDef o = hk_default_render_def();
        o.width = 160, o.height = 120, o.threads = k + 1, o.shadow_map_size = 128;
        hk_RenderStats stats;
        assert_int_equal(hk_render(&h, &ball, &v, &o, &img[k], &stats, NULL), HK_OK);
        assert_true(stats.hair_fragments > 1000 && stats.light_fragments > 1000);
    }
    const size_t n = 3 * 160 * 120;
    assert_memory_equal(img[0].rgb, img[1].rgb, n * sizeof(float));
    double lo = 1e9, hi = -1e9;
    for (size_t i = 0; i < n; i++) {
        assert_true(isfinite(img[0].rgb[i]) && img[0].rgb[i] >= 0.0f);
        lo = fmin(lo, img[0].rgb[i]), hi = fmax(hi, img[0].rgb[i]);
    }
    assert_true(hi - lo > 0.1); /* not a flat (black) frame */
    char path[4096];
    snprintf(path, sizeof path, "%s/render.png", hk_test_tmpdir());
    assert_int_equal(hk_render_write_png(&img[0], path, NULL), HK_OK);
    int w, hgt;
    uint8_t *rgb;
    assert_int_equal(hk_png_read_rgb8(path, &w, &hgt, &rgb, NULL), HK_OK);
    assert_int_equal(w, 160);
    assert_int_equal(hgt, 120);
    hk_free(rgb);
    hk_canvas_free(&img[0]);
    hk_canvas_free(&img[1]);
    hk_mesh_free(&ball);
    hk_hair_free(&h);
}

/* The PNG's bytes against the sRGB curve written out here (IEC 61966-2-1, rounded to
 * the nearest byte): floats spread over [0, 1] (every 2^12th), the floats around each
 * byte's first value, and those outside [0, 1] and NaN, which take 0 or 255. */
static uint8_t reference_srgb_byte(float linear)
{
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const double v = linear <= 0.0031308f ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (uint8_t)lrint(v * 255.0);
}

static float float_from_bits(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

static void test_png_srgb_bytes(void **state)
{
    (void)state;
    const uint32_t one = 0x3f800000u, step = 1u << 12, spread = one / step + 1;
    const float odd[] = {-0.0f, -1.0f, 1.0f, 2.0f, INFINITY, -INFINITY, NAN, 1e-30f};
    const size_t odd_count = sizeof odd / sizeof *odd, count = spread + 255 * 5 + odd_count;
    hk_Canvas c;
    c.width = 512, c.height = (int)((count + 3 * 512 - 1) / (3 * 512));
    c.rgb = hk_calloc_array(3 * (size_t)c.width * (size_t)c.height, sizeof *c.rgb, NULL);
    size_t at = 0;
    for (uint32_t k = 0; k < spread; k++) c.rgb[at++] = float_from_bits(k * step);
    for (int b = 1; b < 256; b++) { /* the first float of byte b, by bisection, and two either side */
        uint32_t lo = 0, hi = one;
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (reference_srgb_byte(float_from_bits(mid)) >= b)
                hi = mid;
            else
                lo = mid;
        }
        for (uint32_t d = 0; d < 5; d++) c.rgb[at++] = float_from_bits(hi - 2 + d);
    }
    for (size_t k = 0; k < odd_count; k++) c.rgb[at++] = odd[k];
    char path[4096];
    snprintf(path, sizeof path, "%s/srgb.png", hk_test_tmpdir());
    assert_int_equal(hk_render_write_png(&c, path, NULL), HK_OK);
    int w, h;
    uint8_t *bytes;
    assert_int_equal(hk_png_read_rgb8(path, &w, &h, &bytes, NULL), HK_OK);
    assert_int_equal(w, c.width);
    assert_int_equal(h, c.height);
    size_t wrong = 0;
    for (size_t k = 0; k < 3 * (size_t)w * (size_t)h; k++) wrong += bytes[k] != reference_srgb_byte(c.rgb[k]);
    assert_int_equal(wrong, 0);
    hk_free(bytes);
    hk_free(c.rgb);
}

/* The depth order made as it is read (read in steps, as the tiles do) equals a plain
 * stable sort by depth: spreads narrow and wide, many ties, zero, negatives and NaN
 * (which sort as zero), sizes around the small-bucket threshold. */
static int key_before(float a, float b)
{
    const float x = a > 0.0f ? a : 0.0f, y = b > 0.0f ? b : 0.0f;
    return x < y;
}

static void test_depth_order(void **state)
{
    (void)state;
    const uint32_t sizes[] = {0, 1, 2, 31, 33, 200, 5000};
    const double spreads[] = {0.0, 1e-6, 0.02, 3.0};
    for (size_t a = 0; a < sizeof sizes / sizeof *sizes; a++)
        for (size_t b = 0; b < sizeof spreads / sizeof *spreads; b++) {
            const uint32_t n = sizes[a];
            float *depth = hk_alloc_array(n + 1, sizeof *depth, NULL);
            uint32_t *order = hk_alloc_array(n + 1, sizeof *order, NULL);
            uint32_t *work = hk_alloc_array(3 * (size_t)n + 1, sizeof *work, NULL);
            uint32_t *expect = hk_alloc_array(n + 1, sizeof *expect, NULL);
            for (uint32_t i = 0; i < n; i++) {
                const double u = hk_rng_uniform(7, a * 10 + b, i);
                depth[i] = (float)(1.0 + spreads[b] * floor(u * 50.0) / 50.0); /* ties */
                if (i % 97 == 5) depth[i] = -1.0f;
                if (i % 89 == 7) depth[i] = NAN;
                if (i % 83 == 3) depth[i] = 0.0f;
            }
            for (uint32_t i = 0; i < n; i++) { /* insertion sort: stable */
                uint32_t j = i;
                for (; j > 0 && key_before(depth[i], depth[expect[j - 1]]); j--) expect[j] = expect[j - 1];
                expect[j] = i;
            }
            hk_DepthOrder d;
            hk_depth_order_begin(&d, n, depth, NULL, order, work);
            for (uint32_t k = 0; k < n; k += 7) hk_depth_order_ready(&d, k + 9);
            hk_depth_order_ready(&d, n);
            if (n) assert_memory_equal(order, expect, n * sizeof *order);
            hk_free(depth), hk_free(order), hk_free(work), hk_free(expect);
        }
}

/* An empty tile: no segments and no work arrays allocated yet (NULL). clang's UBSan
 * saw NULL + 0 here on every render with an empty tile ("applying zero offset to null
 * pointer"); gcc's does not check it, so this fails under `CC=clang make asan`. */
static void test_depth_order_empty(void **state)
{
    (void)state;
    hk_DepthOrder d;
    hk_depth_order_begin(&d, 0, NULL, NULL, NULL, NULL);
    hk_depth_order_ready(&d, 0);
    assert_int_equal(d.n, 0);
}

/* Lines with ends that are not finite, or so far apart that their difference
 * overflows, draw nothing and leave every pixel finite (a NaN end blended NaN into the
 * pixels near the other end; 1e308 went through (int), undefined). And the strand plot
 * of an ellipsoid of semi-axis 1e308 (`hairkit strand --plot`). */
static void test_canvas_non_finite(void **state)
{
    (void)state;
    hk_Canvas c;
    hk_Error err;
    assert_int_equal(hk_canvas_alloc(20, 20, hk_v3(1, 1, 1), &c, &err), HK_OK);
    const hk_Vec3 black = hk_v3(0, 0, 0);
    hk_canvas_line(&c, NAN, 5.0, 5.0, 5.0, 2.0, black, 1.0);
    hk_canvas_line(&c, 5.0, 5.0, 5.0, NAN, 2.0, black, 1.0);
    hk_canvas_line(&c, -1e308, 5.0, 1e308, 5.0, 2.0, black, 1.0);
    hk_canvas_line(&c, 5.0, -1e308, 5.0, 1e308, 2.0, black, 1.0);
    hk_canvas_line(&c, 1e308, 1e308, INFINITY, 1e308, 2.0, black, 1.0);
    hk_canvas_line(&c, 5.0, 5.0, 6.0, 6.0, NAN, black, 1.0);
    hk_canvas_disc(&c, -1e300, -1e300, 1e300, black, 1.0);
    for (int i = 0; i < 3 * 20 * 20; i++) assert_true(isfinite(c.rgb[i]));
    /* An ordinary line still draws. */
    hk_canvas_line(&c, 2.0, 10.0, 18.0, 10.0, 2.0, black, 1.0);
    assert_true(c.rgb[3 * (10 * 20 + 10)] < 0.5f);
    hk_canvas_free(&c);

    const hk_Vec3 axes[3] = {hk_v3(1, 0, 0), hk_v3(0, 1, 0), hk_v3(0, 0, 1)};
    const hk_Shape big[2] = {hk_shape_ellipsoid(hk_v3(0, 0, 0), hk_v3(1e308, 0.1, 0.1), axes, 0.0, 1000.0),
                             hk_shape_cuboid(hk_v3(0, 0, 0), hk_v3(1e308, 1e308, 1e308), axes, 0.0, 1000.0)};
    const hk_Vec3 pts[2] = {hk_v3(0, 0, 0), hk_v3(0.1, -0.1, 0)};
    const hk_PlotStrand strand = {pts, 2, black};
    char path[600];
    snprintf(path, sizeof path, "%s/plot.png", hk_test_tmpdir());
    for (int k = 1; k <= 2; k++)
        assert_int_equal(hk_plot_strands_png(path, 200, 100, &strand, 1, big, k, 1.0, &err), HK_OK);
}

/* A pixel's fragment keys (depth bits above the fragment's index, indices increasing
 * as drawn): insertion sort within its budget, else the radix sort on what the
 * insertion sort left, give the keys in order whatever the budget. */
static int u64_less(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : (x > y);
}

static void test_fragment_key_sort(void **state)
{
    (void)state;
    enum { N = 300 };
    uint64_t keys[N], expect[N], tmp[N];
    const size_t budgets[] = {0, 10, 500, 100000};
    for (size_t b = 0; b < sizeof budgets / sizeof *budgets; b++) {
        for (int i = 0; i < N; i++) {
            const float z = (float)(1.0 + floor(hk_rng_uniform(3, b, (uint64_t)i) * 40.0) / 40.0);
            uint32_t bits;
            memcpy(&bits, &z, sizeof bits);
            keys[i] = ((uint64_t)bits << 32) | (uint64_t)i;
        }
        memcpy(expect, keys, sizeof keys);
        qsort(expect, N, sizeof *expect, u64_less);
        if (!hk_sort_nearly_sorted(keys, N, budgets[b])) hk_sort_by_high_bits(keys, N, tmp);
        assert_memory_equal(keys, expect, sizeof keys);
    }
}

/* A renderer kept over pictures of different scenes, sizes and thread counts (its
 * buffers grow and are reused; a failed draw in between) draws each the same bytes
 * as hk_render. */
static void same_as_render(hk_Renderer *r, const hk_HairFile *h, const hk_Mesh *head, const hk_RenderDef *o)
{
    hk_Visuality v = hk_default_visuality();
    hk_Canvas fresh;
    assert_int_equal(hk_render(h, head, &v, o, &fresh, NULL, NULL), HK_OK);
    assert_int_equal(hk_renderer_draw(r, h, head, NULL, o, NULL, NULL), HK_OK);
    const hk_Canvas *kept = hk_renderer_picture(r);
    assert_int_equal(kept->width, o->width);
    assert_int_equal(kept->height, o->height);
    assert_memory_equal(kept->rgb, fresh.rgb, 3 * (size_t)o->width * (size_t)o->height * sizeof(float));
    hk_canvas_free(&fresh);
}

static void test_renderer_reuse(void **state)
{
    (void)state;
    hk_HairFile big, small;
    hk_Mesh ball;
    make_scene(&big, &ball);
    make_strands(&small, 3, 9, 0.1, 0.01, 0.0);
    hk_Renderer *r;
    assert_int_equal(hk_renderer_create(&r, NULL), HK_OK);
    hk_RenderDef o = hk_default_render_def();
    o.width = 160, o.height = 120, o.threads = 2, o.shadow_map_size = 128;
    same_as_render(r, &big, &ball, &o);
    hk_RenderDef p = plain_options(64);
    p.threads = 1;
    same_as_render(r, &small, NULL, &p);
    hk_RenderDef bad = o;
    bad.width = 0;
    assert_int_equal(hk_renderer_draw(r, &big, &ball, NULL, &bad, NULL, NULL), HK_ERR_INVALID);
    assert_int_equal(hk_renderer_picture(r)->width, 0);
    o.width = 200, o.height = 100, o.threads = 1, o.shadow_map_size = 256;
    same_as_render(r, &big, &ball, &o);
    hk_renderer_destroy(r);
    hk_mesh_free(&ball);
    hk_hair_free(&big);
    hk_hair_free(&small);
}

static void test_bad_options(void **state)
{
    (void)state;
    hk_HairFile h;
    make_strands(&h, 1, 5, 0.1, 0.0, 0.0);
    hk_Visuality v = hk_default_visuality();
    hk_RenderDef o = hk_default_render_def();
    hk_Canvas img;
    hk_Error err;
    o.width = 0;
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "picture size");
    o = hk_default_render_def();
    o.shadow_map_size = 8; /* 0 is the picture's size; else 16 to 8192 */
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "shadow map size");
    o = hk_default_render_def();
    o.opacity_layers = 99;
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, &err), HK_ERR_INVALID);
    o = hk_default_render_def();
    assert_int_equal(o.scattering, HK_SCATTERING_DUAL); /* the default */
    o.scattering = (hk_Scattering)7;
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "scattering");
    h.points[4] = NAN;
    o = hk_default_render_def();
    assert_int_equal(hk_render(&h, NULL, &v, &o, &img, NULL, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "not finite");
    assert_null(img.rgb);
    hk_hair_free(&h);
}

/* The light's maps sized from the picture when shadow_map_size is 0 (the default;
 * issue 18, item 4): the rule of hk_render_shadow_map_texels worked out by hand (512 x
 * the larger of width / 1200 and height / 900, rounded up to a multiple of 32, 64 to
 * 512), the picture drawn with the map it names, and full-size pictures the same bytes
 * as with the 512 texels they always had. */
static void test_shadow_map_from_picture(void **state)
{
    (void)state;
    static const struct {
        int width, height, texels;
    } rule[] = {
        {1200, 900, 512}, {1920, 1080, 512}, {600, 900, 512}, /* the height's scale is 1 */
        {640, 480, 288},                                      /* 273.1 up to 288 */
        {160, 120, 96},                                       /* 68.3 up to 96 */
        {600, 450, 256},                                      /* exactly 256 */
        {64, 48, 64},                                         /* 27.3: at least 64 */
    };
    hk_RenderDef o = hk_default_render_def();
    assert_int_equal(o.shadow_map_size, 0);
    for (size_t k = 0; k < sizeof rule / sizeof rule[0]; k++) {
        o.width = rule[k].width, o.height = rule[k].height;
        assert_int_equal(hk_render_shadow_map_texels(&o), rule[k].texels);
    }
    o.shadow_map_size = 300; /* given: kept */
    assert_int_equal(hk_render_shadow_map_texels(&o), 300);

    hk_HairFile h;
    hk_Mesh ball;
    make_scene(&h, &ball);
    const size_t sizes[2][2] = {{160, 120}, {1200, 900}};
    for (int z = 0; z < 2; z++) {
        hk_Canvas automatic, given, full;
        hk_RenderDef a = hk_default_render_def();
        a.width = (int)sizes[z][0], a.height = (int)sizes[z][1], a.threads = 2;
        hk_RenderDef g = a, f = a;
        g.shadow_map_size = hk_render_shadow_map_texels(&a);
        f.shadow_map_size = 512;
        assert_int_equal(hk_render(&h, &ball, NULL, &a, &automatic, NULL, NULL), HK_OK);
        assert_int_equal(hk_render(&h, &ball, NULL, &g, &given, NULL, NULL), HK_OK);
        assert_int_equal(hk_render(&h, &ball, NULL, &f, &full, NULL, NULL), HK_OK);
        const size_t n = 3 * sizes[z][0] * sizes[z][1] * sizeof(float);
        assert_memory_equal(automatic.rgb, given.rgb, n);
        if (z == 0) /* 96 texels, not 512: the shadows differ */
            assert_memory_not_equal(automatic.rgb, full.rgb, n);
        else /* full size: the pictures of before */
            assert_memory_equal(automatic.rgb, full.rgb, n);
        hk_canvas_free(&automatic);
        hk_canvas_free(&given);
        hk_canvas_free(&full);
    }
    hk_mesh_free(&ball);
    hk_hair_free(&h);
}

/* The level of detail (hk_render_strand_stride; Cook et al. 2007's stochastic
 * simplification): the stride follows the rule the header states, recomputed here
 * from the camera's fitted distance; every strand is drawn when asked, for a full-size
 * picture and for few strands; a thumbnail drawn with one strand in k keeps the
 * picture's mean brightness (the coverage is kept on average) with k times fewer
 * fragments, and the same bytes for 1 and 2 threads. */
static void test_strand_level_of_detail(void **state)
{
    (void)state;
    hk_HairFile h;
    const int strands = 100000;
    make_strands(&h, strands, 8, 0.25, 5e-6, 0.0); /* a sheet 50 cm by 50 cm */
    h.default_thickness = 8e-5f;
    const struct {
        int width, height;
    } sizes[] = {{64, 48}, {160, 120}, {320, 240}, {1200, 900}, {4000, 3000}};
    int strides[5];
    for (size_t z = 0; z < 5; z++) {
        hk_RenderDef o = hk_default_render_def();
        o.width = sizes[z].width, o.height = sizes[z].height;
        hk_Vec3 target;
        double distance;
        assert_int_equal(hk_render_fit_camera(&h, NULL, &o, &target, &distance, NULL), HK_OK);
        const double focal = 0.5 * o.height / tan(0.5 * o.fov_deg * HK_PI / 180.0);
        const double pixels = 8e-5 * focal / distance; /* the strand's width at the target */
        double expected = pixels >= 0.25 ? 1.0 : fmin(fmin(floor(0.25 / pixels), 64.0), floor(strands / 5000.0));
        strides[z] = hk_render_strand_stride(&h, NULL, &o, NULL);
        print_message("%dx%d: a strand %.4f pixels wide, one in %d drawn\n", o.width, o.height, pixels, strides[z]);
        assert_int_equal(strides[z], (int)fmax(expected, 1.0));
        o.strand_lod = 0;
        assert_int_equal(hk_render_strand_stride(&h, NULL, &o, NULL), 1);
    }
    assert_true(strides[0] == 20 && strides[4] == 1); /* not vacuous: both ends of the rule */
    /* A picture of the sheet, lit from the front, at 64 x 48. */
    hk_RenderDef o = hk_default_render_def();
    o.width = 64, o.height = 48;
    o.azimuth_deg = 0.0, o.elevation_deg = 0.0, o.light_azimuth_deg = 20.0, o.light_elevation_deg = 30.0;
    hk_RenderDef all = o;
    all.strand_lod = 0;
    hk_Canvas lod[2], every;
    hk_RenderStats s_lod, s_every;
    for (int t = 0; t < 2; t++) {
        o.threads = t + 1;
        assert_int_equal(hk_render(&h, NULL, NULL, &o, &lod[t], &s_lod, NULL), HK_OK);
    }
    assert_int_equal(hk_render(&h, NULL, NULL, &all, &every, &s_every, NULL), HK_OK);
    const size_t n = 3 * 64 * 48;
    assert_memory_equal(lod[0].rgb, lod[1].rgb, n * sizeof(float));
    assert_int_equal(s_lod.strand_stride, strides[0]);
    assert_int_equal(s_every.strand_stride, 1);
    /* the background's pixels are the same; the hair's mean is kept */
    double sum_lod = 0.0, sum_every = 0.0, background = 0.0;
    for (size_t i = 0; i < n; i++) sum_lod += lod[0].rgb[i], sum_every += every.rgb[i];
    for (size_t i = 0; i < 3; i++) background += every.rgb[i]; /* the top-left corner: background */
    print_message("64x48: mean %.5f with one strand in %d, %.5f with every one; fragments %lld against %lld\n",
                  sum_lod / (double)n, s_lod.strand_stride, sum_every / (double)n, s_lod.hair_fragments,
                  s_every.hair_fragments);
    assert_true(fabs(sum_lod - sum_every) <= 0.01 * sum_every);
    assert_true(s_lod.hair_fragments * strides[0] <= 2 * s_every.hair_fragments);
    assert_true(background > 0.0);
    hk_canvas_free(&lod[0]);
    hk_canvas_free(&lod[1]);
    hk_canvas_free(&every);
    /* few strands (under 2 x 5,000): every one drawn */
    hk_HairFile few;
    make_strands(&few, 9000, 8, 0.25, 5.5e-5, 0.0);
    few.default_thickness = 8e-5f;
    hk_RenderDef small = hk_default_render_def();
    small.width = 64, small.height = 48;
    assert_int_equal(hk_render_strand_stride(&few, NULL, &small, NULL), 1);
    hk_hair_free(&few);
    hk_hair_free(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_kajiya_kay_pixel),
        cmocka_unit_test(test_shadow_from_occluder),
        cmocka_unit_test(test_subpixel_coverage),
        cmocka_unit_test(test_segment_columns),
        cmocka_unit_test(test_triangle_samples),
        cmocka_unit_test(test_scene_deterministic_finite_png),
        cmocka_unit_test(test_png_srgb_bytes),
        cmocka_unit_test(test_depth_order),
        cmocka_unit_test(test_fragment_key_sort),
        cmocka_unit_test(test_renderer_reuse),
        cmocka_unit_test(test_bad_options),
        cmocka_unit_test(test_depth_order_empty),
        cmocka_unit_test(test_canvas_non_finite),
        cmocka_unit_test(test_shadow_map_from_picture),
        cmocka_unit_test(test_strand_level_of_detail),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
