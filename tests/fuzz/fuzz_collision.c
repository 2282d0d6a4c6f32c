/* libFuzzer: collision files (src/io/collision_file.c). */
#include "fuzz_file.h"
#include "hairkit/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("collision.txt", data, size);
    hk_Shape *shapes = NULL;
    int count = 0;
    hk_Error err;
    if (path && hk_collision_load(path, &shapes, &count, &err) == HK_OK) hk_free(shapes);
    return 0;
}
