/* hairkit import (hairkit/capture.h; docs/capture.md, "Importing a groom"): a groom and a
 * head become a folder that `hairkit simulate` runs at rest:
 *     DIR/setup.txt      HairstyleInfo, HeadModel, HeadCollider, Load/LoadFile, ImportFile
 *     DIR/hairstyle.txt  the material (copied from --hairstyle, or the defaults)
 *     DIR/head.obj       the head, scaled and turned as the hair (a copy: the folder is
 *                        complete by itself, and the head is in the hair's frame)
 *     DIR/guides.txt     the guides and attachments (hk_imported_groom_save)
 *     DIR/strands.hair   the captured strands, moved out of the head, in input order */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "core/core_internal.h"
#include "hairkit/capture.h"
#include "hairkit/io.h"
#include "hairkit/mesh.h"
#include "io/outfile.h"

hk_ImportRunDef hk_default_import_run_def(void)
{
    hk_ImportRunDef d;
    memset(&d, 0, sizeof d);
    d.format = HK_HAIR_FORMAT_AUTO;
    d.scale = 1.0;
    d.up = HK_AXIS_POS_Y;
    d.head_scale = 1.0;
    d.head_up = HK_AXIS_POS_Y;
    d.collider_volume = 0.0;
    d.collider_penalty = 10.0;
    d.groom = hk_default_groom_import_def();
    return d;
}

static const char DEFAULT_HAIRSTYLE[] =
    "# The material of an imported groom (hairkit import; docs/capture.md).\n"
    "# HairLengths, the helix and HairDensity are not used by an import: its guides have\n"
    "# the captured lengths and shapes.\n"
    "HairLengths     0.2\n"
    "HelixRadius     0\n"
    "HelixStep       0.1\n"
    "HairRadius1     0.00004\n"
    "HairRadius2     0.00004\n"
    "Young           3e9\n"
    "Poisson         0.48\n"
    "Density         1300\n"
    "Gravity         9.81\n"
    "CollisionStep   0.005\n"
    "VisualityStep   0.005\n";

static hk_Status write_text(const char *path, const char *text, size_t n, hk_Error *err)
{
    hk_OutFile of;
    hk_Status st = hk_outfile_open(&of, path, err);
    if (st != HK_OK) return st;
    if (fwrite(text, 1, n, of.fp) != n) {
        hk_outfile_abort(&of);
        return hk_error_set(err, HK_ERR_IO, "%s: cannot write", path);
    }
    return hk_outfile_commit(&of, err);
}

/* The bytes of a (small) text file. */
static hk_Status read_all(const char *path, char **out, size_t *n, hk_Error *err)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: %s", path, strerror(errno));
    char *buf = hk_alloc_array((size_t)HK_MAX_INPUT_FILE_BYTES + 1, 1, err);
    if (!buf) {
        fclose(fp);
        return HK_ERR_NOMEM;
    }
    *n = fread(buf, 1, (size_t)HK_MAX_INPUT_FILE_BYTES + 1, fp);
    fclose(fp);
    if (*n > (size_t)HK_MAX_INPUT_FILE_BYTES) {
        hk_free(buf);
        return hk_error_set(err, HK_ERR_INVALID, "%s: larger than a hairstyle file can be", path);
    }
    *out = buf;
    return HK_OK;
}

static hk_Status path_in(char *buf, size_t size, const char *dir, const char *name, hk_Error *err)
{
    if (snprintf(buf, size, "%s/%s", dir, name) >= (int)size)
        return hk_error_set(err, HK_ERR_INVALID, "%s: folder name too long", dir);
    return HK_OK;
}

/* DIR/hairstyle.txt and the material it gives. */
static hk_Status write_hairstyle(const hk_ImportRunDef *d, hk_RodMaterial *material, double *collision_step,
                                 hk_Error *err)
{
    char path[4096];
    hk_Status st = path_in(path, sizeof path, d->dir, "hairstyle.txt", err);
    if (st != HK_OK) return st;
    if (d->hairstyle) {
        char *text = NULL;
        size_t n = 0;
        st = read_all(d->hairstyle, &text, &n, err);
        if (st == HK_OK) st = write_text(path, text, n, err);
        hk_free(text);
    } else {
        st = write_text(path, DEFAULT_HAIRSTYLE, sizeof DEFAULT_HAIRSTYLE - 1, err);
    }
    hk_Hairstyle style = hk_default_hairstyle();
    if (st == HK_OK) st = hk_hairstyle_load(path, &style, err);
    if (st == HK_OK) {
        const hk_StrandDef *s = &style.strand;
        *material = hk_rod_material(s->radius1, s->radius2, s->young, s->poisson, s->density,
                                    hk_v3_scale(s->gravity_dir, s->gravity));
        *collision_step = s->collision_step;
    }
    hk_hairstyle_free(&style);
    return st;
}

hk_Status hk_import_run(const hk_ImportRunDef *def, hk_ImportRunReport *report, hk_Error *err)
{
    hk_ImportRunReport local;
    if (!report) report = &local;
    memset(report, 0, sizeof *report);
    const double t0 = hk_seconds_now();
    if (!def->hair || !def->dir) return hk_error_set(err, HK_ERR_INVALID, "import: no hair file or no folder");
    if (mkdir(def->dir, 0777) != 0 && errno != EEXIST)
        return hk_error_set(err, HK_ERR_IO, "%s: cannot make the folder: %s", def->dir, strerror(errno));
    hk_GroomImportDef gd = def->groom;
    hk_Status st = write_hairstyle(def, &gd.material, &gd.collision_step, err);
    if (st != HK_OK) return st;

    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Mesh head;
    memset(&head, 0, sizeof head);
    hk_CollisionSet body = {0};
    hk_ImportedGroom g;
    memset(&g, 0, sizeof g);
    hk_Error sub;
    st = hk_hair_read(def->hair, def->format, &hair, err);
    if (st == HK_OK && def->scale != 1.0 && hk_hair_scale(&hair, def->scale, &sub) != HK_OK)
        st = hk_error_set(err, sub.code, "%s: scale: %s", def->hair, sub.message);
    if (st == HK_OK) hk_hair_up_to_y(&hair, def->up);
    if (st == HK_OK && def->head) {
        st = hk_mesh_load(def->head, &head, err);
        if (st == HK_OK && def->head_scale != 1.0 && hk_mesh_scale(&head, def->head_scale, &sub) != HK_OK)
            st = hk_error_set(err, sub.code, "%s: head scale: %s", def->head, sub.message);
        if (st == HK_OK) hk_mesh_up_to_y(&head, def->head_up);
    }
    const double t1 = hk_seconds_now();
    report->seconds_read = t1 - t0;
    report->points = hair.point_count;
    report->head_triangles = head.triangle_count;
    if (st == HK_OK && def->head) {
        st = hk_collision_add_mesh(&body, &head, NULL, def->collider_volume, def->collider_penalty, err);
        if (st == HK_OK) memcpy(report->field_size, body.fields[0]->size, sizeof report->field_size);
    }
    const double t2 = hk_seconds_now();
    report->seconds_field = t2 - t1;
    if (st == HK_OK) st = hk_groom_import(&hair, body.shapes, body.count, &gd, &g, &report->groom, err);
    const double t3 = hk_seconds_now();
    char path[4096];
    if (st == HK_OK && def->head) {
        if ((st = path_in(path, sizeof path, def->dir, "head.obj", err)) == HK_OK)
            st = hk_obj_save(path, &head, "the head of hairkit import, in metres, y up", err);
    }
    if (st == HK_OK && (st = path_in(path, sizeof path, def->dir, "guides.txt", err)) == HK_OK)
        st = hk_imported_groom_save(path, "strands.hair", &g, err);
    if (st == HK_OK && (st = path_in(path, sizeof path, def->dir, "setup.txt", err)) == HK_OK) {
        char text[1024];
        int n = snprintf(text, sizeof text,
                         "# made by hairkit import (docs/capture.md, \"Importing a groom\")\n"
                         "HairstyleInfo   hairstyle.txt\n"
                         "Load            true\n"
                         "LoadFile        strands.hair     # the capture, as imported\n"
                         "ImportFile      guides.txt       # the guides simulate moves\n");
        if (def->head)
            n += snprintf(text + n, sizeof text - (size_t)n,
                          "HeadModel       head.obj\n"
                          "HeadCollider    %.17g %.17g   # Volume Penalty of the head's distance field\n",
                          def->collider_volume, def->collider_penalty);
        st = write_text(path, text, (size_t)n, err);
    }
    report->seconds_write = hk_seconds_now() - t3;
    report->seconds = hk_seconds_now() - t0;
    hk_imported_groom_free(&g);
    hk_collision_free(&body);
    hk_mesh_free(&head);
    hk_hair_free(&hair);
    return st;
}
