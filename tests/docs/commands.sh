#!/usr/bin/env bash
# The documentation's commands, run (issue 18): every line of a fenced block in README.md
# and docs/*.md that starts with "$ " is a command a reader may type at the repository's
# root (lines ending in "\" continue it); the lines after it are what it printed. Each is
# run here, in order and per page, in a temporary folder that looks like the repository
# root (examples/ and assets/ linked, ./build/hairkit and `hairkit` the program under
# test), and must exit 0. Blocks without "$ " (synopses, file layouts, output alone) are
# not run.
#
# To keep `make test` short, sizes are cut where only the size changes (the rewrites in
# shrink() below: pictures 160x120, 2 frames after 0.1 s of settling, 0.3 s of a
# strand's motion, follicles 1 cm apart) and commands that are not hairkit's own (make, ffmpeg) or need a window
# (view, which tests/cli/view.sh checks headless) are skipped, each said on stdout.
# Commands on the real grooms of ../shared/hair-data (Bangs_100.hair, sintel.obj, ...)
# run with those files linked into the folder, and are skipped, saying so, without them.
#
# Usage: commands.sh HAIRKIT SRCDIR [SANITIZED]. Under the sanitizers (SANITIZED = ON) it
# skips (exit 77): it checks the documentation, which the normal build checks already.
set -u
hk=$1
src=$2
if [ "${3:-OFF}" = "ON" ]; then
    echo "docs commands: skipped under the sanitizers (the documentation is checked by make test)"
    exit 77
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
data="$src/../shared/hair-data"

mkdir -p "$tmp/root/build" "$tmp/bin"
ln -s "$src/examples" "$tmp/root/examples"
ln -s "$src/assets" "$tmp/root/assets"
ln -s "$hk" "$tmp/root/build/hairkit"
ln -s "$hk" "$tmp/bin/hairkit"
have_data=0
if [ -f "$data/SOURCES.md" ]; then
    have_data=1
    for f in "$data"/*; do ln -s "$f" "$tmp/root/$(basename "$f")"; done
fi
export PATH="$tmp/bin:$PATH"

# shrink CMD: the same command at a size that runs in seconds (a simulation settles for
# 0.1 s instead of its default second).
shrink() {
    local c=$1
    if grep -qE ' simulate ' <<<"$c" && ! grep -qE -- '--rebuild|--preroll' <<<"$c"; then c="$c --preroll 0.1"; fi
    sed -E -e 's/--width [0-9]+/--width 160/g; s/--height [0-9]+/--height 120/g' \
        -e 's/--frames [0-9]+/--frames 2/g; s/--frame 45/--frame 1/g' \
        -e 's/--simulate [0-9.]+/--simulate 0.3/g' \
        -e 's/--follicles 0\.00[0-9]+/--follicles 0.01/g' <<<"$c"
}

# The real grooms' file names: a command naming one needs ../shared/hair-data.
needs_data() {
    grep -qE '(Bangs_|Curly_|Sintel|sintel|bear\.tfx|Ratboy|tressfx_)' <<<"$1"
}

runs=0 skips=0 fails=0
for page in "$src/README.md" "$src"/docs/*.md; do
    name=${page#"$src/"}
    # One command per record: "LINE<TAB>COMMAND", continuation lines joined.
    awk '
        /^```/ { inblock = !inblock; next }
        !inblock { next }
        cont { cmd = cmd " " $0; sub(/[ \t]*\\$/, "", cmd); if ($0 !~ /\\$/) { print line "\t" cmd; cont = 0 }; next }
        /^\$ / { line = NR; cmd = substr($0, 3); if (cmd ~ /\\$/) { sub(/[ \t]*\\$/, "", cmd); cont = 1 } else print line "\t" cmd }
    ' "$page" >"$tmp/commands"
    [ -s "$tmp/commands" ] || continue
    while IFS=$'\t' read -r line cmd; do
        cmd=$(sed -E 's/[[:space:]]+#[^"]*$//' <<<"$cmd") # a trailing comment
        first=$(awk '{print $1}' <<<"$cmd")
        second=$(awk '{print $2}' <<<"$cmd")
        where="$name:$line"
        if [ "$first" != "hairkit" ] && [ "$first" != "./build/hairkit" ]; then
            echo "skip $where: not hairkit's: $cmd"
            skips=$((skips + 1))
            continue
        fi
        if [ "$second" = "view" ]; then
            echo "skip $where: needs a window (tests/cli/view.sh runs the viewer headless): $cmd"
            skips=$((skips + 1))
            continue
        fi
        if needs_data "$cmd" && [ "$have_data" = 0 ]; then
            echo "skip $where: needs ../shared/hair-data, absent: $cmd"
            skips=$((skips + 1))
            continue
        fi
        small=$(shrink "$cmd")
        t0=$(date +%s%N)
        if (cd "$tmp/root" && timeout 300 bash -c "$small" >"$tmp/out" 2>"$tmp/err" </dev/null); then
            runs=$((runs + 1))
            echo "ran  $where in $((($(date +%s%N) - t0) / 1000000)) ms: $small"
        else
            echo "FAIL $where: exit $? of: $small" >&2
            tail -n 5 "$tmp/err" >&2
            fails=$((fails + 1))
        fi
    done <"$tmp/commands"
done
echo "docs commands: $runs ran, $skips skipped, $fails failed"
[ "$fails" -eq 0 ]
