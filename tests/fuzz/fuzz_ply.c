/* libFuzzer: PLY strands, binary and ASCII (src/io/hair_ply.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.ply", HK_HAIR_FORMAT_PLY, data, size);
}
