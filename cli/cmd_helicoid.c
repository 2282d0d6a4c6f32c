/* hairkit helicoid: generalized helicoids (paper 003): trace helicoid files into hair,
 * interpolate guides over a surface, fit helicoids to .hair strands, and reconstruct a
 * full head from sparse fitted strands. */
#include <getopt.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "hairkit/follicle_sampling.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/rng.h"

static const char *const CMD = "helicoid";

/* Interpolated strands leave the surface at least this steeply (radians; §4.3, see
 * hk_phelicoid_interpolate_on_surface): a floor for averages of guides that lean different
 * ways, not a style (the guides set the angle). */
static const double MIN_ELEVATION = 0.17453292519943295; /* 10 degrees */

static void usage(FILE *out)
{
    fprintf(out,
            "usage: hairkit helicoid trace FILE.txt -o OUT.hair [--step S]\n"
            "       hairkit helicoid interpolate GUIDES.txt --surface MESH.obj -o OUT.hair\n"
            "               [--density D | --count N | --follicles SPACING [--head HEAD.obj]]\n"
            "               [--power P] [--seed N] [--params OUT.txt]\n"
            "       hairkit helicoid fit IN.hair -o OUT.txt [--tolerance M] [--lambda L]\n"
            "               [--max-pieces N]\n"
            "       hairkit helicoid reconstruct IN.hair -o OUT.hair [--every K] [--power P]\n"
            "\n"
            "Generalized helicoids (Piuze, Kry, Siddiqi; docs/helicoids.md):\n"
            "  trace        p-helicoid strands of a helicoid file (docs/file-formats.md), with\n"
            "               their waviness and wisps, as a .hair file\n"
            "  interpolate  new strands rooted on a surface mesh (area-uniform random roots,\n"
            "               or follicles with --follicles), each the inverse-distance blend of\n"
            "               the file's guides (paper 4.1-4.3), their root frames averaged\n"
            "               relative to the surface normal so that every strand leaves it\n"
            "  fit          a p-helicoid for every strand of a .hair file (Frechet coupling,\n"
            "               Nelder-Mead, recursive splitting, paper 5); prints the error of\n"
            "               every strand and in all; writes a helicoid file\n"
            "  reconstruct  fits every K-th strand of a .hair file and interpolates all the\n"
            "               others from them at their roots (paper 5.4); prints the error\n"
            "\n"
            "options:\n"
            "  -o, --output FILE  the file to write\n"
            "  --step S           tracing step in metres (default: the file's Step, or 2 mm)\n"
            "  --surface MESH     OBJ mesh the interpolated roots lie on (e.g. assets/wick.obj)\n"
            "  --density D        interpolated strands per cm^2 of the surface (default 100)\n"
            "  --count N          or exactly N interpolated strands\n"
            "  --follicles D      or one strand per follicle, follicles D metres apart spread\n"
            "                     by repelling particles over an implicit surface fitted to the\n"
            "                     --surface mesh (the wick) and the head around it (paper 4.3,\n"
            "                     docs/follicle-sampling.md); 0.005 gives about 2,300 on\n"
            "                     assets/wick.obj in a second or two, 0.003 about 6,400\n"
            "                     in ten; the time grows as 1 / D^2 or faster\n"
            "  --head MESH        with --follicles: the head mesh, whose vertices near the\n"
            "                     wick are fitted too (e.g. assets/head.obj; optional)\n"
            "  --power P          inverse-distance power (default 3, the paper's)\n"
            "  --params FILE      also write the interpolated strands as a helicoid file\n"
            "  --tolerance M      accept a fit when its mean leash (normalised Frechet\n"
            "                     coupling) is below M metres (default 0.0002)\n"
            "  --lambda L         regularisation of eq. 5 (default 1e-7)\n"
            "  --max-pieces N     pieces per fitted strand (default 16)\n"
            "  --every K          reconstruct: fit one strand in K (default 10)\n"
            "  --seed N           random seed (default 1)\n"
            "  --threads N        threads (default: all cores); results do not depend on it\n"
            "  --quiet            no summary on stderr\n"
            "  -h, --help         this help\n");
}

typedef struct Args {
    const char *action, *input, *output, *surface, *params, *head;
    double step, density, power, tolerance, lambda, follicles; /* follicles: spacing, 0 = random roots */
    int density_given;
    long count, max_pieces, every;
    uint64_t seed;
    int threads, quiet;
} Args;

static int parse_args(int argc, char **argv, Args *a)
{
    enum { OPT_STEP = 3000, OPT_SURFACE, OPT_DENSITY, OPT_COUNT, OPT_POWER, OPT_PARAMS, OPT_TOLERANCE, OPT_LAMBDA,
           OPT_MAX_PIECES, OPT_EVERY, OPT_FOLLICLES, OPT_HEAD };
    static const struct option options[] = {
        {"output", required_argument, NULL, 'o'},      {"step", required_argument, NULL, OPT_STEP},
        {"surface", required_argument, NULL, OPT_SURFACE}, {"density", required_argument, NULL, OPT_DENSITY},
        {"count", required_argument, NULL, OPT_COUNT}, {"power", required_argument, NULL, OPT_POWER},
        {"params", required_argument, NULL, OPT_PARAMS}, {"tolerance", required_argument, NULL, OPT_TOLERANCE},
        {"lambda", required_argument, NULL, OPT_LAMBDA}, {"max-pieces", required_argument, NULL, OPT_MAX_PIECES},
        {"every", required_argument, NULL, OPT_EVERY}, {"seed", required_argument, NULL, 's'},
        {"follicles", required_argument, NULL, OPT_FOLLICLES}, {"head", required_argument, NULL, OPT_HEAD},
        {"threads", required_argument, NULL, 't'},     {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},              {NULL, 0, NULL, 0},
    };
    memset(a, 0, sizeof *a);
    a->density = 100.0;
    a->power = 3.0;
    a->tolerance = hk_helicoid_fit_options().tolerance;
    a->lambda = hk_helicoid_fit_options().lambda;
    a->max_pieces = hk_helicoid_fit_options().max_pieces;
    a->every = 10;
    a->seed = 1;
    if (argc < 2) return hk_cli_usage_error(CMD, "missing action: trace, interpolate, fit or reconstruct");
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(stdout);
        return -1;
    }
    a->action = argv[1];
    if (strcmp(a->action, "trace") && strcmp(a->action, "interpolate") && strcmp(a->action, "fit") &&
        strcmp(a->action, "reconstruct"))
        return hk_cli_usage_error(CMD, "unknown action '%s' (trace, interpolate, fit, reconstruct)", a->action);
    optind = 2;
    opterr = 0;
    int c, rc;
    while ((c = getopt_long(argc, argv, ":ho:", options, NULL)) != -1) {
        switch (c) {
        case 'o': a->output = optarg; break;
        case OPT_SURFACE: a->surface = optarg; break;
        case OPT_PARAMS: a->params = optarg; break;
        case OPT_HEAD: a->head = optarg; break;
        case OPT_FOLLICLES:
            if (!hk_cli_parse_double(optarg, &a->follicles) || !(a->follicles > 0.0 && a->follicles <= 1.0))
                return hk_cli_usage_error(CMD, "--follicles expects a spacing in metres in (0, 1], got '%s'", optarg);
            break;
        case OPT_STEP:
            if (!hk_cli_parse_double(optarg, &a->step) || !(a->step > 0.0 && a->step <= 1.0))
                return hk_cli_usage_error(CMD, "--step expects metres in (0, 1], got '%s'", optarg);
            break;
        case OPT_DENSITY:
            if (!hk_cli_parse_double(optarg, &a->density) || !(a->density > 0.0 && a->density <= 100000.0))
                return hk_cli_usage_error(CMD, "--density expects strands per cm^2 in (0, 100000], got '%s'", optarg);
            a->density_given = 1;
            break;
        case OPT_COUNT:
            if (!hk_cli_parse_int(optarg, 1, 10000000, &a->count))
                return hk_cli_usage_error(CMD, "--count expects 1 to 10000000, got '%s'", optarg);
            break;
        case OPT_POWER:
            if (!hk_cli_parse_double(optarg, &a->power) || !(a->power > 0.0 && a->power <= 20.0))
                return hk_cli_usage_error(CMD, "--power expects a number in (0, 20], got '%s'", optarg);
            break;
        case OPT_TOLERANCE:
            if (!hk_cli_parse_double(optarg, &a->tolerance) || !(a->tolerance > 0.0))
                return hk_cli_usage_error(CMD, "--tolerance expects metres > 0, got '%s'", optarg);
            break;
        case OPT_LAMBDA:
            if (!hk_cli_parse_double(optarg, &a->lambda) || !(a->lambda >= 0.0))
                return hk_cli_usage_error(CMD, "--lambda expects a number >= 0, got '%s'", optarg);
            break;
        case OPT_MAX_PIECES:
            if (!hk_cli_parse_int(optarg, 1, HK_HELICOID_MAX_PIECES, &a->max_pieces))
                return hk_cli_usage_error(CMD, "--max-pieces expects 1 to %d, got '%s'", HK_HELICOID_MAX_PIECES, optarg);
            break;
        case OPT_EVERY:
            if (!hk_cli_parse_int(optarg, 1, 1000000, &a->every))
                return hk_cli_usage_error(CMD, "--every expects 1 to 1000000, got '%s'", optarg);
            break;
        case 's':
            if ((rc = hk_cli_seed_option(CMD, optarg, &a->seed))) return rc;
            break;
        case 't':
            if ((rc = hk_cli_threads_option(CMD, optarg, &a->threads))) return rc;
            break;
        case 'q': a->quiet = 1; break;
        case 'h': usage(stdout); return -1;
        case ':': return hk_cli_usage_error(CMD, "option '%s' needs a value", argv[optind - 1]);
        default: return hk_cli_usage_error(CMD, "unknown option '%s'", argv[optind - 1]);
        }
    }
    if (optind >= argc) return hk_cli_usage_error(CMD, "%s: missing input file", a->action);
    if (optind + 1 < argc) return hk_cli_usage_error(CMD, "unexpected argument '%s'", argv[optind + 1]);
    a->input = argv[optind];
    if (!a->output) return hk_cli_usage_error(CMD, "no output: give -o FILE");
    if (!strcmp(a->action, "interpolate") && !a->surface)
        return hk_cli_usage_error(CMD, "interpolate needs --surface MESH.obj for the roots");
    if (a->follicles > 0.0 && (a->count || a->density_given))
        return hk_cli_usage_error(CMD, "--follicles places one strand per follicle: drop --%s",
                                  a->count ? "count" : "density");
    if (a->head && !(a->follicles > 0.0))
        return hk_cli_usage_error(CMD, "--head is fitted with the wick by --follicles: give --follicles SPACING");
    return 0;
}

/* ---- strands to .hair ------------------------------------------------------------- */

/* Traces the set's strands, each followed by its wisp strands, into a .hair file. */
static hk_Status trace_set(const hk_HelicoidSet *set, double step, int threads, hk_HairFile *hair, hk_Error *err)
{
    /* Point counts first, so that the file is allocated once. */
    long total = 0;
    for (int s = 0; s < set->count; s++) {
        total += 1 + set->wisp_count[s];
        if (total > 100000000L) return hk_error_set(err, HK_ERR_INVALID, "more than 1e8 strands with the wisps");
    }
    uint32_t *counts = hk_alloc_array((size_t)total, sizeof(uint32_t), err);
    long *first = hk_alloc_array((size_t)set->count + 1, sizeof(long), err);
    if (!counts || !first) {
        hk_free(counts), hk_free(first);
        return HK_ERR_NOMEM;
    }
    hk_Status st = HK_OK;
    long k = 0;
    for (int s = 0; s < set->count && st == HK_OK; s++) {
        first[s] = k;
        const int n = hk_phelicoid_point_count(&set->strands[s], step);
        if (n < 2 || n > 65536)
            st = hk_error_set(err, HK_ERR_INVALID, "strand %d: %d points at step %g (2 to 65536 allowed)", s + 1, n,
                              step);
        for (int w = 0; w <= set->wisp_count[s]; w++) counts[k++] = (uint32_t)(n > 0 ? n : 0);
    }
    first[set->count] = k;
    if (st == HK_OK) st = hk_hair_alloc(hair, (uint32_t)total, counts, err);
    hk_free(counts);
    if (st != HK_OK) {
        hk_free(first);
        return st;
    }
    int failed = -1;
    hk_Error first_err;
    hk_error_clear(&first_err);
    const int saved = omp_get_max_threads();
    if (threads > 0) omp_set_num_threads(threads);
#pragma omp parallel for schedule(dynamic, 16)
    for (int s = 0; s < set->count; s++) {
        const hk_PHelicoid *h = &set->strands[s];
        const int n = (int)(hair->first_point[first[s] + 1] - hair->first_point[first[s]]);
        const int m = 1 + set->wisp_count[s];
        hk_Vec3 *pts = hk_alloc_array((size_t)n * (size_t)m, sizeof(hk_Vec3), NULL);
        hk_Error e;
        hk_Status rs = pts ? hk_phelicoid_trace(h, step, &set->waviness, NULL, pts, NULL, &e) : HK_ERR_NOMEM;
        if (rs == HK_OK && m > 1)
            rs = hk_phelicoid_wisp(h, m - 1, set->wisp_radius[s], set->wisp_spread[s], (uint64_t)s, step,
                                   &set->waviness, pts + n, &e);
        if (rs == HK_OK) {
            float *out = hair->points + 3 * (size_t)hair->first_point[first[s]];
            for (long i = 0; i < (long)n * m; i++) {
                out[3 * i] = (float)pts[i].x, out[3 * i + 1] = (float)pts[i].y, out[3 * i + 2] = (float)pts[i].z;
            }
        } else {
#pragma omp critical(hk_helicoid_cli)
            if (failed < 0 || s < failed) {
                failed = s;
                first_err = e;
                if (!pts) hk_error_set(&first_err, HK_ERR_NOMEM, "out of memory");
            }
        }
        hk_free(pts);
    }
    if (threads > 0) omp_set_num_threads(saved);
    hk_free(first);
    if (failed >= 0) {
        hk_hair_free(hair);
        return hk_error_set(err, first_err.code, "strand %d: %s", failed + 1, first_err.message);
    }
    hair->default_thickness = 1e-4f;
    hk_hair_set_info(hair, "hairkit generalized helicoids");
    return HK_OK;
}

static int do_trace(const Args *a)
{
    hk_Error err;
    hk_HelicoidSet set;
    if (hk_helicoid_file_load(a->input, &set, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    const double step = a->step > 0.0 ? a->step : set.step;
    const double t0 = hk_cli_now();
    hk_Status st = trace_set(&set, step, a->threads, &hair, &err);
    if (st == HK_OK) st = hk_hair_save(a->output, &hair, &err);
    if (st == HK_OK && !a->quiet)
        fprintf(stderr, "hairkit %s trace: %d helicoid strands, %u hair strands (with wisps), %u points in %.3f s\n",
                CMD, set.count, hair.strand_count, hair.point_count, hk_cli_now() - t0);
    hk_hair_free(&hair);
    hk_helicoid_set_free(&set);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

/* ---- roots on a surface ------------------------------------------------------------- */

/* count roots uniform by area on the mesh (a triangle by its area, then uniform in it),
 * each from the counter-based RNG keyed by its index: the same roots whatever the threads. */
static void mesh_roots(const hk_Mesh *m, long count, uint64_t seed, const double *cumulative, hk_Vec3 *pos,
                       hk_Vec3 *normal)
{
#pragma omp parallel for schedule(static)
    for (long i = 0; i < count; i++) {
        const double u = hk_rng_uniform(seed, 101, (uint64_t)i) * cumulative[m->triangle_count];
        int lo = 0, hi = m->triangle_count - 1;
        while (lo < hi) {
            const int mid = (lo + hi) / 2;
            if (cumulative[mid + 1] <= u) lo = mid + 1;
            else hi = mid;
        }
        double r1 = hk_rng_uniform(seed, 102, (uint64_t)i), r2 = hk_rng_uniform(seed, 103, (uint64_t)i);
        if (r1 + r2 > 1.0) r1 = 1.0 - r1, r2 = 1.0 - r2;
        const int *t = m->triangles + 3 * lo;
        const double b[3] = {1.0 - r1 - r2, r1, r2};
        hk_Vec3 p = hk_v3_zero(), n = hk_v3_zero();
        for (int k = 0; k < 3; k++) {
            p = hk_v3_madd(p, m->positions[t[k]], b[k]);
            n = hk_v3_madd(n, m->normals[t[k]], b[k]);
        }
        pos[i] = p;
        normal[i] = hk_v3_normalize(n);
    }
}

/* Interpolates the guides at the roots into out. With guide_normals (then normals too) on the
 * surface (§4.3: frames relative to the normals); else plain IDW, normals (may be NULL) only
 * keeping E_T out of the surface. */
static hk_Status interpolate_at(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals, int guide_count,
                                const hk_Vec3 *roots, const hk_Vec3 *normals, long count, double power,
                                hk_PHelicoid *out, hk_Error *err)
{
    int failed = -1;
    hk_Error first;
    hk_error_clear(&first);
#pragma omp parallel for schedule(static)
    for (long i = 0; i < count; i++) {
        hk_Error e;
        const hk_Vec3 x = roots[i];
        const hk_Status st =
            guide_normals
                ? hk_phelicoid_interpolate_on_surface(guides, guide_normals, guide_count, x, normals[i], power,
                                                      MIN_ELEVATION, &out[i], &e)
                : hk_phelicoid_interpolate(guides, guide_count, x, normals ? &normals[i] : NULL, power, &out[i], &e);
        if (st != HK_OK) {
#pragma omp critical(hk_helicoid_cli)
            if (failed < 0 || i < failed) failed = (int)i, first = e;
        }
    }
    if (failed >= 0) return hk_error_set(err, first.code, "interpolated strand %d: %s", failed + 1, first.message);
    return HK_OK;
}

/* Roots drawn area-uniformly on the mesh: --count N, or --density per cm^2 of its area. */
static hk_Status random_roots(const Args *a, const hk_Mesh *mesh, long *count, hk_Vec3 **roots, hk_Vec3 **normals,
                              hk_Error *err)
{
    double *cumulative = hk_alloc_array((size_t)mesh->triangle_count + 1, sizeof(double), err);
    if (!cumulative) return HK_ERR_NOMEM;
    cumulative[0] = 0.0;
    for (int t = 0; t < mesh->triangle_count; t++) cumulative[t + 1] = cumulative[t] + hk_mesh_triangle_area(mesh, t);
    const double area = cumulative[mesh->triangle_count];
    long n = a->count ? a->count : (long)llround(area * 1e4 * a->density);
    hk_Status st = HK_OK;
    if (n < 1 || !(area > 0.0))
        st = hk_error_set(err, HK_ERR_INVALID, "%s: no area to grow %ld strands on", a->surface, n);
    else if (n > 10000000)
        st = hk_error_set(err, HK_ERR_INVALID, "%ld strands: at most 10,000,000", n);
    if (st == HK_OK) {
        *roots = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
        *normals = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
        if (!*roots || !*normals) st = HK_ERR_NOMEM;
    }
    if (st == HK_OK) {
        mesh_roots(mesh, n, a->seed, cumulative, *roots, *normals);
        *count = n;
    }
    hk_free(cumulative);
    return st;
}

/* Roots at follicles (§4.3): the particle sampler on the implicit surface of the wick (the
 * --surface mesh) and the head around it, normals from that surface. Prints a summary. */
static hk_Status follicle_roots(const Args *a, const hk_Mesh *wick, long *count, hk_Vec3 **roots, hk_Vec3 **normals,
                                hk_Error *err)
{
    hk_Mesh head;
    memset(&head, 0, sizeof head);
    if (a->head && hk_obj_load(a->head, &head, err) != HK_OK) return err->code;
    if (hk_cli_stderr_is_tty() && !a->quiet)
        fprintf(stderr, "hairkit %s interpolate: sampling follicles %g mm apart on %s...\n", CMD, 1e3 * a->follicles,
                a->surface);
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    def.spacing = a->follicles;
    def.seed = a->seed;
    def.threads = a->threads;
    hk_FollicleSamples f;
    hk_Error e;
    const double t0 = hk_cli_now();
    hk_Status st = hk_wick_follicles(a->head ? &head : NULL, wick, &def, &f, &e);
    hk_mesh_free(&head);
    if (st != HK_OK) {
        if (a->head) return hk_error_set(err, st, "follicles on %s (head %s): %s", a->surface, a->head, e.message);
        return hk_error_set(err, st, "follicles on %s: %s", a->surface, e.message);
    }
    if (!a->quiet)
        fprintf(stderr, "hairkit %s interpolate: %d follicles %g mm apart on %s (%.4g cm^2), %d iterations, %.3f s\n",
                CMD, f.count, 1e3 * a->follicles, a->surface, 1e4 * hk_mesh_area(wick), f.iterations,
                hk_cli_now() - t0);
    *count = f.count, *roots = f.points, *normals = f.normals;
    f.points = f.normals = NULL; /* handed over */
    hk_follicle_samples_free(&f);
    return HK_OK;
}

/* The surface normal at each guide's root: at the closest point of the surface mesh (§4.3's W_i).
 * Warns about guides that leave into the surface (their neighbours are lifted off it, they are
 * not: a guide is reproduced as it is). */
static hk_Status guide_normals(const Args *a, const hk_Mesh *mesh, const hk_HelicoidSet *guides, hk_Vec3 *normals,
                               hk_Error *err)
{
    for (int i = 0; i < guides->count; i++) {
        const hk_PHelicoid *g = &guides->strands[i];
        const double d = hk_mesh_closest_point(mesh, g->root, NULL, &normals[i]);
        if (d < 0.0 || !(hk_v3_norm(normals[i]) > 0.5))
            return hk_error_set(err, HK_ERR_INVALID, "%s: no surface normal for guide %d of %s", a->surface, i + 1,
                                a->input);
        const double lean = hk_v3_dot(hk_m3_col(&g->frame, 0), normals[i]);
        if (lean < 0.0 && !a->quiet)
            fprintf(stderr, "hairkit %s interpolate: warning: guide %d of %s points %.0f degrees into %s at its root\n",
                    CMD, i + 1, a->input, asin(fmin(1.0, -lean)) * 57.29577951308232, a->surface);
    }
    return HK_OK;
}

static int do_interpolate(const Args *a)
{
    hk_Error err;
    hk_HelicoidSet guides, made;
    memset(&made, 0, sizeof made);
    hk_Mesh mesh;
    memset(&mesh, 0, sizeof mesh);
    if (hk_helicoid_file_load(a->input, &guides, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_Status st = hk_obj_load(a->surface, &mesh, &err);
    hk_Vec3 *roots = NULL, *normals = NULL, *gnormals = NULL;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    const int saved = omp_get_max_threads();
    if (a->threads > 0) omp_set_num_threads(a->threads);
    long count = 0;
    if (st == HK_OK) {
        gnormals = hk_alloc_array((size_t)guides.count, sizeof(hk_Vec3), &err);
        st = gnormals ? guide_normals(a, &mesh, &guides, gnormals, &err) : HK_ERR_NOMEM;
    }
    if (st == HK_OK)
        st = a->follicles > 0.0 ? follicle_roots(a, &mesh, &count, &roots, &normals, &err)
                                : random_roots(a, &mesh, &count, &roots, &normals, &err);
    const double t0 = hk_cli_now();
    if (st == HK_OK) st = hk_helicoid_set_alloc(&made, (int)count, &err);
    if (st == HK_OK)
        st = interpolate_at(guides.strands, gnormals, guides.count, roots, normals, count, a->power, made.strands,
                            &err);
    const double t1 = hk_cli_now();
    made.step = a->step > 0.0 ? a->step : guides.step;
    made.waviness = guides.waviness;
    if (st == HK_OK) st = trace_set(&made, made.step, a->threads, &hair, &err);
    const double t2 = hk_cli_now();
    if (a->threads > 0) omp_set_num_threads(saved);
    if (st == HK_OK) st = hk_hair_save(a->output, &hair, &err);
    if (st == HK_OK && a->params) st = hk_helicoid_file_save(a->params, &made, "interpolated by hairkit", &err);
    if (st == HK_OK && !a->quiet)
        fprintf(stderr,
                "hairkit %s interpolate: %ld strands from %d guides: parameters %.3f s, traced %.3f s (%u points)\n",
                CMD, count, guides.count, t1 - t0, t2 - t1, hair.point_count);
    hk_hair_free(&hair);
    hk_free(roots), hk_free(normals), hk_free(gnormals);
    hk_mesh_free(&mesh);
    hk_helicoid_set_free(&made);
    hk_helicoid_set_free(&guides);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

/* ---- fitting ------------------------------------------------------------------------ */

typedef struct FitReport {
    double error, frechet; /* normalised coupling and Fréchet distance (m) */
    int pieces;
    long evaluations;
} FitReport;

/* Fits strands idx[0..n) of the hair file into out[0..n), in parallel, one fitter per
 * thread. */
static hk_Status fit_strands(const hk_HairFile *hair, const long *idx, long n, const hk_CurveFitOptions *opt,
                             int threads, hk_PHelicoid *out, FitReport *report, hk_Error *err)
{
    int failed = -1;
    hk_Error first;
    hk_error_clear(&first);
    const int saved = omp_get_max_threads();
    if (threads > 0) omp_set_num_threads(threads);
#pragma omp parallel
    {
        hk_Error e;
        hk_HelicoidFitter *f = hk_helicoid_fitter_create(HK_CURVEFIT_MAX_SAMPLES, &e);
        hk_Vec3 *pts = hk_alloc_array(65536, sizeof(hk_Vec3), NULL);
#pragma omp for schedule(dynamic, 4)
        for (long i = 0; i < n; i++) {
            const uint32_t a = hair->first_point[idx[i]], b = hair->first_point[idx[i] + 1];
            hk_Status st = (f && pts) ? HK_OK : HK_ERR_NOMEM;
            if (st == HK_OK && (b - a < 2 || b - a > HK_CURVEFIT_MAX_SAMPLES))
                st = hk_error_set(&e, HK_ERR_INVALID, "%u points (2 to %d can be fitted)", b - a,
                                  HK_CURVEFIT_MAX_SAMPLES);
            hk_CurveFit fit;
            if (st == HK_OK) {
                for (uint32_t p = a; p < b; p++) {
                    const float *q = hair->points + 3 * (size_t)p;
                    pts[p - a] = hk_v3(q[0], q[1], q[2]);
                }
                st = hk_helicoid_fit(f, pts, (int)(b - a), opt, &out[i], &fit, &e);
            }
            if (st == HK_OK) {
                report[i] = (FitReport){fit.error, fit.frechet, fit.piece_count, fit.evaluations};
            } else {
#pragma omp critical(hk_helicoid_cli)
                if (failed < 0 || i < failed) failed = (int)i, first = e;
            }
        }
        hk_helicoid_fitter_destroy(f);
        hk_free(pts);
    }
    if (threads > 0) omp_set_num_threads(saved);
    if (failed >= 0)
        return hk_error_set(err, first.code, "strand %ld: %s", idx[failed] + 1, first.message);
    return HK_OK;
}

static hk_CurveFitOptions fit_options(const Args *a)
{
    hk_CurveFitOptions o = hk_helicoid_fit_options();
    o.tolerance = a->tolerance;
    o.lambda = a->lambda;
    o.max_pieces = (int)a->max_pieces;
    return o;
}

static int do_fit(const Args *a)
{
    hk_Error err;
    hk_HairFile hair;
    if (hk_hair_load(a->input, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    hk_HelicoidSet set;
    long *idx = NULL;
    FitReport *rep = NULL;
    hk_Status st = hk_helicoid_set_alloc(&set, (int)hair.strand_count, &err);
    if (st == HK_OK) {
        idx = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(long), &err);
        rep = hk_alloc_array(hair.strand_count ? hair.strand_count : 1, sizeof(FitReport), &err);
        if (!idx || !rep) st = HK_ERR_NOMEM;
    }
    const hk_CurveFitOptions opt = fit_options(a);
    const double t0 = hk_cli_now();
    if (st == HK_OK) {
        for (uint32_t s = 0; s < hair.strand_count; s++) idx[s] = s;
        st = fit_strands(&hair, idx, hair.strand_count, &opt, a->threads, set.strands, rep, &err);
    }
    const double seconds = hk_cli_now() - t0;
    if (st == HK_OK) st = hk_helicoid_file_save(a->output, &set, "fitted by hairkit helicoid fit", &err);
    if (st == HK_OK) {
        double sum = 0.0, worst = 0.0, fr = 0.0;
        long pieces = 0;
        printf("strand,points,pieces,error_m,frechet_m\n");
        for (uint32_t s = 0; s < hair.strand_count; s++) {
            printf("%u,%u,%d,%.6g,%.6g\n", s + 1, hair.first_point[s + 1] - hair.first_point[s], rep[s].pieces,
                   rep[s].error, rep[s].frechet);
            sum += rep[s].error, worst = fmax(worst, rep[s].error), fr = fmax(fr, rep[s].frechet);
            pieces += rep[s].pieces;
        }
        const double n = hair.strand_count ? (double)hair.strand_count : 1.0;
        printf("# strands=%u mean_error_m=%.6g max_error_m=%.6g max_frechet_m=%.6g mean_pieces=%.3g "
               "fits_per_second=%.1f\n",
               hair.strand_count, sum / n, worst, fr, pieces / n, hair.strand_count / fmax(seconds, 1e-9));
    }
    hk_free(idx), hk_free(rep);
    hk_helicoid_set_free(&set);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

static int do_reconstruct(const Args *a)
{
    hk_Error err;
    hk_HairFile hair, out;
    memset(&out, 0, sizeof out);
    if (hk_hair_load(a->input, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    const long n = hair.strand_count, k = (n + a->every - 1) / a->every;
    hk_HelicoidSet guides, all;
    memset(&all, 0, sizeof all);
    long *idx = NULL;
    FitReport *rep = NULL;
    hk_Vec3 *roots = NULL;
    hk_Status st = n > 0 ? hk_helicoid_set_alloc(&guides, (int)k, &err)
                         : hk_error_set(&err, HK_ERR_INVALID, "%s has no strands", a->input);
    if (st == HK_OK) st = hk_helicoid_set_alloc(&all, (int)n, &err);
    if (st == HK_OK) {
        idx = hk_alloc_array((size_t)k, sizeof(long), &err);
        rep = hk_alloc_array((size_t)k, sizeof(FitReport), &err);
        roots = hk_alloc_array((size_t)n, sizeof(hk_Vec3), &err);
        if (!idx || !rep || !roots) st = HK_ERR_NOMEM;
    }
    const hk_CurveFitOptions opt = fit_options(a);
    const double t0 = hk_cli_now();
    if (st == HK_OK) {
        for (long i = 0; i < k; i++) idx[i] = i * a->every;
        st = fit_strands(&hair, idx, k, &opt, a->threads, guides.strands, rep, &err);
    }
    const double t1 = hk_cli_now();
    if (st == HK_OK) {
        for (long s = 0; s < n; s++) {
            const float *q = hair.points + 3 * (size_t)hair.first_point[s];
            roots[s] = hk_v3(q[0], q[1], q[2]);
        }
        const int saved = omp_get_max_threads();
        if (a->threads > 0) omp_set_num_threads(a->threads);
        st = interpolate_at(guides.strands, NULL, guides.count, roots, NULL, n, a->power, all.strands, &err);
        if (a->threads > 0) omp_set_num_threads(saved);
    }
    const double step = a->step > 0.0 ? a->step : 0.002;
    all.step = step;
    if (st == HK_OK) st = trace_set(&all, step, a->threads, &out, &err);
    const double t2 = hk_cli_now();
    if (st == HK_OK) st = hk_hair_save(a->output, &out, &err);
    if (st == HK_OK) {
        /* Error of the reconstruction: each strand against the original, by the mean
         * leash of their Fréchet coupling. */
        double sum = 0.0, worst = 0.0;
        for (long s = 0; s < n && st == HK_OK; s++) {
            const uint32_t a0 = hair.first_point[s], a1 = hair.first_point[s + 1];
            const uint32_t b0 = out.first_point[s], b1 = out.first_point[s + 1];
            hk_Vec3 *pa = hk_alloc_array(a1 - a0 + (b1 - b0), sizeof(hk_Vec3), &err);
            if (!pa) {
                st = HK_ERR_NOMEM;
                break;
            }
            hk_Vec3 *pb = pa + (a1 - a0);
            for (uint32_t p = a0; p < a1; p++) pa[p - a0] = hk_v3(hair.points[3 * p], hair.points[3 * p + 1], hair.points[3 * p + 2]);
            for (uint32_t p = b0; p < b1; p++) pb[p - b0] = hk_v3(out.points[3 * p], out.points[3 * p + 1], out.points[3 * p + 2]);
            hk_FrechetMeasures m;
            if (hk_frechet_measures(pa, (int)(a1 - a0), pb, (int)(b1 - b0), &m, &err) == HK_OK) {
                sum += m.normalized;
                worst = fmax(worst, m.normalized);
            }
            hk_free(pa);
        }
        if (st == HK_OK)
            printf("# strands=%ld fitted=%ld fit_s=%.3f interpolated_and_traced_s=%.3f mean_error_m=%.6g "
                   "max_error_m=%.6g\n",
                   n, k, t1 - t0, t2 - t1, sum / n, worst);
    }
    hk_free(idx), hk_free(rep), hk_free(roots);
    hk_helicoid_set_free(&guides);
    hk_helicoid_set_free(&all);
    hk_hair_free(&out);
    hk_hair_free(&hair);
    return st == HK_OK ? HK_EXIT_OK : hk_cli_fail(CMD, &err);
}

int hk_cmd_helicoid(int argc, char **argv)
{
    Args a;
    int rc = parse_args(argc, argv, &a);
    if (rc) return rc < 0 ? HK_EXIT_OK : rc;
    if (!strcmp(a.action, "trace")) return do_trace(&a);
    if (!strcmp(a.action, "interpolate")) return do_interpolate(&a);
    if (!strcmp(a.action, "fit")) return do_fit(&a);
    return do_reconstruct(&a);
}
