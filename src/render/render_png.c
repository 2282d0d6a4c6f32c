/* Linear RGB to 8-bit sRGB (IEC 61966-2-1 transfer curve), written through libpng. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "hairkit/image.h"
#include "hairkit/render.h"

static uint8_t srgb_byte(float linear)
{
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const double v = linear <= 0.0031308f ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (uint8_t)lrint(v * 255.0);
}

static float float_of(uint32_t bits)
{
    float f;
    memcpy(&f, &bits, sizeof f);
    return f;
}

/* at[k] = the smallest float whose byte is k or more (k = 1 .. 255), found by bisection
 * over the bits of positive floats (which order like integers). srgb_byte does not
 * decrease, so a value's byte is the number of these it reaches: the same bytes as
 * srgb_byte without a pow per channel (3 million a picture, the writing's cost). */
static void byte_thresholds(float at[256])
{
    uint32_t one;
    const float f1 = 1.0f;
    memcpy(&one, &f1, sizeof one);
    at[0] = 0.0f;
    for (int k = 1; k < 256; k++) {
        uint32_t lo = 0, hi = one; /* byte(lo) < k <= byte(hi) */
        while (hi - lo > 1) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (srgb_byte(float_of(mid)) >= k)
                hi = mid;
            else
                lo = mid;
        }
        at[k] = float_of(hi);
    }
}

static uint8_t srgb_byte_from(const float at[256], float linear)
{
    if (!(linear > 0.0f)) return 0; /* NaN too */
    int k = 0;
    for (int step = 128; step > 0; step >>= 1)
        if (k + step < 256 && at[k + step] <= linear) k += step;
    return (uint8_t)k;
}

hk_Status hk_render_write_png(const hk_Canvas *image, const char *path, hk_Error *err)
{
    const size_t n = (size_t)image->width * (size_t)image->height * 3;
    uint8_t *bytes = hk_alloc_array(n, 1, err);
    if (!bytes) return HK_ERR_NOMEM;
    float at[256];
    byte_thresholds(at);
    /* In parallel: each byte depends on its value alone. */
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)n; i++) bytes[i] = srgb_byte_from(at, image->rgb[i]);
    hk_Status st = hk_png_write_rgb8(path, image->width, image->height, bytes, err);
    hk_free(bytes);
    return st;
}
