/* Hair file formats: choosing the format, reading and writing any of them, and the
 * transforms a groom made elsewhere needs (units, up axis, resampling). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "hair_io.h"
#include "hairkit/hair_formats.h"

static const struct {
    hk_HairFormat format;
    const char *name, *alias, *ext;
} formats[] = {
    {HK_HAIR_FORMAT_CYHAIR, "cyhair", "hair", ".hair"}, {HK_HAIR_FORMAT_TFX, "tfx", "tressfx", ".tfx"},
    {HK_HAIR_FORMAT_USC, "usc", "data", ".data"},       {HK_HAIR_FORMAT_PLY, "ply", NULL, ".ply"},
    {HK_HAIR_FORMAT_OBJ, "obj", NULL, ".obj"},          {HK_HAIR_FORMAT_USDA, "usda", "usd", ".usda"},
};
#define FORMAT_COUNT (sizeof formats / sizeof *formats)

static int lower_equal(const char *a, const char *b)
{
    for (; *a && *b; a++, b++) {
        char x = *a >= 'A' && *a <= 'Z' ? (char)(*a - 'A' + 'a') : *a;
        if (x != *b) return 0;
    }
    return *a == *b;
}

hk_HairFormat hk_hair_format_from_path(const char *path)
{
    if (!path) return HK_HAIR_FORMAT_AUTO;
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    if (!dot) return HK_HAIR_FORMAT_AUTO;
    for (size_t i = 0; i < FORMAT_COUNT; i++)
        if (lower_equal(dot, formats[i].ext)) return formats[i].format;
    return HK_HAIR_FORMAT_AUTO;
}

int hk_hair_format_from_name(const char *name)
{
    if (!name) return -1;
    if (lower_equal(name, "auto")) return HK_HAIR_FORMAT_AUTO;
    for (size_t i = 0; i < FORMAT_COUNT; i++)
        if (lower_equal(name, formats[i].name) || (formats[i].alias && lower_equal(name, formats[i].alias)))
            return (int)formats[i].format;
    return -1;
}

const char *hk_hair_format_name(hk_HairFormat format)
{
    for (size_t i = 0; i < FORMAT_COUNT; i++)
        if (formats[i].format == format) return formats[i].name;
    return "auto";
}

/* The format of a file whose extension says nothing, from its first bytes. */
static hk_HairFormat sniff(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return HK_HAIR_FORMAT_AUTO;
    char head[8] = {0};
    size_t n = fread(head, 1, sizeof head, fp);
    fclose(fp);
    if (n >= 4 && memcmp(head, "HAIR", 4) == 0) return HK_HAIR_FORMAT_CYHAIR;
    if (n >= 4 && memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r')) return HK_HAIR_FORMAT_PLY;
    if (n >= 5 && memcmp(head, "#usda", 5) == 0) return HK_HAIR_FORMAT_USDA;
    return HK_HAIR_FORMAT_AUTO;
}

hk_Status hk_hair_read(const char *path, hk_HairFormat format, hk_HairFile *hair, hk_Error *err)
{
    memset(hair, 0, sizeof *hair);
    if (!path) return hk_error_set(err, HK_ERR_INVALID, "no file name");
    if (format == HK_HAIR_FORMAT_AUTO) format = hk_hair_format_from_path(path);
    if (format == HK_HAIR_FORMAT_AUTO) format = sniff(path);
    switch (format) {
    case HK_HAIR_FORMAT_CYHAIR:
        return hk_hair_load(path, hair, err);
    case HK_HAIR_FORMAT_TFX:
        return hk_tfx_load(path, hair, err);
    case HK_HAIR_FORMAT_USC:
        return hk_usc_load(path, hair, err);
    case HK_HAIR_FORMAT_PLY:
        return hk_ply_hair_load(path, hair, err);
    case HK_HAIR_FORMAT_OBJ:
        return hk_obj_hair_load(path, hair, err);
    case HK_HAIR_FORMAT_USDA:
        return hk_usda_hair_load(path, hair, err);
    case HK_HAIR_FORMAT_AUTO:
        break;
    }
    FILE *fp = fopen(path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    fclose(fp);
    return hk_error_set(err, HK_ERR_PARSE,
                        "%s: unknown hair format (extensions read: .hair .tfx .data .ply .obj .usda; "
                        "name the format with --from)",
                        path);
}

hk_HairWriteDef hk_hair_write_defaults(void)
{
    hk_HairWriteDef d;
    memset(&d, 0, sizeof d);
    d.format = HK_HAIR_FORMAT_AUTO;
    d.points = 0;
    d.ascii = 0;
    d.meters_per_unit = 1.0;
    return d;
}

double hk_hair_extent(const hk_HairFile *h)
{
    if (!h->point_count || !h->points) return 0.0;
    /* In SSE (the command line asks it two or three times of a file of millions of
     * points: 3 % of `hairkit render` in scalars). The comparisons pass over a NaN
     * coordinate, as they did in scalars. */
    float lo[3], hi[3];
    hk_float_points_bounds(h->points, h->point_count, lo, hi);
    double extent = 0.0;
    for (int k = 0; k < 3; k++) extent = fmax(extent, (double)hi[k] - (double)lo[k]);
    return extent;
}

double hk_hair_guess_meters_per_unit(const hk_HairFile *h)
{
    const double extent = hk_hair_extent(h);
    if (extent >= 200.0 && extent < 20000.0) return 0.001;
    if (extent >= 5.0 && extent < 200.0) return 0.01;
    return 1.0;
}

int hk_hair_thickness_implausible(const hk_HairFile *h, double meters_per_unit)
{
    if ((h->flags & HK_HAIR_THICKNESS) && h->thickness) return 0;
    if (!(meters_per_unit > 0.0)) meters_per_unit = hk_hair_guess_meters_per_unit(h);
    const double t = (double)h->default_thickness;
    return t > 0.01 * hk_hair_extent(h) || t * meters_per_unit > HK_MAX_HAIR_DIAMETER;
}

int hk_hair_uniform_strands(const hk_HairFile *h)
{
    for (uint32_t s = 1; s < h->strand_count; s++)
        if (hk_hair_strand_points(h, s) != hk_hair_strand_points(h, 0)) return 0;
    return 1;
}

/* Whether every strand already has n points. */
static int all_strands_have(const hk_HairFile *h, uint32_t n)
{
    return h->strand_count == 0 || (hk_hair_uniform_strands(h) && hk_hair_strand_points(h, 0) == n);
}

hk_Status hk_hair_write(const char *path, const hk_HairFile *hair, const hk_HairWriteDef *def, hk_Error *err)
{
    hk_HairWriteDef d = def ? *def : hk_hair_write_defaults();
    if (!path) return hk_error_set(err, HK_ERR_INVALID, "no output file name");
    if (!hair->points || (!hair->first_point && hair->strand_count))
        return hk_error_set(err, HK_ERR_INVALID, "%s: the hair has no points or no strand index", path);
    hk_HairFormat format = d.format != HK_HAIR_FORMAT_AUTO ? d.format : hk_hair_format_from_path(path);
    if (format == HK_HAIR_FORMAT_AUTO)
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: unknown hair format (extensions written: .hair .tfx .data .ply .obj .usda; "
                            "name the format with --to)",
                            path);
    if (d.points == 1 || d.points > 65536)
        return hk_error_set(err, HK_ERR_INVALID, "%s: cannot resample to %u points per strand (2 to 65536)", path,
                            d.points);
    /* --points N: every strand resampled to N points, unless all already have N. */
    hk_HairFile resampled;
    memset(&resampled, 0, sizeof resampled);
    const hk_HairFile *h = hair;
    if (d.points && !all_strands_have(hair, d.points)) {
        hk_Status st = hk_hair_resample(hair, d.points, &resampled, err);
        if (st != HK_OK) return st;
        h = &resampled;
    }
    hk_Status st = HK_ERR_INVALID;
    switch (format) {
    case HK_HAIR_FORMAT_CYHAIR:
        st = hk_hair_save(path, h, err);
        break;
    case HK_HAIR_FORMAT_TFX:
        st = hk_tfx_save(path, h, 0, err);
        break;
    case HK_HAIR_FORMAT_USC:
        st = hk_usc_save(path, h, err);
        break;
    case HK_HAIR_FORMAT_PLY:
        st = hk_ply_hair_save(path, h, d.ascii, err);
        break;
    case HK_HAIR_FORMAT_OBJ:
        st = hk_obj_hair_save(path, h, err);
        break;
    case HK_HAIR_FORMAT_USDA:
        st = hk_usda_hair_save(path, h, d.meters_per_unit, err);
        break;
    case HK_HAIR_FORMAT_AUTO:
        break;
    }
    hk_hair_free(&resampled);
    return st;
}

/* ---- transforms ---- */

hk_Status hk_hair_scale(hk_HairFile *h, double s, hk_Error *err)
{
    if (!(s > 0.0) || !isfinite(s)) return hk_error_set(err, HK_ERR_INVALID, "scale %g: must be > 0 and finite", s);
    if (s == 1.0) return HK_OK;
    const size_t np = h->point_count;
    for (size_t i = 0; i < 3 * np; i++) h->points[i] = (float)((double)h->points[i] * s);
    if (h->thickness)
        for (size_t i = 0; i < np; i++) h->thickness[i] = (float)((double)h->thickness[i] * s);
    h->default_thickness = (float)((double)h->default_thickness * s);
    for (size_t i = 0; i < 3 * np; i++)
        if (!isfinite(h->points[i]))
            return hk_error_set(err, HK_ERR_INVALID, "scale %g: point %zu overflows single precision", s, i / 3);
    return HK_OK;
}

static const char *const axis_names[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};

int hk_axis_from_name(const char *name)
{
    if (!name) return -1;
    char buf[3];
    if (strlen(name) == 1) {
        buf[0] = '+', buf[1] = name[0], buf[2] = '\0';
        name = buf;
    }
    for (int i = 0; i < 6; i++)
        if (lower_equal(name, axis_names[i])) return i;
    return -1;
}

const char *hk_axis_name(hk_Axis axis) { return (unsigned)axis < 6 ? axis_names[axis] : "?"; }

void hk_hair_up_to_y(hk_HairFile *h, hk_Axis up)
{
    if (up == HK_AXIS_POS_Y) return;
    for (size_t i = 0; i < (size_t)h->point_count; i++) {
        float *p = h->points + 3 * i;
        /* float -> double -> float is exact, and the rotation only swaps and negates */
        const hk_Vec3 q = hk_v3_up_to_y(hk_v3(p[0], p[1], p[2]), up);
        p[0] = (float)q.x, p[1] = (float)q.y, p[2] = (float)q.z;
    }
}

hk_Status hk_hair_resample(const hk_HairFile *in, uint32_t points, hk_HairFile *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    if (points < 2 || points > 65536)
        return hk_error_set(err, HK_ERR_INVALID, "cannot resample to %u points per strand (2 to 65536)", points);
    if ((uint64_t)in->strand_count * points > UINT32_MAX)
        return hk_error_set(err, HK_ERR_INVALID, "%u strands of %u points are more than 2^32 points", in->strand_count,
                            points);
    uint32_t *counts = hk_alloc_array(in->strand_count, sizeof *counts, err);
    if (!counts) return HK_ERR_NOMEM;
    for (uint32_t s = 0; s < in->strand_count; s++) counts[s] = points;
    hk_Status st = hk_hair_alloc(out, in->strand_count, counts, err);
    hk_free(counts);
    if (st != HK_OK) return st;
    out->default_thickness = in->default_thickness;
    out->default_transparency = in->default_transparency;
    memcpy(out->default_color, in->default_color, sizeof out->default_color);
    memcpy(out->info, in->info, sizeof out->info);
    for (uint32_t s = 0; s < in->strand_count; s++) {
        const float *p = in->points + 3 * (size_t)in->first_point[s];
        const uint32_t n = hk_hair_strand_points(in, s);
        float *q = out->points + 3 * (size_t)s * points;
        if (n == points) { /* kept exactly */
            memcpy(q, p, 3 * sizeof(float) * points);
            continue;
        }
        /* Total length, then walk the segments once. */
        double total = 0.0;
        for (uint32_t i = 1; i < n; i++) {
            const double dx = (double)p[3 * i] - p[3 * i - 3], dy = (double)p[3 * i + 1] - p[3 * i - 2],
                         dz = (double)p[3 * i + 2] - p[3 * i - 1];
            total += sqrt(dx * dx + dy * dy + dz * dz);
        }
        uint32_t seg = 0; /* current segment: points seg, seg + 1 */
        double seg_start = 0.0, seg_len = 0.0;
        if (n > 1) {
            const double dx = (double)p[3] - p[0], dy = (double)p[4] - p[1], dz = (double)p[5] - p[2];
            seg_len = sqrt(dx * dx + dy * dy + dz * dz);
        }
        memcpy(q, p, 3 * sizeof(float));
        for (uint32_t k = 1; k + 1 < points; k++) {
            const double target = total * (double)k / (double)(points - 1);
            while (n > 1 && seg + 2 < n && seg_start + seg_len < target) {
                seg_start += seg_len;
                seg++;
                const double dx = (double)p[3 * seg + 3] - p[3 * seg], dy = (double)p[3 * seg + 4] - p[3 * seg + 1],
                             dz = (double)p[3 * seg + 5] - p[3 * seg + 2];
                seg_len = sqrt(dx * dx + dy * dy + dz * dz);
            }
            float *o = q + 3 * (size_t)k;
            if (n < 2 || seg_len <= 0.0) {
                memcpy(o, p + 3 * (size_t)(n < 2 ? 0 : seg), 3 * sizeof(float));
                continue;
            }
            double t = (target - seg_start) / seg_len;
            if (t < 0.0) t = 0.0;
            if (t > 1.0) t = 1.0;
            for (int c = 0; c < 3; c++)
                o[c] = (float)((1.0 - t) * p[3 * seg + (uint32_t)c] + t * p[3 * seg + 3 + (uint32_t)c]);
        }
        memcpy(q + 3 * (size_t)(points - 1), p + 3 * (size_t)(n - 1), 3 * sizeof(float));
    }
    return HK_OK;
}
