/* Linear RGB to 8-bit sRGB (IEC 61966-2-1 transfer curve), written through libpng. */
#include <math.h>
#include <stdint.h>

#include "hairkit/image.h"
#include "hairkit/render.h"

static uint8_t srgb_byte(float linear)
{
    if (!(linear > 0.0f)) return 0;
    if (linear >= 1.0f) return 255;
    const double v = linear <= 0.0031308f ? 12.92 * linear : 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
    return (uint8_t)lrint(v * 255.0);
}

hk_Status hk_render_write_png(const hk_Canvas *image, const char *path, hk_Error *err)
{
    const size_t n = (size_t)image->width * (size_t)image->height * 3;
    uint8_t *bytes = hk_alloc_array(n, 1, err);
    if (!bytes) return HK_ERR_NOMEM;
    for (size_t i = 0; i < n; i++) bytes[i] = srgb_byte(image->rgb[i]);
    hk_Status st = hk_png_write_rgb8(path, image->width, image->height, bytes, err);
    hk_free(bytes);
    return st;
}
