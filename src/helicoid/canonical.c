/* The pi-rotation rule of Piuze et al. 2011 §4.1, as derived in docs/helicoids.md: with
 * D = diag(1, -1, -1) (pi about E_T), the field of k' = (-k_T, k_N, k_B, alpha) at D x has
 * theta' = -theta and phi' = -phi, so Q D E_T(k', D x) = Q E_T(k, x): the strand is unchanged.
 * The frame at a piece's end becomes Q D F(-theta, -phi) = Q F(theta, phi) D, so every later
 * piece's frame turns by the same D and its k_T must change sign too. */
#include "helicoid_internal.h"

void hk_phelicoid_canonical(hk_PHelicoid *h)
{
    if (!h || h->piece_count < 1 || h->piece_count > HK_HELICOID_MAX_PIECES) return;
    if (!(h->k[0].kt < 0.0)) return;
    for (int r = 0; r < 3; r++) {
        h->frame.m[r][1] = -h->frame.m[r][1];
        h->frame.m[r][2] = -h->frame.m[r][2];
    }
    for (int i = 0; i < h->piece_count; i++) h->k[i].kt = -h->k[i].kt;
}
