#!/usr/bin/env bash
# Command-line contract of `hairkit render` and `hairkit run` (DESIGN.md): a picture
# from a .hair file or from a setup file, the same bytes whatever the thread count,
# and clear errors. Usage: render.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

png() { [ "$(head -c 4 "$1" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "$1 is not a PNG"; }

expect 0 "$hk" render --help
contains "$tmp/out" "usage: hairkit render HAIR -o OUT.png"
expect 0 "$hk" run --help
contains "$tmp/out" "usage: hairkit run SETUP.txt -o OUT.png"
expect 2 "$hk" render
expect 2 "$hk" run "$src/examples/default/setup.txt"
contains "$tmp/err" "no output"
expect 2 "$hk" run "$src/examples/default/setup.txt" -o "$tmp/x.png" --width 3
expect 2 "$hk" run "$src/examples/default/setup.txt" -o "$tmp/x.png" --shading phong
expect 2 "$hk" run "$src/examples/default/setup.txt" -o "$tmp/x.png" --scattering triple
expect 2 "$hk" run "$src/examples/default/setup.txt" -o "$tmp/x.png" --view 10
expect 2 "$hk" run "$src/examples/default/setup.txt" -o "$tmp/x.png" --light 0,120

# A light copy of the default scene (about 2,000 strands), small pictures.
scene="$tmp/scene"
light_scene "$scene"

expect 0 "$hk" run "$scene/setup.txt" -o "$tmp/one.png" --width 200 --height 150 --threads 1 --hair "$tmp/h.hair"
png "$tmp/one.png"
contains "$tmp/err" "guides"
contains "$tmp/err" "200x150"
expect 0 "$hk" run "$scene/setup.txt" -o "$tmp/two.png" --width 200 --height 150 --threads 2 --quiet
[ -s "$tmp/err" ] && fail "--quiet printed to stderr: $(cat "$tmp/err")"
cmp -s "$tmp/one.png" "$tmp/two.png" || fail "1 and 2 threads give different pictures"

# render: the saved hair gives the same picture as run; options change it.
expect 0 "$hk" render "$tmp/h.hair" --head "$src/assets/head.obj" --visuality "$scene/visuality.txt" \
    -o "$tmp/r.png" --width 200 --height 150 --quiet
cmp -s "$tmp/one.png" "$tmp/r.png" || fail "render of the saved hair differs from run"
for opt in "--no-shadows" "--shading marschner" "--scattering single" "--view -60,20" "--light 60,30" "--thickness 0.0002"; do
    # shellcheck disable=SC2086
    expect 0 "$hk" render "$tmp/h.hair" --head "$src/assets/head.obj" -o "$tmp/o.png" --width 200 --height 150 $opt
    png "$tmp/o.png"
    cmp -s "$tmp/one.png" "$tmp/o.png" && fail "$opt did not change the picture"
done
# Hair without a head, and a file of another tool (thickness and colours absent).
expect 0 "$hk" render "$tmp/h.hair" -o "$tmp/nohead.png" --width 120 --height 90
png "$tmp/nohead.png"
[ -n "$(find "$tmp" -name '*.tmp-*')" ] && fail "temporary file left behind"

# Errors: exit 1 with the file named; an existing picture is left alone.
expect 1 "$hk" render "$tmp/missing.hair" -o "$tmp/x.png"
contains "$tmp/err" "missing.hair"
head -c 100 "$tmp/h.hair" > "$tmp/cut.hair"
cp "$tmp/one.png" "$tmp/keep.png"
expect 1 "$hk" render "$tmp/cut.hair" -o "$tmp/keep.png"
contains "$tmp/err" "cut.hair"
cmp -s "$tmp/one.png" "$tmp/keep.png" || fail "a failed render damaged the existing picture"
printf 'v 0 0 0\nf 1 2 3\n' > "$tmp/bad.obj"
expect 1 "$hk" render "$tmp/h.hair" --head "$tmp/bad.obj" -o "$tmp/x.png"
contains "$tmp/err" "bad.obj:2:"
printf 'Glossiness -1\n' > "$tmp/vis.txt"
expect 1 "$hk" render "$tmp/h.hair" --visuality "$tmp/vis.txt" -o "$tmp/x.png"
contains "$tmp/err" "vis.txt:1:"
sed 's/^Young .*/Young -5/' "$scene/hairstyle.txt" > "$scene/bad_style.txt"
sed 's/^HairstyleInfo .*/HairstyleInfo bad_style.txt/' "$scene/setup.txt" > "$scene/bad_setup.txt"
expect 1 "$hk" run "$scene/bad_setup.txt" -o "$tmp/x.png"
contains "$tmp/err" "bad_style.txt:[0-9]*:.*Young"
[ -e "$tmp/x.png" ] && fail "a picture was written despite an error"

finish "render CLI"
