/* Hairstyle Info files (thesis 004 §4.2.1 and Appendix B): the mechanical parameters
 * of a strand, checked for physical sense with file:line messages. */
#include <math.h>
#include <string.h>
#include <strings.h>

#include "hairkit/io.h"
#include "keyfile.h"

enum Key {
    K_VISUALITY_STEP, K_COLLISION_STEP, K_MAX_ITER, K_EPSILON, K_LENGTHS, K_HAIR_DENSITY,
    K_RADIUS1, K_RADIUS2, K_HELIX_RADIUS, K_HELIX_STEP, K_POISSON, K_YOUNG, K_DENSITY,
    K_GRAVITY, K_GRAVITY_DIR, K_COUNT
};

typedef struct KeyInfo {
    const char *name, *alias;
    int required;
} KeyInfo;

static const KeyInfo keys[K_COUNT] = {
    [K_VISUALITY_STEP] = {"VisualityStep", NULL, 0}, [K_COLLISION_STEP] = {"CollisionStep", NULL, 0},
    [K_MAX_ITER] = {"MaxIter", NULL, 0},             [K_EPSILON] = {"Epsilon", NULL, 0},
    [K_LENGTHS] = {"HairLengths", "HairLength", 1},  [K_HAIR_DENSITY] = {"HairDensity", NULL, 0},
    [K_RADIUS1] = {"HairRadius1", NULL, 1},          [K_RADIUS2] = {"HairRadius2", NULL, 1},
    [K_HELIX_RADIUS] = {"HelixRadius", NULL, 1},     [K_HELIX_STEP] = {"HelixStep", NULL, 1},
    [K_POISSON] = {"Poisson", NULL, 0},              [K_YOUNG] = {"Young", NULL, 1},
    [K_DENSITY] = {"Density", NULL, 0},              [K_GRAVITY] = {"Gravity", NULL, 0},
    [K_GRAVITY_DIR] = {"GravityDirection", NULL, 0},
};

hk_HairstyleDef hk_default_hairstyle(void)
{
    hk_HairstyleDef d;
    memset(&d, 0, sizeof d);
    d.visuality_step = 0.0025;
    d.collision_step = 0.005;
    d.max_iter = 20;
    d.epsilon = 1e-4;
    d.hair_density = 250.0;
    d.poisson = 0.48;
    d.density = 1300.0;
    d.gravity = 9.81;
    d.gravity_dir = hk_v3(0.0, -1.0, 0.0);
    return d;
}

double hk_hairstyle_length(const hk_HairstyleDef *def)
{
    double s = 0.0;
    for (int i = 0; i < def->element_count; i++) s += def->element_lengths[i];
    return s;
}

void hk_hairstyle_free(hk_HairstyleDef *def)
{
    hk_free(def->element_lengths);
    *def = hk_default_hairstyle();
}

hk_Status hk_hairstyle_copy(const hk_HairstyleDef *src, hk_HairstyleDef *dst, hk_Error *err)
{
    *dst = *src;
    dst->element_lengths = NULL;
    if (src->element_count > 0) {
        dst->element_lengths = hk_alloc_array((size_t)src->element_count, sizeof(double), err);
        if (!dst->element_lengths) {
            *dst = hk_default_hairstyle();
            return HK_ERR_NOMEM;
        }
        memcpy(dst->element_lengths, src->element_lengths, (size_t)src->element_count * sizeof(double));
    }
    return HK_OK;
}

static int find_key(const char *name)
{
    for (int k = 0; k < K_COUNT; k++)
        if (!strcasecmp(name, keys[k].name) || (keys[k].alias && !strcasecmp(name, keys[k].alias))) return k;
    return -1;
}

/* One number from line kl, which must satisfy lo < v (or lo <= v) and v < hi. */
static hk_Status ranged(const hk_KeyFile *kf, const hk_KeyLine *kl, double *out, double lo, int lo_open,
                        double hi, const char *range_text, hk_Error *err)
{
    hk_Status st = hk_keyline_doubles(kf, kl, 1, out, err);
    if (st != HK_OK) return st;
    if ((lo_open ? !(*out > lo) : !(*out >= lo)) || !(*out < hi))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s must be %s, got %g", keys[find_key(kl->key)].name,
                                range_text, *out);
    return HK_OK;
}

static hk_Status read_value(const hk_KeyFile *kf, const hk_KeyLine *kl, int key, hk_HairstyleDef *d, hk_Error *err)
{
    long iv;
    double v3[3];
    switch (key) {
    case K_VISUALITY_STEP: return ranged(kf, kl, &d->visuality_step, 0.0, 1, HUGE_VAL, "> 0", err);
    case K_COLLISION_STEP: return ranged(kf, kl, &d->collision_step, 0.0, 1, HUGE_VAL, "> 0", err);
    case K_MAX_ITER: {
        hk_Status st = hk_keyline_int(kf, kl, 1, 1000000000L, &iv, err);
        d->max_iter = (int)iv;
        return st;
    }
    case K_EPSILON: return ranged(kf, kl, &d->epsilon, 0.0, 1, HUGE_VAL, "> 0", err);
    case K_LENGTHS: {
        double buf[HK_MAX_ELEMENTS];
        int n = 0;
        hk_Status st = hk_keyline_double_list(kf, kl, HK_MAX_ELEMENTS, buf, &n, err);
        if (st != HK_OK) return st;
        for (int i = 0; i < n; i++)
            if (!(buf[i] > 0.0) || buf[i] > 10.0)
                return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                        "element length %d must be in (0, 10] m, got %g", i + 1, buf[i]);
        d->element_lengths = hk_alloc_array((size_t)n, sizeof(double), err);
        if (!d->element_lengths) return HK_ERR_NOMEM;
        memcpy(d->element_lengths, buf, (size_t)n * sizeof(double));
        d->element_count = n;
        return HK_OK;
    }
    case K_HAIR_DENSITY: return ranged(kf, kl, &d->hair_density, 0.0, 0, 100000.0 + 1e-9, "in [0, 100000] hairs/cm^2", err);
    case K_RADIUS1: return ranged(kf, kl, &d->radius1, 0.0, 1, 0.01, "in (0, 0.01) m", err);
    case K_RADIUS2: return ranged(kf, kl, &d->radius2, 0.0, 1, 0.01, "in (0, 0.01) m", err);
    case K_HELIX_RADIUS: return ranged(kf, kl, &d->helix_radius, 0.0, 0, HUGE_VAL, ">= 0 (0: straight hair)", err);
    case K_HELIX_STEP: return ranged(kf, kl, &d->helix_step, -HUGE_VAL, 1, HUGE_VAL, "finite", err);
    case K_POISSON: return ranged(kf, kl, &d->poisson, -1.0, 1, 0.5, "in (-1, 0.5)", err);
    case K_YOUNG: return ranged(kf, kl, &d->young, 0.0, 1, HUGE_VAL, "> 0", err);
    case K_DENSITY: return ranged(kf, kl, &d->density, 0.0, 1, HUGE_VAL, "> 0", err);
    case K_GRAVITY: return ranged(kf, kl, &d->gravity, 0.0, 0, HUGE_VAL, ">= 0", err);
    case K_GRAVITY_DIR: {
        hk_Status st = hk_keyline_doubles(kf, kl, 3, v3, err);
        if (st != HK_OK) return st;
        hk_Vec3 g = hk_v3(v3[0], v3[1], v3[2]);
        if (!(hk_v3_norm(g) > 0.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "GravityDirection must not be zero");
        d->gravity_dir = hk_v3_normalize(g);
        return HK_OK;
    }
    }
    return HK_OK;
}

hk_Status hk_hairstyle_load(const char *path, hk_HairstyleDef *out, hk_Error *err)
{
    *out = hk_default_hairstyle();
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    hk_HairstyleDef d = hk_default_hairstyle();
    int seen[K_COUNT] = {0};
    for (int i = 0; i < kf.line_count && st == HK_OK; i++) {
        const hk_KeyLine *kl = &kf.lines[i];
        int k = find_key(kl->key);
        if (k < 0) {
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "unknown key '%s' in a hairstyle file", kl->key);
            break;
        }
        if (seen[k]) {
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "duplicate key '%s' (first given at line %d)",
                                  keys[k].name, seen[k]);
            break;
        }
        seen[k] = kl->line;
        st = read_value(&kf, kl, k, &d, err);
    }
    for (int k = 0; k < K_COUNT && st == HK_OK; k++)
        if (keys[k].required && !seen[k])
            st = hk_keyfile_error(&kf, 0, HK_ERR_PARSE, err, "missing required key '%s'", keys[k].name);
    if (st == HK_OK) {
        /* Sample counts follow from the length: refuse absurd ones before anyone allocates. */
        const double len = hk_hairstyle_length(&d);
        if (len / d.visuality_step > HK_MAX_SAMPLES_PER_STRAND)
            st = hk_keyfile_error(&kf, seen[K_VISUALITY_STEP], HK_ERR_INVALID, err,
                                  "VisualityStep %g gives %.3g samples over the %g m strand (at most %d)",
                                  d.visuality_step, len / d.visuality_step, len, HK_MAX_SAMPLES_PER_STRAND);
        else if (len / d.collision_step > HK_MAX_SAMPLES_PER_STRAND)
            st = hk_keyfile_error(&kf, seen[K_COLLISION_STEP], HK_ERR_INVALID, err,
                                  "CollisionStep %g gives %.3g samples over the %g m strand (at most %d)",
                                  d.collision_step, len / d.collision_step, len, HK_MAX_SAMPLES_PER_STRAND);
    }
    hk_keyfile_free(&kf);
    if (st != HK_OK) {
        hk_free(d.element_lengths);
        return st;
    }
    *out = d;
    return HK_OK;
}
