/* hk_FirstError, the error of the lowest failing index of a parallel loop (core.h):
 *  - nothing recorded: HK_OK, err untouched, nothing skipped;
 *  - recorded in any order, sequentially, the lowest index and its own error win;
 *  - only iterations above a recorded failure are skipped;
 *  - in a parallel loop over many failing indices, visited in increasing, decreasing
 *    and scattered order with 1 to 8 threads and dynamic schedules, with and without
 *    the skip, the error kept is always the lowest failing index's: the reference is
 *    the sequential loop's first failure. */
#include "hk_test.h"

#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "core/core_internal.h"
#include "hairkit/core.h"

static hk_Error error_of(long index)
{
    hk_Error e;
    hk_error_set(&e, index % 2 ? HK_ERR_NUMERIC : HK_ERR_INVALID, "item %ld failed", index);
    return e;
}

static void test_nothing_failed(void **state)
{
    (void)state;
    hk_FirstError fe;
    hk_first_error_init(&fe);
    assert_int_equal(fe.index, -1);
    hk_Error err;
    hk_error_set(&err, HK_ERR_IO, "untouched");
    assert_int_equal(hk_first_error_status(&fe, &err), HK_OK);
    assert_int_equal(err.code, HK_ERR_IO);
    assert_string_equal(err.message, "untouched");
    assert_int_equal(hk_first_error_status(&fe, NULL), HK_OK);
    for (long i = 0; i < 100; i++) assert_false(hk_first_error_skip(&fe, i));
}

/* Every order of four failures, recorded one by one: the lowest wins with its error. */
static void test_lowest_index_wins_in_any_order(void **state)
{
    (void)state;
    const long failing[4] = {7, 3, 12, 5};
    const int perms = 24;
    for (int p = 0; p < perms; p++) {
        long order[4], pool[4];
        memcpy(pool, failing, sizeof pool);
        int left = 4, code = p;
        for (int k = 0; k < 4; k++) { /* the p-th permutation (factorial number system) */
            const int pick = code % left;
            code /= left;
            order[k] = pool[pick];
            pool[pick] = pool[--left];
        }
        hk_FirstError fe;
        hk_first_error_init(&fe);
        for (int k = 0; k < 4; k++) {
            const hk_Error e = error_of(order[k]);
            hk_first_error_record(&fe, order[k], &e);
        }
        assert_int_equal(fe.index, 3);
        hk_Error err;
        assert_int_equal(hk_first_error_status(&fe, &err), HK_ERR_NUMERIC);
        assert_string_equal(err.message, "item 3 failed");
        assert_string_equal(fe.error.message, "item 3 failed");
    }
}

static void test_skips_only_above_the_lowest_failure(void **state)
{
    (void)state;
    hk_FirstError fe;
    hk_first_error_init(&fe);
    hk_Error e = error_of(40);
    hk_first_error_record(&fe, 40, &e);
    assert_false(hk_first_error_skip(&fe, 0));
    assert_false(hk_first_error_skip(&fe, 39));
    assert_false(hk_first_error_skip(&fe, 40));
    assert_true(hk_first_error_skip(&fe, 41));
    e = error_of(10);
    hk_first_error_record(&fe, 10, &e);
    assert_false(hk_first_error_skip(&fe, 9));
    assert_true(hk_first_error_skip(&fe, 11));
    /* a higher failure recorded later changes nothing */
    e = error_of(20);
    hk_first_error_record(&fe, 20, &e);
    assert_int_equal(fe.index, 10);
    assert_string_equal(fe.error.message, "item 10 failed");
}

/* Whether item i fails: a sparse, irregular set (about 1 in 37 items). */
static int fails(long i, long n) { return (i * 7919 + 13) % 37 == 0 && i > n / 5; }

/* The item visited at position k of n: increasing, decreasing, or scattered by a
 * permutation (k * 7 mod n with n prime to 7). */
static long visit(int order, long k, long n)
{
    if (order == 0) return k;
    if (order == 1) return n - 1 - k;
    return (k * 7) % n;
}

static hk_FirstError parallel_loop(long n, int threads, int order, int chunk, int use_skip)
{
    hk_FirstError fe;
    hk_first_error_init(&fe);
#pragma omp parallel for num_threads(threads) schedule(dynamic, chunk)
    for (long k = 0; k < n; k++) {
        const long i = visit(order, k, n);
        if (use_skip && hk_first_error_skip(&fe, i)) continue;
        volatile double work = 0.0; /* uneven work, so threads interleave differently */
        for (long j = 0; j < (i * 31) % 200; j++) work += (double)j;
        (void)work;
        if (fails(i, n)) {
            const hk_Error e = error_of(i);
            hk_first_error_record(&fe, i, &e);
        }
    }
    return fe;
}

static void test_parallel_loop_is_deterministic(void **state)
{
    (void)state;
    const long n = 5003; /* prime: k * 7 mod n visits every item */
    long first = -1;
    for (long i = 0; i < n && first < 0; i++)
        if (fails(i, n)) first = i;
    assert_true(first > 0);
    char expected[64];
    snprintf(expected, sizeof expected, "item %ld failed", first);
    const int threads[4] = {1, 2, 4, 8}, chunks[2] = {1, 16};
    for (int t = 0; t < 4; t++)
        for (int order = 0; order < 3; order++)
            for (int c = 0; c < 2; c++)
                for (int skip = 0; skip < 2; skip++)
                    for (int rep = 0; rep < 5; rep++) {
                        const hk_FirstError fe = parallel_loop(n, threads[t], order, chunks[c], skip);
                        hk_Error err;
                        if (fe.index != first)
                            fail_msg("%d threads, order %d, chunk %d, skip %d: index %ld, expected %ld", threads[t],
                                     order, chunks[c], skip, fe.index, first);
                        assert_int_equal(hk_first_error_status(&fe, &err), error_of(first).code);
                        assert_string_equal(err.message, expected);
                    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nothing_failed),
        cmocka_unit_test(test_lowest_index_wins_in_any_order),
        cmocka_unit_test(test_skips_only_above_the_lowest_failure),
        cmocka_unit_test(test_parallel_loop_is_deterministic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
