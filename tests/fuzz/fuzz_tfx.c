/* libFuzzer: TressFX .tfx v3 and v4 (src/io/hair_tfx.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.tfx", HK_HAIR_FORMAT_TFX, data, size);
}
