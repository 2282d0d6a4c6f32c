#!/usr/bin/env bash
# One exit-code rule for every command (issue 18, item 3; README "Exit codes"): 0 success,
# 1 bad input data or a failed computation, 2 a bad command line (options, values, output
# paths of the wrong kind), said before any long work: an output that cannot be written
# is refused before the settling or the growing, so no progress line comes first and
# nothing is written. Folders of `-o DIR` are made with their parents.
# Usage: exit_codes.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

scene="$tmp/scene"
light_scene "$scene"
g200="$src/examples/guides200/setup.txt"
nothing_written() { [ -z "$(ls -A "$1")" ] || fail "$2: something was written: $(ls -A "$1")"; }
no_work() { grep -qiE 'settl|guides|frame|strands' "$tmp/err" && fail "$1: work started: $(head -c 300 "$tmp/err")"; }

# 2: a value that names nothing (an unknown scripted motion, not a file either), as
# every other bad option value; before the settling.
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 --motion wobble -o "$tmp/sim"
contains "$tmp/err" "unknown motion 'wobble' (still, nod, shake, tilt, sway or jump)"
no_work "--motion wobble"
expect 2 "$hk" strand "$src/examples/strand/wavy.txt" --simulate 0.1 --motion shak
contains "$tmp/err" "did you mean shake?"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 --damping maybe -o "$tmp/sim"
# ... while a motion file with bad data is bad input data: 1, naming file and line.
printf 'Pivot 0 0 0\n0 0 0 0 1 0 0 0\n0 0 0 0 1 0 0 10\n' > "$tmp/motion.txt"
expect 1 "$hk" strand "$src/examples/strand/wavy.txt" --simulate 0.1 --motion "$tmp/motion.txt"
contains "$tmp/err" "motion.txt:3"

# 2: a picture written to a name without .png, refused before the work.
mkdir "$tmp/pics"
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/head.hair" --quiet
expect 2 "$hk" render "$tmp/head.hair" -o "$tmp/pics/x.txt" --width 64 --height 48
contains "$tmp/err" "x.txt: the file written is a PNG picture; give a name ending in .png"
expect 2 "$hk" run "$scene/setup.txt" -o "$tmp/pics/head.jpg"
no_work "run -o head.jpg"
expect 2 "$hk" strand "$src/examples/strand/wavy.txt" --plot "$tmp/pics/plot"
[ -s "$tmp/out" ] && fail "strand --plot plot: the shape was printed"
nothing_written "$tmp/pics" "pictures without .png"
# Upper case is a PNG all the same.
expect 0 "$hk" render "$tmp/head.hair" -o "$tmp/pics/x.PNG" --width 64 --height 48 --quiet

# 2: an output in a folder that does not exist, or that is a folder, before growing.
expect 2 "$hk" run "$scene/setup.txt" -o "$tmp/nodir/head.png"
contains "$tmp/err" "no folder $tmp/nodir to write it in"
no_work "run -o nodir/head.png"
expect 2 "$hk" groom "$scene/setup.txt" -o "$tmp/nodir/head.hair"
expect 2 "$hk" groom "$scene/setup.txt" -o "$tmp/pics"
contains "$tmp/err" "pics: is a folder, not a file"
expect 2 "$hk" run "$scene/setup.txt" -o "$tmp/ok.png" --hair "$tmp/nodir/head.hair"
[ -e "$tmp/ok.png" ] && fail "run drew the picture although --hair cannot be written"
expect 2 "$hk" convert "$tmp/head.hair" "$tmp/nodir/head.ply"
expect 2 "$hk" helicoid trace "$src/examples/helicoid/curly.txt" -o "$tmp/nodir/curly.hair"
[ -e "$tmp/nodir" ] && fail "a folder was made for an output file"

# 2: the setup's SaveFile ('Save true') in a folder that does not exist, said before
# the growing (it was written only after it), by groom without -o, by run and by view.
light_scene "$tmp/saving" "Save true" "SaveFile $tmp/nodir/saved.hair"
expect 2 "$hk" groom "$tmp/saving/setup.txt"
contains "$tmp/err" "SaveFile $tmp/nodir/saved.hair: no folder $tmp/nodir to write it in"
no_work "groom with SaveFile in nodir"
expect 2 "$hk" run "$tmp/saving/setup.txt" -o "$tmp/saving.png"
no_work "run with SaveFile in nodir"
[ -e "$tmp/saving.png" ] && fail "run drew the picture although SaveFile cannot be written"
# ... and by view (before the window opens: no display needed), when it is built.
if "$hk" view --help > /dev/null 2>&1; then
    expect 2 "$hk" view "$tmp/saving/setup.txt" --frames 1 --screenshot "$tmp/saving-view.png"
    contains "$tmp/err" "SaveFile $tmp/nodir/saved.hair: no folder $tmp/nodir to write it in"
    no_work "view with SaveFile in nodir"
fi
# ... and a SaveFile that can be written is written, without -o.
light_scene "$tmp/saved" "Save true" "SaveFile saved.hair"
expect 0 "$hk" groom "$tmp/saved/setup.txt" --quiet
[ -s "$tmp/saved/saved.hair" ] || fail "groom with Save true wrote no SaveFile"

# 2: simulate -o naming a file (it writes a folder of frames), before the settling.
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 -o "$tmp/head.hair"
contains "$tmp/err" "head.hair: is a file, not a folder"
no_work "simulate -o head.hair (a file)"
expect 2 "$hk" simulate "$g200" --frames 2 --fps 30 -o "$tmp/new.hair"
contains "$tmp/err" "names a .hair file"
[ -e "$tmp/new.hair" ] && fail "simulate made a folder named new.hair"
expect 2 "$hk" simulate --rebuild "$tmp" --frame 0 -o "$tmp/pics"
contains "$tmp/err" "is a folder, not a file"
expect 2 "$hk" import "$tmp/head.hair" --head "$src/assets/head.obj" -o "$tmp/head.hair"

# mkdir -p: the folders of -o DIR are made.
expect 0 "$hk" simulate "$scene/setup.txt" --frames 1 --fps 30 --guides-only --preroll 0 \
    -o "$tmp/nodir/sub/out" --quiet
[ -s "$tmp/nodir/sub/out/guides_0000.hair" ] || fail "simulate -o nodir/sub/out wrote no frame"

# 1: bad input data (a setup that names no file) and a failed read.
printf 'HairstyleInfo nowhere.txt\n' > "$tmp/bad-setup.txt"
expect 1 "$hk" groom "$tmp/bad-setup.txt" -o "$tmp/x.hair"
expect 1 "$hk" info "$tmp/pics/x.PNG"
# a setup that cannot be read: 1, and no empty output folder left behind
expect 1 "$hk" simulate "$tmp/no-such-setup.txt" --frames 2 --fps 30 -o "$tmp/never/made"
contains "$tmp/err" "no-such-setup.txt: cannot open"
[ -e "$tmp/never" ] && fail "simulate made its output folder for a setup it cannot read"

# 2: the operands (hk_cli_one_operand, hk_cli_bad_option): none, one too many, an option
# without its value; said before any work, for each command that takes one operand.
for cmd in groom run simulate strand render import view; do
    expect 2 "$hk" $cmd
    contains "$tmp/err" "hairkit $cmd: missing"
    expect 2 "$hk" $cmd "$scene/setup.txt" extra
    contains "$tmp/err" "hairkit $cmd: unexpected argument 'extra'"
done
expect 2 "$hk" helicoid fit
contains "$tmp/err" "fit: missing input file"
expect 2 "$hk" simulate "$g200" --frames
contains "$tmp/err" "option '--frames' needs a value"

finish exit_codes

