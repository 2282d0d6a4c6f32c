/* hairkit convert: hair strands from any readable format to any writable one
 * (hairkit/hair_formats.h), with units, up axis and resampling. */
#include <getopt.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "core/core_internal.h"
#include "hairkit/hair_formats.h"

static const char *const CMD = "convert";

static void usage(FILE *out)
{
    fprintf(out, "usage: hairkit convert IN OUT [--from F] [--to F] [--scale S] [--up AXIS]\n"
                 "                       [--points N] [--ascii] [--quiet]\n"
                 "\n"
                 "Converts hair strands between file formats; the format comes from each file's\n"
                 "extension unless --from / --to name it:\n"
                 "  hair  (.hair)  cyHair                          read, write\n"
                 "  tfx   (.tfx)   AMD TressFX v3, v4              read; write v4\n"
                 "  usc   (.data)  USC-HairSalon                   read, write\n"
                 "  ply   (.ply)   PLY strands (CT2Hair), edges    read; write binary or ASCII\n"
                 "  obj   (.obj)   OBJ polylines (v + l)           read, write\n"
                 "  usda  (.usda)  USD ascii, linear BasisCurves   read, write\n"
                 "Points are copied exactly (float32) and strands keep their order unless an option\n"
                 "asks otherwise. Then, in this order: --scale, --up, --points.\n"
                 "\n"
                 "options:\n"
                 "  --from F           format of IN (hair, tfx, usc, ply, obj, usda)\n"
                 "  --to F             format of OUT\n"
                 "  --scale S          multiply coordinates (and thickness) by S > 0: 0.001 turns\n"
                 "                     millimetres into metres, 0.01 centimetres (hairkit works in\n"
                 "                     metres; 'hairkit info IN' hints at the units)\n"
                 "  --up AXIS          the input's up axis (+x -x +y -y +z -z), rotated onto +y\n"
                 "                     (hairkit's up) by the smallest rotation: +x by +90 degrees\n"
                 "                     about z, -x by -90 about z, +z by -90 about x, -z by +90\n"
                 "                     about x, -y by 180 about x; +y changes nothing\n"
                 "  --points N         resample every strand by arc length to N points (2 to\n"
                 "                     65536; strands that have N already are kept as they are).\n"
                 "                     TressFX needs the same count in every strand: without\n"
                 "                     --points, strands that differ are refused\n"
                 "  --ascii            PLY output in ASCII (default binary little-endian)\n"
                 "  --quiet            no summary on stderr\n"
                 "  -h, --help         this help\n");
    HK_CLI_EXAMPLES(out, "hairkit groom examples/coupe4/setup.txt -o coupe4.hair",
                    "# TressFX wants the same number of points in every strand",
                    "hairkit convert coupe4.hair coupe4.tfx --points 16",
                    "# millimetres, z up, ASCII PLY (as CT2Hair writes)",
                    "hairkit convert coupe4.hair coupe4.ply --scale 1000 --up -z --ascii");
}

enum { OPT_FROM = 1, OPT_TO, OPT_SCALE, OPT_UP, OPT_POINTS, OPT_ASCII, OPT_QUIET };

int hk_cmd_convert(int argc, char **argv)
{
    static const struct option options[] = {
        {"from", required_argument, NULL, OPT_FROM},
        {"to", required_argument, NULL, OPT_TO},
        {"scale", required_argument, NULL, OPT_SCALE},
        {"up", required_argument, NULL, OPT_UP},
        {"points", required_argument, NULL, OPT_POINTS},
        {"ascii", no_argument, NULL, OPT_ASCII},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    hk_HairFormat from = HK_HAIR_FORMAT_AUTO;
    hk_HairWriteDef def = hk_hair_write_defaults();
    hk_CliTransform tf = hk_cli_default_transform();
    int quiet = 0, c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":h", options, NULL)) != -1) {
        switch (c) {
        case OPT_FROM:
        case OPT_TO: {
            const int f = hk_hair_format_from_name(optarg);
            if (f <= 0)
                return hk_cli_usage_error(CMD, "--%s expects hair, tfx, usc, ply, obj or usda, got '%s'",
                                          c == OPT_FROM ? "from" : "to", optarg);
            if (c == OPT_FROM)
                from = (hk_HairFormat)f;
            else
                def.format = (hk_HairFormat)f;
            break;
        }
        case OPT_SCALE:
        case OPT_UP: {
            const int rc = hk_cli_transform_option(CMD, c == OPT_SCALE ? "scale" : "up", optarg, &tf);
            if (rc) return rc;
            break;
        }
        case OPT_POINTS: {
            long n;
            if (!hk_cli_parse_int(optarg, 2, 65536, &n))
                return hk_cli_usage_error(CMD, "--points expects 2 to 65536, got '%s'", optarg);
            def.points = (uint32_t)n;
            break;
        }
        case OPT_ASCII:
            def.ascii = 1;
            break;
        case OPT_QUIET:
            quiet = 1;
            break;
        case 'h':
            usage(stdout);
            return HK_EXIT_OK;
        default: /* ':' (a missing value) or an unknown option */
            return hk_cli_bad_option(CMD, c, options, argv);
        }
    }
    if (optind >= argc) return hk_cli_usage_error(CMD, "missing IN and OUT files");
    if (optind + 1 >= argc) return hk_cli_usage_error(CMD, "missing the OUT file");
    if (optind + 2 < argc) return hk_cli_usage_error(CMD, "unexpected argument '%s'", argv[optind + 2]);
    const char *in = argv[optind], *out = argv[optind + 1];
    const hk_HairFormat to = def.format != HK_HAIR_FORMAT_AUTO ? def.format : hk_hair_format_from_path(out);
    if (to == HK_HAIR_FORMAT_AUTO)
        return hk_cli_usage_error(CMD, "cannot tell the format of '%s' from its extension: give --to", out);
    if (def.ascii && to != HK_HAIR_FORMAT_PLY)
        return hk_cli_usage_error(CMD, "--ascii is for PLY output, not %s", hk_hair_format_name(to));
    def.format = to;
    const int out_rc = hk_cli_output_file(CMD, "OUT", out, NULL);
    if (out_rc) return out_rc;

    hk_Error err;
    hk_HairFile hair;
    const double t0 = hk_seconds_now();
    if (hk_hair_read(in, from, &hair, &err) != HK_OK) return hk_cli_fail(CMD, &err);
    const uint32_t strands = hair.strand_count, points = hair.point_count;
    hk_Status st = hk_cli_transform_hair(&tf, &hair, &err);
    if (st == HK_OK) st = hk_hair_write(out, &hair, &def, &err);
    if (st != HK_OK) {
        hk_hair_free(&hair);
        return hk_cli_fail(CMD, &err);
    }
    if (!quiet) {
        const hk_HairFormat got = from != HK_HAIR_FORMAT_AUTO ? from : hk_hair_format_from_path(in);
        fprintf(stderr, "hairkit %s: %u strands, %u points: %s -> %s", CMD, strands, points,
                got != HK_HAIR_FORMAT_AUTO ? hk_hair_format_name(got) : "(by content)", hk_hair_format_name(to));
        if (tf.scale != 1.0) fprintf(stderr, ", scale %g", tf.scale);
        if (tf.up != HK_AXIS_POS_Y) fprintf(stderr, ", up %s onto +y", hk_axis_name(tf.up));
        if (def.points) fprintf(stderr, ", %u points per strand", def.points);
        fprintf(stderr, " (%.3f s)\n", hk_seconds_now() - t0);
    }
    hk_hair_free(&hair);
    return HK_EXIT_OK;
}
