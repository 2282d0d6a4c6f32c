#!/usr/bin/env bash
# Command-line contract of the dynamics (DESIGN.md): `hairkit strand --simulate` and
# `hairkit simulate`, their outputs, determinism and errors. Usage: dynamics.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

wavy="$src/examples/strand/wavy.txt"

# strand --simulate: the strand command's format at time T, the tip last at s = L.
expect 0 "$hk" strand "$wavy" --simulate 0.5 --dt 0.02 --tip-csv "$tmp/tip.csv" --quiet
head -n 1 "$tmp/out" | grep -Eq '^# energy=-?[0-9.]+e[-+][0-9]+ iterations=25 evaluations=[0-9]+ solver=dynamics-linear$' \
    || fail "bad first line: $(head -n 1 "$tmp/out")"
[ "$(sed -n 2p "$tmp/out")" = "s,x,y,z" ] || fail "bad CSV header"
[ "$(sed -n 3p "$tmp/out")" = "0,0,0,0" ] || fail "first row is not the root: $(sed -n 3p "$tmp/out")"
len=$(awk '$1 == "HairLengths" { s = 0; for (i = 2; i <= NF && $i !~ /^#/; i++) s += $i; print s }' "$wavy")
tail -n 1 "$tmp/out" | awk -F, -v L="$len" '{ exit !($1 + 0 == L + 0) }' || fail "last row is not s = $len"
[ "$(head -n 1 "$tmp/tip.csv")" = "t,x,y,z" ] || fail "bad tip CSV header"
[ "$(wc -l < "$tmp/tip.csv")" -eq 27 ] || fail "tip CSV: wanted t = 0 and 25 steps, got $(wc -l < "$tmp/tip.csv") lines"
tail -n 1 "$tmp/tip.csv" | grep -q '^0\.5,' || fail "tip CSV does not end at t = 0.5: $(tail -n 1 "$tmp/tip.csv")"
# it fell: the tip is lower at the end than at the start (gravity along -y)
awk -F, 'NR == 2 { y0 = $3 } END { exit !($3 < y0 - 0.01) }' "$tmp/tip.csv" || fail "the strand did not fall"
cp "$tmp/out" "$tmp/first"
expect 0 "$hk" strand "$wavy" --simulate 0.5 --dt 0.02 --quiet
cmp -s "$tmp/out" "$tmp/first" || fail "two runs differ"
# the dense solver with the full stiffness, damping off, a head motion, a collision file
expect 0 "$hk" strand "$wavy" --simulate 0.3 --dynamics-solver dense --damping off --motion nod --quiet
contains "$tmp/out" "solver=dynamics-dense"
# the linearly implicit Euler step of issue 6: one evaluation per step (and its splits)
expect 0 "$hk" strand "$wavy" --simulate 0.3 --integrator euler --quiet
head -n 1 "$tmp/out" | awk '{ split($3, a, "="); split($4, b, "="); exit !(a[2] == 9 && b[2] >= 9 && b[2] < 18) }' \
    || fail "euler: wanted 9 steps of one evaluation each: $(head -n 1 "$tmp/out")"
# issue 12: a 1 m wavy strand (N = 40) shaken at the paper's step failed at t = 0.9 s
awk '$1 == "HairLengths" { printf "HairLengths"; for (i = 0; i < 40; i++) printf " 0.025"; print ""; next } { print }' \
    "$wavy" > "$tmp/wavy1m.txt"
expect 0 "$hk" strand "$tmp/wavy1m.txt" --simulate 1.5 --motion shake --quiet
contains "$tmp/out" "iterations=45 "
expect 0 "$hk" strand "$src/examples/thesis/hairstyle.txt" --collision "$src/examples/thesis/collision.txt" \
    --root 0,0.151,0 --dir 0,1,0.3 --simulate 0.2 --motion "$src/examples/motions/nod-and-shake.txt" --quiet
# the default dt is the paper's 1/30 s: 0.1 s is 3 steps
expect 0 "$hk" strand "$wavy" --simulate 0.1 --quiet
contains "$tmp/out" "iterations=3 "

# Errors: usage (exit 2) and bad files (exit 1, naming the file and line).
expect 2 "$hk" strand "$wavy" --dt 0.01
contains "$tmp/err" "need --simulate"
expect 2 "$hk" strand "$wavy" --simulate -1
expect 2 "$hk" strand "$wavy" --simulate 1 --dt 0
expect 2 "$hk" strand "$wavy" --simulate 1 --damping maybe
expect 2 "$hk" strand "$wavy" --simulate 1 --dynamics-solver fast
expect 2 "$hk" strand "$wavy" --simulate 1 --integrator rk4
contains "$tmp/err" "--integrator must be trbdf2 or euler"
expect 2 "$hk" strand "$wavy" --simulate 1e5 --dt 1e-6
contains "$tmp/err" "1e8 steps"
printf 'Pivot 0 0 0\n0 0 0 0 1 0 0 0\n0 0 0 0 1 0 0 10\n' > "$tmp/motion.txt"
expect 1 "$hk" strand "$wavy" --simulate 0.1 --motion "$tmp/motion.txt"
contains "$tmp/err" "motion.txt:3"
expect 1 "$hk" strand "$wavy" --simulate 0.1 --motion nodd
contains "$tmp/err" "unknown motion 'nodd'"
expect 1 "$hk" strand "$wavy" --simulate 0.1 --motion "$tmp/none.txt"
contains "$tmp/err" "none.txt"
expect 1 "$hk" strand "$wavy" --simulate 0.1 --tip-csv "$tmp/no/such/dir/tip.csv"
[ -s "$tmp/out" ] && fail "output written despite an error"
sed 's/^Young .*/Young 1e9\nInternalFriction -1/' "$wavy" > "$tmp/bad.txt"
expect 1 "$hk" strand "$tmp/bad.txt" --simulate 0.1
contains "$tmp/err" "bad.txt:"
contains "$tmp/err" "InternalFriction"

# simulate: the 201-guide scene, guides only (a light run for the sanitizers).
g200="$src/examples/guides200/setup.txt"
expect 0 "$hk" simulate "$g200" --frames 3 --fps 30 --guides-only --motion shake --preroll 0.1 -o "$tmp/g1" \
    --threads 1 --quiet
[ "$(ls "$tmp/g1" | wc -l)" -eq 3 ] || fail "wanted 3 guide files, got: $(ls "$tmp/g1")"
expect 0 "$hk" info "$tmp/g1/guides_0002.hair"
contains "$tmp/out" "201"
# the same bytes with 2 threads
expect 0 "$hk" simulate "$g200" --frames 3 --fps 30 --guides-only --motion shake --preroll 0.1 -o "$tmp/g2" \
    --threads 2 --quiet
for f in guides_0000 guides_0001 guides_0002; do
    cmp -s "$tmp/g1/$f.hair" "$tmp/g2/$f.hair" || fail "$f differs between 1 and 2 threads"
done
# the full job on a light scene: interpolated hair and a picture per frame
light_scene "$tmp/light"
sed -i "s|wick.obj|wick-200.obj|" "$tmp/light/setup.txt"
expect 0 "$hk" simulate "$tmp/light/setup.txt" --frames 2 --fps 30 --motion nod --preroll 0 --width 96 --height 72 \
    --shadow-map 64 -o "$tmp/full" --quiet
for f in frame_0000.hair frame_0001.hair frame_0000.png frame_0001.png; do
    [ -s "$tmp/full/$f" ] || fail "missing $f"
done
[ "$(head -c 4 "$tmp/full/frame_0001.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "frame is not a PNG"
ls "$tmp/full" | grep -q 'tmp' && fail "temporary file left behind"

expect 2 "$hk" simulate "$g200" --frames 3 -o "$tmp/x"
contains "$tmp/err" "--fps"
expect 2 "$hk" simulate "$g200" --fps 30 -o "$tmp/x"
expect 2 "$hk" simulate "$g200" --frames 0 --fps 30 -o "$tmp/x"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30
contains "$tmp/err" "-o DIR"
expect 1 "$hk" simulate "$tmp/missing.txt" --frames 2 --fps 30 -o "$tmp/x"
contains "$tmp/err" "missing.txt"
expect 1 "$hk" simulate "$g200" --frames 2 --fps 30 -o "$tmp/x" --motion "$tmp/motion.txt"
contains "$tmp/err" "motion.txt:3"
expect 0 "$hk" simulate --help
contains "$tmp/out" "usage: hairkit simulate"

finish dynamics
