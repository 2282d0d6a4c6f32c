#!/usr/bin/env bash
# Helps that teach (issue 18, item 2): `hairkit --help`, every command's `--help` and
# every helicoid action's `--help` exit 0, print one synopsis that lists every option
# of the help (or says "[options]"), print only their own command (or action), and end
# with two or three examples. Then every example is RUN, from a fresh folder holding
# the repository's examples/ and assets/ (as from the repository root), in the order
# the help gives them, so that the helps cannot drift from the program.
#
# Long examples are run smaller, by these rewrites of the example's line only:
#   --frames N       -> --frames 2 (simulate, view)
#   hairkit simulate -> --preroll 0 added (no settling before frame 0)
#   hairkit bench    -> --quick added (a smoke run: figures not meaningful)
#   hairkit view     -> headless: --frames 1 added when the line has no --frames,
#                       --width 160 --height 120 added, run under xvfb-run; skipped
#                       (saying so) without the viewer or xvfb-run
# Usage: help.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

# The commands, as `hairkit --help` lists them.
expect 0 "$hk" --help
commands=$(sed -n '/^commands:/,/^$/p' "$tmp/out" | awk 'NF > 1 {print $1}')
[ "$(echo "$commands" | wc -w)" -ge 10 ] || fail "hairkit --help lists too few commands: $commands"

viewer=1
if "$hk" view /nonexistent.hair 2>&1 | grep -q "built without the viewer"; then
    viewer=0
    echo "help: view examples not run: hairkit was built without the viewer"
elif ! command -v xvfb-run > /dev/null 2>&1; then
    viewer=0
    echo "help: view examples not run: xvfb-run is not installed"
fi

# Under the sanitizers (`make asan` sets ASAN_OPTIONS) a full head takes minutes: the
# helps are checked there, their examples run by `make test` only.
run_examples=1
if [ -n "${ASAN_OPTIONS:-}" ]; then
    run_examples=0
    echo "help: examples not run under the sanitizers (a full head is too slow there); make test runs them"
fi

# run_example DIR LINE: the example as documented above, in DIR.
run_example() {
    local dir=$1 line=$2
    [ "$run_examples" -eq 1 ] || return 0
    line=$(echo "$line" | sed -E 's/--frames [0-9]+/--frames 2/')
    local prefix=""
    case "$line" in
    "hairkit bench"*) line="$line --quick" ;;
    "hairkit simulate --rebuild"*) ;;
    "hairkit simulate"*) line="$line --preroll 0" ;;
    "hairkit view"*)
        [ "$viewer" -eq 1 ] || { echo "help: not run (no viewer): $line"; return; }
        case "$line" in *--frames*) ;; *) line="$line --frames 1" ;; esac
        line="$line --width 160 --height 120"
        prefix='xvfb-run -a -s "-screen 0 640x480x24"'
        ;;
    esac
    line="$prefix \"\$hk\" ${line#hairkit }"
    local t0=$SECONDS
    (cd "$dir" && eval "$line") > "$tmp/ex.out" 2> "$tmp/ex.err" ||
        fail "example failed (exit $?): $2 ; stderr: $(tail -n 5 "$tmp/ex.err")"
    echo "help: $((SECONDS - t0)) s: $2"
}

# check_help NAME ARGS...: the help of `hairkit ARGS`.
check_help() {
    local name=$1; shift
    "$hk" "$@" > "$tmp/help" 2> "$tmp/help.err"
    local rc=$?
    [ "$rc" -eq 0 ] || { fail "$name: exit $rc"; return; }
    [ -s "$tmp/help.err" ] && fail "$name: wrote to stderr: $(head -c 200 "$tmp/help.err")"
    head -n 1 "$tmp/help" | grep -q '^usage: hairkit' || [ "$name" = "hairkit" ] ||
        fail "$name: does not start with 'usage: hairkit'"
    # The synopsis: from the first line to the first blank line.
    sed -n '1,/^$/p' "$tmp/help" > "$tmp/synopsis"
    if ! grep -q '\[options\]' "$tmp/synopsis"; then
        # Option rows: "  --name ..." or "  -o, --name ...": either form will do.
        grep -oE '^  (-[a-z], )?--[a-z][a-z0-9-]*' "$tmp/help" | sort -u | while read -r row; do
            local long=${row##* } short=""
            case "$row" in -?,*) short=${row%%,*} ;; esac
            [ "$long" = "--help" ] && continue
            grep -qE -- "$long\b" "$tmp/synopsis" && continue
            [ -n "$short" ] && grep -qE -- "$short\b" "$tmp/synopsis" && continue
            fail "$name: the synopsis lacks $long and does not say [options]"
        done
    fi
    # The last section: the examples, two or three commands (and '#' lines).
    local last
    last=$(awk 'BEGIN {RS = ""} {s = $0} END {print s}' "$tmp/help")
    echo "$last" | head -n 1 | grep -q '^examples' || { fail "$name: does not end with examples"; return; }
    echo "$last" | tail -n +2 > "$tmp/examples"
    local n
    n=$(grep -c '^  hairkit ' "$tmp/examples")
    [ "$n" -ge 2 ] && [ "$n" -le 3 ] || fail "$name: $n examples, wanted two or three"
    grep -vE '^  (hairkit |# )' "$tmp/examples" && fail "$name: an example line is neither a command nor '# ...'"
    local dir="$tmp/run-${name// /-}"
    mkdir -p "$dir"
    ln -s "$src/examples" "$dir/examples"
    ln -s "$src/assets" "$dir/assets"
    while IFS= read -r line; do
        case "$line" in "  hairkit "*) run_example "$dir" "${line#  }" ;; esac
    done < "$tmp/examples"
    rm -rf "$dir"
}

check_help hairkit --help
for c in $commands; do
    check_help "$c" "$c" --help
    # Only its own help: no other command's synopsis.
    for other in $commands; do
        [ "$other" = "$c" ] && continue
        grep -q "^usage: hairkit $other\b" "$tmp/help" && fail "$c --help prints the help of $other"
    done
done
actions="trace interpolate fit reconstruct"
for a in $actions; do
    check_help "helicoid $a" helicoid "$a" --help
    for other in $actions; do
        [ "$other" = "$a" ] && continue
        grep -q "hairkit helicoid $other" "$tmp/synopsis" && fail "helicoid $a --help prints $other's synopsis"
    done
    # `hairkit help helicoid ACTION` is the same help.
    "$hk" help helicoid "$a" > "$tmp/help2" 2>&1 || fail "hairkit help helicoid $a failed"
    "$hk" helicoid "$a" --help | cmp -s - "$tmp/help2" || fail "hairkit help helicoid $a differs from helicoid $a --help"
done
# `hairkit helicoid --help` gives every action.
expect 0 "$hk" helicoid --help
for a in $actions; do contains "$tmp/out" "hairkit helicoid $a"; done

finish help
