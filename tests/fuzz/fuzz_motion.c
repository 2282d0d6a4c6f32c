/* libFuzzer: head motion files (src/io/motion_file.c), and the motion evaluated
 * before, inside and after its keyframes. */
#include <math.h>

#include "fuzz_file.h"
#include "hairkit/motion.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = hk_fuzz_write("motion.txt", data, size);
    hk_HeadMotion *m = NULL;
    hk_Error err;
    if (!path || hk_head_motion_load(path, &m, &err) != HK_OK) return 0;
    const double end = hk_head_motion_duration(m);
    hk_RigidState st;
    for (int i = -1; i <= 9; i++) hk_head_motion_eval(m, isfinite(end) ? end * i / 8.0 : i, &st);
    hk_head_motion_destroy(m);
    return 0;
}
