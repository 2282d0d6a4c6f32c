/* libFuzzer: a simulation folder's manifest, simulation.txt (src/io/simulation_file.c). */
#include "fuzz_file.h"
#include "hairkit/simulation_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("simulation.txt", data, size);
    hk_SimulationManifest m;
    hk_Error err;
    if (path && hk_simulation_manifest_load(path, &m, &err) == HK_OK) hk_simulation_manifest_free(&m);
    return 0;
}
