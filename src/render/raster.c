/* Anti-aliased segments for hair (camera and light views) and filled triangles (the
 * head), with the pixel boxes the tile bins (tile_bins.c) sort them by, and the
 * growth of the fragment buffers the segments are drawn into. */
#include <stdlib.h>

#include "raster_inline.h"

int hk_segment_box(hk_RasterPoint a, hk_RasterPoint b, float width, int image_w, int image_h, hk_Rect *box)
{
    return hk_segment_box_inline(a, b, width, image_w, image_h, box);
}

void hk_raster_triangle(const hk_RasterPoint v[3], hk_Rect clip, int supersample, hk_SampleFn emit, void *user)
{
    const float area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (!(fabsf(area) > 1e-12f)) return;
    const int x0 = ifloor(clampf(minf(v[0].x, minf(v[1].x, v[2].x)), (float)clip.x0, (float)clip.x1));
    const int x1 = iceil(clampf(maxf(v[0].x, maxf(v[1].x, v[2].x)), (float)clip.x0 - 1.0f, (float)clip.x1 - 1.0f));
    const int y0 = ifloor(clampf(minf(v[0].y, minf(v[1].y, v[2].y)), (float)clip.y0, (float)clip.y1));
    const int y1 = iceil(clampf(maxf(v[0].y, maxf(v[1].y, v[2].y)), (float)clip.y0 - 1.0f, (float)clip.y1 - 1.0f));
    const float inv = 1.0f / area;
    const int n = supersample == 2 ? 2 : 1;
    const float offset[2] = {n == 2 ? 0.25f : 0.5f, 0.75f}; /* of the samples in a pixel */
    /* Each factor of the edge functions depends on one coordinate of the sample: the
     * factors of a row of samples are taken once for the row, the products are as
     * before (a sample of the head took 50 instructions, its offsets converted and
     * every factor found again). The samples are emitted row of samples by row rather
     * than pixel by pixel: each is still emitted once, and the callbacks keep the
     * nearest of what each sample receives. */
    for (int y = y0; y <= y1; y++)
        for (int sy = 0; sy < n; sy++) {
            const float py = (float)y + offset[sy];
            const float r0 = v[0].y - py, r1 = v[1].y - py, r2 = v[2].y - py;
            for (int x = x0; x <= x1; x++)
                for (int sx = 0; sx < n; sx++) {
                    const float px = (float)x + offset[sx];
                    const float c0 = v[0].x - px, c1 = v[1].x - px, c2 = v[2].x - px;
                    /* Edge functions, normalised: the screen-space barycentric coordinates. */
                    const float l0 = (c1 * r2 - c2 * r1) * inv;
                    const float l1 = (c2 * r0 - c0 * r2) * inv;
                    const float l2 = 1.0f - l0 - l1;
                    if (l0 >= 0.0f && l1 >= 0.0f && l2 >= 0.0f) emit(user, x, y, n * sy + sx, l0, l1, l2);
                }
        }
}

int hk_triangle_box(const hk_RasterPoint v[3], int image_w, int image_h, hk_Rect *box)
{
    for (int i = 0; i < 3; i++)
        if (!(v[i].z > 0.0f)) return 0; /* behind the eye (or NaN): not drawn */
    hk_RasterPoint a = v[0], b = v[1];
    a.x = minf(v[0].x, minf(v[1].x, v[2].x)), a.y = minf(v[0].y, minf(v[1].y, v[2].y));
    b.x = maxf(v[0].x, maxf(v[1].x, v[2].x)), b.y = maxf(v[0].y, maxf(v[1].y, v[2].y));
    return hk_segment_box(a, b, 0.0f, image_w, image_h, box);
}

__attribute__((noinline)) void *hk_grow_fragments(void *array, size_t *cap, size_t size)
{
    const size_t n = *cap ? 2 * *cap : 4096;
    void *grown = realloc(array, n * size);
    if (grown) *cap = n;
    return grown;
}
