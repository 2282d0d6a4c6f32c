/* Hair geometry in Cem Yuksel's cyHair format (.hair), the save/load format of
 * hairkit and what many renderers and hair datasets read.
 *
 * Layout (little-endian): a 128-byte header "HAIR", u32 strand count, u32 point count,
 * u32 flags, u32 default segment count, f32 default thickness, f32 default
 * transparency, f32[3] default colour, char[88] information; then, in this order and
 * only when their flag is set, u16 segments[strands] (0x1), f32 points[3 points] (0x2),
 * f32 thickness[points] (0x4), f32 transparency[points] (0x8), f32 colours[3 points]
 * (0x10). Strand i has segments[i] + 1 points (or default + 1 without the array). */
#ifndef HAIRKIT_HAIRFILE_H
#define HAIRKIT_HAIRFILE_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_HAIR_SEGMENTS     0x1u
#define HK_HAIR_POINTS       0x2u
#define HK_HAIR_THICKNESS    0x4u
#define HK_HAIR_TRANSPARENCY 0x8u
#define HK_HAIR_COLORS       0x10u
#define HK_HAIR_INFO_SIZE    88

typedef struct hk_HairFile {
    uint32_t strand_count;
    uint32_t point_count;
    uint32_t flags;
    uint32_t default_segments;
    float default_thickness;
    float default_transparency;
    float default_color[3];
    char info[HK_HAIR_INFO_SIZE]; /* kept byte for byte (not necessarily NUL-terminated) */
    uint16_t *segments;           /* strand_count, when flags & HK_HAIR_SEGMENTS */
    float *points;                /* 3 * point_count (always present after loading) */
    float *thickness;             /* point_count or NULL */
    float *transparency;          /* point_count or NULL */
    float *colors;                /* 3 * point_count or NULL */
    uint32_t *first_point;        /* strand_count + 1 offsets, derived (not in the file) */
} hk_HairFile;

/* Reads a .hair file; sizes are checked against the file's length before anything is
 * allocated, and truncated or inconsistent files are refused with a clear message. A
 * file without the points array is refused (there is no hair to read). */
HK_API hk_Status hk_hair_load(const char *path, hk_HairFile *hair, hk_Error *err);

/* Writes atomically. Every array whose flag is set must be present. */
HK_API hk_Status hk_hair_save(const char *path, const hk_HairFile *hair, hk_Error *err);

/* Allocates a file for strands of the given point counts (flags: segments and
 * points; other arrays absent). */
HK_API hk_Status hk_hair_alloc(hk_HairFile *hair, uint32_t strand_count, const uint32_t *points_per_strand,
                               hk_Error *err);

/* Fills first_point from segments / default_segments; checks the total. */
HK_API hk_Status hk_hair_index(hk_HairFile *hair, hk_Error *err);

/* Points of strand i. */
static inline uint32_t hk_hair_strand_points(const hk_HairFile *hair, uint32_t i)
{
    return hair->first_point[i + 1] - hair->first_point[i];
}

/* Sets the 88-byte information field from a string (truncated, NUL-padded). */
HK_API void hk_hair_set_info(hk_HairFile *hair, const char *text);

HK_API void hk_hair_free(hk_HairFile *hair);

#ifdef __cplusplus
}
#endif

#endif
