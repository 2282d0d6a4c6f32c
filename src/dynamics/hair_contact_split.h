/* The pairs of the contacts' solve dealt to two groups that share no strand and the
 * pairs between them (hair_contact_solve.c sweeps the two groups side by side, then
 * the pairs between them; docs/dynamics.md, "Contacts solved together"). */
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
} hk_ContactSplit;

void hk_contact_split_free(hk_ContactSplit *sp);

/* Splits the strands in two by a plane across one of the world axes through their
 * roots, the axis and the plane that make the larger group's pairs plus the pairs
 * across the fewest (each pair counted with its weight): writes order (pair_count)
 * with the first group's pairs, the second's, then those across, each in pair order,
 * and bounds[0..3] their starts and end (bounds[0] = 0, bounds[3] = pair_count).
 * The same input gives the same split. Returns 0 when out of memory (then every pair
 * is in the third group, in pair order). */
int hk_contact_split(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int pair_count,
                     const hk_HcPair *pairs, const double *weight, int *order, int bounds[4]);

#endif
