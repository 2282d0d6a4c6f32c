/* The manifest of a simulation's output folder, DIR/simulation.txt (docs/file-formats.md,
 * "Simulation manifest"): what `hairkit simulate` needs besides DIR/guides_kkkk.hair to
 * grow the interpolated hair of any frame again, byte for byte. Read with file:line
 * errors and written atomically. */
#ifndef HAIRKIT_SIMULATION_FILE_H
#define HAIRKIT_SIMULATION_FILE_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_SIMULATION_FILE_NAME "simulation.txt"
/* 2: the body shapes and the head's motion (the interpolated hair of every frame is
 * kept out of the body posed at that frame). Format 1 is refused: its frames grew
 * through the body. */
#define HK_SIMULATION_FILE_VERSION 2

typedef struct hk_SimulationManifest {
    int version;        /* HK_SIMULATION_FILE_VERSION */
    char *setup;        /* Setup: the setup file, absolute path */
    uint64_t seed;      /* Seed of the interpolation */
    long frames;        /* Frames asked for (the run may have stopped earlier) */
    double fps;         /* Fps */
    int guides, points; /* Guides, PointsPerStrand of every guides_kkkk.hair */
    int interpolated;   /* Interpolated: false for --guides-only runs */
    int full_hair;      /* FullHair: frame_kkkk.hair written too */
    /* HairstyleHash, WickHash: FNV-1a 64 of the bytes of the two files the regrowth
     * reads, so that a rebuild after either changed is refused, not silently different */
    uint64_t hairstyle_hash, wick_hash;
    /* CollisionHash: the same of the setup's collision file, continued over the meshes
     * its Mesh lines name (has_collision 0: the setup has none), whose body shapes the
     * hair is kept out of */
    int has_collision;
    uint64_t collision_hash;
    /* The head's motion, which poses the body at frame k (t = k / Fps): either
     * `Motion NAME AMPLITUDE FREQUENCY PX PY PZ`, a scripted motion as given to
     * hk_head_motion_scripted (motion_script set), or `MotionFile "PATH"` and
     * `MotionHash HASH`, a motion file (absolute path) and its fingerprint */
    char *motion_script;
    double motion_amplitude, motion_frequency, motion_pivot[3];
    char *motion_file;
    uint64_t motion_hash;
} hk_SimulationManifest;

HK_API hk_Status hk_simulation_manifest_load(const char *path, hk_SimulationManifest *out, hk_Error *err);
HK_API hk_Status hk_simulation_manifest_save(const char *path, const hk_SimulationManifest *m, hk_Error *err);
HK_API void hk_simulation_manifest_free(hk_SimulationManifest *m);

#ifdef __cplusplus
}
#endif

#endif
