/* Helicoid files: sets of p-helicoid strands as text (docs/file-formats.md, "Helicoid
 * file"), read with file:line errors and written atomically. */
#ifndef HAIRKIT_HELICOID_FILE_H
#define HAIRKIT_HELICOID_FILE_H

#include "hairkit/export.h"
#include "hairkit/helicoid.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_HELICOID_FILE_MAX_STRANDS 1000000

typedef struct hk_HelicoidSet {
    double step;          /* Step: tracing step along the strands (m), default 0.002 */
    hk_Waviness waviness; /* Waviness a b (eq. 4), default none; phase 0 */
    double wave_jitter;   /* Waviness a b j: strand i's waves start at phase 2 pi j u_i, u_i
                             uniform in [0, 1) from the trace's seed (0: all in step) */
    int count;            /* strands */
    hk_PHelicoid *strands;
    int *wisp_count; /* Wisp count radius spread, per strand (count 0: none) */
    double *wisp_radius, *wisp_spread;
    /* Waves a b c, per strand: a strand's own waves of eq. 4 (amplitude, frequency, phase
     * in radians), as a fit with waves finds them (hk_helicoid_fit_wavy); where
     * has_waves[i] they replace the file's Waviness for strand i (its wisp too). */
    unsigned char *has_waves;
    hk_Waviness *waves;
} hk_HelicoidSet;

HK_API hk_Status hk_helicoid_file_load(const char *path, hk_HelicoidSet *out, hk_Error *err);

/* Writes the set (17 significant digits: a load gives back the same numbers). */
HK_API hk_Status hk_helicoid_file_save(const char *path, const hk_HelicoidSet *set, const char *comment, hk_Error *err);

/* An empty set with `count` strands allocated (zeroed, one piece each unset). */
HK_API hk_Status hk_helicoid_set_alloc(hk_HelicoidSet *set, int count, hk_Error *err);
HK_API void hk_helicoid_set_free(hk_HelicoidSet *set);

#ifdef __cplusplus
}
#endif

#endif
