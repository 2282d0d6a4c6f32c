/* The hair segment rasterisers, inline: they run per candidate pixel and call back per
 * fragment, and where the callback is a known static function (tile_hair.c,
 * light_maps.c) the compiler folds it into the loop; through raster.c's pointer call
 * it cost a function call per fragment. The helpers are shared with raster.c. */
#ifndef HK_RASTER_INLINE_H
#define HK_RASTER_INLINE_H

/* The fragment callbacks are forced inline into the rasterisers in optimised builds
 * (a call per fragment was a measurable part of a picture). The sanitizer builds
 * (-O1) cannot inline a callback through its pointer there, so they only ask. */
#if defined(__SANITIZE_ADDRESS__)
#define HK_FRAGMENT_INLINE static inline
#else
#define HK_FRAGMENT_INLINE static inline __attribute__((always_inline))
#endif

#include "render_internal.h"

/* A fragment buffer of *cap items of `size` bytes reallocated to twice as many (at
 * least 4096); NULL when out of memory (the buffer is kept). Out of line, so that the
 * fragment callbacks that call it stay small enough to fold into the rasterisers. */
void *hk_grow_fragments(void *array, size_t *cap, size_t size);

static inline float clampf(float v, float lo, float hi) { return v < lo ? lo : (v > hi ? hi : v); }
/* min and max without libm calls (fminf and fmaxf are not inlined: they must handle
 * NaN, and the renderer has refused non-finite points before drawing). */
static inline float minf(float a, float b) { return a < b ? a : b; }
static inline float maxf(float a, float b) { return a > b ? a : b; }

/* floor and ceil to int for |v| < 2^31 without a libm call (x86-64's baseline has no
 * rounding instruction; these run per pixel). */
static inline int ifloor(float v)
{
    const int i = (int)v;
    return i - (v < (float)i);
}
static inline int iceil(float v)
{
    const int i = (int)v;
    return i + (v > (float)i);
}

/* hk_segment_box (raster.c), inline. */
static inline int hk_segment_box_inline(hk_RasterPoint a, hk_RasterPoint b, float width, int image_w, int image_h,
                                        hk_Rect *box)
{
    const float r = 0.5f * (width > 1.0f ? width : 1.0f) + 1.0f;
    if (!(a.z > 0.0f && b.z > 0.0f)) return 0; /* behind the camera, or NaN */
    float xa = minf(a.x, b.x) - r, xb = maxf(a.x, b.x) + r;
    float ya = minf(a.y, b.y) - r, yb = maxf(a.y, b.y) + r;
    if (!(xb >= 0.0f && ya < (float)image_h && yb >= 0.0f && xa < (float)image_w)) return 0;
    /* Clamped to the image, so non-negative: floor is truncation (cheaper, and this
     * runs for every segment in both views). */
    box->x0 = (int)clampf(xa, 0.0f, (float)image_w);
    box->x1 = iceil(clampf(xb + 1.0f, 0.0f, (float)image_w));
    box->y0 = (int)clampf(ya, 0.0f, (float)image_h);
    box->y1 = iceil(clampf(yb + 1.0f, 0.0f, (float)image_h));
    return box->x0 < box->x1 && box->y0 < box->y1;
}

/* Both rasterisers take a clip inside the image (x0, y0 >= 0): within it, truncation
 * to int is floor. */

/* Draws the segment a-b of width `width` pixels (the hair's projected diameter; at
 * least one pixel is drawn, thinner hair becomes more transparent) into `clip`. A
 * pixel belongs to the segment when its centre projects onto [0, 1) of it, so that
 * consecutive segments of a strand do not cover the same pixel twice. Coverage is a
 * box filter of the pixel against the line's width. Pixels where closed (NULL: none;
 * rows of HK_TILE from the clip's corner) is non-zero are passed over before any
 * arithmetic: in a full head's tiles half the fragments fell on pixels already
 * opaque. */
static inline void hk_raster_segment_columns(hk_RasterPoint a, hk_RasterPoint b, float width, hk_Rect clip,
                                             const uint8_t *closed, hk_FragmentFn emit, void *user, int narrow)
{
    const float drawn = width > 1.0f ? width : 1.0f;
    const float thin = width < 1.0f ? width : 1.0f; /* sub-pixel hair: coverage becomes opacity */
    const float reach = 0.5f * drawn + 0.5f;        /* beyond this distance a pixel is not covered */
    const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    if (!(len2 > 1e-12f) || !(thin > 0.0f)) return;
    const float inv_len2 = 1.0f / len2, inv_len = sqrtf(inv_len2);
    /* Walk the major axis; across it, the pixels within reach of the line. */
    const int x_major = fabsf(dx) >= fabsf(dy);
    const float major_a = x_major ? a.x : a.y, major_b = x_major ? b.x : b.y;
    const float d_major = x_major ? dx : dy, d_minor = x_major ? dy : dx;
    const float minor_a = x_major ? a.y : a.x;
    const float across = reach * sqrtf(len2) / fabsf(d_major); /* reach measured across */
    const int lo_major = x_major ? clip.x0 : clip.y0, hi_major = x_major ? clip.x1 : clip.y1;
    const int lo_minor = x_major ? clip.y0 : clip.x0, hi_minor = x_major ? clip.y1 : clip.x1;
    /* The columns: a pixel drawn has its centre c = a + t (b - a) + s n, t in [0, 1)
     * and |s| < reach along the line's unit normal n, whose major component is
     * d_minor / len: c's major coordinate lies within reach |d_minor| / len of the ends'
     * range, not reach, and the columns are those whose centres do (the columns past
     * the ends of a segment near the major axis held only pixels projecting outside
     * [0, 1)). A sixteenth of a pixel and 2^-16 of the ends' coordinates more cover
     * the rounding of t and of the distance (a few units in the last place of the
     * coordinates), and at most reach keeps the columns a subset of those within reach
     * of the ends: the pixels are the same. narrow 0: every column within reach of the
     * ends (the test's reference).
     * Clamp in floats first: a segment far off screen must not overflow an int. */
    int m0, m1;
    if (narrow) {
        const float slack = 0.0625f + (fabsf(a.x) + fabsf(a.y) + fabsf(b.x) + fabsf(b.y)) * (1.0f / 65536.0f);
        const float beyond = minf(reach, reach * fabsf(d_minor) * inv_len + slack);
        m0 = iceil(clampf(minf(major_a, major_b) - beyond - 0.5f, (float)lo_major, (float)hi_major));
        m1 = ifloor(clampf(maxf(major_a, major_b) + beyond - 0.5f, (float)lo_major - 1.0f, (float)hi_major - 1.0f));
    } else {
        m0 = ifloor(clampf(minf(major_a, major_b) - reach, (float)lo_major, (float)hi_major));
        m1 = iceil(clampf(maxf(major_a, major_b) + reach, (float)lo_major - 1.0f, (float)hi_major - 1.0f));
    }
    const float slope = d_minor / d_major;
    for (int m = m0; m <= m1; m++) {
        const float cm = (float)m + 0.5f;
        const float centre = minor_a + (cm - major_a) * slope;
        const float lo = clampf(centre - across, (float)lo_minor, (float)hi_minor);
        const float hi = clampf(centre + across, (float)lo_minor - 1.0f, (float)hi_minor - 1.0f);
        /* Truncation is floor for lo >= lo_minor >= 0; hi >= lo_minor - 1 >= -1. */
        int n0 = (int)lo, n1 = hi >= 0.0f ? (int)hi : -1;
        if (n0 < lo_minor) n0 = lo_minor;
        if (n1 > hi_minor - 1) n1 = hi_minor - 1;
        for (int n = n0; n <= n1; n++) {
            if (closed &&
                closed[x_major ? (n - clip.y0) * HK_TILE + (m - clip.x0) : (m - clip.y0) * HK_TILE + (n - clip.x0)])
                continue;
            const float cx = x_major ? cm : (float)n + 0.5f, cy = x_major ? (float)n + 0.5f : cm;
            const float px = cx - a.x, py = cy - a.y;
            const float t = (px * dx + py * dy) * inv_len2;
            if (!(t >= 0.0f && t < 1.0f)) continue;
            const float dist = fabsf(px * dy - py * dx) * inv_len;
            const float cover = reach - dist;
            if (cover <= 0.0f) continue;
            emit(user, x_major ? m : n, x_major ? n : m, t, (cover < 1.0f ? cover : 1.0f) * thin);
        }
    }
}


static inline void hk_raster_segment(hk_RasterPoint a, hk_RasterPoint b, float width, hk_Rect clip,
                                     const uint8_t *closed, hk_FragmentFn emit, void *user)
{
    hk_raster_segment_columns(a, b, width, clip, closed, emit, user, 1);
}

/* The pixels hk_raster_segment_thin can emit for a-b, whatever its clip and width,
 * clipped to the image: 0 when none (and, as hk_segment_box_inline, when an end is
 * behind the eye). Its columns' centres lie between the ends along the major axis (a
 * pixel whose centre m + 1/2 is at or above the lower end is not below the pixel of
 * that end) and across, its pixel is the floor of a point between them: the pixels of
 * the ends' box, with a slack far above the rounding of the rasteriser's sums. Smaller than
 * hk_segment_box_inline's, which pads by half the drawn width and a pixel for the
 * camera's wide rasteriser: a segment is binned into fewer tiles of the light's map
 * (the tiles it left emitted no fragment there). */
static inline int hk_segment_box_thin_inline(hk_RasterPoint a, hk_RasterPoint b, int image_w, int image_h, hk_Rect *box)
{
    if (!(a.z > 0.0f && b.z > 0.0f)) return 0; /* behind the eye, or NaN */
    const float slack = (fabsf(a.x) + fabsf(b.x) + fabsf(a.y) + fabsf(b.y) + 1.0f) * (1.0f / 65536.0f);
    const float xa = minf(a.x, b.x) - slack, xb = maxf(a.x, b.x) + slack;
    const float ya = minf(a.y, b.y) - slack, yb = maxf(a.y, b.y) + slack;
    if (!(xb >= 0.0f && ya < (float)image_h && yb >= 0.0f && xa < (float)image_w)) return 0;
    /* Clamped to the image, so non-negative: floor is truncation. */
    box->x0 = (int)clampf(xa, 0.0f, (float)image_w);
    box->x1 = (int)clampf(xb, 0.0f, (float)(image_w - 1)) + 1;
    box->y0 = (int)clampf(ya, 0.0f, (float)image_h);
    box->y1 = (int)clampf(yb, 0.0f, (float)(image_h - 1)) + 1;
    return box->x0 < box->x1 && box->y0 < box->y1;
}

/* One pixel per step along the major axis (the pixel the centre line crosses), with
 * the opacity of the strip of the given width within that column (clamped to 1): the
 * segment's total opacity at half the fragments, for the light's opacity map. The
 * major axis is known to the compiler in each of its two copies (x_major 1 or 0): the
 * choices between the axes were made again for every column. */
static inline __attribute__((always_inline)) void hk_raster_segment_thin_axis(hk_RasterPoint a, hk_RasterPoint b,
                                                                              float width, hk_Rect clip,
                                                                              hk_FragmentFn emit, void *user,
                                                                              const int x_major)
{
    const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    const float major_a = x_major ? a.x : a.y, d_major = x_major ? dx : dy;
    const float minor_a = x_major ? a.y : a.x, d_minor = x_major ? dy : dx;
    /* The strip of width w crosses each column over a length sqrt(len2) / |d_major|. */
    float alpha = width * sqrtf(len2) / fabsf(d_major);
    if (alpha > 1.0f) alpha = 1.0f;
    const int lo_major = x_major ? clip.x0 : clip.y0, hi_major = x_major ? clip.x1 : clip.y1;
    const int lo_minor = x_major ? clip.y0 : clip.x0, hi_minor = x_major ? clip.y1 : clip.x1;
    /* The columns whose centre c = m + 1/2 the test on t below can accept: with A =
     * major_a and D = d_major, t = (c - A) / D rounded is in [0, 1) only for c between A
     * and A + D (exact sums; rounding is monotonic, so c - A beyond D in size rounds to
     * t >= 1, and of the other sign to t < 0). Those are the integers m in
     * [lo - 1/2, hi - 1/2], widened by a slack far above the rounding of these sums:
     * the columns passed over are ones the test rejected, each at the cost of a
     * division (they were 60 % of the columns visited in a full head's map). */
    const float e = major_a + d_major, lo = minf(major_a, e), hi = maxf(major_a, e);
    const float slack = (fabsf(major_a) + fabsf(d_major) + 1.0f) * (1.0f / 65536.0f);
    const int m0 = iceil(clampf(lo - 0.5f - slack, (float)lo_major, (float)hi_major));
    const int m1 = ifloor(clampf(hi - 0.5f + slack, (float)lo_major - 1.0f, (float)hi_major - 1.0f));
    for (int m = m0; m <= m1; m++) {
        const float t = ((float)m + 0.5f - major_a) / d_major;
        if (!(t >= 0.0f && t < 1.0f)) continue;
        const float minor = minor_a + t * d_minor;
        if (!(minor >= (float)lo_minor && minor < (float)hi_minor)) continue;
        const int n = (int)minor; /* floor, and in [lo_minor, hi_minor): minor is, lo_minor >= 0 */
        emit(user, x_major ? m : n, x_major ? n : m, t, alpha);
    }
}

static inline __attribute__((always_inline)) void
hk_raster_segment_thin(hk_RasterPoint a, hk_RasterPoint b, float width, hk_Rect clip, hk_FragmentFn emit, void *user)
{
    const float dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
    if (!(len2 > 1e-12f) || !(width > 0.0f)) return;
    if (fabsf(dx) >= fabsf(dy))
        hk_raster_segment_thin_axis(a, b, width, clip, emit, user, 1);
    else
        hk_raster_segment_thin_axis(a, b, width, clip, emit, user, 0);
}

#endif
