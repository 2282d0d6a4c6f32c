/* A scene loaded from a setup file, its hair and its picture (include/hairkit/scene.h).
 * The one place that turns a setup file into what the jobs need: `hairkit groom`,
 * `run` and `simulate`, the rebuild of a simulated frame and the benchmarks all start
 * here. */
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/scene.h"

static void scene_empty(hk_Scene *s)
{
    memset(s, 0, sizeof *s);
    s->style = hk_default_hairstyle();
    s->visuality = hk_default_visuality();
}

void hk_scene_free(hk_Scene *s)
{
    if (!s) return;
    hk_mesh_free(&s->wick);
    hk_mesh_free(&s->head);
    hk_collision_free(&s->collision);
    hk_hairstyle_free(&s->style);
    hk_setup_free(&s->setup);
    hk_free(s->setup_path);
    scene_empty(s);
}

/* HeadCollider: the HeadModel's signed distance field appended to the shapes as a body
 * shape (docs/file-formats.md, "Setup file"), as a collision file's Mesh line is. */
static hk_Status add_head_collider(hk_Scene *s, hk_Error *err)
{
    hk_Mesh head;
    hk_Status st = hk_mesh_load(s->setup.head_model, &head, err);
    if (st == HK_OK)
        st = hk_collision_add_mesh(&s->collision, &head, NULL, s->setup.head_collider_volume,
                                   s->setup.head_collider_penalty, err);
    hk_mesh_free(&head);
    return st;
}

/* The part of the scene bit `part` names: its file in the setup, and where it goes. */
static hk_Status load_part(hk_Scene *s, unsigned part, const char *setup_path, hk_Error *err)
{
    const hk_Setup *setup = &s->setup;
    switch (part) {
    case HK_SCENE_HAIRSTYLE:
        if (!setup->hairstyle) return hk_error_set(err, HK_ERR_PARSE, "%s: no HairstyleInfo", setup_path);
        hk_hairstyle_free(&s->style);
        s->style = hk_default_hairstyle();
        return hk_hairstyle_load(setup->hairstyle, &s->style, err);
    case HK_SCENE_COLLISION: {
        hk_Status st = setup->collision ? hk_collision_load(setup->collision, &s->collision, err) : HK_OK;
        return st == HK_OK && setup->head_collider ? add_head_collider(s, err) : st;
    }
    case HK_SCENE_VISUALITY:
        return setup->visuality ? hk_visuality_load(setup->visuality, &s->visuality, err) : HK_OK;
    case HK_SCENE_HEAD:
        return setup->head_model ? hk_mesh_load(setup->head_model, &s->head, err) : HK_OK;
    case HK_SCENE_WICK:
        if (!setup->wick_model) return hk_error_set(err, HK_ERR_PARSE, "%s: no WickModel", setup_path);
        return hk_mesh_load(setup->wick_model, &s->wick, err);
    default:
        return HK_OK;
    }
}

/* Clears part `part` (read or half read) back to its empty state. */
static void drop_part(hk_Scene *s, unsigned part)
{
    switch (part) {
    case HK_SCENE_HAIRSTYLE:
        hk_hairstyle_free(&s->style);
        s->style = hk_default_hairstyle();
        break;
    case HK_SCENE_COLLISION:
        hk_collision_free(&s->collision);
        break;
    case HK_SCENE_VISUALITY:
        s->visuality = hk_default_visuality();
        break;
    case HK_SCENE_HEAD:
        hk_mesh_free(&s->head);
        break;
    case HK_SCENE_WICK:
        hk_mesh_free(&s->wick);
        break;
    default:
        break;
    }
}

hk_Status hk_scene_load_parts(hk_Scene *s, unsigned parts, hk_Error *err)
{
    if (parts & HK_SCENE_HAIR) parts = (parts & ~(unsigned)HK_SCENE_HAIR) | (s->setup.load ? 0u : HK_SCENE_GROOMING);
    /* The small text files first, then the meshes. */
    static const unsigned order[] = {HK_SCENE_HAIRSTYLE, HK_SCENE_COLLISION, HK_SCENE_VISUALITY, HK_SCENE_HEAD,
                                     HK_SCENE_WICK};
    unsigned added = 0;
    for (size_t k = 0; k < sizeof order / sizeof *order; k++) {
        const unsigned part = order[k];
        if (!(parts & part) || (s->parts & part)) continue;
        const hk_Status st = load_part(s, part, s->setup_path, err);
        if (st != HK_OK) {
            drop_part(s, part);
            for (size_t j = 0; j < k; j++)
                if (added & order[j]) drop_part(s, order[j]);
            return st;
        }
        added |= part;
    }
    s->parts |= added;
    return HK_OK;
}

hk_Status hk_scene_load(const char *setup_path, unsigned parts, hk_Scene *out, hk_Error *err)
{
    scene_empty(out);
    hk_Status st = hk_setup_load(setup_path, &out->setup, err);
    if (st == HK_OK) {
        out->setup_path = hk_strdup(setup_path, err);
        if (!out->setup_path) st = HK_ERR_NOMEM;
    }
    if (st == HK_OK) st = hk_scene_load_parts(out, parts, err);
    if (st != HK_OK) hk_scene_free(out);
    return st;
}

hk_Status hk_scene_hair(const hk_Scene *s, const hk_GroomDef *options, hk_HairFile *hair, hk_SceneHairReport *report,
                        hk_Error *err)
{
    hk_SceneHairReport local;
    if (!report) report = &local;
    memset(hair, 0, sizeof *hair);
    memset(report, 0, sizeof *report);
    const hk_GroomDef defaults = hk_default_groom_def();
    if (!options) options = &defaults;
    hk_Status st = HK_OK;
    if (s->setup.load) {
        st = hk_hair_read(s->setup.load_file, HK_HAIR_FORMAT_AUTO, hair, err);
    } else {
        if ((s->parts & HK_SCENE_GROOMING) != HK_SCENE_GROOMING)
            return hk_error_set(err, HK_ERR_INVALID,
                                "scene: growing the hair needs the scene loaded with "
                                "HK_SCENE_GROOMING");
        hk_Groom groom;
        memset(&groom, 0, sizeof groom);
        /* hk_groom_grow checks the same; here the message can name the files. */
        hk_Error sub;
        st = hk_groom_check_size(&s->style.strand, &s->style.interpolation, &s->wick, options, NULL, &sub);
        if (st != HK_OK)
            return hk_error_set(err, st, "%s, %s: %s", s->setup.hairstyle, s->setup.wick_model, sub.message);
        st = hk_groom_grow(&s->style.strand, &s->style.interpolation, s->collision.shapes, s->collision.count, &s->wick,
                           options, &groom, err);
        if (st == HK_OK) st = hk_groom_to_hair(&groom, &s->style.strand, hair, err);
        report->grown = st == HK_OK;
        report->guides = groom.guide_count;
        report->strands = groom.strand_count;
        report->points_per_strand = groom.points_per_strand;
        report->stats = groom.stats;
        hk_groom_free(&groom);
    }
    if (st == HK_OK && s->setup.save) st = hk_hair_save(s->setup.save_file, hair, err);
    if (st != HK_OK) hk_hair_free(hair);
    return st;
}

hk_Status hk_scene_render(const hk_Scene *s, const hk_HairFile *hair, const hk_RenderDef *options, hk_Canvas *out,
                          hk_RenderStats *stats, hk_Error *err)
{
    const hk_RenderDef defaults = hk_default_render_def();
    return hk_render(hair, s->head.vertex_count > 0 ? &s->head : NULL, &s->visuality, options ? options : &defaults,
                     out, stats, err);
}
