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

/* The bytes by the upper 16 bits of a float (its exponent and 7 bits of mantissa): an
 * interval of floats 2^-7 of its value wide, narrower than the gaps between the
 * thresholds at, so that a value's byte is its interval's first float's or one more
 * (every one of the 2^32 floats checked against srgb_byte, 7 December 2026). The
 * binary search over at took 8 dependent comparisons a channel, most of the
 * conversion's 85 instructions. */
enum { LEAD_SHIFT = 16 };
typedef struct ByteTable {
    float at[256];
    uint32_t first_lead, leads; /* the leads of at[1] .. 1.0f */
    uint8_t byte[0x3f80];       /* of each lead's first float (0x3f80: 1.0f's lead) */
} ByteTable;

/* The byte of linear, as srgb_byte: the count of at[1 .. 255] it reaches. */
static uint8_t srgb_byte_from(const ByteTable *b, float linear)
{
    if (!(linear > 0.0f)) return 0; /* NaN too */
    uint32_t bits;
    memcpy(&bits, &linear, sizeof bits);
    const uint32_t lead = (bits >> LEAD_SHIFT) - b->first_lead;
    if (lead >= b->leads) return linear < b->at[1] ? 0 : 255; /* below at[1], or 1 and above */
    int k = b->byte[lead];
    while (k < 255 && b->at[k + 1] <= linear) k++;
    return (uint8_t)k;
}

static void byte_table(ByteTable *b)
{
    byte_thresholds(b->at);
    uint32_t first, one;
    const float f1 = 1.0f;
    memcpy(&first, &b->at[1], sizeof first);
    memcpy(&one, &f1, sizeof one);
    b->first_lead = first >> LEAD_SHIFT, b->leads = (one >> LEAD_SHIFT) - b->first_lead;
    int k = 0;
    for (uint32_t lead = 0; lead < b->leads; lead++) {
        const float v = float_of((b->first_lead + lead) << LEAD_SHIFT);
        while (k < 255 && b->at[k + 1] <= v) k++;
        b->byte[lead] = (uint8_t)k;
    }
}

hk_Status hk_render_write_png(const hk_Canvas *image, const char *path, hk_Error *err)
{
    const size_t n = (size_t)image->width * (size_t)image->height * 3;
    uint8_t *bytes = hk_alloc_array(n, 1, err);
    if (!bytes) return HK_ERR_NOMEM;
    ByteTable table;
    byte_table(&table);
    /* In parallel: each byte depends on its value alone. */
#pragma omp parallel for schedule(static)
    for (long i = 0; i < (long)n; i++) bytes[i] = srgb_byte_from(&table, image->rgb[i]);
    hk_Status st = hk_png_write_rgb8(path, image->width, image->height, bytes, err);
    hk_free(bytes);
    return st;
}
