/* libFuzzer: TressFX .tfx v3 and v4 (src/io/hair_tfx.c), read through hk_hair_read, and a walk
 * over what was read. */
#include "fuzz_file.h"
#include "hairkit/hair_formats.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
float hk_fuzz_sink; /* what the walk read, so that it is not optimised away */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("hair.tfx", data, size);
    hk_HairFile hair;
    hk_Error err;
    if (!path || hk_hair_read(path, HK_HAIR_FORMAT_TFX, &hair, &err) != HK_OK) return 0;
    float sum = 0.0f;
    for (uint32_t s = 0; s < hair.strand_count; s++) {
        const uint32_t n = hk_hair_strand_points(&hair, s);
        if (n) sum += hair.points[3 * (size_t)(hair.first_point[s] + n - 1)];
    }
    hk_fuzz_sink = sum;
    hk_hair_free(&hair);
    return 0;
}
