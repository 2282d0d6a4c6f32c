/* libFuzzer: cyHair .hair files (src/io/hair_file.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.hair", HK_HAIR_FORMAT_CYHAIR, data, size);
}
