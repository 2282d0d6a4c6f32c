/* The manifest of a simulation's output folder, DIR/simulation.txt (docs/file-formats.md,
 * "Simulation manifest"): what `hairkit simulate` needs besides DIR/guides_kkkk.hair to
 * grow the interpolated hair of any frame again, byte for byte. Read with file:line
 * errors and written atomically. */
#ifndef HAIRKIT_SIMULATION_FILE_H
#define HAIRKIT_SIMULATION_FILE_H

#include <stdint.h>

#include "hairkit/core.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_SIMULATION_FILE_NAME "simulation.txt"
#define HK_SIMULATION_FILE_VERSION 1

typedef struct hk_SimulationManifest {
    int version;               /* HK_SIMULATION_FILE_VERSION */
    char *setup;               /* Setup: the setup file, absolute path */
    uint64_t seed;             /* Seed of the interpolation */
    long frames;               /* Frames asked for (the run may have stopped earlier) */
    double fps;                /* Fps */
    int guides, points;        /* Guides, PointsPerStrand of every guides_kkkk.hair */
    int interpolated;          /* Interpolated: false for --guides-only runs */
    int full_hair;             /* FullHair: frame_kkkk.hair written too */
    /* HairstyleHash, WickHash: FNV-1a 64 of the bytes of the two files the regrowth
     * reads, so that a rebuild after either changed is refused, not silently different */
    uint64_t hairstyle_hash, wick_hash;
} hk_SimulationManifest;

hk_Status hk_simulation_manifest_load(const char *path, hk_SimulationManifest *out, hk_Error *err);
hk_Status hk_simulation_manifest_save(const char *path, const hk_SimulationManifest *m, hk_Error *err);
void hk_simulation_manifest_free(hk_SimulationManifest *m);

/* FNV-1a 64 of a file's bytes ("path: cannot read" when it cannot be read). */
hk_Status hk_file_fingerprint(const char *path, uint64_t *out, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
