/* Pictures: 8-bit RGB images read and written as PNG through libpng. */
#ifndef HAIRKIT_IMAGE_H
#define HAIRKIT_IMAGE_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_MAX_IMAGE_SIDE 32768

/* Writes w x h RGB pixels (row-major, top row first) to path atomically. */
HK_API hk_Status hk_png_write_rgb8(const char *path, int width, int height, const uint8_t *rgb, hk_Error *err);

/* Reads a PNG of any colour type into 8-bit RGB (alpha dropped); *rgb is allocated
 * with hk_alloc_array and released with hk_free. */
HK_API hk_Status hk_png_read_rgb8(const char *path, int *width, int *height, uint8_t **rgb, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
