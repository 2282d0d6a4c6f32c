/* libFuzzer: USC-HairSalon .data (src/io/hair_usc.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.data", HK_HAIR_FORMAT_USC, data, size);
}
