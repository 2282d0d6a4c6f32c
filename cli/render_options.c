/* Command-line options of the renderer, shared by `render` and `run`. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

void hk_cli_render_options_help(FILE *out)
{
    fprintf(out, "  --width W, --height H  picture size in pixels (default 1200 x 900)\n"
                 "  --no-shadows       no deep opacity map or head shadow\n"
                 "  --shading MODEL    kajiya-kay (default, thesis 4.1.5) or marschner\n"
                 "  --scattering S     dual (default: multiple scattering by the dual scattering\n"
                 "                     approximation) or single (the thesis's shadow floor)\n"
                 "  --view AZ,EL       camera direction in degrees: azimuth about the vertical\n"
                 "                     axis from the front of the face (+z) towards +x, and\n"
                 "                     elevation (default 35,12: three-quarter front)\n"
                 "  --light AZ,EL      direction of the key light, the same way (default -30,40)\n"
                 "  --shadow-map N     texels per side of the light's maps (default: 512 from\n"
                 "                     1200x900 up, less in proportion below, at least 64)\n"
                 "  --thickness D      strand diameter in scene units (default: the file's, or\n"
                 "                     70 um when the file's is not a hair's)\n"
                 "  --all-strands      draw every strand: by default, where strands are under a\n"
                 "                     quarter pixel wide (thumbnails), one in k is drawn k times\n"
                 "                     as wide (the same coverage, k times faster)\n");
}

int hk_cli_parse_pair(const char *text, double *a, double *b)
{
    char first[64];
    const char *comma = strchr(text, ',');
    if (!comma || (size_t)(comma - text) >= sizeof first) return 0;
    memcpy(first, text, (size_t)(comma - text));
    first[comma - text] = '\0';
    return hk_cli_parse_double(first, a) && hk_cli_parse_double(comma + 1, b);
}

int hk_cli_render_option(const char *cmd, int option, const char *value, hk_RenderDef *o)
{
    long n;
    double a, b;
    switch (option) {
    case HK_OPT_WIDTH:
    case HK_OPT_HEIGHT:
        if (!hk_cli_parse_int(value, 8, 16384, &n))
            return hk_cli_usage_error(cmd, "--%s expects 8 to 16384 pixels, got '%s'",
                                      option == HK_OPT_WIDTH ? "width" : "height", value);
        *(option == HK_OPT_WIDTH ? &o->width : &o->height) = (int)n;
        return 0;
    case HK_OPT_NO_SHADOWS:
        o->shadows = 0;
        return 0;
    case HK_OPT_ALL_STRANDS:
        o->strand_lod = 0;
        return 0;
    case HK_OPT_SHADING:
        if (!strcmp(value, "kajiya-kay") || !strcmp(value, "kajiya"))
            o->shading = HK_SHADING_KAJIYA_KAY;
        else if (!strcmp(value, "marschner"))
            o->shading = HK_SHADING_MARSCHNER;
        else
            return hk_cli_usage_error(cmd, "--shading expects kajiya-kay or marschner, got '%s'", value);
        return 0;
    case HK_OPT_SCATTERING:
        if (!strcmp(value, "dual"))
            o->scattering = HK_SCATTERING_DUAL;
        else if (!strcmp(value, "single"))
            o->scattering = HK_SCATTERING_SINGLE;
        else
            return hk_cli_usage_error(cmd, "--scattering expects dual or single, got '%s'", value);
        return 0;
    case HK_OPT_VIEW:
    case HK_OPT_LIGHT:
        if (!hk_cli_parse_pair(value, &a, &b) || b < -90.0 || b > 90.0)
            return hk_cli_usage_error(cmd, "--%s expects AZIMUTH,ELEVATION in degrees (elevation -90 to 90), got '%s'",
                                      option == HK_OPT_VIEW ? "view" : "light", value);
        if (option == HK_OPT_VIEW)
            o->azimuth_deg = a, o->elevation_deg = b;
        else
            o->light_azimuth_deg = a, o->light_elevation_deg = b;
        return 0;
    case HK_OPT_SHADOW_MAP:
        if (!hk_cli_parse_int(value, 16, 8192, &n))
            return hk_cli_usage_error(cmd, "--shadow-map expects 16 to 8192 texels, got '%s'", value);
        o->shadow_map_size = (int)n;
        return 0;
    case HK_OPT_THICKNESS:
        if (!hk_cli_parse_double(value, &a) || !(a > 0.0))
            return hk_cli_usage_error(cmd, "--thickness expects a positive diameter, got '%s'", value);
        o->hair_thickness = a;
        return 0;
    default:
        return hk_cli_usage_error(cmd, "unknown render option");
    }
}

void hk_cli_report_render(const char *cmd, const char *path, const hk_RenderDef *o, const hk_RenderStats *s)
{
    fprintf(stderr,
            "hairkit %s: %s %dx%d; light maps %.2f s (%lld fragments), camera %.2f s, "
            "head and hair %.2f s (%lld fragments, up to %d in a pixel)\n",
            cmd, path, o->width, o->height, s->seconds_light, s->light_fragments, s->seconds_camera, s->seconds_hair,
            s->hair_fragments, s->max_depth_complexity);
    if (s->strand_stride > 1)
        fprintf(stderr,
                "hairkit %s: strands under a quarter pixel wide: one in %d drawn, %d times as wide "
                "(--all-strands draws every one)\n",
                cmd, s->strand_stride, s->strand_stride);
}
