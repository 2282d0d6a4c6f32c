#!/usr/bin/env bash
# Outputs that are not ordinary files (issue 13): `-o` naming a symbolic link (followed),
# a FIFO or a character device (written in place, never replaced by a regular file) or
# a folder (refused); and outputs interrupted by a signal (no NAME.tmp-XXXXXX left, a
# rerun of `simulate` cleans up the frames). Usage: outputs.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

no_temporaries() { [ -z "$(find "$tmp" -name '*.tmp-*')" ] || fail "$1: temporary left: $(find "$tmp" -name '*.tmp-*')"; }

scene="$tmp/scene"
light_scene "$scene"
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/ref.hair" --quiet

# A symbolic link (relative, into another folder): the link stays, its target gets the hair.
mkdir "$tmp/real"
echo old > "$tmp/real/target.hair"
ln -s real/target.hair "$tmp/link.hair"
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/link.hair" --quiet
[ -L "$tmp/link.hair" ] || fail "the symbolic link was replaced by a regular file"
cmp -s "$tmp/ref.hair" "$tmp/real/target.hair" || fail "the link's target does not hold the hair"
# A dangling link names the file to make.
ln -s real/new.png "$tmp/dangling.png"
expect 0 "$hk" render "$tmp/ref.hair" -o "$tmp/dangling.png" --width 64 --height 48 --quiet
[ -L "$tmp/dangling.png" ] || fail "the dangling link was replaced"
[ -s "$tmp/real/new.png" ] || fail "the dangling link's target was not made"

# A FIFO: written in place for the program reading it.
mkfifo "$tmp/pipe"
timeout 120 cat "$tmp/pipe" > "$tmp/from-pipe" &
reader=$!
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/pipe" --quiet
if [ -p "$tmp/pipe" ]; then
    wait "$reader" || fail "the FIFO's reader failed"
    cmp -s "$tmp/ref.hair" "$tmp/from-pipe" || fail "the FIFO's reader did not get the hair"
else
    fail "the FIFO was replaced by a regular file"
    kill "$reader" 2>/dev/null
    wait "$reader" 2>/dev/null
fi

# A character device (a node of the null device's numbers made here, not /dev/null
# itself, which the unfixed command replaced when run as root): written in place.
if mknod "$tmp/null" c 1 3 2>/dev/null; then
    expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/null" --quiet
    [ -c "$tmp/null" ] || fail "the character device was replaced by a regular file"
    rm -f "$tmp/null"
else
    echo "outputs: no device nodes here (not root): character device not checked"
fi

# A folder: refused, untouched.
expect 2 "$hk" groom "$scene/setup.txt" -o "$tmp/real" --quiet
contains "$tmp/err" "real: is a folder, not a file"
[ -d "$tmp/real" ] || fail "the folder was replaced"
no_temporaries "after -o on links, a FIFO and a folder"

# SIGTERM while an output is open: `strand --simulate --tip-csv` writes the tip's CSV
# all along the run; the handler removes its temporary and the process ends by the
# signal (exit 143), as without the handler. (SIGINT is checked in tests/test_outfile.c:
# a background job of a script ignores it.)
"$hk" strand "$src/examples/strand/wavy.txt" --simulate 10000 --dt 0.001 --tip-csv "$tmp/tip.csv" \
    --quiet > /dev/null 2>&1 &
pid=$!
for _ in $(seq 600); do
    [ -n "$(find "$tmp" -name 'tip.csv.tmp-*')" ] && break
    sleep 0.1
done
[ -n "$(find "$tmp" -name 'tip.csv.tmp-*')" ] || fail "no temporary of the tip CSV seen"
kill -TERM "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 143 ] || fail "strand ended with $rc after SIGTERM, wanted 143"
[ -e "$tmp/tip.csv" ] && fail "an interrupted tip CSV was made"
no_temporaries "after SIGTERM"

# An interrupted simulation: no temporary left; the last frames may lack files (the
# order is documented in docs/file-formats.md) and a rerun into the folder removes them.
g200="$src/examples/guides200/setup.txt"
"$hk" simulate "$g200" --frames 100000 --fps 30 --guides-only --preroll 0 -o "$tmp/sim" --quiet \
    > /dev/null 2>&1 &
pid=$!
for _ in $(seq 1200); do
    [ -e "$tmp/sim/guides_0002.hair" ] && break
    sleep 0.1
done
[ -e "$tmp/sim/guides_0002.hair" ] || fail "simulate wrote no third frame"
kill -TERM "$pid"
wait "$pid"
rc=$?
[ "$rc" -eq 143 ] || fail "simulate ended with $rc after SIGTERM, wanted 143"
no_temporaries "after simulate was stopped"
expect 0 "$hk" simulate "$g200" --frames 1 --fps 30 --guides-only --preroll 0 -o "$tmp/sim"
contains "$tmp/err" "files of an earlier run"
[ "$(find "$tmp/sim" -name 'guides_*.hair' | wc -l)" -eq 1 ] || fail "frames of the stopped run left: $(ls "$tmp/sim")"

finish "outputs CLI"
