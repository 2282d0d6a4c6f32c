/* hairkit helicoid: the command's parts (cmd_helicoid.c: options, trace; helicoid_interpolate.c;
 * helicoid_fit.c: fit and reconstruct). Private to the command line. */
#ifndef HK_CLI_HELICOID_H
#define HK_CLI_HELICOID_H

#include "cli.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_hair.h"

#define HK_HELICOID_CMD "helicoid"

typedef struct hk_HelicoidArgs {
    const char *action, *input, *output, *surface, *params, *head;
    double step, density, power, tolerance, lambda, follicles; /* follicles: spacing, 0 = random roots */
    double piece_length, root_piece;                           /* layout by length (m), 0 = none */
    int density_given;
    long count, max_pieces, every, pieces; /* pieces: fixed layout, 0 = split as needed */
    int pieces_given, max_pieces_given;
    hk_CurveFitMethod method;
    uint64_t seed;
    int threads, quiet;
    int waves; /* fit --waves: hk_helicoid_fit_strands_wavy */
} hk_HelicoidArgs;

int hk_helicoid_cli_interpolate(const hk_HelicoidArgs *a);
int hk_helicoid_cli_fit(const hk_HelicoidArgs *a);
int hk_helicoid_cli_reconstruct(const hk_HelicoidArgs *a);

#endif
