/* What `groom` and `run` say about the hair of their setup file (hk_scene_hair):
 * read from LoadFile, or grown, with the growing's figures. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

void hk_cli_report_scene_hair(const char *cmd, const hk_Setup *setup, const hk_HairFile *hair,
                              const hk_SceneHairReport *r)
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
