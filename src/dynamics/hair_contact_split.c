/* Two groups of guides that share no contact pair, for sweeping the contacts of each
 * group side by side (hair_contact_split.h). The guides of a head touch their
 * neighbours: a plane through the head leaves most pairs on one side or the other, and
 * the pairs across it are swept after both groups. Nested dissection (George 1973)
 * cut once, the cut chosen along the world axes by the pairs' weights. */
#include <stdlib.h>
#include <string.h>

#include "hairkit/core.h"
#include "hair_contact_split.h"

void hk_contact_split_free(hk_ContactSplit *sp)
{
    hk_free(sp->rank), hk_free(sp->sorted), hk_free(sp->below), hk_free(sp->above), hk_free(sp->side);
    memset(sp, 0, sizeof *sp);
}

static int reserve(hk_ContactSplit *sp, int strand_count)
{
    if (strand_count <= sp->strand_cap) return 1;
    hk_contact_split_free(sp);
    const size_t g = (size_t)strand_count;
    sp->rank = hk_alloc_array(g, sizeof(int), NULL);
    sp->sorted = hk_alloc_array(g, sizeof *sp->sorted, NULL);
    sp->below = hk_alloc_array(g + 1, sizeof(double), NULL);
    sp->above = hk_alloc_array(g + 1, sizeof(double), NULL);
    sp->side = hk_alloc_array(g, sizeof(int), NULL);
    if (!sp->rank || !sp->sorted || !sp->below || !sp->above || !sp->side) {
        hk_contact_split_free(sp);
        return 0;
    }
    sp->strand_cap = strand_count;
    return 1;
}

static int key_cmp(const void *x, const void *y)
{
    const hk_SplitKey *a = x, *b = y;
    if (a->at != b->at) return a->at < b->at ? -1 : 1;
    return (a->strand > b->strand) - (a->strand < b->strand);
}

/* sp->rank of the strands along an axis: by the root's coordinate, then by index (a
 * total order, so that any sort gives it). */
static void rank_along(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int axis)
{
    for (int s = 0; s < strand_count; s++) sp->sorted[s] = (hk_SplitKey){hk_v3_get(roots[s], axis), s};
    qsort(sp->sorted, (size_t)strand_count, sizeof *sp->sorted, key_cmp);
    for (int r = 0; r < strand_count; r++) sp->rank[sp->sorted[r].strand] = r;
}

int hk_contact_split(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int pair_count,
                     const hk_HcPair *pairs, const double *weight, int *order, int bounds[4])
{
    const int g = strand_count;
    bounds[0] = bounds[1] = bounds[2] = 0, bounds[3] = pair_count;
    if (!reserve(sp, g)) {
        for (int k = 0; k < pair_count; k++) order[k] = k;
        return 0;
    }
    double best_cost = HUGE_VAL;
    int best_axis = -1, best_t = 0;
    for (int axis = 0; axis < 3; axis++) {
        rank_along(sp, g, roots, axis);
        /* below[t]: the pairs with both strands ranked below t (the first group when
         * the plane passes before rank t), above[t]: both at t or beyond. */
        memset(sp->below, 0, (size_t)(g + 1) * sizeof(double));
        memset(sp->above, 0, (size_t)(g + 1) * sizeof(double));
        double total = 0.0;
        for (int k = 0; k < pair_count; k++) {
            const int a = sp->rank[pairs[k].i], b = sp->rank[pairs[k].j];
            const int lo = a < b ? a : b, hi = a < b ? b : a;
            sp->below[hi + 1] += weight[k]; /* counted from t = hi + 1 on */
            sp->above[lo] += weight[k];     /* counted up to t = lo */
            total += weight[k];
        }
        for (int t = 1; t <= g; t++) sp->below[t] += sp->below[t - 1];
        for (int t = g - 1; t >= 0; t--) sp->above[t] += sp->above[t + 1];
        for (int t = 1; t < g; t++) {
            const double across = total - sp->below[t] - sp->above[t];
            const double cost = (sp->below[t] > sp->above[t] ? sp->below[t] : sp->above[t]) + across;
            if (cost < best_cost) best_cost = cost, best_axis = axis, best_t = t;
        }
    }
    if (best_axis < 0) { /* one strand: no split */
        for (int k = 0; k < pair_count; k++) order[k] = k;
        return 1;
    }
    rank_along(sp, g, roots, best_axis);
    for (int s = 0; s < g; s++) sp->side[s] = sp->rank[s] >= best_t;
    int fill = 0;
    for (int group = 0; group < 3; group++) {
        bounds[group] = fill;
        for (int k = 0; k < pair_count; k++) {
            const int a = sp->side[pairs[k].i], b = sp->side[pairs[k].j];
            const int in = a != b ? 2 : a;
            if (in == group) order[fill++] = k;
        }
    }
    bounds[3] = fill;
    return 1;
}
