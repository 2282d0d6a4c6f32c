/* The hair a setup file stands for, shared by `groom` and `run`: read from LoadFile
 * (Load true) or grown from the hairstyle, collision and wick files; then saved to
 * SaveFile when Save is true (thesis 004 §4.2.2). */
#include <stdio.h>
#include <string.h>

#include "cli.h"

hk_Status hk_cli_setup_hair(const hk_SetupDef *setup, const hk_GroomOptions *go, hk_HairFile *hair,
                            hk_SetupHairReport *report, hk_Error *err)
{
    memset(hair, 0, sizeof *hair);
    memset(report, 0, sizeof *report);
    hk_HairstyleDef style = hk_default_hairstyle();
    hk_Shape *shapes = NULL;
    int shape_count = 0;
    hk_Mesh wick = {0, 0, NULL, NULL, NULL};
    hk_Groom groom;
    memset(&groom, 0, sizeof groom);
    hk_Status st = HK_OK;
    if (setup->load) {
        st = hk_hair_load(setup->load_file, hair, err);
    } else {
        if (st == HK_OK) st = hk_hairstyle_load(setup->hairstyle, &style, err);
        if (st == HK_OK && setup->collision) st = hk_collision_load(setup->collision, &shapes, &shape_count, err);
        if (st == HK_OK) st = hk_obj_load(setup->wick_model, &wick, err);
        if (st == HK_OK) {
            /* hk_groom_grow checks the same; here the message can name the files. */
            hk_Error sub;
            st = hk_groom_check_size(&style, &wick, go, NULL, &sub);
            if (st != HK_OK) hk_error_set(err, st, "%s, %s: %s", setup->hairstyle, setup->wick_model, sub.message);
        }
        if (st == HK_OK) st = hk_groom_grow(&style, shapes, shape_count, &wick, go, &groom, err);
        if (st == HK_OK) st = hk_groom_to_hair(&groom, &style, hair, err);
        report->grown = st == HK_OK;
        report->guides = groom.guide_count;
        report->strands = groom.strand_count;
        report->points_per_strand = groom.points_per_strand;
        report->stats = groom.stats;
    }
    if (st == HK_OK && setup->save) st = hk_hair_save(setup->save_file, hair, err);
    if (st != HK_OK) hk_hair_free(hair);
    hk_groom_free(&groom);
    hk_mesh_free(&wick);
    hk_free(shapes);
    hk_hairstyle_free(&style);
    return st;
}

void hk_cli_report_setup_hair(const char *cmd, const hk_SetupDef *setup, const hk_HairFile *hair,
                              const hk_SetupHairReport *r)
{
    if (!r->grown) {
        fprintf(stderr, "hairkit %s: loaded %u strands from %s\n", cmd, hair->strand_count, setup->load_file);
        return;
    }
    fprintf(stderr,
            "hairkit %s: %d guides (%.2f s, %ld Newton steps%s), %d interpolated strands (%.2f s), %d points each\n",
            cmd, r->guides, r->stats.seconds_guides, r->stats.guide_iterations,
            r->stats.guides_not_converged ? ", some stopped by the iteration limit" : "", r->strands,
            r->stats.seconds_strands, r->points_per_strand);
}
