/* libFuzzer: helicoid files (src/io/helicoid_file.c). */
#include "fuzz_file.h"
#include "hairkit/helicoid_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("helicoid.txt", data, size);
    hk_HelicoidSet set;
    hk_Error err;
    if (path && hk_helicoid_file_load(path, &set, &err) == HK_OK) hk_helicoid_set_free(&set);
    return 0;
}
