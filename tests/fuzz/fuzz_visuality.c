/* libFuzzer: visuality files (src/io/visuality.c). */
#include "fuzz_file.h"
#include "hairkit/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("visuality.txt", data, size);
    hk_Visuality v;
    hk_Error err;
    if (path) hk_visuality_load(path, &v, &err);
    return 0;
}
