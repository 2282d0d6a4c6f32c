/* Internals of the renderer shared by its passes: projections, rasterisers, tile bins
 * and the light's maps. */
#ifndef HK_RENDER_INTERNAL_H
#define HK_RENDER_INTERNAL_H

#include <math.h>
#include <stdint.h>

#include "hairkit/render.h"
#include "shading.h"

#include <stdatomic.h>

#define HK_TILE 32 /* pixels per side of a tile: the unit of parallel work */

/* A projection onto an image: perspective (a camera) or orthographic (the light). */
typedef struct hk_View {
    int perspective;
    hk_Vec3 origin;             /* eye (perspective) or centre of the map (orthographic) */
    hk_Vec3 right, up, forward; /* orthonormal; forward points into the picture */
    double focal;               /* pixels per unit at depth 1 (perspective) or per unit */
    double depth_offset;        /* orthographic: added to the depth to keep it positive */
    int width, height;
    hk_Vec3 target; /* camera: the point looked at, at `distance` from origin */
    double distance;
} hk_View;

/* A projected point: pixel position (x right, y down), depth along forward, and the
 * number of pixels a scene unit spans there. */
typedef struct hk_RasterPoint {
    float x, y, z, px_per_unit;
} hk_RasterPoint;

static inline hk_RasterPoint hk_view_project(const hk_View *v, hk_Vec3 p)
{
    hk_Vec3 d = hk_v3_sub(p, v->origin);
    double z = hk_v3_dot(d, v->forward);
    double s = v->perspective ? (z > 1e-9 ? v->focal / z : 0.0) : v->focal;
    hk_RasterPoint r;
    r.x = (float)(0.5 * v->width + s * hk_v3_dot(d, v->right));
    r.y = (float)(0.5 * v->height - s * hk_v3_dot(d, v->up));
    r.z = (float)(v->perspective ? z : z + v->depth_offset);
    r.px_per_unit = (float)s;
    return r;
}

/* hk_view_project of every point of h into out, in parallel (view_points.c). */
void hk_view_project_points(const hk_View *v, const hk_HairFile *h, hk_RasterPoint *out, int threads);

/* Pixel rectangle [x0, x1) x [y0, y1). */
typedef struct hk_Rect {
    int x0, y0, x1, y1;
} hk_Rect;

/* Fragment sink of the line rasteriser: pixel, parameter t in [0, 1) along the
 * segment, and opacity (coverage times the sub-pixel width). */
typedef void (*hk_FragmentFn)(void *user, int x, int y, float t, float alpha);

/* hk_raster_segment and hk_raster_segment_thin, the hair's segments: raster_inline.h. */


/* Pixel bounding box of a segment drawn by hk_raster_segment, clipped to the image;
 * 0 when it is empty (hk_segment_box_inline in raster_inline.h: the same). */
int hk_segment_box(hk_RasterPoint a, hk_RasterPoint b, float width, int image_w, int image_h, hk_Rect *box);

/* Fills a triangle: emit(x, y, sample, l0, l1, l2) for every sample inside it, with
 * its screen-space barycentric coordinates; one sample per pixel at its centre, or
 * 2 x 2 (supersample 2: sample = 2 * row + column at quarter offsets). */
typedef void (*hk_SampleFn)(void *user, int x, int y, int sample, float l0, float l1, float l2);
void hk_raster_triangle(const hk_RasterPoint v[3], hk_Rect clip, int supersample, hk_SampleFn emit, void *user);
int hk_triangle_box(const hk_RasterPoint v[3], int image_w, int image_h, hk_Rect *box);

/* The items 0 .. n-1 sorted by increasing depth (stable: ties keep item order), made
 * as they are read (depth_order.c): after hk_depth_order_begin (order holds n numbers,
 * work 3 n), order[0 .. k) is final once hk_depth_order_ready(d, k) returned. order
 * holds value[item] (value NULL: the item), and keys[k] the bits of order[k]'s depth
 * (clamped to 0 and above: the bits of a positive float order as integers). */
typedef struct hk_DepthOrder {
    uint32_t n, sorted, bucket;
    int shift;           /* the byte of the keys the buckets are by */
    uint32_t start[257]; /* bucket b is order[start[b] .. start[b + 1]) */
    uint32_t *order, *keys, *key_tmp, *order_tmp;
} hk_DepthOrder;
void hk_depth_order_begin(hk_DepthOrder *d, uint32_t n, const float *depth, const uint32_t *value, uint32_t *order,
                          uint32_t *work);
void hk_depth_order_ready(hk_DepthOrder *d, uint32_t upto);

/* Sorts keys[0..n) into increasing order, given that keys with the same upper 32 bits
 * (a depth's bits) are already in increasing order of their lower bits (an index,
 * filled in increasing order): a stable radix sort on the upper bits alone then gives
 * the full order, the same as any sort of the whole keys. tmp holds n keys. */
void hk_sort_by_high_bits(uint64_t *keys, uint32_t n, uint64_t *tmp);

/* Insertion sort of keys[0..n), for keys that are nearly in order: 1 when sorted, 0
 * when it gave up after `budget` moves (keys[0..i) sorted, the rest as it was, so
 * that the precondition of hk_sort_by_high_bits still holds). */
int hk_sort_nearly_sorted(uint64_t *keys, size_t n, size_t budget);

/* Makes *buffer hold at least count items of `size` bytes, reusing it when it is large
 * enough (its contents are then kept) and otherwise replacing it (contents lost);
 * 0 when out of memory (*buffer NULL, err set). *cap counts items (reuse.c). */
int hk_reserve(void **buffer, size_t *cap, size_t count, size_t size, hk_Error *err);
#define HK_RESERVE(ptr, cap, count, err) hk_reserve((void **)&(ptr), &(cap), (count), sizeof *(ptr), (err))

/* A buffer of one thread's, kept from picture to picture. */
typedef struct hk_ThreadBuffer {
    void *data;
    size_t cap;
} hk_ThreadBuffer;

/* An item's pixel box [x0, x1) x [y0, y1) (sides are at most 16384 pixels); empty
 * when x1 <= x0. */
typedef struct hk_TileBox {
    uint16_t x0, y0, x1, y1;
} hk_TileBox;

/* Items (segments, triangles) sorted into the tiles their box touches, in item order
 * within each tile (so that every tile sees them in the same order whatever the
 * thread count) (tile_bins.c). */
typedef struct hk_TileBins {
    int tiles_x, tiles_y;
    uint32_t *start; /* tiles_x * tiles_y + 1 offsets into items */
    uint32_t *items;
    hk_TileBox *boxes; /* every item's box, as box_of gave it */
    float *keys;       /* with items: each entry's item's key, when the build had keys */
    uint32_t *heavy;   /* the tiles, most items first: the order to hand them to threads */
    uint64_t *count;   /* work space of the build */
    size_t start_cap, items_cap, boxes_cap, keys_cap, heavy_cap, count_cap;
} hk_TileBins;

/* The tile bins are built by HK_TILE_BINS_BUILD (tile_bins_inline.h). Its
 * steps (tile_bins.c): the arrays for item_count items and `ranges` ranges (counts
 * zeroed); the offsets from the counts, and the entries' arrays (with keys when
 * `keys`); the tiles ordered busiest first. On failure the bins are freed. */
hk_Status hk_tile_bins_begin(uint32_t item_count, int width, int height, hk_TileBins *bins, int ranges, hk_Error *err);
hk_Status hk_tile_bins_offsets(hk_TileBins *bins, int ranges, int keys, hk_Error *err);
void hk_tile_bins_end(hk_TileBins *bins);
void hk_tile_bins_free(hk_TileBins *bins);
static inline hk_Rect hk_tile_rect(const hk_TileBins *b, int tile, int width, int height)
{
    hk_Rect r;
    r.x0 = (tile % b->tiles_x) * HK_TILE;
    r.y0 = (tile / b->tiles_x) * HK_TILE;
    r.x1 = r.x0 + HK_TILE < width ? r.x0 + HK_TILE : width;
    r.y1 = r.y0 + HK_TILE < height ? r.y0 + HK_TILE : height;
    return r;
}

/* The light's maps (orthographic, along the light): a depth map of the head and the
 * deep opacity map of the hair (Yuksel & Keyser 2008; thesis §4.1.6). */
typedef struct hk_LightMaps {
    hk_View view;
    int size, layers;
    double texel;                           /* scene units per texel */
    float layer_end[HK_MAX_OPACITY_LAYERS]; /* end of layer k behind z0 (scene units) */
    float *head_depth;                      /* size^2; +inf where the head is not */
    float *hair_z0;                         /* size^2; depth where the hair begins, +inf: none */
    float *opacity;                         /* size^2 * layers: opacity accumulated up to the
                                               end of each layer */
    /* Kept from one build to the next: the maps' capacities, and the work space (the
     * points in the light's view and their bins, head then hair; each thread's
     * fragments). */
    size_t head_depth_cap, hair_z0_cap, opacity_cap, proj_cap;
    hk_RasterPoint *proj;
    hk_TileBins bins;
    hk_ThreadBuffer *frag;
    int frag_threads;
} hk_LightMaps;

/* The scene as the passes see it. */
typedef struct hk_Scene {
    const hk_HairFile *hair;
    const hk_Mesh *head;
    const hk_Visuality *vis;
    const hk_RenderDef *opt;
    hk_Vec3 light_dir; /* unit, towards the light */
    hk_Vec3 lo, hi;    /* bounding box of hair and head */
    double thickness;  /* strand diameter (scene units) when the file has no array */
    uint32_t segment_count;
    /* Where a point's diameter comes from, chosen once (hk_scene_thickness): the
     * file's array, or else one value (the options' or the file's). Read for every
     * segment in both views' bins and rasterisers: through opt and hair it was a chain
     * of three dependent loads a segment. */
    const float *thickness_point;
    double thickness_fixed;
    int threads; /* OpenMP threads of every parallel loop: opt->threads, or OpenMP's
                    default when that is <= 0 (hk_render_threads) */
    /* The level of detail (hk_render_strand_stride): every diameter is multiplied by
     * it (exactly 1 when every strand is drawn; set by hk_scene_thickness). */
    double thickness_scale;
} hk_Scene;

/* The threads a picture is drawn with: options->threads, or OpenMP's default. */
int hk_render_threads(const hk_RenderDef *options);

static inline void hk_scene_thickness(hk_Scene *s, int stride)
{
    const int forced = s->opt->hair_thickness > 0.0;
    s->thickness_point = forced ? NULL : s->hair->thickness;
    s->thickness_fixed = forced ? s->opt->hair_thickness : s->thickness;
    s->thickness_scale = (double)stride;
}

/* The strands' diameter when the file gives no array: its default, or a thousandth of
 * the scene's box when it has none (hk_scene_bounds first). */
static inline double hk_scene_file_thickness(const hk_Scene *s)
{
    return s->hair->default_thickness > 0.0f ? s->hair->default_thickness : 1e-3 * hk_v3_dist(s->lo, s->hi);
}

static inline double hk_hair_thickness_at(const hk_Scene *s, uint32_t point)
{
    return (s->thickness_point ? s->thickness_point[point] : s->thickness_fixed) * s->thickness_scale;
}

static inline hk_Vec3 hk_hair_point(const hk_HairFile *h, uint32_t i)
{
    const float *p = h->points + 3 * (size_t)i;
    return hk_v3(p[0], p[1], p[2]);
}

/* Segment i starts at point i; valid unless i is the last point of its strand:
 * s[0 .. point_count) set to 1 where a segment starts, 0 elsewhere; returns their
 * number. */
uint32_t hk_segment_starts(const hk_HairFile *hair, int stride, uint8_t *s, int threads);

/* The level of detail of the scene seen by cam (hk_render_strand_stride); the scene's
 * thickness must be set (hk_scene_thickness, any stride). */
int hk_scene_strand_stride(const hk_Scene *sc, const hk_View *cam);

/* hk_render's checks of its options, and the scene's bounding box (render.c). */
hk_Status hk_render_check_options(const hk_RenderDef *o, hk_Error *err);
hk_Status hk_scene_bounds(hk_Scene *sc, hk_Error *err);

/* maps: zeroed before its first build; a build reuses the memory of the one before. */
hk_Status hk_light_maps_build(const hk_Scene *scene, const uint8_t *segment_start, hk_LightMaps *maps,
                              hk_RenderStats *stats, hk_Error *err);
void hk_light_maps_free(hk_LightMaps *maps);

/* Light reaching p: *head_visible in [0, 1] from the head's depth map (3 x 3
 * percentage-closer filter), *opacity the hair's opacity in front of p (bilinear
 * over the four nearest texels, each interpolated between its layers). */
void hk_light_lookup(const hk_LightMaps *maps, hk_Vec3 p, double *head_visible, double *opacity);

/* Perspective camera of the options framing the points of hair and head. */
hk_View hk_camera_frame(const hk_Scene *scene);

/* A hair vertex's colour and whether it is shaded in this picture, side by side: the
 * vertices are reached in depth order, and with the state in an array of its own each
 * one cost two cache misses instead of one. state: the shader's busy or done for this
 * picture, anything else for a vertex not shaded yet. */
typedef struct hk_VertexColour {
    float rgb[3];
    atomic_uint state;
} hk_VertexColour;

/* Colours of the hair vertices, computed when first asked for (hair_shading.c):
 * ambient plus the shading model times the light that reaches the vertex (maps NULL:
 * no shadows). The shader is zeroed before its first init; an init reuses the arrays
 * of the one before. */
typedef struct hk_HairShader {
    const hk_Scene *scene;
    const uint8_t *segment_start;
    const hk_LightMaps *maps;
    const hk_View *camera;
    hk_MarschnerParams marschner;
    hk_Vec3 ambient;
    /* Dual scattering: the table of the hair colour's fibre (made at init, kept while
     * the colour stays the same: the frames of an animation), and the ambient light the
     * hair reflects with its diffuse colour (the skin's). */
    hk_DualScattering dual;
    hk_Vec3 dual_colour;
    int dual_ready;
    double ambient_light;
    hk_VertexColour *colour;
    /* The states of this picture's vertices: a new picture takes two new values, so
     * that the states need no clearing (the earlier pictures' values mean new). */
    uint32_t busy, done;
    uint32_t *strand_of;              /* the strand of each vertex, unless strand_length */
    uint32_t strand_length;           /* points of every strand when they all have as many, else 0 */
    size_t colour_cap, strand_of_cap; /* kept from picture to picture */
} hk_HairShader;
hk_Status hk_hair_shader_init(hk_HairShader *s, const hk_Scene *scene, const uint8_t *segment_start,
                              const hk_LightMaps *maps, const hk_View *camera, hk_Error *err);
void hk_hair_shader_free(hk_HairShader *s);
/* The colour of vertex i (thread-safe). */
void hk_hair_shader_get(hk_HairShader *s, uint32_t i, float out[3]);

/* sRGB-encoded colour (the visuality file's, as the thesis's colours are display
 * values) to linear RGB. */
hk_Vec3 hk_srgb_to_linear(hk_Vec3 c);

/* ---- per tile of the picture ---------------------------------------------------- */

/* What every tile reads. */
typedef struct hk_TileInput {
    const hk_Scene *scene;
    const hk_View *camera;
    const hk_LightMaps *maps;        /* NULL: no shadows */
    const hk_RasterPoint *hair_proj; /* hair points on the picture */
    hk_HairShader *shader;           /* their colours */
    const hk_TileBins *hair_bins;    /* segments (by first point) per tile, keyed by their
                                        nearer depth */
    const hk_RasterPoint *head_proj; /* head vertices on the picture, or NULL */
    const hk_TileBins *head_bins;    /* front-facing head triangles per tile, or NULL */
    const hk_TileBins *tiles;        /* the tiles' layout (tiles_x, tiles_y) */
} hk_TileInput;

/* The head in one tile: 2 x 2 samples per pixel, Lambert-shaded and shadowed, averaged
 * over the background; base[] gets the colour behind the hair and cutoff[] the depth
 * beyond which hair is hidden (the farthest head sample; +inf where a sample misses). */
typedef struct hk_TileBase {
    float base[HK_TILE * HK_TILE][3], cutoff[HK_TILE * HK_TILE];
} hk_TileBase;
/* The work space of hk_tile_head: the samples. */
typedef struct hk_TileHead {
    float sample_z[HK_TILE * HK_TILE * 4], sample_l[HK_TILE * HK_TILE * 4][2];
    int sample_tri[HK_TILE * HK_TILE * 4];
    /* the triangle being drawn */
    int tri;
    const hk_RasterPoint *tv;
    hk_Rect r;
} hk_TileHead;
/* Fills out; returns the tile's farthest cutoff (+inf when a sample of the tile misses
 * the head): hair behind it is hidden in every pixel of the tile. */
float hk_tile_head(const hk_TileInput *in, int tile, hk_TileHead *work, hk_TileBase *out);

/* Hair of one tile composited over the head: a workspace reused from tile to tile. */
typedef struct hk_TileHair hk_TileHair;
hk_TileHair *hk_tile_hair_create(void);
void hk_tile_hair_destroy(hk_TileHair *w);
/* Draws the tile into image; 0 when out of memory. Counts fragments kept and the
 * most in one pixel. */
int hk_tile_hair(hk_TileHair *w, const hk_TileInput *in, int tile, const hk_TileBase *head, hk_Canvas *image,
                 long long *fragments, int *most);

#endif
