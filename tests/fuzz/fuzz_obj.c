/* libFuzzer: the OBJ reader (src/io/obj.c), then what the groom computes first from a
 * wick: its area and strand counts (hk_groom_check_size). */
#include "fuzz_file.h"
#include "hairkit/groom.h"
#include "hairkit/io.h"
#include "hairkit/mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("mesh.obj", data, size);
    hk_Mesh mesh;
    hk_Error err;
    if (!path || hk_obj_load(path, &mesh, &err) != HK_OK) return 0;
    hk_Hairstyle style = hk_default_hairstyle();
    double lengths[1] = {0.2};
    style.strand.element_count = 1, style.strand.element_lengths = lengths;
    long strands;
    hk_groom_check_size(&style.strand, &style.interpolation, &mesh, NULL, &strands, &err);
    hk_mesh_free(&mesh);
    return 0;
}
