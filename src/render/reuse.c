/* Buffers kept from one picture to the next (hk_Renderer): allocating and faulting in
 * several hundred MB a picture cost the frames of an animation about 7 % of their
 * time in the kernel. */
#include "render_internal.h"

int hk_reserve(void **buffer, size_t *cap, size_t count, size_t size, hk_Error *err)
{
    if (count == 0) count = 1;
    if (*buffer && count <= *cap) return 1;
    /* The contents are not kept: free first, so that old and new are never both held. */
    hk_free(*buffer);
    *cap = 0;
    /* A little room to spare: the next frame's hair is rarely exactly as long. */
    const size_t want = count + count / 16;
    *buffer = hk_alloc_array(want >= count ? want : count, size, err);
    if (!*buffer) return 0;
    *cap = want >= count ? want : count;
    return 1;
}
