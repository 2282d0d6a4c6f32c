#include "hk_test_strand.h"

#include "hk_test.h"

#include <stdio.h>

#include "hairkit/statics.h"

hk_SuperHelix *hk_test_strand_on_head(const char *type, const hk_Shape *shapes, int count, hk_Hairstyle *def,
                                      hk_StrandEnvDef *body)
{
    char path[512];
    snprintf(path, sizeof path, "%s/examples/strand/%s.txt", HK_SOURCE_DIR, type);
    hk_Error err;
    assert_int_equal(hk_hairstyle_load(path, def, &err), HK_OK);
    hk_SuperHelix *sh = NULL;
    assert_int_equal(hk_superhelix_from_def(&def->strand, hk_v3(0.0, 0.148, 0.01), hk_v3(0.3, 1.0, -0.5), &sh, &err),
                     HK_OK);
    const hk_StrandEnvDef env = {shapes, count, 0.5, def->strand.collision_step};
    *body = env;
    hk_StaticsDef so = hk_default_statics_def();
    hk_MinimizeResult res;
    assert_int_equal(hk_statics_solve(sh, body, &so, &res, &err), HK_OK);
    return sh;
}
