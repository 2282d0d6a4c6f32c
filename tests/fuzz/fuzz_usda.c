/* libFuzzer: USD ascii BasisCurves (src/io/hair_usda.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.usda", HK_HAIR_FORMAT_USDA, data, size);
}
