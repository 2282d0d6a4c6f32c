/* Anti-aliased 2D drawing on a float canvas, for strand plots in docs and the demo. */
#include "hairkit/canvas.h"

#include <math.h>
#include <stdint.h>

#include "hairkit/image.h"

hk_Status hk_canvas_alloc(int width, int height, hk_Vec3 background, hk_Canvas *out, hk_Error *err)
{
    out->width = out->height = 0;
    out->rgb = NULL;
    if (width < 1 || height < 1 || width > HK_MAX_IMAGE_SIDE || height > HK_MAX_IMAGE_SIDE)
        return hk_error_set(err, HK_ERR_INVALID, "canvas size %dx%d out of range", width, height);
    out->rgb = hk_alloc_array((size_t)width * (size_t)height, 3 * sizeof(float), err);
    if (!out->rgb) return HK_ERR_NOMEM;
    out->width = width;
    out->height = height;
    for (size_t i = 0; i < (size_t)width * (size_t)height; i++) {
        out->rgb[3 * i] = (float)background.x;
        out->rgb[3 * i + 1] = (float)background.y;
        out->rgb[3 * i + 2] = (float)background.z;
    }
    return HK_OK;
}

void hk_canvas_free(hk_Canvas *c)
{
    hk_free(c->rgb);
    c->rgb = NULL;
    c->width = c->height = 0;
}

static void blend(hk_Canvas *c, int x, int y, hk_Vec3 color, double a)
{
    float *px = c->rgb + 3 * ((size_t)y * (size_t)c->width + (size_t)x);
    px[0] = (float)(px[0] + a * (color.x - px[0]));
    px[1] = (float)(px[1] + a * (color.y - px[1]));
    px[2] = (float)(px[2] + a * (color.z - px[2]));
}

void hk_canvas_line(hk_Canvas *c, double x0, double y0, double x1, double y1, double width, hk_Vec3 color,
                    double opacity)
{
    /* A point that is not finite draws nothing; the box is clipped to the canvas
     * before it becomes ints (a plot of a 1e308 ellipsoid gave NaN and 1e308 here). */
    if (!(isfinite(x0) && isfinite(y0) && isfinite(x1) && isfinite(y1) && isfinite(width) && width >= 0.0)) return;
    const double r = 0.5 * width + 1.0;
    const double fxa = floor(fmin(x0, x1) - r), fxb = ceil(fmax(x0, x1) + r);
    const double fya = floor(fmin(y0, y1) - r), fyb = ceil(fmax(y0, y1) + r);
    if (fxb < 0.0 || fyb < 0.0 || fxa > c->width - 1 || fya > c->height - 1) return;
    const int xa = fxa < 0.0 ? 0 : (int)fxa, xb = fxb > c->width - 1 ? c->width - 1 : (int)fxb;
    const int ya = fya < 0.0 ? 0 : (int)fya, yb = fyb > c->height - 1 ? c->height - 1 : (int)fyb;
    const double dx = x1 - x0, dy = y1 - y0, len2 = dx * dx + dy * dy;
    for (int y = ya; y <= yb; y++)
        for (int x = xa; x <= xb; x++) {
            /* Distance from the pixel centre to the segment; coverage of a box filter. */
            double px = x + 0.5 - x0, py = y + 0.5 - y0;
            double t = len2 > 0.0 ? (px * dx + py * dy) / len2 : 0.0;
            t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
            double ex = px - t * dx, ey = py - t * dy;
            double cover = 0.5 * width + 0.5 - sqrt(ex * ex + ey * ey);
            if (!(cover > 0.0)) continue; /* NaN too: ends 1e308 apart overflow dx */
            if (cover > 1.0) cover = 1.0;
            if (width < 1.0) cover *= width; /* thin lines fade rather than vanish */
            blend(c, x, y, color, cover * opacity);
        }
}

void hk_canvas_disc(hk_Canvas *c, double x, double y, double radius, hk_Vec3 color, double opacity)
{
    hk_canvas_line(c, x, y, x, y, 2.0 * radius, color, opacity);
}

static uint8_t to_byte(float v)
{
    if (!(v > 0.0f)) return 0;
    if (v >= 1.0f) return 255;
    return (uint8_t)lrintf(v * 255.0f);
}

hk_Status hk_canvas_write_png(const hk_Canvas *c, const char *path, hk_Error *err)
{
    const size_t n = (size_t)c->width * (size_t)c->height * 3;
    uint8_t *bytes = hk_alloc_array(n, 1, err);
    if (!bytes) return HK_ERR_NOMEM;
    for (size_t i = 0; i < n; i++) bytes[i] = to_byte(c->rgb[i]);
    hk_Status st = hk_png_write_rgb8(path, c->width, c->height, bytes, err);
    hk_free(bytes);
    return st;
}
