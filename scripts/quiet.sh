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
# Progress read line by line in bash: awk (mawk) buffers its input from a pipe and
# would show the quarters late.
progress() {
    local shown=0 line q text
    while IFS= read -r line; do
        q=0
        if [[ $line =~ ^\[\ *([0-9]+)%\] ]]; then
            q=$((BASH_REMATCH[1] * 4 / 100))
            text="${BASH_REMATCH[1]}%"
        elif [[ $line =~ ^\ *([0-9]+)/([0-9]+)\ Test\ +# ]] && [ "${BASH_REMATCH[2]}" -gt 0 ]; then
            q=$((BASH_REMATCH[1] * 4 / BASH_REMATCH[2]))
            text="${BASH_REMATCH[1]} of ${BASH_REMATCH[2]} tests done"
        fi
        if [ "$q" -gt "$shown" ]; then
            echo "$label: $text"
            shown=$q
        fi
    done
}
(cd "$dir" && "$@") 2>&1 | tee "$log" | progress
rc=$?
if [ "$rc" -ne 0 ]; then
    echo "$label: FAILED (exit $rc); the output without its progress lines:"
    grep -vE '^\[ *[0-9]+%\] |^ *Start +[0-9]+: |Test +#[0-9]+: .* Passed +[0-9.]+ sec$' "$log"
    echo "$label: FAILED (exit $rc); the whole output is in $log"
    exit "$rc"
fi
echo "$label: done in $((SECONDS - start)) s (the whole output is in $log)"
