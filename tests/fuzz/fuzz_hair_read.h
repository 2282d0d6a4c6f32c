/* Shared by the harnesses of the hair formats: the input written to a file of the
 * format's extension, read by hk_hair_read in that format, and a walk over what was
 * read (each strand's last point), so that the reader's output is touched too. */
#ifndef HK_FUZZ_HAIR_READ_H
#define HK_FUZZ_HAIR_READ_H

#include "fuzz_file.h"
#include "hairkit/hair_formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
float hk_fuzz_sink; /* what the walk read, so that it is not optimised away */

static int hk_fuzz_read_hair(const char *name, hk_HairFormat format, const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write(name, data, size);
    hk_HairFile hair;
    hk_Error err;
    if (!path || hk_hair_read(path, format, &hair, &err) != HK_OK) return 0;
    float sum = 0.0f;
    for (uint32_t s = 0; s < hair.strand_count; s++) {
        const uint32_t n = hk_hair_strand_points(&hair, s);
        if (n) sum += hair.points[3 * (size_t)(hair.first_point[s] + n - 1)];
    }
    hk_fuzz_sink = sum;
    hk_hair_free(&hair);
    return 0;
}

#endif
