/* libFuzzer: PLY meshes, binary and ASCII (src/io/mesh_ply.c, through the PLY reader
 * ply.c it shares with the strands), then what a head is used for first: its area and
 * the closest point to a point near it. */
#include "fuzz_file.h"
#include "hairkit/mesh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("head.ply", data, size);
    hk_Mesh mesh;
    hk_Error err;
    if (!path || hk_mesh_load(path, &mesh, &err) != HK_OK) return 0;
    (void)hk_mesh_area(&mesh);
    hk_Vec3 point, normal;
    (void)hk_mesh_closest_point(&mesh, hk_v3(0.1, 0.2, 0.3), &point, &normal);
    hk_mesh_up_to_y(&mesh, HK_AXIS_POS_X);
    (void)hk_mesh_scale(&mesh, 0.001, &err);
    hk_mesh_free(&mesh);
    return 0;
}
