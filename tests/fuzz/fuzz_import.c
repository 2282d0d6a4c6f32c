/* libFuzzer: imported-guides files (src/io/import_file.c), with a valid strands.hair of
 * two strands of three points beside them (the file's StrandsFile), so that inputs
 * naming it reach the checks of the strands against the guides. */
#include "fuzz_file.h"
#include "hairkit/capture.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static int have_strands;
    if (!have_strands) {
        hk_HairFile h;
        memset(&h, 0, sizeof h);
        float points[18] = {0, 0, 0, 0, -0.01f, 0, 0, -0.02f, 0, 0.01f, 0, 0, 0.01f, -0.01f, 0, 0.01f, -0.02f, 0};
        uint16_t segments[2] = {2, 2};
        uint32_t first[3] = {0, 3, 6};
        h.strand_count = 2, h.point_count = 6, h.flags = HK_HAIR_POINTS | HK_HAIR_SEGMENTS;
        h.points = points, h.segments = segments, h.first_point = first;
        const char *p = hk_fuzz_write("strands.hair", (const uint8_t *)"", 0);
        hk_Error err;
        if (p && hk_hair_save(p, &h, &err) == HK_OK) have_strands = 1;
    }
    const char *path = hk_fuzz_write("guides.txt", data, size);
    hk_ImportedGroom g;
    hk_Error err;
    if (path && hk_imported_groom_load(path, &g, &err) == HK_OK) hk_imported_groom_free(&g);
    return 0;
}
