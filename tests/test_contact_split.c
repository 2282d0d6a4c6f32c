/* The split of the contacts' pairs into the sweeps' six groups
 * (src/dynamics/hair_contact_split.c), checked against a brute force over every plane:
 *  - every pair is in one group, each group in pair order, and the groups swept side by
 *    side (0 and 1, 2 and 3, 4 and 5) share no strand;
 *  - the first plane makes the heavier side plus the pairs across it weigh least;
 *  - the second plane, over the pairs across the first, makes the heavier of groups 2
 *    and 3 plus the pairs across it (groups 4 and 5) weigh least. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dynamics/hair_contact_split.h"

#define STRANDS 60
#define PAIRS   400

/* A small deterministic generator (the test's own, the same on every platform). */
static double uniform(unsigned long long *state)
{
    *state = *state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*state >> 11) / 9007199254740992.0;
}

typedef struct Problem {
    hk_Vec3 roots[STRANDS];
    hk_HcPair pairs[PAIRS];
    double weight[PAIRS];
    int count;
} Problem;

/* Roots on a sphere's cap, pairs between near strands (sorted by (i, j) as the
 * contacts list them), weights of the three kinds the solve gives (and between). */
static void make_problem(Problem *p, unsigned long long seed)
{
    unsigned long long st = seed;
    for (int s = 0; s < STRANDS; s++) {
        const double phi = 2.0 * HK_PI * uniform(&st), z = 0.2 + 0.8 * uniform(&st), r = sqrt(1.0 - z * z);
        p->roots[s] = hk_v3(r * cos(phi), r * sin(phi), z);
    }
    p->count = 0;
    for (int i = 0; i < STRANDS && p->count < PAIRS; i++)
        for (int j = i + 1; j < STRANDS && p->count < PAIRS; j++) {
            if (hk_v3_norm(hk_v3_sub(p->roots[i], p->roots[j])) > 0.45 || uniform(&st) < 0.3) continue;
            p->pairs[p->count] = (hk_HcPair){i, 0, j, 0, 0.0, 0.0, 0.0};
            const double kind = uniform(&st);
            p->weight[p->count++] = kind < 0.3 ? 14400.0 + 280.0 * 30 * uniform(&st) : 700.0 + 32.0 * 30 * uniform(&st);
        }
}

/* The strands' ranks along an axis: by the root's coordinate, then by index. */
static void ranks(const Problem *p, int axis, int *rank)
{
    for (int s = 0; s < STRANDS; s++) {
        rank[s] = 0;
        const double a = hk_v3_get(p->roots[s], axis);
        for (int o = 0; o < STRANDS; o++) {
            const double b = hk_v3_get(p->roots[o], axis);
            rank[s] += b < a || (b == a && o < s);
        }
    }
}

static int group_of(const int *order, const int bounds[HK_SPLIT_GROUPS + 1], int k)
{
    for (int g = 0; g < HK_SPLIT_GROUPS; g++)
        for (int x = bounds[g]; x < bounds[g + 1]; x++)
            if (order[x] == k) return g;
    return -1;
}

static void check_split(unsigned long long seed)
{
    Problem p;
    make_problem(&p, seed);
    const int n = p.count;
    hk_ContactSplit sp;
    memset(&sp, 0, sizeof sp);
    int order[PAIRS], bounds[HK_SPLIT_GROUPS + 1];
    assert_int_equal(hk_contact_split(&sp, STRANDS, p.roots, n, p.pairs, p.weight, order, bounds), 1);
    /* A partition in pair order; the groups side by side share no strand. */
    assert_int_equal(bounds[0], 0);
    assert_int_equal(bounds[HK_SPLIT_GROUPS], n);
    int group[PAIRS];
    double w[HK_SPLIT_GROUPS] = {0};
    for (int k = 0; k < n; k++) {
        group[k] = group_of(order, bounds, k);
        assert_true(group[k] >= 0);
        w[group[k]] += p.weight[k];
    }
    for (int g = 0; g < HK_SPLIT_GROUPS; g++)
        for (int x = bounds[g] + 1; x < bounds[g + 1]; x++) assert_true(order[x - 1] < order[x]);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b++) {
            if (group[a] / 2 != group[b] / 2 || group[a] == group[b]) continue;
            assert_int_not_equal(p.pairs[a].i, p.pairs[b].i), assert_int_not_equal(p.pairs[a].i, p.pairs[b].j);
            assert_int_not_equal(p.pairs[a].j, p.pairs[b].i), assert_int_not_equal(p.pairs[a].j, p.pairs[b].j);
        }
    /* The first plane by brute force: its least cost, and its sides. */
    int rank[3][STRANDS], side[STRANDS];
    double best = HUGE_VAL;
    for (int axis = 0; axis < 3; axis++) {
        ranks(&p, axis, rank[axis]);
        for (int t = 1; t < STRANDS; t++) {
            double below = 0.0, above = 0.0, across = 0.0;
            for (int k = 0; k < n; k++) {
                const int a = rank[axis][p.pairs[k].i] >= t, b = rank[axis][p.pairs[k].j] >= t;
                *(a != b ? &across : a ? &above : &below) += p.weight[k];
            }
            const double cost = fmax(below, above) + across;
            if (cost < best) {
                best = cost;
                for (int s = 0; s < STRANDS; s++) side[s] = rank[axis][s] >= t;
            }
        }
    }
    const double total = w[0] + w[1] + w[2] + w[3] + w[4] + w[5];
    hk_assert_near(fmax(w[0], w[1]) + w[2] + w[3] + w[4] + w[5], best, 1e-12 * total);
    /* The second plane over the pairs across the first: the heavier of groups 2 and 3
     * plus the pairs across both planes. */
    double best2 = HUGE_VAL;
    for (int axis = 0; axis < 3; axis++)
        for (int t = 1; t < STRANDS; t++) {
            double q[4] = {0};
            for (int k = 0; k < n; k++) {
                const int i = p.pairs[k].i, j = p.pairs[k].j;
                if (side[i] == side[j]) continue;
                const int ci = rank[axis][i] >= t, cj = rank[axis][j] >= t;
                q[ci == cj ? ci : 2 + (side[i] != ci)] += p.weight[k];
            }
            best2 = fmin(best2, fmax(q[0], q[1]) + q[2] + q[3]);
        }
    hk_assert_near(fmax(w[2], w[3]) + w[4] + w[5], best2, 1e-12 * total);
    print_message("seed %llu: %d pairs, groups %.0f %.0f | %.0f %.0f | %.0f %.0f\n", seed, n, w[0], w[1], w[2], w[3],
                  w[4], w[5]);
    hk_contact_split_free(&sp);
}

static void test_split_groups_and_planes(void **state)
{
    (void)state;
    for (unsigned long long seed = 1; seed <= 8; seed++) check_split(seed);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_split_groups_and_planes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
