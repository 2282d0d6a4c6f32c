/* libFuzzer: hairstyle files (src/io/hairstyle.c, over the key-file reader). */
#include "fuzz_file.h"
#include "hairkit/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("hairstyle.txt", data, size);
    hk_Hairstyle style;
    hk_Error err;
    if (path && hk_hairstyle_load(path, &style, &err) == HK_OK) hk_hairstyle_free(&style);
    return 0;
}
