#!/usr/bin/env bash
# scripts/asan-retry-tracer.sh [CTEST_ARGS...]: run in a sanitized build folder after
# its ctest failed. LeakSanitizer's stop-the-world tracer sometimes crashes at a
# process's exit, after the test has passed ("Tracer caught signal 11 ... LeakSanitizer
# has encountered a fatal error": a fault of the sanitizer runtime, seen with threads,
# google/sanitizers#1353; here once in sim_frames, 6 December 2026, not again in six
# reruns). Each test that failed that way, and only that way, is run once more; any
# other failure, or a second failure, keeps the exit code non-zero.
set -uo pipefail
failed=Testing/Temporary/LastTestsFailed.log
log=Testing/Temporary/LastTest.log
[ -f "$failed" ] && [ -f "$log" ] || { echo "asan: no ctest record of the failures" >&2; exit 1; }
cp "$log" "$log.first"
status=0
while IFS=: read -r _ name; do
    # The test's own output in ctest's log: from its "Test: NAME" line to "<end of output>".
    output=$(awk -v t="Test: $name" '$0 ~ t"$" {on = 1} on {print} on && /<end of output>/ {exit}' "$log.first")
    if grep -q "Tracer caught signal" <<<"$output" &&
        grep -q "LeakSanitizer has encountered a fatal error" <<<"$output" &&
        ! grep -qE "ERROR: (AddressSanitizer|LeakSanitizer): detected|runtime error:|\[  FAILED  \]" <<<"$output"; then
        echo "asan: $name: LeakSanitizer's tracer crashed after the test (not a test failure); running it again" >&2
        ctest --output-on-failure -R "^${name}\$" "$@" || status=1
    else
        echo "asan: $name failed" >&2
        status=1
    fi
done <"$failed"
exit $status
