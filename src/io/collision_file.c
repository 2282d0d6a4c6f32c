/* Collision Info files (Lansink 2010 §4.2.1 and Appendix B): spheres, ellipsoids and
 * cuboids with their envelope Volume and Penalty stiffness (§4.1.2). */
#include <ctype.h>
#include <math.h>
#include <string.h>

#include "hairkit/io.h"
#include "keyfile.h"

#define HK_AXIS_TOLERANCE 1e-3 /* largest |cos| between two axes taken as orthogonal */

/* Unit vector along (x, y, z), scaled by its largest component first so that neither
 * (1e300, 1e300, 0) overflows nor (1e-200, 0, 0) underflows; zero stays zero. */
static hk_Vec3 unit(double x, double y, double z)
{
    double m = fmax(fabs(x), fmax(fabs(y), fabs(z)));
    if (!(m > 0.0)) return hk_v3_zero();
    return hk_v3_normalize(hk_v3(x / m, y / m, z / m));
}

/* Axes U, V, W from values 8..16 of an ellipsoid or cuboid line, normalised. */
static hk_Status read_axes(const hk_KeyFile *kf, const hk_KeyLine *kl, const double *v, hk_Vec3 axes[3], hk_Error *err)
{
    static const char *const names[3] = {"U", "V", "W"};
    for (int i = 0; i < 3; i++) {
        axes[i] = unit(v[8 + 3 * i], v[9 + 3 * i], v[10 + 3 * i]);
        if (hk_v3_norm2(axes[i]) == 0.0)
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "axis %s of the %s is zero", names[i], kl->key);
    }
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++) {
            double c = hk_v3_dot(axes[i], axes[j]);
            if (fabs(c) > HK_AXIS_TOLERANCE)
                return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                        "axes %s and %s of the %s are not orthogonal (cosine %.3g, "
                                        "at most %g allowed)",
                                        names[i], names[j], kl->key, c, HK_AXIS_TOLERANCE);
        }
    return HK_OK;
}

static hk_Status read_shape(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Shape *shape, hk_Error *err)
{
    /* Appendix B's sample spells "Elipsoid"; files written after it keep working. */
    const int sphere = hk_key_equal(kl->key, "Sphere");
    const int ellipsoid = hk_key_equal(kl->key, "Ellipsoid") || hk_key_equal(kl->key, "Elipsoid");
    const int cuboid = hk_key_equal(kl->key, "Cuboid");
    if (!sphere && !ellipsoid && !cuboid)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "unknown shape '%s' (expected Sphere, Ellipsoid or Cuboid)", kl->key);
    /* An optional last word says what the shape is: `Body` (the default, so the
     * thesis's files keep their meaning) or `Styling`, a field that shapes the guides
     * but that hair may enter (docs/file-formats.md). */
    const int numbers = sphere ? 6 : 17;
    hk_KeyLine nums = *kl;
    int styling = 0;
    if (kl->count == numbers + 1) {
        const char *role = kl->values[numbers];
        if (hk_key_equal(role, "Styling"))
            styling = 1;
        else if (!hk_key_equal(role, "Body")) {
            /* A word where a number cannot be is a misspelt role, not a count error. */
            if (isalpha((unsigned char)role[0]) && !hk_key_equal(role, "nan") && !hk_key_equal(role, "inf"))
                return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                        "unknown role '%s' after the %s's numbers (expected Body or Styling)", role,
                                        kl->key);
            role = NULL;
        }
        if (role) nums.count = numbers;
    }
    double v[17];
    hk_Status st = hk_keyline_doubles(kf, &nums, numbers, v, err);
    if (st != HK_OK) return st;
    /* v[0] is the Volume (envelope thickness, §4.1.2.2): any finite value, negative
     * shrinks the shape. */
    if (!(v[1] >= 0.0))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Penalty must be >= 0, got %s", kl->values[1]);
    const hk_Vec3 centre = hk_v3(v[2], v[3], v[4]);
    if (sphere) {
        if (!(v[5] > 0.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "sphere radius must be > 0, got %s",
                                    kl->values[5]);
        *shape = hk_shape_sphere(centre, v[5], v[0], v[1]);
        shape->styling = styling;
        return HK_OK;
    }
    if (!(v[5] > 0.0) || !(v[6] > 0.0) || !(v[7] > 0.0))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s dimensions must be > 0, got %s %s %s", kl->key,
                                kl->values[5], kl->values[6], kl->values[7]);
    hk_Vec3 axes[3];
    st = read_axes(kf, kl, v, axes, err);
    if (st != HK_OK) return st;
    const hk_Vec3 dims = hk_v3(v[5], v[6], v[7]);
    *shape = ellipsoid ? hk_shape_ellipsoid(centre, dims, axes, v[0], v[1])
                       : hk_shape_cuboid(centre, dims, axes, v[0], v[1]);
    shape->styling = styling;
    return HK_OK;
}

hk_Status hk_collision_load(const char *path, hk_Shape **shapes, int *count, hk_Error *err)
{
    *shapes = NULL;
    *count = 0;
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    /* Every non-empty line is one shape: count before allocating. */
    if (kf.line_count > HK_MAX_SHAPES) {
        st = hk_keyfile_error(&kf, kf.lines[HK_MAX_SHAPES].line, HK_ERR_INVALID, err, "more than %d collision shapes",
                              HK_MAX_SHAPES);
        hk_keyfile_free(&kf);
        return st;
    }
    hk_Shape *out = NULL;
    if (kf.line_count > 0) {
        out = hk_alloc_array((size_t)kf.line_count, sizeof *out, err);
        if (!out) {
            hk_keyfile_free(&kf);
            return HK_ERR_NOMEM;
        }
    }
    for (int i = 0; i < kf.line_count && st == HK_OK; i++) st = read_shape(&kf, &kf.lines[i], &out[i], err);
    if (st == HK_OK) {
        *shapes = out;
        *count = kf.line_count;
    } else {
        hk_free(out);
    }
    hk_keyfile_free(&kf);
    return st;
}
