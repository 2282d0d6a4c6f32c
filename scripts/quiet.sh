#!/usr/bin/env bash
# scripts/quiet.sh [-C DIR] LABEL LOG COMMAND...: runs COMMAND (in DIR) with its whole
# output in LOG and shows only its progress in a few lines: the build's percentage
# (cmake's "[ 45%]" lines) or the tests done (ctest's "12/68 Test" lines) at each
# quarter, then one line saying how long it took and where the log is. When COMMAND
# fails, its output is shown (without the lines of progress and of passed tests:
# what is left are the compiler's messages, the failed tests' output and ctest's
# summary) and the exit code is COMMAND's, so that CI logs show the failure.
# Used by `make build`, `make demo` and `make test` (issue 18, item 5).
set -uo pipefail
dir=.
if [ "${1:-}" = "-C" ]; then
    dir=$2
    shift 2
fi
label=$1 log=$2
shift 2
mkdir -p "$(dirname "$log")"
log="$(cd "$(dirname "$log")" && pwd)/$(basename "$log")"
start=$SECONDS
(cd "$dir" && "$@") 2>&1 | tee "$log" | awk -v label="$label" '
    # a quarter is shown once, when first reached
    function show(fraction, text,    q) {
        q = int(4 * fraction + 1e-9)
        if (q > shown) { printf "%s: %s\n", label, text; fflush(); shown = q }
    }
    /^\[ *[0-9]+%\]/ { p = $0; sub(/^\[ */, "", p); sub(/%.*/, "", p); show(p / 100, p "%") }
    /^ *[0-9]+\/[0-9]+ Test +#/ { split($1, n, "/"); if (n[2] > 0) show(n[1] / n[2], n[1] " of " n[2] " tests done") }
'
rc=$?
if [ "$rc" -ne 0 ]; then
    echo "$label: FAILED (exit $rc); the output without its progress lines:"
    grep -vE '^\[ *[0-9]+%\] |^ *Start +[0-9]+: |Test +#[0-9]+: .* Passed +[0-9.]+ sec$' "$log"
    echo "$label: FAILED (exit $rc); the whole output is in $log"
    exit "$rc"
fi
echo "$label: done in $((SECONDS - start)) s (the whole output is in $log)"
