#!/usr/bin/env bash
# Regenerates the pictures under docs/images/ with the project's own tools.
set -euo pipefail
cd "$(dirname "$0")/.."
hk=./build/hairkit
[ -x "$hk" ] || make build
for hair in straight wavy curly fuzzy; do
    "$hk" strand "examples/strand/$hair.txt" --collision examples/strand/head.txt \
        --root 0.04,0.137,0.03 --dir 1,0.6,0.3 --plot "docs/images/strand-$hair.png" --quiet > /dev/null
done
cp docs/images/strand-wavy.png docs/images/demo-strand.png
# The guides of the default head and of the thesis's four coupes (docs/grooming.md).
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for scene in default coupe1 coupe2 coupe3 coupe4; do
    "$hk" groom "examples/$scene/setup.txt" -o "$tmp/$scene.hair" --quiet
    build/plot_hair "$tmp/$scene.hair" "docs/images/groom-$scene.png" "examples/$scene/collision.txt"
done
# Rendered pictures (docs/rendering.md, README).
"$hk" run examples/default/setup.txt -o docs/images/render-default.png --width 960 --height 720 --quiet
for scene in coupe1 coupe2 coupe3 coupe4; do
    "$hk" run "examples/$scene/setup.txt" -o "docs/images/render-$scene.png" --width 480 --height 360 --quiet
done
"$hk" run examples/default/setup.txt -o docs/images/render-shadows.png --width 480 --height 360 --quiet \
    --hair "$tmp/default.hair"
"$hk" render "$tmp/default.hair" --head assets/head.obj --visuality examples/default/visuality.txt \
    -o docs/images/render-no-shadows.png --width 480 --height 360 --no-shadows --quiet
"$hk" render "$tmp/default.hair" --head assets/head.obj --visuality examples/default/visuality.txt \
    -o docs/images/render-marschner.png --width 480 --height 360 --shading marschner --quiet
# Dynamics (docs/dynamics.md): a strand falling, and the 201 guides on a shaking head.
for t in 0.1 0.2 0.3; do
    "$hk" strand examples/strand/straight.txt --simulate "$t" --plot "docs/images/dynamics-fall-$t.png" --quiet \
        > /dev/null
done
"$hk" simulate examples/guides200/setup.txt --frames 13 --fps 30 --motion shake --amplitude 40 --frequency 1.5 \
    --width 400 --height 300 -o "$tmp/shake" --quiet
for k in 0000 0004 0008 0012; do cp "$tmp/shake/frame_$k.png" "docs/images/dynamics-shake-$k.png"; done
# The accuracy figure: the curly strand's tip at dt = 1/30 s against 1 ms, and the linear
# Euler step. Needs gnuplot (apt-get install gnuplot-nox), which only this script uses.
scripts/plot-dynamics-bounce.sh "$hk" docs/images/dynamics-bounce.png
# Follicles sampled on the wick (docs/follicle-sampling.md).
build/plot_follicles assets/head.obj assets/wick.obj 0.006 docs/images/follicles-wick.png
# Generalized helicoids (docs/helicoids.md).
for f in wavy curly messy wisp; do
    "$hk" helicoid trace "examples/helicoid/$f.txt" -o "$tmp/helicoid-$f.hair" --quiet
    "$hk" render "$tmp/helicoid-$f.hair" -o "docs/images/helicoid-$f.png" --width 240 --height 320 --thickness 0.0006 \
        --quiet
done
# Two hairstyles of guides (examples/helicoid/guides.txt and bob.txt, made by
# build/make_helicoid_styles), interpolated at follicles 3 mm apart on the wick (paper 4.3).
for style in guides:helicoid-head bob:helicoid-head-curly; do
    "$hk" helicoid interpolate "examples/helicoid/${style%%:*}.txt" --surface assets/wick.obj --head assets/head.obj \
        --follicles 0.003 -o "$tmp/${style#*:}.hair" --quiet
    "$hk" render "$tmp/${style#*:}.hair" --head assets/head.obj --visuality examples/default/visuality.txt \
        -o "docs/images/${style#*:}.png" --width 480 --height 360 --thickness 0.0005 --quiet
done
# Reconstruction (paper 5.4): the long hair without its waves at follicles 4 mm apart, and
# the same rebuilt from the fits of one strand in ten (docs/helicoid-fitting.md).
sed 's/^Waviness.*//' examples/helicoid/guides.txt > "$tmp/smooth.txt"
"$hk" helicoid interpolate "$tmp/smooth.txt" --surface assets/wick.obj --head assets/head.obj --follicles 0.004 \
    -o "$tmp/smooth.hair" --quiet
"$hk" helicoid reconstruct "$tmp/smooth.hair" --every 10 -o "$tmp/rebuilt.hair" --quiet
for pair in smooth:helicoid-reconstruct-original rebuilt:helicoid-reconstruct; do
    "$hk" render "$tmp/${pair%%:*}.hair" --head assets/head.obj --visuality examples/default/visuality.txt \
        -o "docs/images/${pair#*:}.png" --width 320 --height 300 --thickness 0.0005 --quiet
done
# A real groom (docs/helicoid-fitting.md): the TressFX Sintel groom of ../shared/hair-data,
# every strand fitted and traced back, and rebuilt from the fits of one strand in ten.
data=../shared/hair-data
if [ -f "$data/SintelHairOriginal-sintel_hair.16points.tfx" ]; then
    sintel="$data/SintelHairOriginal-sintel_hair.16points.tfx"
    "$hk" helicoid fit "$sintel" -o "$tmp/sintel-fit.txt" --quiet > /dev/null
    "$hk" helicoid trace "$tmp/sintel-fit.txt" -o "$tmp/sintel-fitted.hair" --quiet
    "$hk" helicoid reconstruct "$sintel" --every 10 -o "$tmp/sintel-rebuilt.hair" --quiet > /dev/null
    for pair in "$sintel":original "$tmp/sintel-fitted.hair":fitted "$tmp/sintel-rebuilt.hair":rebuilt; do
        "$hk" render "${pair%:*}" --head "$data/sintel.obj" -o "docs/images/helicoid-sintel-${pair##*:}.png" \
            --width 320 --height 300 --thickness 0.00007 --quiet
    done
else
    echo "make-doc-images: $data is absent: the Sintel pictures of docs/helicoid-fitting.md are kept as they are"
fi
echo "docs/images updated"
