/* Units and up axis of files made elsewhere, shared by the commands that read them:
 * --scale S and --up AXIS for hair (convert, render, run), --head-scale S and --head-up
 * AXIS for head meshes (render, run). The rotation is hk_v3_up_to_y's (hairkit/vecmath.h)
 * for both. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "hairkit/hair_formats.h"

hk_CliTransform hk_cli_default_transform(void)
{
    hk_CliTransform t = {1.0, HK_AXIS_POS_Y, 0};
    return t;
}

int hk_cli_transform_option(const char *cmd, const char *option, const char *value, hk_CliTransform *t)
{
    if (strstr(option, "scale")) {
        if (!hk_cli_parse_double(value, &t->scale) || !(t->scale > 0.0))
            return hk_cli_usage_error(cmd, "--%s expects a number > 0, got '%s'", option, value);
    } else {
        const int up = hk_axis_from_name(value);
        if (up < 0) return hk_cli_usage_error(cmd, "--%s expects +x, -x, +y, -y, +z or -z, got '%s'", option, value);
        t->up = (hk_Axis)up;
    }
    t->given = 1;
    return 0;
}

int hk_cli_transforms_option(const char *cmd, int code, const char *value, hk_CliTransform *hair, hk_CliTransform *head)
{
    static const char *const names[] = {"scale", "up", "head-scale", "head-up"};
    hk_CliTransform *t = code == HK_OPT_HAIR_SCALE || code == HK_OPT_HAIR_UP ? hair : head;
    return hk_cli_transform_option(cmd, names[code - HK_OPT_HAIR_SCALE], value, t);
}

hk_Status hk_cli_transform_hair(const hk_CliTransform *t, hk_HairFile *hair, hk_Error *err)
{
    hk_Status st = hk_hair_scale(hair, t->scale, err);
    if (st == HK_OK) hk_hair_up_to_y(hair, t->up);
    return st;
}

hk_Status hk_cli_transform_mesh(const hk_CliTransform *t, const char *path, hk_Mesh *mesh, hk_Error *err)
{
    hk_Error sub;
    if (hk_mesh_scale(mesh, t->scale, &sub) != HK_OK)
        return hk_error_set(err, sub.code, "%s: --head-scale: %s", path, sub.message);
    hk_mesh_up_to_y(mesh, t->up);
    return HK_OK;
}

void hk_cli_transform_help(FILE *out, int hair, int head)
{
    if (hair)
        fprintf(out, "  --scale S          multiply the hair's coordinates (and thickness) by S > 0:\n"
                     "                     0.001 turns millimetres into metres, 0.01 centimetres\n"
                     "                     (hairkit works in metres; 'hairkit info' hints at units)\n"
                     "  --up AXIS          the hair file's up axis (+x -x +y -y +z -z), rotated onto\n"
                     "                     +y by the smallest rotation (as 'hairkit convert --up')\n");
    if (head)
        fprintf(out, "  --head-scale S     the same for the head mesh: multiply its vertices by S\n"
                     "  --head-up AXIS     the head mesh's up axis, rotated onto +y the same way\n");
}

int hk_cli_fine_hair(const char *cmd, const hk_HairFile *hair, double diameter, int metres, hk_RenderDef *ro)
{
    const double per_unit = metres ? 1.0 : hk_hair_guess_meters_per_unit(hair);
    if (ro->hair_thickness > 0.0 || !hk_hair_thickness_implausible(hair, per_unit)) return 0;
    ro->hair_thickness = diameter / per_unit;
    const char *units = per_unit == 1.0 ? "metres" : per_unit == 0.01 ? "centimetres" : "millimetres";
    fprintf(stderr,
            "hairkit %s: the file's strand width %g is not hair's (over 1%% of the groom's extent %.3g, or over "
            "0.5 mm): drawing hair %g um across, %g in %s%s; --thickness sets the width\n",
            cmd, (double)hair->default_thickness, hk_hair_extent(hair), diameter * 1e6, ro->hair_thickness, units,
            metres ? "" : " (units guessed from the extent; --scale gives them)");
    return 1;
}

int hk_cli_warn_units(const char *cmd, const char *path, const hk_HairFile *hair)
{
    const double per_unit = hk_hair_guess_meters_per_unit(hair);
    if (per_unit == 1.0) return 0;
    fprintf(stderr,
            "hairkit %s: %s: warning: the groom spans %.3g units, which looks like %s (hairkit works in metres): "
            "'hairkit convert %s OUT.hair --scale %g' first if it is\n",
            cmd, path, hk_hair_extent(hair), per_unit == 0.01 ? "centimetres" : "millimetres", path, per_unit);
    return 1;
}
