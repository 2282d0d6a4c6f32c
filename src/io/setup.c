/* Setup files (Lansink 2010 §4.2.1, Appendix B): the files that make up a scene, with
 * paths relative to the setup file and the Load/Save switches. */
#include <string.h>
#include <unistd.h>

#include "hairkit/io.h"
#include "keyfile.h"

enum {
    S_LOAD,
    S_SAVE,
    S_LOAD_FILE,
    S_SAVE_FILE,
    S_HAIRSTYLE,
    S_COLLISION,
    S_VISUALITY,
    S_HEAD,
    S_WICK,
    S_HEAD_VERT,
    S_HEAD_FRAG,
    S_HAIR_VERT,
    S_HAIR_FRAG,
    S_IMPORT,
    S_HEAD_COLLIDER,
    S_COUNT
};

/* Nothing is required by itself: what is needed depends on Load (checked below). */
static const hk_KeySpec specs[S_COUNT] = {
    [S_LOAD] = {"Load", NULL, 0},
    [S_SAVE] = {"Save", NULL, 0},
    [S_LOAD_FILE] = {"LoadFile", "LoadPath", 0},
    [S_SAVE_FILE] = {"SaveFile", "SavePath", 0},
    [S_HAIRSTYLE] = {"HairstyleInfo", NULL, 0},
    [S_COLLISION] = {"CollisionInfo", NULL, 0},
    [S_VISUALITY] = {"VisualityInfo", NULL, 0},
    [S_HEAD] = {"HeadModel", NULL, 0},
    [S_WICK] = {"WickModel", "HairModel", 0},
    [S_HEAD_VERT] = {"HeadVert", NULL, 0},
    [S_HEAD_FRAG] = {"HeadFrag", NULL, 0},
    [S_HAIR_VERT] = {"HairVert", NULL, 0},
    [S_HAIR_FRAG] = {"HairFrag", NULL, 0},
    [S_IMPORT] = {"ImportFile", NULL, 0},
    [S_HEAD_COLLIDER] = {"HeadCollider", NULL, 0},
};

void hk_setup_free(hk_Setup *d)
{
    hk_free(d->load_file);
    hk_free(d->save_file);
    hk_free(d->hairstyle);
    hk_free(d->collision);
    hk_free(d->visuality);
    hk_free(d->head_model);
    hk_free(d->wick_model);
    hk_free(d->import_file);
    hk_free(d->head_vert);
    hk_free(d->head_frag);
    hk_free(d->hair_vert);
    hk_free(d->hair_frag);
    memset(d, 0, sizeof *d);
}

/* One line's value; paths[k] non-NULL for the keys that name a file. */
static hk_Status read_value(const hk_KeyFile *kf, const hk_KeyLine *kl, int k, hk_Setup *d, char **const paths[S_COUNT],
                            hk_Error *err)
{
    if (k == S_LOAD) return hk_keyline_bool(kf, kl, &d->load, err);
    if (k == S_SAVE) return hk_keyline_bool(kf, kl, &d->save, err);
    if (k == S_HEAD_COLLIDER) {
        double v[2] = {0.0, 0.0};
        hk_Status st = hk_keyline_doubles(kf, kl, 2, v, err);
        if (st == HK_OK && !(v[1] >= 0.0))
            st = hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "HeadCollider's Penalty must be >= 0, got %s",
                                  kl->values[1]);
        d->head_collider = st == HK_OK;
        d->head_collider_volume = v[0];
        d->head_collider_penalty = v[1];
        return st;
    }
    const char *value;
    hk_Status st = hk_keyline_string(kf, kl, &value, err);
    if (st != HK_OK || !paths[k]) return st;
    *paths[k] = hk_keyfile_resolve_path(kf, value, err);
    return *paths[k] ? HK_OK : HK_ERR_NOMEM;
}

/* What the switches need, and files to read that exist: each message names the line. */
static hk_Status check_needs(const hk_KeyFile *kf, const hk_Setup *d, char **const paths[S_COUNT],
                             const int line_of[S_COUNT], hk_Error *err)
{
    if (d->load && !d->load_file)
        return hk_keyfile_error(kf, line_of[S_LOAD], HK_ERR_PARSE, err, "Load is true but no LoadFile is given");
    if (d->save && !d->save_file)
        return hk_keyfile_error(kf, line_of[S_SAVE], HK_ERR_PARSE, err, "Save is true but no SaveFile is given");
    static const int grow_needs[] = {S_HAIRSTYLE, S_WICK};
    if (d->head_collider && !d->head_model)
        return hk_keyfile_error(kf, line_of[S_HEAD_COLLIDER], HK_ERR_PARSE, err,
                                "HeadCollider makes the HeadModel a collider, but no HeadModel is given");
    for (size_t i = 0; !d->load && !d->import_file && i < sizeof grow_needs / sizeof grow_needs[0]; i++)
        if (!*paths[grow_needs[i]])
            return hk_keyfile_error(kf, 0, HK_ERR_PARSE, err, "missing key '%s' (needed to grow hair)",
                                    specs[grow_needs[i]].name);
    for (int k = 0; k < S_COUNT; k++) {
        /* The shaders are the viewer's: the jobs that do not draw with them need not find them. */
        const int shader = k == S_HEAD_VERT || k == S_HEAD_FRAG || k == S_HAIR_VERT || k == S_HAIR_FRAG;
        if (!paths[k] || !*paths[k] || shader || k == S_SAVE_FILE || (k == S_LOAD_FILE && !d->load)) continue;
        if (access(*paths[k], R_OK) != 0)
            return hk_keyfile_error(kf, line_of[k], HK_ERR_IO, err, "%s '%s' cannot be read", specs[k].name, *paths[k]);
    }
    return HK_OK;
}

hk_Status hk_setup_load(const char *path, hk_Setup *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    hk_Setup d;
    memset(&d, 0, sizeof d);
    char **const paths[S_COUNT] = {
        [S_LOAD_FILE] = &d.load_file, [S_SAVE_FILE] = &d.save_file, [S_HAIRSTYLE] = &d.hairstyle,
        [S_COLLISION] = &d.collision, [S_VISUALITY] = &d.visuality, [S_HEAD] = &d.head_model,
        [S_WICK] = &d.wick_model,     [S_IMPORT] = &d.import_file,  [S_HEAD_VERT] = &d.head_vert,
        [S_HEAD_FRAG] = &d.head_frag, [S_HAIR_VERT] = &d.hair_vert, [S_HAIR_FRAG] = &d.hair_frag};
    int line_of[S_COUNT];
    st = hk_keyfile_check_keys(&kf, specs, S_COUNT, "setup", line_of, err);
    for (int i = 0; i < kf.line_count && st == HK_OK; i++)
        st = read_value(&kf, &kf.lines[i], hk_keyspec_find(specs, S_COUNT, kf.lines[i].key), &d, paths, err);
    if (st == HK_OK) st = check_needs(&kf, &d, paths, line_of, err);
    hk_keyfile_free(&kf);
    if (st != HK_OK) {
        hk_setup_free(&d);
        return st;
    }
    *out = d;
    return HK_OK;
}
