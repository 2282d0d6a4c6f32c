/* --motion and its amplitude and frequency, shared by hairkit strand --simulate and
 * hairkit simulate: a scripted head motion by name, or a head motion file. */
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "hairkit/motion.h"

static const char *const scripted[] = {"still", "nod", "shake", "tilt", "sway", "jump"};

static int is_scripted(const char *name)
{
    for (size_t i = 0; i < sizeof scripted / sizeof scripted[0]; i++)
        if (strcmp(name, scripted[i]) == 0) return 1;
    return 0;
}

hk_CliMotion hk_cli_default_motion(void)
{
    hk_CliMotion m = {"still", 0.0, 1.0, 0};
    return m;
}

int hk_cli_motion_option(const char *cmd, int option, const char *value, hk_CliMotion *m)
{
    double v;
    switch (option) {
    case HK_OPT_MOTION:
        /* A bare word that is neither a scripted motion nor a file was meant as a
         * motion's name: a bad value (exit 2), said before the settling. */
        if (!is_scripted(value) && !strchr(value, '/') && !strchr(value, '.') && access(value, F_OK) != 0)
            return hk_cli_unknown_name(cmd, "motion", value, scripted, sizeof scripted / sizeof scripted[0]);
        m->spec = value;
        return 0;
    case HK_OPT_AMPLITUDE:
        if (!hk_cli_parse_double(value, &v))
            return hk_cli_usage_error(cmd, "--amplitude expects a number, got '%s'", value);
        m->amplitude = v;
        m->has_amplitude = 1;
        return 0;
    case HK_OPT_FREQUENCY:
        if (!hk_cli_parse_double(value, &v) || !(v > 0.0))
            return hk_cli_usage_error(cmd, "--frequency expects a number > 0 (Hz), got '%s'", value);
        m->frequency = v;
        return 0;
    default:
        return hk_cli_usage_error(cmd, "internal: not a motion option");
    }
}

void hk_cli_motion_options_help(FILE *out)
{
    fprintf(out, "head motion:\n"
                 "  --motion NAME|FILE scripted motion: still (default), nod, shake, tilt (degrees\n"
                 "                     about the neck), sway, jump (metres along x, y); or a head\n"
                 "                     motion file (docs/file-formats.md)\n"
                 "  --amplitude A      of a scripted motion (default 25 degrees or 0.03 m)\n"
                 "  --frequency F      of a scripted motion in Hz (default 1)\n");
}

hk_Status hk_cli_motion_create(const hk_CliMotion *m, hk_HeadMotion **out, hk_Error *err)
{
    if (!is_scripted(m->spec)) {
        hk_Status st = hk_head_motion_load(m->spec, out, err);
        /* A bare word that is no file was meant as a motion's name: say so. */
        if (st == HK_ERR_IO && !strchr(m->spec, '/') && !strchr(m->spec, '.'))
            st =
                hk_error_set(err, HK_ERR_INVALID,
                             "unknown motion '%s': give still, nod, shake, tilt, sway, jump or a motion file", m->spec);
        return st;
    }
    const int translation = strcmp(m->spec, "sway") == 0 || strcmp(m->spec, "jump") == 0;
    const double amplitude = m->has_amplitude ? m->amplitude : (translation ? 0.03 : 25.0);
    return hk_head_motion_scripted(m->spec, amplitude, m->frequency, hk_default_head_pivot(), out, err);
}
