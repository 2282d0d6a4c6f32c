#!/usr/bin/env bash
# Command-line contract of `hairkit view` (docs/viewer.md), headless under xvfb-run with
# Mesa's software OpenGL: the screenshot frames the same picture as `hairkit run` at the
# same size and view (foreground masks compared by tools/mask_diff.c), a bad shader is
# reported with its file and line, no display is a clear error. Skipped (exit 77) when
# hairkit was built without the viewer or xvfb-run is absent. Usage: view.sh HAIRKIT SRCDIR
if [ -z "${HK_VIEW_UNDER_XVFB:-}" ]; then
    if ! "$1" view /nonexistent.hair 2>&1 | grep -q "built without the viewer"; then
        if command -v xvfb-run >/dev/null 2>&1; then
            HK_VIEW_UNDER_XVFB=1 exec xvfb-run -a -s "-screen 0 640x480x24" bash "$0" "$@"
        fi
        echo "view: SKIPPED: xvfb-run is not installed (scripts/install-deps.sh installs it)"
    else
        echo "view: SKIPPED: hairkit was built without the viewer (HK_VIEWER off)"
    fi
    exit 77
fi
source "$(dirname "$0")/lib/common.sh"
# Mesa's allocations are not hairkit's: no leak reports from the GL driver under ASan.
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"
mask_diff="$(dirname "$hk")/mask_diff"
[ -x "$mask_diff" ] || { echo "view: $mask_diff is missing (cmake --build BUILD --target mask_diff)" >&2; exit 1; }

expect 0 "$hk" view --help
contains "$tmp/out" "usage: hairkit view SETUP.txt | HAIR"
expect 2 "$hk" view
expect 2 "$hk" view x.hair --frames 0
expect 2 "$hk" view x.hair --view 10

# The light copy of the default scene (about 2,000 strands), 160 x 120 pictures.
scene="$tmp/scene"
light_scene "$scene"
expect 0 "$hk" run "$scene/setup.txt" -o "$tmp/run.png" --width 160 --height 120 --hair "$tmp/h.hair" --quiet
head=(--head "$src/assets/head.obj" --visuality "$scene/visuality.txt")

# pixels whose bytes differ inside the top left W,H box ($3) and outside: at least $4 inside, none outside
corner() {
    local out
    out=$("$mask_diff" --box "$3" "$1" "$2") || { fail "mask_diff --box $3 $1 $2"; return; }
    set -- "$1" "$2" "$3" "$4" $out
    [ "$8" = 0 ] || fail "$1 and $2 differ outside the top left $3 pixels: $5 $6 $7 $8"
    [ "$6" -ge "$4" ] || fail "$1 and $2 differ in under $4 pixels of the top left $3: $5 $6 $7 $8"
}

# the fraction of pixels covered by one picture only must stay under $3 (or over, with "over")
masks() {
    local out
    out=$("$mask_diff" "$1" "$2") || { fail "mask_diff $1 $2"; return; }
    local differ=${out##* }
    if [ "${4:-under}" = under ]; then
        awk -v d="$differ" -v t="$3" 'BEGIN { exit !(d < t) }' || fail "$1 and $2 cover different pixels: $out"
    else
        awk -v d="$differ" -v t="$3" 'BEGIN { exit !(d > t) }' || fail "$1 and $2 should differ: $out"
    fi
}

expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 2 --screenshot "$tmp/view.png"
contains "$tmp/err" "2385 strands"
contains "$tmp/err" "frames/s"
contains "$tmp/err" "wrote $tmp/view.png (160x120)"
# Same framing as the CPU renderer: at most 1% of the pixels covered by one picture
# only (measured: 0.2%); a camera turned by 10 degrees gives 2%, -35 instead of 35 7.5%.
masks "$tmp/run.png" "$tmp/view.png" 0.01
# The text overlay (off headless unless asked): on the third frame, three lines of at
# most 14 glyphs of 6 x 8 pixels (the rate of the second frame, "12.3 frames/s", the
# strands, the points) on a backing with a margin of 2 pixels: within the top left
# 88 x 27 pixels, at least the backing of 13 glyphs (82 x 27 = 2214 pixels) differs, the
# rest of the picture is the same bytes as without it.
expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 3 --screenshot "$tmp/text.png" \
    --overlay --quiet
expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 3 --screenshot "$tmp/notext.png" \
    --quiet
corner "$tmp/notext.png" "$tmp/text.png" 88,27 2214
expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 3 --screenshot "$tmp/text0.png" \
    --overlay --no-overlay --quiet
cmp -s "$tmp/notext.png" "$tmp/text0.png" || fail "--no-overlay draws text"
expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 1 --screenshot "$tmp/turned.png" \
    --view -35,12 --quiet
masks "$tmp/run.png" "$tmp/turned.png" 0.03 over
# The options of render: a view and a light of their own, no shadows, Marschner, a setup.
expect 0 "$hk" render "$tmp/h.hair" "${head[@]}" -o "$tmp/side.png" --width 160 --height 120 --view 80,0 --quiet
expect 0 "$hk" view "$tmp/h.hair" "${head[@]}" --width 160 --height 120 --frames 1 --screenshot "$tmp/vside.png" \
    --view 80,0 --light 60,30 --no-shadows --shading marschner --quiet
masks "$tmp/side.png" "$tmp/vside.png" 0.01
light_scene "$tmp/loaded" "Load true" "LoadFile $tmp/h.hair"
expect 0 "$hk" view "$tmp/loaded/setup.txt" --width 160 --height 120 --frames 1 --screenshot "$tmp/vsetup.png" --quiet
masks "$tmp/run.png" "$tmp/vsetup.png" 0.01

# Live dynamics on a light scene of 201 guides (examples/guides200's wick), one step a
# frame, 10 steps (1/3 s): the still head's hair stays where the statics put it (the
# static picture's pixels within 1%; measured 0.3%), a shaking head's moves (measured
# 2.6% of the pixels against the still one); the same bytes with 1 thread.
light_scene "$tmp/sim"
sed -i 's|/wick.obj|/wick-200.obj|' "$tmp/sim/setup.txt"
sim=("$tmp/sim/setup.txt" --width 160 --height 120 --quiet)
expect 0 "$hk" view "${sim[@]}" --frames 1 --screenshot "$tmp/static.png"
expect 0 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/still.png" --simulate --preroll 0
expect 0 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/shake.png" --simulate --preroll 0 --motion shake \
    --frequency 2
masks "$tmp/static.png" "$tmp/still.png" 0.01
masks "$tmp/still.png" "$tmp/shake.png" 0.01 over
expect 0 env OMP_NUM_THREADS=1 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/still1.png" --simulate \
    --preroll 0
cmp -s "$tmp/still.png" "$tmp/still1.png" || fail "a simulated picture depends on the threads"
# Simulating, the overlay has two lines more ("simulated 0.30 s", "playing"): the top
# left 100 x 43 pixels (16 glyphs, 5 lines; measured: all 4300 differ), beyond the 27
# rows of three lines.
expect 0 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/simtext.png" --simulate --preroll 0 --overlay
corner "$tmp/still.png" "$tmp/simtext.png" 100,43 4000
"$mask_diff" --box 100,27 "$tmp/still.png" "$tmp/simtext.png" | grep -q "outside 0$" &&
    fail "the overlay has no lines for the simulation"
expect 0 "$hk" view "$tmp/sim/setup.txt" --width 160 --height 120 --frames 2 --simulate --preroll 0
contains "$tmp/err" "201 guides solved"
contains "$tmp/err" "simulated 0.07 s (2 steps"
# A head motion file, as hairkit simulate takes it: the head nods (measured 6.6% of the
# pixels against the still head after 10 steps).
expect 0 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/file.png" --simulate --preroll 0 \
    --motion "$src/examples/motions/nod-and-shake.txt"
masks "$tmp/still.png" "$tmp/file.png" 0.01 over
# The head dragged 30 pixels to the right before the first step (as Shift + left drag):
# head and hair move across the picture (measured 31% of the pixels against the still).
expect 0 "$hk" view "${sim[@]}" --frames 10 --screenshot "$tmp/drag.png" --simulate --preroll 0 --drag 30,0
masks "$tmp/still.png" "$tmp/drag.png" 0.1 over
expect 2 "$hk" view "${sim[@]}" --drag 30,0
contains "$tmp/err" "--drag needs --simulate"
# The toggles' first state: guides alone cover fewer pixels, the shapes' outlines more.
expect 0 "$hk" view "${sim[@]}" --frames 1 --screenshot "$tmp/guides.png" --guides-only
masks "$tmp/static.png" "$tmp/guides.png" 0.02 over
expect 0 "$hk" view "${sim[@]}" --frames 1 --screenshot "$tmp/shapes.png" --show-shapes
masks "$tmp/static.png" "$tmp/shapes.png" 0.005 over
# Live dynamics needs a setup that grows its hair.
expect 2 "$hk" view "$tmp/h.hair" --simulate
contains "$tmp/err" "--simulate needs a setup file"
expect 1 "$hk" view "$tmp/loaded/setup.txt" --frames 1 --simulate
contains "$tmp/err" "Load true"
# A motion that names nothing is a bad command line (README, "The command line"): 2.
expect 2 "$hk" view "${sim[@]}" --frames 1 --simulate --motion wobble
contains "$tmp/err" "unknown motion 'wobble'"

# The benchmark without a display says so and measures nothing (its figures: docs/viewer.md).
expect 0 env -u DISPLAY -u WAYLAND_DISPLAY "$hk" bench view --quick
contains "$tmp/out" "view: skipped: no display"

# A shader that does not compile: the file and the line the compiler names.
{
    echo "#version 330 core"
    echo "out vec4 FragColor;"
    echo "void main()"
    echo "{"
    echo "    FragColor = vec4(undeclared_thing, 1.0);"
    echo "}"
} > "$tmp/bad.frag"
expect 1 "$hk" view "$tmp/h.hair" --frames 1 --hair-frag "$tmp/bad.frag"
contains "$tmp/err" "$tmp/bad.frag:5:"
light_scene "$tmp/badsetup" "Load true" "LoadFile $tmp/h.hair" "HairFrag $tmp/bad.frag"
expect 1 "$hk" view "$tmp/badsetup/setup.txt" --frames 1
contains "$tmp/err" "$tmp/bad.frag:5:"
expect 1 "$hk" view "$tmp/h.hair" --frames 1 --head-vert "$tmp/missing.vert"
contains "$tmp/err" "missing.vert: cannot be read"
expect 1 "$hk" view "$tmp/missing.hair" --frames 1
contains "$tmp/err" "missing.hair"

# No display: a message, exit 1, no crash.
expect 1 env -u DISPLAY -u WAYLAND_DISPLAY "$hk" view "$tmp/h.hair" --frames 1 --screenshot "$tmp/none.png"
contains "$tmp/err" "cannot open a window"
[ -e "$tmp/none.png" ] && fail "a screenshot without a display"

finish view
