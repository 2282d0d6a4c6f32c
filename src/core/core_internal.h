/* Internal to hairkit (not installed, not exported from the shared library): the first
 * error of a parallel loop and the monotonic clock. The library, the hairkit program, the
 * benchmarks, the tools and the tests include it as "core/core_internal.h". */
#ifndef HK_CORE_INTERNAL_H
#define HK_CORE_INTERNAL_H

#include <sched.h>
#include <stddef.h>

#include "hairkit/core.h"

/* The error of the lowest failing index of a parallel loop, so that the error reported
 * is the same whatever the thread count and the schedule (DESIGN.md: results do not
 * depend on the threads). Iterations run in any order; each failure is recorded with
 * its index and the lowest one is kept:
 *
 *     hk_FirstError fe;
 *     hk_first_error_init(&fe);
 *     #pragma omp parallel for schedule(dynamic)
 *     for (long i = 0; i < n; i++) {
 *         if (hk_first_error_skip(&fe, i)) continue; // optional: cannot change the outcome
 *         hk_Error e;
 *         if (work(i, &e) != HK_OK) hk_first_error_record(&fe, i, &e);
 *     }
 *     if (fe.index >= 0) return hk_error_set(err, fe.error.code, "item %ld: %s", fe.index,
 *                                            fe.error.message);
 *
 * (or `return hk_first_error_status(&fe, err);` to pass the error on as it is). Read
 * the fields after the loop only.*/
typedef struct hk_FirstError {
    long index;     /* lowest failing index recorded, -1 while none */
    hk_Error error; /* the error recorded with it */
} hk_FirstError;

/* No failure yet. */
void hk_first_error_init(hk_FirstError *fe);

/* Records err (not NULL) as the failure of iteration `index` (>= 0) if no lower index
 * has failed. Safe to call from any thread of a parallel region. */
void hk_first_error_record(hk_FirstError *fe, long index, const hk_Error *err);

/* Whether a lower index than `index` has failed already, so that iteration `index` can
 * be skipped without changing which error is kept (an iteration below every recorded
 * failure is never skipped). Safe to call from any thread. */
int hk_first_error_skip(const hk_FirstError *fe, long index);

/* After the loop: HK_OK when nothing failed; else copies the lowest index's error into
 * err (when not NULL) and returns its code. */
hk_Status hk_first_error_status(const hk_FirstError *fe, hk_Error *err);

/* Seconds on a monotonic clock (CLOCK_MONOTONIC) from an arbitrary origin: for timings
 * and progress reports, never for results.*/
double hk_seconds_now(void);
double hk_thread_cpu_seconds(void); /* CPU time of the calling thread (s) */

/* One pause of a spin-wait: a wait of a few hundred cycles, then the core given up now
 * and then: on a machine with more runnable threads than cores the thread waited for
 * needs it. Call it with the same *spins (from 0) for each check of the wait. */
static inline void hk_spin_pause(long *spins)
{
    if (++*spins % 256 == 0) sched_yield();
    for (volatile int k = 0; k < 64; k++) {}
}

/* The box of n points stored as three floats each (x y z x y z ...): lo and hi
 * (+HUGE_VALF and -HUGE_VALF when n is 0), in SSE where there is. Returns 1 when a
 * coordinate is not finite (the box then means nothing; the caller finds the point).
 * Min and max are exact in any order: the same box whatever the path. */
int hk_float_points_bounds(const float *xyz, size_t n, float lo[3], float hi[3]);

#endif /* HK_CORE_INTERNAL_H */
