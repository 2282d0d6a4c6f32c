#!/usr/bin/env bash
# Hair and heads made elsewhere (issue 14, items 3 and 4): `render` and `run` read any
# hair format and OBJ or PLY heads, with --scale/--up for the hair and
# --head-scale/--head-up for the head; a file whose strand width is not a hair's is
# drawn at 70 um, once said on stderr, unless --thickness is given. The real grooms of
# ../shared/hair-data are used when the folder is there. Usage: foreign.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

data="$src/../shared/hair-data"
small=(--width 160 --height 120 --threads 2)

expect 0 "$hk" render --help
contains "$tmp/out" "--head-scale S"
contains "$tmp/out" "--head-up AXIS"
contains "$tmp/out" "OBJ or PLY"
expect 0 "$hk" run --help
contains "$tmp/out" "--head-scale S"
contains "$tmp/out" "--scale S, --up AXIS"

# Hair from the light scene, in hairkit's .hair and as PLY strands and TressFX.
scene="$tmp/scene"
light_scene "$scene"
expect 0 "$hk" run "$scene/setup.txt" -o "$tmp/run.png" "${small[@]}" --quiet --hair "$tmp/h.hair"
expect 0 "$hk" convert "$tmp/h.hair" "$tmp/h.ply" --quiet
expect 0 "$hk" convert "$tmp/h.hair" "$tmp/h.tfx" --quiet

# The head as binary and ASCII PLY, written from the OBJ (v and f lines only: 0-based).
obj="$src/assets/head.obj"
nv=$(grep -c '^v ' "$obj")
nf=$(grep -c '^f ' "$obj")
{
    printf 'ply\nformat ascii 1.0\ncomment assets/head.obj\nelement vertex %d\n' "$nv"
    printf 'property float x\nproperty float y\nproperty float z\nelement face %d\n' "$nf"
    printf 'property list uchar int vertex_indices\nend_header\n'
    grep '^v ' "$obj" | cut -d' ' -f2-4
    grep '^f ' "$obj" | awk '{ printf "%d", NF - 1; for (i = 2; i <= NF; i++) { split($i, c, "/"); printf " %d", c[1] - 1 } printf "\n" }'
} > "$tmp/head.ply"
# The same head, metres -> millimetres and +y up -> +z up (x, y, z) -> (x, -z, y): the
# inverse of --head-up +z, whose rotation is (x, y, z) -> (x, z, -y).
awk 'BEGIN { body = 0 } /^end_header/ { print; body = 1; next }
     body == 0 { print; next }
     NF == 3 && n < '"$nv"' { printf "%.9g %.9g %.9g\n", 1000 * $1, -1000 * $3, 1000 * $2; n++; next }
     { print }' "$tmp/head.ply" > "$tmp/head-mm-z.ply"

# Reference: hair and OBJ head with the hair's own width.
expect 0 "$hk" render "$tmp/h.hair" --head "$obj" -o "$tmp/ref.png" "${small[@]}" --quiet
expect 0 "$hk" render "$tmp/h.hair" --head "$tmp/head.ply" -o "$tmp/ply.png" "${small[@]}"
[ -s "$tmp/err" ] || fail "no summary on stderr"
grep -q "not hair's" "$tmp/err" && fail "hairkit's own hair was called implausible: $(cat "$tmp/err")"
# (the PLY's vertices are float, the OBJ's read as doubles: a pixel may differ)
[ "$(head -c 4 "$tmp/ply.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "PLY head: no picture"
expect 0 "$hk" render "$tmp/h.hair" --head "$tmp/head-mm-z.ply" --head-scale 0.001 --head-up +z \
    -o "$tmp/ply2.png" "${small[@]}" --quiet
cmp -s "$tmp/ply.png" "$tmp/ply2.png" || fail "--head-scale 0.001 --head-up +z did not undo mm and z up"
expect 0 "$hk" render "$tmp/h.hair" --head "$tmp/head-mm-z.ply" -o "$tmp/ply3.png" "${small[@]}" --quiet
cmp -s "$tmp/ply.png" "$tmp/ply3.png" && fail "a head in mm, z up, drew the same picture"

# Hair in other formats: PLY strands and TressFX carry no width (the default 1.0), so
# 70 um hair is drawn, said once; --thickness gives the width and says nothing.
expect 0 "$hk" render "$tmp/h.tfx" --head "$obj" -o "$tmp/tfx.png" "${small[@]}"
[ "$(grep -c "not hair's" "$tmp/err")" -eq 1 ] || fail "the width warning is not said exactly once: $(cat "$tmp/err")"
contains "$tmp/err" "drawing hair 70 um across"
expect 0 "$hk" render "$tmp/h.ply" --head "$obj" -o "$tmp/plyhair.png" "${small[@]}" --quiet
cmp -s "$tmp/tfx.png" "$tmp/plyhair.png" || fail "the same strands as .tfx and .ply drew different pictures"
expect 0 "$hk" render "$tmp/h.tfx" --head "$obj" -o "$tmp/t2.png" "${small[@]}" --thickness 7e-5
grep -q "not hair's" "$tmp/err" && fail "--thickness did not silence the width warning"
cmp -s "$tmp/tfx.png" "$tmp/t2.png" || fail "--thickness 7e-5 differs from the 70 um default"
expect 0 "$hk" render "$tmp/h.tfx" --head "$obj" -o "$tmp/slab.png" "${small[@]}" --thickness 1 --quiet
cmp -s "$tmp/tfx.png" "$tmp/slab.png" && fail "--thickness 1 drew the same picture as 70 um"
# --scale/--up on the hair, the inverse of a convert.
expect 0 "$hk" convert "$tmp/h.hair" "$tmp/h-mm.ply" --scale 1000 --quiet
expect 0 "$hk" render "$tmp/h-mm.ply" --scale 0.001 --head "$obj" -o "$tmp/mm.png" "${small[@]}" --quiet
# (x 1000 then x 0.001 in float32 may move a point by an ulp: the picture is close, not
# always the same bytes; it must exist)
[ -s "$tmp/mm.png" ] || fail "--scale: no picture"

# Errors and usage.
expect 2 "$hk" render "$tmp/h.hair" -o "$tmp/x.png" --head-scale 0
contains "$tmp/err" "--head-scale expects a number > 0"
expect 2 "$hk" render "$tmp/h.hair" -o "$tmp/x.png" --head-up w
contains "$tmp/err" "--head-up expects"
expect 2 "$hk" render "$tmp/h.hair" -o "$tmp/x.png" --head-up x
contains "$tmp/err" "need --head"
expect 2 "$hk" render "$tmp/h.hair" -o "$tmp/x.png" --up q
head -c 200 "$tmp/head.ply" > "$tmp/cut.ply"
expect 1 "$hk" render "$tmp/h.hair" --head "$tmp/cut.ply" -o "$tmp/x.png"
contains "$tmp/err" "cut.ply:"
expect 1 "$hk" render "$tmp/h.hair" --head "$tmp/h.ply" -o "$tmp/x.png"
contains "$tmp/err" "h.ply: no face element"
expect 2 "$hk" run "$scene/setup.txt" -o "$tmp/x.png" --scale 0.001
contains "$tmp/err" "--scale and --up are for hair read from LoadFile"

# run: LoadFile in another format, a PLY head and wick, the head options.
mkdir -p "$tmp/load"
cp "$scene"/*.txt "$tmp/load/"
sed -i "s|^HeadModel .*|HeadModel $tmp/head-mm-z.ply|" "$tmp/load/setup.txt"
{ echo "Load true"; echo "LoadFile $tmp/h.tfx"; cat "$tmp/load/setup.txt"; } > "$tmp/load/s.txt"
expect 0 "$hk" run "$tmp/load/s.txt" -o "$tmp/load.png" "${small[@]}" --head-scale 0.001 --head-up +z
contains "$tmp/err" "loaded"
contains "$tmp/err" "not hair's"
# the hairstyle's diameter (HairRadius1 + HairRadius2) is drawn, so the picture is the
# one of the .hair, which holds that diameter (same strands, same width, same head)
expect 0 "$hk" render "$tmp/h.hair" --head "$tmp/head.ply" --visuality "$scene/visuality.txt" \
    -o "$tmp/ply-vis.png" "${small[@]}" --quiet
cmp -s "$tmp/load.png" "$tmp/ply-vis.png" || fail "run with the .tfx and the PLY head differs from render of the .hair"
# The wick as PLY (doubles, with its normals): the same hair grown as from the OBJ wick
# (the normals may differ in their last bits: compared through 'info', to 6 digits).
wobj="$src/assets/wick.obj"
{
    printf 'ply\nformat ascii 1.0\nelement vertex %d\n' "$(grep -c '^v ' "$wobj")"
    printf 'property double x\nproperty double y\nproperty double z\n'
    printf 'property double nx\nproperty double ny\nproperty double nz\nelement face %d\n' "$(grep -c '^f ' "$wobj")"
    printf 'property list uchar int vertex_indices\nend_header\n'
    paste -d' ' <(grep '^v ' "$wobj" | cut -d' ' -f2-4) <(grep '^vn ' "$wobj" | cut -d' ' -f2-4)
    grep '^f ' "$wobj" | awk '{ printf "%d", NF - 1; for (i = 2; i <= NF; i++) { split($i, c, "/"); printf " %d", c[1] - 1 } printf "\n" }'
} > "$tmp/wick.ply"
sed "s|^WickModel .*|WickModel $tmp/wick.ply|" "$scene/setup.txt" > "$scene/setup-ply.txt"
expect 0 "$hk" run "$scene/setup-ply.txt" -o "$tmp/wickply.png" "${small[@]}" --quiet --hair "$tmp/w.hair"
"$hk" info "$tmp/h.hair" | grep -v '^file:' > "$tmp/info-obj"
"$hk" info "$tmp/w.hair" | grep -v '^file:' > "$tmp/info-ply"
cmp -s "$tmp/info-obj" "$tmp/info-ply" || fail "a PLY wick grew other hair than the OBJ wick: $(diff "$tmp/info-obj" "$tmp/info-ply")"

# The real grooms and heads.
if [ -f "$data/SOURCES.md" ]; then
    expect 0 "$hk" render "$data/SintelHairOriginal-sintel_hair.16points.tfx" --head "$data/sintel.obj" \
        -o "$tmp/sintel.png" "${small[@]}"
    contains "$tmp/err" "drawing hair 70 um across, 7e-05 in metres"
    expect 0 "$hk" render "$data/Bangs_100.hair" --head "$data/Bangs_head.ply" --up +x --head-up +x \
        -o "$tmp/bangs.png" "${small[@]}"
    contains "$tmp/err" "0.07 in millimetres"
    expect 0 "$hk" render "$data/Curly_100.ply" --scale 0.001 --up +x --head "$data/Bangs_head.ply" \
        --head-scale 0.001 --head-up +x -o "$tmp/curly.png" "${small[@]}"
    contains "$tmp/err" "7e-05 in metres"
else
    echo "skipped the real grooms: $data is absent"
fi

finish foreign
