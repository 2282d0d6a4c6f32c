/* hairkit helicoid: the command's parts (cmd_helicoid.c: options, trace; helicoid_interpolate.c;
 * helicoid_fit.c: fit and reconstruct). Private to the command line. */
#ifndef HK_CLI_HELICOID_H
#define HK_CLI_HELICOID_H

#include "cli.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid_file.h"

#define HK_HELICOID_CMD "helicoid"

typedef struct hk_HelicoidArgs {
    const char *action, *input, *output, *surface, *params, *head;
    double step, density, power, tolerance, lambda, follicles; /* follicles: spacing, 0 = random roots */
    double piece_length, root_piece;                           /* layout by length (m), 0 = none */
    int density_given;
    long count, max_pieces, every, pieces;      /* pieces: fixed layout, 0 = split as needed */
    int pieces_given, max_pieces_given, method; /* method: hk_CurveFitMethod */
    uint64_t seed;
    int threads, quiet;
} hk_HelicoidArgs;

/* Traces the set's strands, each followed by its wisp strands, into a .hair file; `seed` draws
 * the strands' wave phases when the set's waviness has a jitter. */
hk_Status hk_helicoid_cli_trace_set(const hk_HelicoidSet *set, double step, uint64_t seed, int threads,
                                    hk_HairFile *hair, hk_Error *err);

/* Interpolates the guides at the roots into out. With guide_normals (then normals too) on the
 * surface (§4.3: frames relative to the normals); else plain IDW, normals (may be NULL) only
 * keeping E_T out of the surface. */
hk_Status hk_helicoid_cli_interpolate_at(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                         const hk_Vec3 *roots, const hk_Vec3 *normals, long count, double power,
                                         hk_PHelicoid *out, hk_Error *err);

int hk_helicoid_cli_interpolate(const hk_HelicoidArgs *a);
int hk_helicoid_cli_fit(const hk_HelicoidArgs *a);
int hk_helicoid_cli_reconstruct(const hk_HelicoidArgs *a);

#endif
