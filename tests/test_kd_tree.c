/* The k-d tree's nearest neighbours (src/core/kd_tree.c) against the scan it replaced in the
 * reconstruction (helicoid/reconstruct_blend.c until 6 December 2026, kept verbatim as
 * hk_nearest_by_scan): the same indices and the same distances, bit for bit,
 *  - on random points, with k of 1, 3, 16, the count and more than the count;
 *  - on points of a small integer lattice, with duplicates, queried at lattice points and
 *    half-way between them, where many distances tie exactly;
 *  - on points all at one place, on a plane (a scalp seen closely: one axis flat), and on
 *    one point;
 *  - for a query that is not finite (the brute force keeps the first points);
 * and a point that is not finite is refused, naming it. */
#include "hk_test.h"

#include <math.h>
#include <string.h>

#include "core/kd_tree.h"
#include "hairkit/rng.h"

enum { MAX_K = 64 };

/* Every query of `queries` with every k against the brute force; returns the number of
 * queries whose k nearest held an exact tie (so that the tests can say they saw some). */
static int check_same(const hk_Vec3 *points, int count, const hk_Vec3 *queries, int query_count)
{
    hk_KdTree tree;
    assert_int_equal(hk_kd_tree_build(&tree, points, count, NULL), HK_OK);
    const int ks[5] = {1, 3, 16, count, count + 5};
    int ties = 0;
    for (int q = 0; q < query_count; q++)
        for (int c = 0; c < 5; c++) {
            const int k = ks[c] < MAX_K ? ks[c] : MAX_K;
            int ia[MAX_K], ib[MAX_K];
            double da[MAX_K], db[MAX_K];
            const int ma = hk_nearest_by_scan(points, count, queries[q], k, ia, da);
            const int mb = hk_kd_tree_nearest(&tree, queries[q], k, ib, db);
            assert_int_equal(ma, mb);
            for (int i = 0; i < ma; i++) {
                if (ia[i] != ib[i] || memcmp(&da[i], &db[i], sizeof da[i]) != 0)
                    fail_msg("query %d, k %d, neighbour %d: brute force %d at %.17g, tree %d at %.17g", q, k, i, ia[i],
                             da[i], ib[i], db[i]);
                if (c == 2 && i > 0 && da[i] == da[i - 1]) ties++;
            }
        }
    hk_kd_tree_free(&tree);
    return ties;
}

static double uniform(uint64_t stream, uint64_t i, double lo, double hi)
{
    return lo + (hi - lo) * hk_rng_uniform(17, stream, i);
}

static void test_random_points(void **state)
{
    (void)state;
    enum { N = 3000, Q = 400 };
    static hk_Vec3 p[N], q[Q];
    for (int i = 0; i < N; i++)
        p[i] = hk_v3(uniform(1, (uint64_t)i, -0.1, 0.1), uniform(2, (uint64_t)i, 0.0, 0.2),
                     uniform(3, (uint64_t)i, -0.1, 0.1));
    for (int i = 0; i < 50; i++) p[N - 1 - i] = p[7 * i]; /* duplicates, at higher indices */
    for (int i = 0; i < Q; i++)
        q[i] = i % 4 == 0 ? p[(37 * i) % N]
                          : hk_v3(uniform(4, (uint64_t)i, -0.12, 0.12), uniform(5, (uint64_t)i, -0.02, 0.22),
                                  uniform(6, (uint64_t)i, -0.12, 0.12));
    assert_true(check_same(p, N, q, Q) > 0); /* the duplicates queried at themselves tie */
    /* fewer points than a leaf, and than k */
    check_same(p, 5, q, 20);
    check_same(p, 1, q, 20);
}

/* Integer lattice points, 0.5 m apart, many of them repeated: distances tie exactly. */
static void test_lattice_ties_and_duplicates(void **state)
{
    (void)state;
    enum { N = 2000, Q = 300 };
    static hk_Vec3 p[N], q[Q];
    for (int i = 0; i < N; i++) {
        const uint64_t u = (uint64_t)i;
        p[i] = hk_v3(0.5 * floor(uniform(7, u, 0, 12)), 0.5 * floor(uniform(8, u, 0, 12)),
                     0.5 * floor(uniform(9, u, 0, 4)));
    }
    for (int i = 0; i < Q; i++) {
        const uint64_t u = (uint64_t)i;
        const double half = i % 2 ? 0.25 : 0.0; /* half-way: equidistant from 2, 4 or 8 points */
        q[i] = hk_v3(0.5 * floor(uniform(10, u, -1, 13)) + half, 0.5 * floor(uniform(11, u, -1, 13)) + half,
                     0.5 * floor(uniform(12, u, -1, 5)) + half);
    }
    const int ties = check_same(p, N, q, Q);
    print_message("lattice: %d exact ties among the 16 nearest of %d queries\n", ties, Q);
    assert_true(ties > Q); /* the test is about ties: it must see many */
}

static void test_degenerate_sets(void **state)
{
    (void)state;
    enum { N = 500, Q = 60 };
    static hk_Vec3 same[N], plane[N], q[Q];
    for (int i = 0; i < N; i++) {
        same[i] = hk_v3(0.01, -0.02, 0.03);
        plane[i] = hk_v3(uniform(13, (uint64_t)i, -0.05, 0.05), 0.1, uniform(14, (uint64_t)i, -0.05, 0.05));
    }
    for (int i = 0; i < Q; i++)
        q[i] = i % 3 == 0 ? same[0]
                          : hk_v3(uniform(15, (uint64_t)i, -0.06, 0.06), uniform(16, (uint64_t)i, 0.05, 0.15),
                                  uniform(17, (uint64_t)i, -0.06, 0.06));
    assert_true(check_same(same, N, q, Q) > 0);
    check_same(plane, N, q, Q);
}

static void test_query_not_finite(void **state)
{
    (void)state;
    enum { N = 100 };
    hk_Vec3 p[N];
    for (int i = 0; i < N; i++) p[i] = hk_v3(uniform(18, (uint64_t)i, -1, 1), 0.0, uniform(19, (uint64_t)i, -1, 1));
    const hk_Vec3 q[3] = {hk_v3(NAN, 0, 0), hk_v3(INFINITY, 0, 0), hk_v3(0, -INFINITY, INFINITY)};
    hk_KdTree tree;
    assert_int_equal(hk_kd_tree_build(&tree, p, N, NULL), HK_OK);
    for (int i = 0; i < 3; i++) {
        int ia[16], ib[16];
        double da[16], db[16];
        assert_int_equal(hk_nearest_by_scan(p, N, q[i], 16, ia, da), 16);
        assert_int_equal(hk_kd_tree_nearest(&tree, q[i], 16, ib, db), 16);
        for (int j = 0; j < 16; j++) {
            assert_int_equal(ia[j], ib[j]);
            assert_int_equal(isnan(da[j]), isnan(db[j]));
            if (!isnan(da[j])) assert_true(da[j] == db[j]);
        }
    }
    hk_kd_tree_free(&tree);
}

static void test_point_not_finite_is_refused(void **state)
{
    (void)state;
    hk_Vec3 p[4] = {hk_v3(0, 0, 0), hk_v3(1, 0, 0), hk_v3(0, NAN, 0), hk_v3(0, 0, 1)};
    hk_KdTree tree;
    hk_Error err;
    assert_int_equal(hk_kd_tree_build(&tree, p, 4, &err), HK_ERR_INVALID);
    assert_non_null(strstr(err.message, "point 2"));
    assert_null(tree.points);
    assert_int_equal(hk_kd_tree_build(&tree, p, 0, &err), HK_ERR_INVALID);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_points),
        cmocka_unit_test(test_lattice_ties_and_duplicates),
        cmocka_unit_test(test_degenerate_sets),
        cmocka_unit_test(test_query_not_finite),
        cmocka_unit_test(test_point_not_finite_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
