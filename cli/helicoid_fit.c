/* hairkit helicoid fit / reconstruct: p-helicoids fitted to the strands of a .hair file
 * (Piuze, Kry and Siddiqi 2011, §5; docs/helicoid-fitting.md), and a full head rebuilt
 * from the fits of one strand in K (§5.4): the options and the printing; the work is
 * hairkit/helicoid_hair.h's. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "helicoid_cli.h"
#include "hairkit/helicoid_fit.h"

static const char *const CMD = HK_HELICOID_CMD;

/* Fits strands idx[0..n) (hk_helicoid_fit_strands, or with waves not NULL
 * hk_helicoid_fit_strands_wavy) with a progress bar on a terminal; errors name the input
 * file. */
static hk_Status fit_strands(const hk_HairFile *hair, const long *idx, long n, const hk_CurveFitDef *opt,
                             const hk_HelicoidArgs *args, hk_PHelicoid *out, hk_Waviness *waves,
                             hk_HelicoidFitReport *report, hk_Error *err)
{
    hk_CliProgress bar = {hk_cli_stderr_is_tty() && !args->quiet, "", -1};
    hk_WavyFitDef wavy = hk_default_wavy_fit_def();
    wavy.base = *opt;
    hk_Status st =
        waves ? hk_helicoid_fit_strands_wavy(hair, idx, n, &wavy, args->threads, hk_cli_progress, &bar, out, waves,
                                             report, err)
              : hk_helicoid_fit_strands(hair, idx, n, opt, args->threads, hk_cli_progress, &bar, out, report, err);
    hk_cli_progress_done(&bar);
    if (st != HK_OK) {
        const hk_Error inner = *err;
        st = hk_error_set(err, st, "%s: %s", args->input, inner.message);
    }
    return st;
}

/* The fit's options from the command line (layout: --pieces, --piece-length, or split
 * as each strand needs). */
static hk_CurveFitDef fit_options(const hk_HelicoidArgs *a)
{
    hk_CurveFitDef o = hk_default_helicoid_fit_def();
    o.method = a->method;
    o.tolerance = a->tolerance;
    o.lambda = a->lambda;
    o.max_pieces = (int)a->max_pieces;
    o.fixed_pieces = a->piece_length > 0.0 ? 0 : (int)a->pieces;
    o.piece_length = a->piece_length;
    o.root_piece_length = a->root_piece;
    return o;
}

int hk_helicoid_cli_fit(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HairFile hair;
    if (hk_hair_read(a->input, HK_HAIR_FORMAT_AUTO, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_cli_warn_units(CMD, a->input, &hair);
    hk_HelicoidSet set;
    long *idx = NULL;
    hk_HelicoidFitReport *rep = NULL;
    hk_Status st = hk_helicoid_set_alloc(&set, (int)hair.strand_count, &err);
    if (st == HK_OK) {
        idx = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(long), &err);
        rep = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(hk_HelicoidFitReport), &err);
        if (!idx || !rep) st = HK_ERR_NOMEM;
    }
    const hk_CurveFitDef opt = fit_options(a);
    const double t0 = hk_seconds_now();
    if (st == HK_OK) {
        for (uint32_t s = 0; s < hair.strand_count; s++) idx[s] = s;
        st = fit_strands(&hair, idx, hair.strand_count, &opt, a, set.strands, a->waves ? set.waves : NULL, rep, &err);
        for (uint32_t s = 0; a->waves && st == HK_OK && s < hair.strand_count; s++)
            set.has_waves[s] = set.waves[s].amplitude > 0.0;
    }
    const double seconds = hk_seconds_now() - t0;
    if (st == HK_OK) st = hk_helicoid_file_save(a->output, &set, "fitted by hairkit helicoid fit", &err);
    if (st == HK_OK) {
        double sum = 0.0, worst = 0.0, fr = 0.0;
        long pieces = 0, over = 0, waved = 0;
        printf("strand,points,pieces,error_m,frechet_m\n");
        for (uint32_t s = 0; s < hair.strand_count; s++) {
            printf("%u,%u,%d,%.6g,%.6g\n", s + 1, hair.first_point[s + 1] - hair.first_point[s], rep[s].pieces,
                   rep[s].error, rep[s].frechet);
            waved += set.has_waves[s];
            sum += rep[s].error, worst = fmax(worst, rep[s].error), fr = fmax(fr, rep[s].frechet);
            pieces += rep[s].pieces;
            /* a strand the fitter could not bring within the tolerance (after its retry) */
            if (rep[s].error > opt.tolerance && ++over <= 10 && !a->quiet)
                fprintf(stderr, "%s: strand %u fitted to %.3g mm, over the tolerance of %.3g mm\n", CMD, s + 1,
                        1e3 * rep[s].error, 1e3 * opt.tolerance);
        }
        if (over > 10 && !a->quiet)
            fprintf(stderr, "%s: ... and %ld more strands over the tolerance (the CSV lists every error)\n", CMD,
                    over - 10);
        const double n = hair.strand_count ? (double)hair.strand_count : 1.0;
        printf("# strands=%u mean_error_m=%.6g max_error_m=%.6g max_frechet_m=%.6g mean_pieces=%.3g "
               "over_tolerance=%ld fits_per_second=%.1f",
               hair.strand_count, sum / n, worst, fr, pieces / n, over, hair.strand_count / fmax(seconds, 1e-9));
        printf(a->waves ? " with_waves=%ld\n" : "\n", waved);
    }
    hk_free(idx), hk_free(rep);
    hk_helicoid_set_free(&set);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

int hk_helicoid_cli_reconstruct(const hk_HelicoidArgs *a)
{
    hk_Error err;
    hk_HairFile hair, out;
    memset(&out, 0, sizeof out);
    if (hk_hair_read(a->input, HK_HAIR_FORMAT_AUTO, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_cli_warn_units(CMD, a->input, &hair);
    hk_CurveFitDef opt = fit_options(a);
    if (!a->pieces_given && !(a->piece_length > 0.0)) { /* the library's layout for reconstructions */
        opt.piece_length = HK_RECONSTRUCT_PIECE_LENGTH;
        opt.root_piece_length = HK_RECONSTRUCT_ROOT_PIECE;
    }
    hk_CliProgress bar = {hk_cli_stderr_is_tty() && !a->quiet, "", -1};
    hk_HelicoidReconstruction r;
    hk_Status st = hair.strand_count > 0
                       ? hk_helicoid_reconstruct(&hair, a->every, &opt, a->power, a->step > 0.0 ? a->step : 0.002,
                                                 a->seed, a->threads, hk_cli_progress, &bar, &out, &r, &err)
                       : hk_error_set(&err, HK_ERR_INVALID, "%s has no strands", a->input);
    hk_cli_progress_done(&bar);
    if (st != HK_OK && hair.strand_count > 0) {
        const hk_Error inner = err;
        st = hk_error_set(&err, st, "%s: %s", a->input, inner.message);
    }
    if (st == HK_OK) st = hk_hair_save(a->output, &out, &err);
    if (st == HK_OK)
        printf("# strands=%ld fitted=%ld fit_s=%.3f interpolated_and_traced_s=%.3f mean_error_m=%.6g "
               "max_error_m=%.6g\n",
               r.strands, r.fitted, r.seconds_fit, r.seconds_rebuild, r.mean_error, r.max_error);
    hk_hair_free(&out);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}
