/* The pairs of the contacts' solve dealt to three stages of two groups that share no
 * strand (hair_contact_solve.c sweeps each stage's two groups side by side;
 * docs/dynamics.md, "Contacts solved together"). */
#ifndef HK_HAIR_CONTACT_SPLIT_H
#define HK_HAIR_CONTACT_SPLIT_H

#include "hair_contacts_internal.h"

/* A strand along an axis: at its root's coordinate, index the strand. */
typedef hk_HcKey hk_SplitKey;

/* Scratch of hk_contact_split, kept between steps. */
typedef struct hk_ContactSplit {
    int strand_cap;
    int *rank;           /* 3 x strand_count: the strands' places along each axis */
    hk_SplitKey *sorted; /* 3 x strand_count: the strands along each axis */
    int sorted_count;    /* the strands in sorted at the last split (0: none) */
    double *below;       /* strand_count + 1: weight of the pairs whose strands both rank below t */
    double *above;       /* strand_count + 1: ... both at t or above */
    int *side;           /* strand_count: 0 or 1 for the split chosen */
    int *cross_side;     /* strand_count: 0 or 1 for the second plane, of the pairs across the first */
} hk_ContactSplit;

void hk_contact_split_free(hk_ContactSplit *sp);

#define HK_SPLIT_GROUPS 6

/* Splits the strands in two by a plane across one of the world axes through their
 * roots, the axis and the plane that make the larger group's pairs plus the pairs
 * across the fewest (each pair counted with its weight), then the pairs across it by a
 * second such plane, chosen for them alone. Writes order (pair_count) with six groups
 * of pairs, each in pair order: those of the first side, of the second side; those
 * across the first plane with both strands below the second, beyond it; those across
 * both planes between the quarters (below, below) and (beyond, beyond), and between
 * (below, beyond) and (beyond, below). bounds[0..6] are their starts and end
 * (bounds[0] = 0, bounds[6] = pair_count). Groups 0 and 1 share no strand, nor do 2
 * and 3, nor 4 and 5. The same input gives the same split. Returns 0 when out of
 * memory (then every pair is in the last group, in pair order). */
int hk_contact_split(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int pair_count,
                     const hk_HcPair *pairs, const double *weight, int *order, int bounds[HK_SPLIT_GROUPS + 1]);

#endif
