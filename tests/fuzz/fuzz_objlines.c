/* libFuzzer: OBJ polylines (src/io/hair_objlines.c). */
#include "fuzz_hair_read.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return hk_fuzz_read_hair("hair.obj", HK_HAIR_FORMAT_OBJ, data, size);
}
