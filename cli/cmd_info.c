/* hairkit info: what a hair file holds (strands, points, lengths, bounding box), in any
 * format hairkit reads, with a hint at the units. */
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit info FILE [--from F]\n\n"
                 "Prints the number of strands and points, the strand lengths (min, mean, max),\n"
                 "the bounding box, the arrays present and the information field of a hair file\n"
                 "in any format hairkit reads (.hair, .tfx, .data, .ply, .obj, .usda; --from names\n"
                 "the format when the extension does not), and a hint at its units: hairkit works\n"
                 "in metres, and an extent of hundreds suggests millimetres (hairkit convert\n"
                 "--scale 0.001).\n"
                 "\n"
                 "options:\n"
                 "  --from F           format of FILE (hair, tfx, usc, ply, obj, usda)\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "hairkit groom examples/coupe4/setup.txt -o coupe4.hair",
                    "# a PLY in millimetres: info says so from its extent",
                    "hairkit convert coupe4.hair coupe4.ply --scale 1000", "hairkit info coupe4.ply");
}

int hk_cmd_info(int argc, char **argv)
{
    static const struct option options[] = {
        {"from", required_argument, NULL, 'f'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return HK_EXIT_OK;
        }
    hk_HairFormat format = HK_HAIR_FORMAT_AUTO;
    const char *path = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--from")) {
            if (i + 1 >= argc) return hk_cli_usage_error("info", "option '--from' needs a value");
            const int f = hk_hair_format_from_name(argv[++i]);
            if (f < 0)
                return hk_cli_usage_error("info", "--from expects hair, tfx, usc, ply, obj or usda, got '%s'", argv[i]);
            format = (hk_HairFormat)f;
        } else if (!strncmp(argv[i], "--from=", 7)) {
            const int f = hk_hair_format_from_name(argv[i] + 7);
            if (f < 0)
                return hk_cli_usage_error("info", "--from expects hair, tfx, usc, ply, obj or usda, got '%s'",
                                          argv[i] + 7);
            format = (hk_HairFormat)f;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            return hk_cli_unknown_option("info", options, argv[i]);
        } else if (path) {
            return hk_cli_usage_error("info", "expected exactly one FILE");
        } else {
            path = argv[i];
        }
    }
    if (!path) return hk_cli_usage_error("info", "expected exactly one FILE");
    hk_HairFile h;
    hk_Error err;
    if (hk_hair_read(path, format, &h, &err) != HK_OK) return hk_cli_fail("info", &err);
    double lmin = DBL_MAX, lmax = 0.0, lsum = 0.0, lo[3] = {DBL_MAX, DBL_MAX, DBL_MAX},
           hi[3] = {-DBL_MAX, -DBL_MAX, -DBL_MAX};
    uint32_t pmin = UINT32_MAX, pmax = 0;
    for (uint32_t s = 0; s < h.strand_count; s++) {
        double len = 0.0;
        const uint32_t a = h.first_point[s], b = h.first_point[s + 1];
        for (uint32_t p = a; p < b; p++) {
            const float *q = h.points + 3 * (size_t)p;
            for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], q[k]), hi[k] = fmax(hi[k], q[k]);
            if (p > a) len += sqrt(pow(q[0] - q[-3], 2) + pow(q[1] - q[-2], 2) + pow(q[2] - q[-1], 2));
        }
        lmin = fmin(lmin, len), lmax = fmax(lmax, len), lsum += len;
        if (b - a < pmin) pmin = b - a;
        if (b - a > pmax) pmax = b - a;
    }
    char info[HK_HAIR_INFO_SIZE + 1];
    memcpy(info, h.info, HK_HAIR_INFO_SIZE);
    info[HK_HAIR_INFO_SIZE] = '\0';
    if (format == HK_HAIR_FORMAT_AUTO) format = hk_hair_format_from_path(path);
    printf("file:          %s\n", path);
    if (format != HK_HAIR_FORMAT_AUTO) printf("format:        %s\n", hk_hair_format_name(format));
    printf("strands:       %u\n", h.strand_count);
    printf("points:        %u (per strand: min %u, mean %.1f, max %u)\n", h.point_count, h.strand_count ? pmin : 0,
           h.strand_count ? (double)h.point_count / h.strand_count : 0.0, pmax);
    if (h.strand_count)
        printf("length:        min %.6g, mean %.6g, max %.6g (file units)\n", lmin, lsum / h.strand_count, lmax);
    if (h.point_count)
        printf("bounding box:  (%.6g, %.6g, %.6g) to (%.6g, %.6g, %.6g)\n", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    if (h.point_count) {
        /* hairkit works in metres: a head of hair spans tens of centimetres. */
        const double extent = hk_hair_extent(&h), per_unit = hk_hair_guess_meters_per_unit(&h);
        if (per_unit == 0.001)
            printf("units:         extent %.3g: millimetres? --scale 0.001\n", extent);
        else if (per_unit == 0.01)
            printf("units:         extent %.3g: centimetres? --scale 0.01\n", extent);
        else
            printf("units:         extent %.3g\n", extent);
    }
    printf("arrays:        %s%s%s%s%s\n", h.flags & HK_HAIR_SEGMENTS ? "segments " : "", "points ",
           h.flags & HK_HAIR_THICKNESS ? "thickness " : "", h.flags & HK_HAIR_TRANSPARENCY ? "transparency " : "",
           h.flags & HK_HAIR_COLORS ? "colours" : "");
    printf("defaults:      thickness %g, transparency %g, colour (%g, %g, %g)\n", h.default_thickness,
           h.default_transparency, h.default_color[0], h.default_color[1], h.default_color[2]);
    printf("information:   \"%s\"\n", info);
    hk_hair_free(&h);
    return HK_EXIT_OK;
}
