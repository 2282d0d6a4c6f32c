/* libFuzzer: collision files (src/io/collision_file.c). A closed tetrahedron of 2 cm is
 * written beside the input as tetra.obj, so that the seeds' Mesh lines reach the field
 * (corpus/collision/mesh.txt). */
#include "fuzz_file.h"
#include "hairkit/io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char tetra[] = "v 0 0 0\nv 0.02 0 0\nv 0 0.02 0\nv 0 0 0.02\n"
                                "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    static int mesh_written;
    if (!mesh_written) mesh_written = hk_fuzz_write("tetra.obj", (const uint8_t *)tetra, sizeof tetra - 1) != NULL;
    const char *path = hk_fuzz_write("collision.txt", data, size);
    hk_CollisionSet set;
    hk_Error err;
    if (path && hk_collision_load(path, &set, &err) == HK_OK) hk_collision_free(&set);
    return 0;
}
