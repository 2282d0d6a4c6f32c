#!/usr/bin/env bash
# hairkit import (issue 15, items 4 and 5): a groom and a head made guides at rest, a
# setup that simulate runs; the files do not depend on the threads; frame 0 of a still
# run is the capture, byte for byte. Usage: import.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

expect 0 "$hk" import --help
contains "$tmp/out" "--guides K"
contains "$tmp/out" "--head-scale S"
expect 2 "$hk" import
expect 2 "$hk" import "$tmp/none.obj" -o "$tmp/x"
contains "$tmp/err" "missing --head"
expect 2 "$hk" import "$tmp/none.obj" --head "$src/assets/head.obj"
contains "$tmp/err" "missing -o"
expect 2 "$hk" import "$tmp/none.obj" --head "$src/assets/head.obj" -o "$tmp/x" --guides 0

# 30 strands of 8 points in OBJ polylines, over the crown of assets/head.obj, bending down.
awk 'BEGIN { n = 0
  for (i = 0; i < 30; i++) {
    a = 6.2831853 * i / 30; r = 0.03 + 0.01 * (i % 3)
    for (j = 0; j < 8; j++) {
      s = 0.012 * j
      printf "v %.6f %.6f %.6f\n", (r + s) * cos(a), 0.16 - 0.6 * s * s / 0.084, (r + s) * sin(a)
    }
  }
  for (i = 0; i < 30; i++) { printf "l"; for (j = 1; j <= 8; j++) printf " %d", 8 * i + j; printf "\n" } }' > "$tmp/groom.obj"

expect 0 "$hk" import "$tmp/groom.obj" --head "$src/assets/head.obj" -o "$tmp/imp" --guides 6 --threads 1
contains "$tmp/err" "30 strands (240 points), 6 guides"
for f in setup.txt hairstyle.txt head.obj guides.txt strands.hair; do
    [ -s "$tmp/imp/$f" ] || fail "import wrote no $f"
done
contains "$tmp/imp/setup.txt" "ImportFile"
contains "$tmp/imp/setup.txt" "HeadCollider"
expect 0 "$hk" import "$tmp/groom.obj" --head "$src/assets/head.obj" -o "$tmp/imp2" --guides 6 --threads 2 --quiet
cmp -s "$tmp/imp/guides.txt" "$tmp/imp2/guides.txt" || fail "guides.txt differs between 1 and 2 threads"
cmp -s "$tmp/imp/strands.hair" "$tmp/imp2/strands.hair" || fail "strands.hair differs between 1 and 2 threads"

expect 0 "$hk" simulate "$tmp/imp/setup.txt" --frames 3 --fps 30 --preroll 0 --guides-only -o "$tmp/sim" --threads 2
[ -s "$tmp/sim/frame_0002.hair" ] || fail "no frame_0002.hair"
cmp -s "$tmp/sim/frame_0000.hair" "$tmp/imp/strands.hair" || fail "frame 0 of a still run is not the capture"
expect 0 "$hk" info "$tmp/sim/frame_0002.hair"
contains "$tmp/out" "30"
finish import
