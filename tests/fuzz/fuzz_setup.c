/* libFuzzer: setup files (src/io/setup.c). The files a setup may name exist next to
 * it (empty), so that inputs naming them get past the existence checks. */
#include "fuzz_file.h"
#include "hairkit/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int ready;
    if (!ready) {
        const char *names[] = {"hairstyle.txt", "collision.txt", "visuality.txt", "head.obj", "wick.obj", "in.hair"};
        for (int i = 0; i < 6; i++) hk_fuzz_write(names[i], (const uint8_t *)"", 0);
        ready = 1;
    }
    const char *path = hk_fuzz_write("setup.txt", data, size);
    hk_Setup setup;
    hk_Error err;
    if (path && hk_setup_load(path, &setup, &err) == HK_OK) hk_setup_free(&setup);
    return 0;
}
