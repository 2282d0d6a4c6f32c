/* Two groups of guides that share no contact pair, for sweeping the contacts of each
 * group side by side (hair_contact_split.h). The guides of a head touch their
 * neighbours: a plane through the head leaves most pairs on one side or the other, and
 * the pairs across it are swept after both groups: those on either side of a second
 * plane, then those across it too, each in two halves that share no strand. Nested dissection (George 1973), the
 * cuts chosen along the world axes by the pairs' weights. */
#include <stdlib.h>
#include <string.h>

#include "hairkit/core.h"
#include "hair_contact_split.h"

void hk_contact_split_free(hk_ContactSplit *sp)
{
    hk_free(sp->rank), hk_free(sp->sorted), hk_free(sp->below), hk_free(sp->above), hk_free(sp->side),
        hk_free(sp->cross_side);
    memset(sp, 0, sizeof *sp);
}

static int reserve(hk_ContactSplit *sp, int strand_count)
{
    if (strand_count <= sp->strand_cap) return 1;
    hk_contact_split_free(sp);
    const size_t g = (size_t)strand_count;
    sp->rank = hk_alloc_array(3 * g, sizeof(int), NULL);
    sp->sorted = hk_alloc_array(3 * g, sizeof *sp->sorted, NULL);
    sp->below = hk_alloc_array(g + 1, sizeof(double), NULL);
    sp->above = hk_alloc_array(g + 1, sizeof(double), NULL);
    sp->side = hk_alloc_array(g, sizeof(int), NULL);
    sp->cross_side = hk_alloc_array(g, sizeof(int), NULL);
    if (!sp->rank || !sp->sorted || !sp->below || !sp->above || !sp->side || !sp->cross_side) {
        hk_contact_split_free(sp);
        return 0;
    }
    sp->strand_cap = strand_count;
    return 1;
}

/* sp->rank of the strands along each axis: by the root's coordinate, then by index (a
 * total order, so that any sort gives it), once a split. The roots turn with the
 * head, a degree or two a step: the last split's order, its coordinates renewed, is
 * nearly sorted and an insertion sort finishes it in a pass or two (with 8 qsorts a
 * split took 0.51 million instructions a step, so 0.35; examples/guides200 shaking). */
static void rank_axes(hk_ContactSplit *sp, int g, const hk_Vec3 *roots)
{
    const int kept = sp->sorted_count == g;
    for (int axis = 0; axis < 3; axis++) {
        hk_SplitKey *sorted = sp->sorted + (size_t)axis * (size_t)g;
        if (!kept)
            for (int s = 0; s < g; s++) sorted[s] = (hk_SplitKey){hk_v3_get(roots[s], axis), s};
        else
            for (int r = 0; r < g; r++) sorted[r].at = hk_v3_get(roots[sorted[r].index], axis);
        hk_hc_sort_keys(sorted, g);
        int *rank = sp->rank + (size_t)axis * (size_t)g;
        for (int r = 0; r < g; r++) rank[sorted[r].index] = r;
    }
    sp->sorted_count = g;
}

/* The axis and the plane across it (the strands ranked t and beyond along it on the
 * far side) that make the heavier side's pairs plus the pairs across the plane weigh
 * least, over the pairs list[0, count) (every pair when list is NULL). Returns 0 when
 * there is no plane (one strand). */
static int best_plane(hk_ContactSplit *sp, int g, const hk_HcPair *pairs, const double *weight, const int *list,
                      int count, int *axis_out, int *t_out)
{
    double best_cost = HUGE_VAL;
    *axis_out = -1, *t_out = 0;
    for (int axis = 0; axis < 3; axis++) {
        const int *rank = sp->rank + (size_t)axis * (size_t)g;
        /* below[t]: the pairs with both strands ranked below t (the first group when
         * the plane passes before rank t), above[t]: both at t or beyond. */
        memset(sp->below, 0, (size_t)(g + 1) * sizeof(double));
        memset(sp->above, 0, (size_t)(g + 1) * sizeof(double));
        double total = 0.0;
        for (int x = 0; x < count; x++) {
            const int k = list ? list[x] : x;
            const int a = rank[pairs[k].i], b = rank[pairs[k].j];
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
            if (cost < best_cost) best_cost = cost, *axis_out = axis, *t_out = t;
        }
    }
    return *axis_out >= 0;
}

/* side[s] of every strand for the plane (axis, t): 0 below it, 1 beyond. */
static void sides_of(const hk_ContactSplit *sp, int g, int axis, int t, int *side)
{
    const int *rank = sp->rank + (size_t)axis * (size_t)g;
    for (int s = 0; s < g; s++) side[s] = rank[s] >= t;
}

int hk_contact_split(hk_ContactSplit *sp, int strand_count, const hk_Vec3 *roots, int pair_count,
                     const hk_HcPair *pairs, const double *weight, int *order, int bounds[HK_SPLIT_GROUPS + 1])
{
    const int g = strand_count;
    for (int x = 0; x < HK_SPLIT_GROUPS; x++) bounds[x] = 0;
    bounds[HK_SPLIT_GROUPS] = pair_count;
    int axis, t;
    if (reserve(sp, g)) rank_axes(sp, g, roots);
    if (sp->strand_cap < g || !best_plane(sp, g, pairs, weight, NULL, pair_count, &axis, &t)) {
        for (int k = 0; k < pair_count; k++) order[k] = k; /* all in the last group */
        return sp->strand_cap >= g;
    }
    sides_of(sp, g, axis, t, sp->side);
    /* The pairs across the first plane, in pair order, for the second plane. */
    int cross = 0;
    for (int k = 0; k < pair_count; k++)
        if (sp->side[pairs[k].i] != sp->side[pairs[k].j]) order[cross++] = k;
    if (best_plane(sp, g, pairs, weight, order, cross, &axis, &t))
        sides_of(sp, g, axis, t, sp->cross_side);
    else
        memset(sp->cross_side, 0, (size_t)g * sizeof(int));
    int fill = 0;
    for (int group = 0; group < HK_SPLIT_GROUPS; group++) {
        bounds[group] = fill;
        for (int k = 0; k < pair_count; k++) {
            const int i = pairs[k].i, j = pairs[k].j;
            /* Across both planes: between the quarters (0, 0) and (1, 1), or (0, 1) and
             * (1, 0), which share no strand. */
            const int in = sp->side[i] == sp->side[j]               ? sp->side[i]
                           : sp->cross_side[i] == sp->cross_side[j] ? 2 + sp->cross_side[i]
                                                                    : 4 + (sp->side[i] != sp->cross_side[i]);
            if (in == group) order[fill++] = k;
        }
    }
    return 1;
}
