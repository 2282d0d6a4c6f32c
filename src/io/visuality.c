/* Visuality Info files (Lansink 2010 §4.2.1, Appendix B): hair colours and glossiness. */
#include <string.h>

#include "hairkit/io.h"
#include "keyfile.h"

hk_Visuality hk_default_visuality(void)
{
    hk_Visuality v;
    v.ambient = hk_v3(0.10, 0.10, 0.10);
    v.diffuse = hk_v3(0.471, 0.235, 0.0); /* the thesis's "Brown" */
    v.specular = hk_v3(0.2, 0.2, 0.2);
    v.glossiness = 60.0;
    return v;
}

static hk_Status colour(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Vec3 *out, hk_Error *err)
{
    double c[3];
    hk_Status st = hk_keyline_doubles(kf, kl, 3, c, err);
    if (st != HK_OK) return st;
    for (int i = 0; i < 3; i++)
        if (!(c[i] >= 0.0) || c[i] > 100.0)
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s components must be in [0, 100], got %g",
                                    kl->key, c[i]);
    *out = hk_v3(c[0], c[1], c[2]);
    return HK_OK;
}

enum { V_AMBIENT, V_DIFFUSE, V_SPECULAR, V_GLOSSINESS, V_COUNT };

static const hk_KeySpec specs[V_COUNT] = {
    [V_AMBIENT] = {"AmbientColor", "AmbientColour", 0},
    [V_DIFFUSE] = {"DiffuseColor", "DiffuseColour", 0},
    [V_SPECULAR] = {"SpecularColor", "SpecularColour", 0},
    [V_GLOSSINESS] = {"Glossiness", NULL, 0},
};

static hk_Status read_value(const hk_KeyFile *kf, const hk_KeyLine *kl, int k, hk_Visuality *v, hk_Error *err)
{
    if (k == V_AMBIENT) return colour(kf, kl, &v->ambient, err);
    if (k == V_DIFFUSE) return colour(kf, kl, &v->diffuse, err);
    if (k == V_SPECULAR) return colour(kf, kl, &v->specular, err);
    hk_Status st = hk_keyline_doubles(kf, kl, 1, &v->glossiness, err);
    if (st == HK_OK && !(v->glossiness > 0.0 && v->glossiness <= 100000.0))
        st = hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Glossiness must be in (0, 100000], got %g",
                              v->glossiness);
    return st;
}

hk_Status hk_visuality_load(const char *path, hk_Visuality *out, hk_Error *err)
{
    *out = hk_default_visuality();
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    hk_Visuality v = hk_default_visuality();
    int line_of[V_COUNT];
    st = hk_keyfile_check_keys(&kf, specs, V_COUNT, "visuality", line_of, err);
    for (int i = 0; i < kf.line_count && st == HK_OK; i++)
        st = read_value(&kf, &kf.lines[i], hk_keyspec_find(specs, V_COUNT, kf.lines[i].key), &v, err);
    hk_keyfile_free(&kf);
    if (st == HK_OK) *out = v;
    return st;
}
