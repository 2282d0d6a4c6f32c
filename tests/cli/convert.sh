#!/usr/bin/env bash
# Command-line contract of `hairkit convert` and of `hairkit info` on every hair format
# (docs/file-formats.md): the format from the extension or --from/--to, points kept
# exactly when nothing is asked, --scale, --up, --points, --ascii, the units hint, and
# clear errors naming the file. The real grooms of ../shared/hair-data are used when the
# folder is there. Usage: convert.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

data="$src/../shared/hair-data"

expect 0 "$hk" convert --help
contains "$tmp/out" "usage: hairkit convert IN OUT"
contains "$tmp/out" "--points N"
expect 0 "$hk" help convert
contains "$tmp/out" "usage: hairkit convert IN OUT"
expect 0 "$hk" --help
contains "$tmp/out" "convert"
expect 0 "$hk" info --help
contains "$tmp/out" "usage: hairkit info FILE"

# A groom by hand: OBJ polylines in millimetres, x up, strands of 3, 4 and 2 points.
cat > "$tmp/g.obj" <<'EOF'
# three strands, millimetres, x up
v 237 0 0
v 200 1.5 0
v 150 3 0.25
v 237 10 0
v 210 10 5
v 180 10 10
v 140 12.5 10
v 0 -20 0
v 1 -20 0
l 1 2 3
l 4 5 6 7
l 8 9
EOF

# Usage errors: exit 2 with the reason.
expect 2 "$hk" convert
contains "$tmp/err" "missing IN and OUT"
expect 2 "$hk" convert "$tmp/g.obj"
contains "$tmp/err" "missing the OUT file"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" extra
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.xyz"
contains "$tmp/err" "give --to"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --to abc
contains "$tmp/err" "--to expects"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --scale 0
contains "$tmp/err" "--scale expects a number > 0"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --scale abc
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --up w
contains "$tmp/err" "--up expects"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --points 1
contains "$tmp/err" "--points expects 2 to 65536"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --ascii
contains "$tmp/err" "--ascii is for PLY output"
expect 2 "$hk" convert "$tmp/g.obj" "$tmp/a.hair" --bogus
contains "$tmp/err" "unknown option '--bogus'"
expect 2 "$hk" info
expect 2 "$hk" info "$tmp/g.obj" --from abc
[ -e "$tmp/a.hair" ] && fail "output written after a usage error"

# info reads every format, with the units hint.
expect 0 "$hk" info "$tmp/g.obj"
contains "$tmp/out" "format:        obj"
contains "$tmp/out" "strands:       3"
contains "$tmp/out" "points:        9 (per strand: min 2, mean 3.0, max 4)"
contains "$tmp/out" "extent 237: millimetres? --scale 0.001"

# Every format and back: the same bytes as the first .hair (points exactly kept).
expect 0 "$hk" convert "$tmp/g.obj" "$tmp/g.hair"
contains "$tmp/err" "3 strands, 9 points: obj -> cyhair"
for ext in data ply obj usda; do
    expect 0 "$hk" convert "$tmp/g.hair" "$tmp/g2.$ext" --quiet
    [ -s "$tmp/err" ] && fail "--quiet printed: $(cat "$tmp/err")"
    expect 0 "$hk" info "$tmp/g2.$ext"
    contains "$tmp/out" "strands:       3"
    expect 0 "$hk" convert "$tmp/g2.$ext" "$tmp/back-$ext.hair" --quiet
    cmp -s "$tmp/g.hair" "$tmp/back-$ext.hair" || fail "$ext: a round trip changed the points"
done
expect 0 "$hk" convert "$tmp/g.hair" "$tmp/ga.ply" --ascii
head -2 "$tmp/ga.ply" | grep -q "format ascii 1.0" || fail "--ascii did not write ASCII PLY"
expect 0 "$hk" convert "$tmp/ga.ply" "$tmp/back-ga.hair"
cmp -s "$tmp/g.hair" "$tmp/back-ga.hair" || fail "ASCII PLY: a round trip changed the points"
head -2 "$tmp/g2.ply" | grep -q "format binary_little_endian 1.0" || fail "PLY is not binary by default"

# --from / --to whatever the extensions say.
expect 0 "$hk" convert "$tmp/g2.data" "$tmp/g.bin" --to tfx --points 4
expect 0 "$hk" info "$tmp/g.bin" --from tfx
contains "$tmp/out" "points:        12 (per strand: min 4, mean 4.0, max 4)"
expect 1 "$hk" info "$tmp/g.bin"
contains "$tmp/err" "g.bin: unknown hair format"
cp "$tmp/g2.usda" "$tmp/g-usda.txt"
expect 0 "$hk" info "$tmp/g-usda.txt"
contains "$tmp/out" "strands:       3"

# TressFX: strands of different counts are refused without --points, resampled with it.
expect 1 "$hk" convert "$tmp/g.obj" "$tmp/g.tfx"
contains "$tmp/err" "g.tfx: TressFX needs the same number of points in every strand, these have 2 to 4"
contains "$tmp/err" "--points N"
[ -e "$tmp/g.tfx" ] && fail "a refused TressFX file was written"
expect 0 "$hk" convert "$tmp/g.obj" "$tmp/g.tfx" --points 5
contains "$tmp/err" "5 points per strand"
expect 0 "$hk" info "$tmp/g.tfx"
contains "$tmp/out" "points:        15 (per strand: min 5, mean 5.0, max 5)"
contains "$tmp/out" "format:        tfx"
# the straight strand keeps its length; the bent ones lose a little at the corners cut
expect 0 "$hk" info "$tmp/g.tfx"
contains "$tmp/out" "length:        min 1, mean 61.9"

# --scale and --up: millimetres and x up to metres and y up.
expect 0 "$hk" convert "$tmp/g.obj" "$tmp/m.obj" --scale 0.001 --up +x
contains "$tmp/err" "scale 0.001, up +x onto +y"
head -2 "$tmp/m.obj" | tail -1 | grep -qx "v -0 0.237 0" || fail "+x up, mm: first point $(sed -n 2p "$tmp/m.obj")"
expect 0 "$hk" info "$tmp/m.obj"
contains "$tmp/out" "units:         extent 0.237$"
expect 0 "$hk" convert "$tmp/g.obj" "$tmp/u.obj" --up -y
sed -n 2p "$tmp/u.obj" | grep -qx "v 237 -0 -0" || fail "-y up: first point $(sed -n 2p "$tmp/u.obj")"
expect 0 "$hk" convert "$tmp/g.obj" "$tmp/u.obj" --up +z
sed -n 4p "$tmp/u.obj" | grep -qx "v 150 0.25 -3" || fail "+z up: third point $(sed -n 4p "$tmp/u.obj")"

# Errors: exit 1 with the file named, no output left behind.
expect 1 "$hk" convert "$tmp/missing.tfx" "$tmp/x.hair"
contains "$tmp/err" "missing.tfx"
printf 'v 0 0 0\nl 1 2\n' > "$tmp/bad.obj"
expect 1 "$hk" convert "$tmp/bad.obj" "$tmp/x.hair"
contains "$tmp/err" "bad.obj:2: '2' is not a vertex index"
head -c 100 "$tmp/g.tfx" > "$tmp/cut.tfx"
expect 1 "$hk" info "$tmp/cut.tfx"
contains "$tmp/err" "cut.tfx:4: truncated"
head -c 30 "$tmp/g2.ply" > "$tmp/cut.ply"
expect 1 "$hk" convert "$tmp/cut.ply" "$tmp/x.hair"
contains "$tmp/err" "cut.ply"
cp "$tmp/g.hair" "$tmp/keep.hair"
expect 1 "$hk" convert "$tmp/cut.tfx" "$tmp/keep.hair"
cmp -s "$tmp/g.hair" "$tmp/keep.hair" || fail "a failed convert touched the existing output"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"
[ -n "$(find "$tmp" -name '*.tmp-*')" ] && fail "temporary file left behind"

# The real grooms, when they are here.
if [ -r "$data/SOURCES.md" ]; then
    expect 0 "$hk" info "$data/Bangs_100.data"
    contains "$tmp/out" "strands:       100"
    contains "$tmp/out" "points:        1165"
    contains "$tmp/out" "millimetres? --scale 0.001"
    expect 0 "$hk" convert "$data/Bangs_100.data" "$tmp/bangs.hair" --quiet
    cmp -s "$tmp/bangs.hair" "$data/Bangs_100.hair" ||
        fail "Bangs_100.data converted differs from Bangs_100.hair"
    expect 0 "$hk" info "$data/tressfx_ponytail/side.tfx"
    contains "$tmp/out" "centimetres? --scale 0.01"
    expect 0 "$hk" info "$data/Curly_100.ply"
    contains "$tmp/out" "points:        2528"
    contains "$tmp/out" "colours"
    sintel="$data/SintelHairOriginal-sintel_hair.16points.tfx"
    expect 0 "$hk" info "$sintel"
    contains "$tmp/out" "strands:       11400"
    grep -q "^units:.*--scale" "$tmp/out" && fail "Sintel is in metres: no units hint wanted"
    expect 0 "$hk" convert "$sintel" "$tmp/sintel.hair"
    expect 0 "$hk" convert "$tmp/sintel.hair" "$tmp/sintel.tfx"
    cmp -s "$tmp/sintel.tfx" "$sintel" || fail "Sintel .tfx -> .hair -> .tfx changed bytes"
    expect 1 "$hk" info "$data/Bangs_head.ply"
    contains "$tmp/err" "a mesh, not hair strands"
else
    echo "convert.sh: $data is absent: the real grooms are not checked"
fi

finish convert
