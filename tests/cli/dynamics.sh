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
expect 2 "$hk" strand "$wavy" --simulate 0.1 --motion nodd
contains "$tmp/err" "unknown motion 'nodd'"
expect 1 "$hk" strand "$wavy" --simulate 0.1 --motion "$tmp/none.txt"
contains "$tmp/err" "none.txt"
expect 2 "$hk" strand "$wavy" --simulate 0.1 --tip-csv "$tmp/no/such/dir/tip.csv"
[ -s "$tmp/out" ] && fail "output written despite an error"
sed 's/^Young .*/Young 1e9\nInternalFriction -1/' "$wavy" > "$tmp/bad.txt"
expect 1 "$hk" strand "$tmp/bad.txt" --simulate 0.1
contains "$tmp/err" "bad.txt:"
contains "$tmp/err" "InternalFriction"

# simulate: the 201-guide scene, guides only (a light run for the sanitizers).
g200="$src/examples/guides200/setup.txt"
expect 0 "$hk" simulate "$g200" --frames 3 --fps 30 --guides-only --motion shake --preroll 0.1 -o "$tmp/g1" \
    --threads 1 --quiet
[ "$(ls "$tmp/g1" | grep -c '^guides_....\.hair$')" -eq 3 ] || fail "wanted 3 guide files, got: $(ls "$tmp/g1")"
[ "$(ls "$tmp/g1" | wc -l)" -eq 4 ] || fail "wanted 3 guide files and simulation.txt, got: $(ls "$tmp/g1")"
expect 0 "$hk" info "$tmp/g1/guides_0002.hair"
contains "$tmp/out" "201"
# the same bytes with 2 threads
expect 0 "$hk" simulate "$g200" --frames 3 --fps 30 --guides-only --motion shake --preroll 0.1 -o "$tmp/g2" \
    --threads 2 --quiet
for f in guides_0000 guides_0001 guides_0002; do
    cmp -s "$tmp/g1/$f.hair" "$tmp/g2/$f.hair" || fail "$f differs between 1 and 2 threads"
done
# TR-BDF2 on the full head (--integrator trbdf2), the same bytes with 1
# and 2 threads too
for th in 1 2; do
    expect 0 "$hk" simulate "$g200" --frames 2 --fps 30 --guides-only --motion shake --preroll 0 \
        --integrator trbdf2 -o "$tmp/t$th" --threads $th --quiet
done
cmp -s "$tmp/t1/guides_0001.hair" "$tmp/t2/guides_0001.hair" || fail "TR-BDF2 frames differ between 1 and 2 threads"
expect 0 "$hk" simulate "$g200" --frames 2 --fps 30 --guides-only --motion shake --preroll 0 \
    --integrator euler -o "$tmp/e1" --threads 2 --quiet
cmp -s "$tmp/t1/guides_0001.hair" "$tmp/e1/guides_0001.hair" && fail "--integrator trbdf2 made no difference"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 --guides-only --integrator rk4 -o "$tmp/t3"
contains "$tmp/err" "--integrator must be auto, trbdf2 or euler"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 --guides-only --preroll soon -o "$tmp/t3"
contains "$tmp/err" "--preroll expects auto or seconds"
# A guide that cannot be advanced through a frame is held at rest relative to the head
# and said, even with --quiet: 1 m guides with the linear Euler step (four steps a
# frame), alone (no guide-guide contacts, whose solve holds them together) and
# undamped, shaken 90 degrees at 5 Hz; the first guide gives up at frame 2 (3 Hz was
# enough at one step a frame; at two, no guide gave up).
mkdir -p "$tmp/long"
sed 's|^HairstyleInfo.*|HairstyleInfo '"$tmp"'/long/hairstyle.txt|; s|\.\./|'"$src"'/examples/guides200/../|' "$g200" \
    > "$tmp/long/setup.txt"
sed 's|^HairLengths.*|HairLengths 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05 0.05|' \
    "$src/examples/guides200/hairstyle.txt" > "$tmp/long/hairstyle.txt"
expect 0 "$hk" simulate "$tmp/long/setup.txt" --frames 2 --fps 30 --guides-only --no-contacts --preroll 0 \
    --integrator euler --damping off --motion shake --amplitude 90 --frequency 5 -o "$tmp/rec" --quiet
contains "$tmp/err" "could not be advanced through a frame and were held at rest relative to the head"
# Load true is refused, naming the key and the file, never replaced by grown hair
expect 0 "$hk" helicoid trace "$src/examples/helicoid/straight.txt" -o "$tmp/some.hair" --quiet
sed 's|^Load .*|Load true\nLoadFile '"$tmp"'/some.hair|' "$tmp/long/setup.txt" > "$tmp/long/load.txt"
expect 1 "$hk" simulate "$tmp/long/load.txt" --frames 1 --fps 30 --guides-only -o "$tmp/loaded"
contains "$tmp/err" "Load true: simulate grows its guides"
contains "$tmp/err" "some.hair"
# the default preroll settles until the guides rest and says so (2.5 s of settling)
expect 0 "$hk" simulate "$g200" --frames 1 --fps 30 --guides-only --preroll auto -o "$tmp/rest" --threads 2
contains "$tmp/err" "201 guides of 10 elements at rest after"
# the full job on a light scene: the guides and a picture per frame, the full hair
# only with --full-hair; --rebuild grows any frame's full hair again, the same bytes
light_scene "$tmp/light"
sed -i "s|wick.obj|wick-200.obj|" "$tmp/light/setup.txt"
small=(--fps 30 --motion nod --preroll 0 --width 96 --height 72 --shadow-map 64)
expect 0 "$hk" simulate "$tmp/light/setup.txt" --frames 2 "${small[@]}" -o "$tmp/full" --full-hair --threads 1 --quiet
for f in frame_0000.hair frame_0001.hair frame_0000.png frame_0001.png guides_0000.hair guides_0001.hair \
    simulation.txt; do
    [ -s "$tmp/full/$f" ] || fail "missing $f"
done
[ "$(head -c 4 "$tmp/full/frame_0001.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "frame is not a PNG"
ls "$tmp/full" | grep -q 'tmp' && fail "temporary file left behind"
[ -s "$tmp/err" ] && fail "--quiet printed: $(cat "$tmp/err")"
for k in 0000 0001; do
    expect 0 "$hk" simulate --rebuild "$tmp/full" --frame "${k#000}" -o "$tmp/rebuilt_$k.hair" --quiet
    cmp -s "$tmp/rebuilt_$k.hair" "$tmp/full/frame_$k.hair" || fail "rebuilt frame $k differs from --full-hair's"
done
# the same bytes with 2 threads, and without --full-hair the same guides and pictures
expect 0 "$hk" simulate "$tmp/light/setup.txt" --frames 2 "${small[@]}" -o "$tmp/full2" --threads 2
for f in frame_0000.png frame_0001.png guides_0000.hair guides_0001.hair; do
    cmp -s "$tmp/full/$f" "$tmp/full2/$f" || fail "$f differs between 1 and 2 threads or with --full-hair"
done
ls "$tmp/full2" | grep -q 'frame_.*\.hair' && fail "full hair written without --full-hair"
# stderr is no terminal here: a progress line per frame (the first and the last at
# least), then the summary with the bytes written
contains "$tmp/err" "frame 1/2, "
contains "$tmp/err" "frame 2/2, .* s/frame, about .* left"
contains "$tmp/err" "2 frames in $tmp/full2.* in all; per frame .* picture .* MB written"
# the rebuilt frame from the run without --full-hair is the same too
expect 0 "$hk" simulate --rebuild "$tmp/full2" --frame 1 -o "$tmp/rebuilt2.hair" --threads 2 --quiet
cmp -s "$tmp/rebuilt2.hair" "$tmp/full/frame_0001.hair" || fail "rebuild of a default run differs"

# a head that really turns (90 degrees at 2 Hz: 58 degrees at frame 3): every frame's
# interpolated hair is kept out of the body posed at its time (test_hair_sim measures
# the depth), and the rebuild poses it alike from the motion in the manifest
turn=(--fps 20 --motion shake --amplitude 90 --frequency 2 --preroll 0 --width 48 --height 36 --shadow-map 32)
expect 0 "$hk" simulate "$tmp/light/setup.txt" --frames 4 "${turn[@]}" -o "$tmp/shake" --full-hair --quiet
contains "$tmp/shake/simulation.txt" "^Motion  *shake 90 2 0 -0.01"
contains "$tmp/shake/simulation.txt" "^CollisionHash  *[0-9a-f]\{16\}$"
for k in 2 3; do
    expect 0 "$hk" simulate --rebuild "$tmp/shake" --frame $k -o "$tmp/shake_$k.hair" --threads 1 --quiet
    cmp -s "$tmp/shake_$k.hair" "$tmp/shake/frame_000$k.hair" || fail "rebuilt frame $k of the shake differs"
done
# the same with a motion file, recorded by absolute path and fingerprint
cp "$src/examples/motions/nod-and-shake.txt" "$tmp/moves.txt"
(cd "$tmp" && expect 0 "$hk" simulate light/setup.txt --frames 3 --fps 4 --motion moves.txt --preroll 0 --width 48 \
    --height 36 --shadow-map 32 -o "$tmp/moves" --full-hair --quiet)
contains "$tmp/moves/simulation.txt" "^MotionFile  *\"$tmp/moves.txt\""
expect 0 "$hk" simulate --rebuild "$tmp/moves" --frame 2 -o "$tmp/moves_2.hair" --quiet
cmp -s "$tmp/moves_2.hair" "$tmp/moves/frame_0002.hair" || fail "rebuilt frame 2 of the motion file differs"
echo "# changed" >> "$tmp/moves.txt"
expect 1 "$hk" simulate --rebuild "$tmp/moves" --frame 2 -o "$tmp/x.hair"
contains "$tmp/err" "moves.txt has changed since the simulation"
# the body must be the run's: a setup that lost its collision file is refused
grep -v '^CollisionInfo' "$tmp/light/setup.txt" > "$tmp/light/nobody.txt"
sed "s|light/setup.txt|light/nobody.txt|" "$tmp/shake/simulation.txt" > "$tmp/m.txt" && mv "$tmp/m.txt" "$tmp/shake/simulation.txt"
expect 1 "$hk" simulate --rebuild "$tmp/shake" --frame 1 -o "$tmp/x.hair"
contains "$tmp/err" "nobody.txt has changed since the simulation"
# format 1 (frames grown through the body) is refused with a clear message; a bad or
# missing motion names the manifest's line
mkdir "$tmp/v1"
sed 's/^HairkitSimulation .*/HairkitSimulation 1/' "$tmp/full2/simulation.txt" > "$tmp/v1/simulation.txt"
expect 1 "$hk" simulate --rebuild "$tmp/v1" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "simulation.txt:4: a simulation of format 1, whose frames did not keep the hair out of the moving body"
sed 's/^Motion .*/Motion shake 90 2 0 0/' "$tmp/full2/simulation.txt" > "$tmp/v1/simulation.txt"
expect 1 "$hk" simulate --rebuild "$tmp/v1" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "simulation.txt:16: Motion expects NAME AMPLITUDE FREQUENCY"
grep -v '^Motion ' "$tmp/full2/simulation.txt" > "$tmp/v1/simulation.txt"
expect 1 "$hk" simulate --rebuild "$tmp/v1" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "missing required key 'Motion'"

# the README's scene by default: guides and pictures, far below the full hair's 60 MB a
# frame (sizes from the files written; no timing here, see hairkit bench)
expect 0 "$hk" simulate "$g200" --frames 2 --fps 30 --motion shake --preroll 0 --width 160 --height 120 \
    --shadow-map 64 -o "$tmp/g200" --quiet
bytes=$(cat "$tmp/g200"/* | wc -c)
[ "$bytes" -lt $((2 * 7000000)) ] || fail "guides200: $bytes bytes for 2 frames, wanted below 7 MB a frame"
[ -s "$tmp/g200/frame_0001.png" ] || fail "guides200: no picture"

# an earlier run's frames are removed first, and nothing else: a shorter run into the
# same folder leaves no frame of the longer one behind (hair.mp4 would take them)
mkdir -p "$tmp/stale"
for f in frame_0005.png frame_0007.hair guides_0009.hair hair.mp4 frame_0003.png.tmp-AbC123; do
    echo old > "$tmp/stale/$f"
done
for f in notes.txt frame_12.png frame_0001.jpg my_frame_0001.png; do echo mine > "$tmp/stale/$f"; done
mkdir "$tmp/stale/frame_0008.png"
expect 0 "$hk" simulate "$tmp/light/setup.txt" --frames 1 "${small[@]}" -o "$tmp/stale"
contains "$tmp/err" "removed 5 files of an earlier run"
for f in frame_0005.png frame_0007.hair guides_0009.hair hair.mp4 frame_0003.png.tmp-AbC123; do
    [ -e "$tmp/stale/$f" ] && fail "stale $f left in the folder"
done
for f in notes.txt frame_12.png frame_0001.jpg my_frame_0001.png frame_0008.png; do
    [ -e "$tmp/stale/$f" ] || fail "$f removed: not ours"
done
[ -s "$tmp/stale/frame_0000.png" ] || fail "no new frame"

# rebuild errors name the file
expect 2 "$hk" simulate --rebuild "$tmp/full" -o "$tmp/x.hair"
contains "$tmp/err" "--frame K"
expect 2 "$hk" simulate --frame 1 "$g200" --frames 2 --fps 30 -o "$tmp/x"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 -o "$tmp/x" --guides-only --full-hair
expect 1 "$hk" simulate --rebuild "$tmp/full" --frame 2 -o "$tmp/x.hair"
contains "$tmp/err" "frames 0 to 1"
expect 1 "$hk" simulate --rebuild "$tmp/nothing" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "nothing/simulation.txt"
sed 's/^Seed .*/Seed -3/' "$tmp/full/simulation.txt" > "$tmp/full/s.txt" && mv "$tmp/full/s.txt" "$tmp/full/simulation.txt"
expect 1 "$hk" simulate --rebuild "$tmp/full" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "simulation.txt:.*Seed"
cp "$tmp/full2/simulation.txt" "$tmp/full/simulation.txt"
echo "# changed" >> "$tmp/light/hairstyle.txt"
expect 1 "$hk" simulate --rebuild "$tmp/full" --frame 0 -o "$tmp/x.hair"
contains "$tmp/err" "hairstyle.txt has changed"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"
printf 'HAIR' > "$tmp/full2/guides_0001.hair"
sed -i '$d' "$tmp/light/hairstyle.txt"
expect 1 "$hk" simulate --rebuild "$tmp/full2" --frame 1 -o "$tmp/x.hair"
contains "$tmp/err" "guides_0001.hair"

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
