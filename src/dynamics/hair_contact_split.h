/* The pairs of the contacts' solve dealt to two groups that share no strand and the
 * pairs between them, these again in two groups that share no strand and the rest
 * (hair_contact_solve.c sweeps each two groups side by side, then the rest;
 * docs/dynamics.md, "Contacts solved together"). */
#ifndef HK_HAIR_CONTACT_SPLIT_H
#define HK_HAIR_CONTACT_SPLIT_H

#include "hair_contacts_internal.h"

typedef struct hk_SplitKey {
    double at; /* the root's coordinate */
    int strand;
} hk_SplitKey;

/* Scratch of hk_contact_split, kept between steps. */
typedef struct hk_ContactSplit {
    int strand_cap;
    int *rank;           /* strand_count: the strand's place along the axis tried */
    hk_SplitKey *sorted; /* strand_count: the strands along it */
    double *below;       /* strand_count + 1: weight of the pairs whose strands both rank below t */
    double *above;       /* strand_count + 1: ... both at t or above */
    int *side;           /* strand_count: 0 or 1 for the split chosen */
    int *cross_side;     /* strand_count: 0 or 1 for the second plane, of the pairs across the first */
} hk_ContactSplit;

void hk_contact_split_free(hk_ContactSplit *sp);

#define HK_SPLIT_GROUPS 5

/* Splits the strands in two by a plane across one of the world axes through their
 * roots, the axis and the plane that make the larger group's pairs plus the pairs
 * across the fewest (each pair counted with its weight), then the pairs across it by a
 * second such plane, chosen for them alone. Writes order (pair_count) with five groups
 * of pairs, each in pair order: those of the first side, of the second side, those
 * across the first plane with both strands below the second, beyond it, and those
 * across both planes; bounds[0..5] their starts and end (bounds[0] = 0, bounds[5] =
 * pair_count). Groups 0 and 1 share no strand, nor do groups 2 and 3. The same input
 * gives the same split. Returns 0 when out of memory (then every pair is in the last
 * group, in pair order). */
int hk_contact_split(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int pair_count,
                     const hk_HcPair *pairs, const double *weight, int *order, int bounds[HK_SPLIT_GROUPS + 1]);

#endif
