/* Hairstyle Info files (Lansink 2010 §4.2.1 and Appendix B): the mechanical parameters
 * of a strand, checked for physical sense with file:line messages. */
#include <math.h>
#include <string.h>

#include "hairkit/io.h"
#include "keyfile.h"

enum Key {
    K_VISUALITY_STEP,
    K_COLLISION_STEP,
    K_MAX_ITER,
    K_EPSILON,
    K_LENGTHS,
    K_HAIR_DENSITY,
    K_RADIUS1,
    K_RADIUS2,
    K_HELIX_RADIUS,
    K_HELIX_STEP,
    K_POISSON,
    K_YOUNG,
    K_DENSITY,
    K_GRAVITY,
    K_GRAVITY_DIR,
    K_CLUMP,
    K_CLUMP_PROFILE,
    K_STRAY_HAIRS,
    K_MAX_TIP_DISTANCE,
    K_INTERNAL_FRICTION,
    K_AIR_DRAG,
    K_BODY_FRICTION,
    K_COUNT
};

/* The thesis's sample writes `HairLengths`, its text `HairLength` (§4.2.1). */
static const hk_KeySpec specs[K_COUNT] = {
    [K_VISUALITY_STEP] = {"VisualityStep", NULL, 0},
    [K_COLLISION_STEP] = {"CollisionStep", NULL, 0},
    [K_MAX_ITER] = {"MaxIter", NULL, 0},
    [K_EPSILON] = {"Epsilon", NULL, 0},
    [K_LENGTHS] = {"HairLengths", "HairLength", 1},
    [K_HAIR_DENSITY] = {"HairDensity", NULL, 0},
    [K_RADIUS1] = {"HairRadius1", NULL, 1},
    [K_RADIUS2] = {"HairRadius2", NULL, 1},
    [K_HELIX_RADIUS] = {"HelixRadius", NULL, 1},
    [K_HELIX_STEP] = {"HelixStep", NULL, 1},
    [K_POISSON] = {"Poisson", NULL, 0},
    [K_YOUNG] = {"Young", NULL, 1},
    [K_DENSITY] = {"Density", NULL, 0},
    [K_GRAVITY] = {"Gravity", NULL, 0},
    [K_GRAVITY_DIR] = {"GravityDirection", NULL, 0},
    /* Interpolation of the full head (§4.1.4.3-4; docs/grooming.md). */
    [K_CLUMP] = {"ClumpFactor", NULL, 0},
    [K_CLUMP_PROFILE] = {"ClumpProfile", NULL, 0},
    [K_STRAY_HAIRS] = {"StrayHairs", NULL, 0},
    [K_MAX_TIP_DISTANCE] = {"MaxTipDistance", NULL, 0},
    /* Dynamics (Bertails et al. 2006 eq. 5d, 5a and §4.2; docs/dynamics.md). */
    [K_INTERNAL_FRICTION] = {"InternalFriction", NULL, 0},
    [K_AIR_DRAG] = {"AirDrag", NULL, 0},
    [K_BODY_FRICTION] = {"BodyFriction", NULL, 0},
};

/* Allowed interval of a one-number key; `text` says it as the message shows it. */
typedef struct Range {
    double lo, hi;
    int lo_open, hi_open;
    const char *text;
} Range;

#define HK_MAX_ELEMENT_LENGTH 10.0 /* m: no hair is longer than this */
#define HK_MAX_HAIR_RADIUS    0.01 /* m: a hair 2 cm thick is no hair */

static const Range any = {-HUGE_VAL, HUGE_VAL, 0, 0, "finite"};
static const Range positive = {0.0, HUGE_VAL, 1, 0, "> 0"};
static const Range non_negative = {0.0, HUGE_VAL, 0, 0, ">= 0"};
static const Range hair_radius = {0.0, HK_MAX_HAIR_RADIUS, 1, 1, "in (0, 0.01) m"};
static const Range helix_radius = {0.0, HUGE_VAL, 0, 0, ">= 0 (0 is straight hair)"};
static const Range poisson = {-1.0, 0.5, 1, 1, "in (-1, 0.5)"};
static const Range hair_density = {0.0, 100000.0, 0, 0, "in [0, 100000] hairs/cm^2"};
static const Range clump = {0.0, 1.0, 0, 1, "in [0, 1)"};

hk_Hairstyle hk_default_hairstyle(void)
{
    hk_Hairstyle d;
    d.strand = hk_default_strand_def();
    d.interpolation = hk_default_interpolation_def();
    d.dynamics = hk_default_dynamics_def();
    return d;
}

void hk_hairstyle_free(hk_Hairstyle *def)
{
    if (!def) return;
    hk_free(def->strand.element_lengths);
    *def = hk_default_hairstyle();
}

hk_Status hk_hairstyle_copy(const hk_Hairstyle *src, hk_Hairstyle *dst, hk_Error *err)
{
    hk_Hairstyle d = *src;
    d.strand.element_lengths = NULL;
    if (src->strand.element_count > 0) {
        d.strand.element_lengths = hk_alloc_array((size_t)src->strand.element_count, sizeof(double), err);
        if (!d.strand.element_lengths) {
            *dst = hk_default_hairstyle();
            return HK_ERR_NOMEM;
        }
        memcpy(d.strand.element_lengths, src->strand.element_lengths,
               (size_t)src->strand.element_count * sizeof(double));
    }
    *dst = d;
    return HK_OK;
}

/* One number of key k within r. The message quotes the value as written, so that
 * "0.0100000001" is not shown as a puzzling "0.01". */
static hk_Status scalar(const hk_KeyFile *kf, const hk_KeyLine *kl, int k, Range r, double *out, hk_Error *err)
{
    double v;
    hk_Status st = hk_keyline_doubles(kf, kl, 1, &v, err);
    if (st != HK_OK) return st;
    if ((r.lo_open ? !(v > r.lo) : !(v >= r.lo)) || (r.hi_open ? !(v < r.hi) : !(v <= r.hi)))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s must be %s, got %s", specs[k].name, r.text,
                                kl->values[0]);
    *out = v;
    return HK_OK;
}

static hk_Status read_lengths(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Hairstyle *d, hk_Error *err)
{
    /* Count first, then an array of exactly that size: never more than
     * HK_MAX_ELEMENTS doubles, whatever the file says. */
    if (kl->count > HK_MAX_ELEMENTS)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s has %d values (elements), at most %d allowed",
                                specs[K_LENGTHS].name, kl->count, HK_MAX_ELEMENTS);
    double *len = hk_alloc_array(kl->count > 0 ? (size_t)kl->count : 1, sizeof(double), err);
    if (!len) return HK_ERR_NOMEM;
    int n = 0;
    hk_Status st = hk_keyline_double_list(kf, kl, HK_MAX_ELEMENTS, len, &n, err);
    for (int i = 0; i < n && st == HK_OK; i++)
        if (!(len[i] > 0.0) || len[i] > HK_MAX_ELEMENT_LENGTH)
            st = hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "element length %d must be in (0, 10] m, got %s",
                                  i + 1, kl->values[i]);
    if (st != HK_OK) {
        hk_free(len);
        return st;
    }
    d->strand.element_lengths = len;
    d->strand.element_count = n;
    return HK_OK;
}

static hk_Status read_value(const hk_KeyFile *kf, const hk_KeyLine *kl, int k, hk_Hairstyle *d, hk_Error *err)
{
    switch ((enum Key)k) {
    case K_VISUALITY_STEP:
        return scalar(kf, kl, k, positive, &d->strand.visuality_step, err);
    case K_COLLISION_STEP:
        return scalar(kf, kl, k, positive, &d->strand.collision_step, err);
    case K_MAX_ITER: {
        long v = 0;
        hk_Status st = hk_keyline_int(kf, kl, 1, 1000000000L, &v, err);
        if (st == HK_OK) d->strand.max_iter = (int)v;
        return st;
    }
    case K_EPSILON:
        return scalar(kf, kl, k, positive, &d->strand.epsilon, err);
    case K_LENGTHS:
        return read_lengths(kf, kl, d, err);
    case K_HAIR_DENSITY:
        return scalar(kf, kl, k, hair_density, &d->interpolation.hair_density, err);
    case K_RADIUS1:
        return scalar(kf, kl, k, hair_radius, &d->strand.radius1, err);
    case K_RADIUS2:
        return scalar(kf, kl, k, hair_radius, &d->strand.radius2, err);
    case K_HELIX_RADIUS:
        return scalar(kf, kl, k, helix_radius, &d->strand.helix_radius, err);
    case K_HELIX_STEP:
        return scalar(kf, kl, k, any, &d->strand.helix_step, err);
    case K_POISSON:
        return scalar(kf, kl, k, poisson, &d->strand.poisson, err);
    case K_YOUNG:
        return scalar(kf, kl, k, positive, &d->strand.young, err);
    case K_DENSITY:
        return scalar(kf, kl, k, positive, &d->strand.density, err);
    case K_GRAVITY:
        return scalar(kf, kl, k, non_negative, &d->strand.gravity, err);
    case K_GRAVITY_DIR: {
        double v[3];
        hk_Status st = hk_keyline_doubles(kf, kl, 3, v, err);
        if (st != HK_OK) return st;
        /* Scale by the largest component first: |(1e300, 1e300, 0)| overflows and
         * |(1e-200, 0, 0)| underflows, yet both are fine directions. */
        double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
        if (!(m > 0.0)) return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "GravityDirection must not be zero");
        d->strand.gravity_dir = hk_v3_normalize(hk_v3(v[0] / m, v[1] / m, v[2] / m));
        return HK_OK;
    }
    case K_CLUMP:
        return scalar(kf, kl, k, clump, &d->interpolation.clump, err);
    case K_CLUMP_PROFILE:
        return scalar(kf, kl, k, positive, &d->interpolation.clump_profile, err);
    case K_STRAY_HAIRS:
        return hk_keyline_bool(kf, kl, &d->interpolation.stray_hairs, err);
    case K_MAX_TIP_DISTANCE:
        return scalar(kf, kl, k, non_negative, &d->interpolation.max_tip_distance, err);
    case K_INTERNAL_FRICTION:
        return scalar(kf, kl, k, non_negative, &d->dynamics.internal_friction, err);
    case K_AIR_DRAG:
        return scalar(kf, kl, k, non_negative, &d->dynamics.air_drag, err);
    case K_BODY_FRICTION: {
        double v[2];
        hk_Status st = hk_keyline_doubles(kf, kl, 2, v, err);
        if (st != HK_OK) return st;
        if (!(v[0] >= 0.0 && v[1] >= 0.0 && v[0] <= 10.0 && v[1] <= 10.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                    "BodyFriction needs two coefficients in [0, 10] (with and "
                                    "against the scales), got %s %s",
                                    kl->values[0], kl->values[1]);
        d->dynamics.friction_with = v[0];
        d->dynamics.friction_against = v[1];
        return HK_OK;
    }
    case K_COUNT:
        break;
    }
    return HK_OK;
}

/* The sample counts L / step size the arrays of every strand (§4.1.4): refuse absurd
 * ones here, at the step's line (or at HairLengths' when the step is the default). */
static hk_Status check_samples(const hk_KeyFile *kf, const hk_Hairstyle *d, const int *line_of, int k, double step,
                               hk_Error *err)
{
    const double len = hk_strand_def_length(&d->strand), samples = len / step;
    if (samples <= HK_MAX_SAMPLES_PER_STRAND) return HK_OK;
    const int given = line_of[k] != 0;
    return hk_keyfile_error(kf, given ? line_of[k] : line_of[K_LENGTHS], HK_ERR_INVALID, err,
                            "%s %g%s gives %.3g samples over the %g m strand (at most %d)", specs[k].name, step,
                            given ? "" : " (the default)", samples, len, HK_MAX_SAMPLES_PER_STRAND);
}

hk_Status hk_hairstyle_load(const char *path, hk_Hairstyle *out, hk_Error *err)
{
    *out = hk_default_hairstyle();
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    hk_Hairstyle d = hk_default_hairstyle();
    int line_of[K_COUNT];
    st = hk_keyfile_check_keys(&kf, specs, K_COUNT, "hairstyle", line_of, err);
    for (int i = 0; i < kf.line_count && st == HK_OK; i++)
        st = read_value(&kf, &kf.lines[i], hk_keyspec_find(specs, K_COUNT, kf.lines[i].key), &d, err);
    if (st == HK_OK) st = check_samples(&kf, &d, line_of, K_VISUALITY_STEP, d.strand.visuality_step, err);
    if (st == HK_OK) st = check_samples(&kf, &d, line_of, K_COLLISION_STEP, d.strand.collision_step, err);
    hk_keyfile_free(&kf);
    if (st != HK_OK) {
        hk_free(d.strand.element_lengths);
        return st;
    }
    *out = d;
    return HK_OK;
}
