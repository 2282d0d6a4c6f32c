/* A small anti-aliased 2D canvas for plots and diagrams (linear RGB in floats). */
#ifndef HAIRKIT_CANVAS_H
#define HAIRKIT_CANVAS_H

#include "hairkit/collide.h"
#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_Canvas {
    int width, height;
    float *rgb; /* 3 floats per pixel in [0, 1], row-major, top row first */
} hk_Canvas;

/* A canvas of width x height pixels filled with `background` (data: release it with
 * hk_canvas_free, safe on a zeroed or freed canvas). */
HK_API hk_Status hk_canvas_alloc(int width, int height, hk_Vec3 background, hk_Canvas *out, hk_Error *err);
HK_API void hk_canvas_free(hk_Canvas *c);

/* Segment from (x0, y0) to (x1, y1) in pixel units (y down), of the given width,
 * blended with the given opacity; coverage from the exact distance to the segment. */
HK_API void hk_canvas_line(hk_Canvas *c, double x0, double y0, double x1, double y1, double width, hk_Vec3 color,
                           double opacity);

/* Filled disc. */
HK_API void hk_canvas_disc(hk_Canvas *c, double x, double y, double radius, hk_Vec3 color, double opacity);

HK_API hk_Status hk_canvas_write_png(const hk_Canvas *c, const char *path, hk_Error *err);

/* ---- strand plots --------------------------------------------------------------- */

typedef struct hk_PlotStrand {
    const hk_Vec3 *points; /* polyline of the centreline */
    int count;
    hk_Vec3 color;
} hk_PlotStrand;

/* Two orthographic views side by side, same scale, with a 1-2-5 grid: left the side
 * view (horizontal axis z, vertical y), right the front view (horizontal x, vertical
 * y). Collision shapes are drawn as silhouettes, with their envelope (volume * alpha)
 * as a lighter outline. */
HK_API hk_Status hk_plot_strands_png(const char *path, int width, int height, const hk_PlotStrand *strands,
                                     int strand_count, const hk_Shape *shapes, int shape_count, double envelope_alpha,
                                     hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
