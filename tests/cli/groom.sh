#!/usr/bin/env bash
# Command-line contract of `hairkit groom` and `hairkit info` (DESIGN.md): a setup file
# in, a cyHair file out; determinism across thread counts; Load/Save of the setup file;
# clear errors naming file and line. Usage: groom.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

expect 0 "$hk" groom --help
contains "$tmp/out" "usage: hairkit groom SETUP.txt -o OUT.hair"
expect 0 "$hk" info --help
expect 2 "$hk" groom
expect 2 "$hk" groom "$src/examples/default/setup.txt" --threads 0 -o "$tmp/x.hair"
expect 2 "$hk" groom "$src/examples/default/setup.txt" --seed -1 -o "$tmp/x.hair"
expect 2 "$hk" groom "$src/examples/default/setup.txt"
contains "$tmp/err" "no output"

# A light copy of the default scene (density 4 per cm^2: about 2,000 strands) so that
# the test stays quick under the sanitizers; the paths point back to the assets.
scene="$tmp/scene"
light_scene "$scene" "Load false" "Save true" "SaveFile saved.hair"

expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/seed8.hair" --seed 8 --quiet
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/one.hair" --threads 1 --seed 7
contains "$tmp/err" "guides"
[ "$(head -c 4 "$tmp/one.hair")" = "HAIR" ] || fail "not a cyHair file"
cmp -s "$tmp/one.hair" "$scene/saved.hair" || fail "SaveFile differs from -o output"
expect 0 "$hk" groom "$scene/setup.txt" -o "$tmp/two.hair" --threads 2 --seed 7 --quiet
[ -s "$tmp/err" ] && fail "--quiet printed to stderr: $(cat "$tmp/err")"
cmp -s "$tmp/one.hair" "$tmp/two.hair" || fail "1 and 2 threads give different bytes"
cmp -s "$tmp/one.hair" "$tmp/seed8.hair" && fail "seeds 7 and 8 give the same hair"
[ -n "$(find "$tmp" -name '*.tmp-*')" ] && fail "temporary file left behind"

# info: counts consistent with the groom (401 guides + interpolated strands, 41 points).
expect 0 "$hk" info "$tmp/one.hair"
contains "$tmp/out" "points:.*min 41, mean 41.0, max 41"
strands=$(sed -n 's/^strands: *//p' "$tmp/out")
[ "$strands" -gt 1500 ] && [ "$strands" -lt 3500 ] || fail "unexpected strand count $strands"
# Polyline lengths: a little under the 20 cm arc length (chords of a wavy strand).
sed -n 's/^length: *min \([0-9.e-]*\), mean [0-9.e-]*, max \([0-9.e-]*\).*/\1 \2/p' "$tmp/out" |
    awk '{ exit !($1 > 0.199 && $2 <= 0.2000001) }' || fail "strand lengths off: $(grep length "$tmp/out")"

# Load: the setup reads the saved file instead of growing, and writes it back unchanged.
sed -e 's/^Load false/Load true/' -e 's/^Save true/Save false/' "$scene/setup.txt" > "$scene/load.txt"
echo "LoadFile saved.hair" >> "$scene/load.txt"
expect 0 "$hk" groom "$scene/load.txt" -o "$tmp/loaded.hair"
contains "$tmp/err" "loaded $strands strands"
cmp -s "$tmp/one.hair" "$tmp/loaded.hair" || fail "load then save changed the bytes"

# Bad input: exit 1, message with file and line.
expect 1 "$hk" groom "$tmp/missing.txt" -o "$tmp/x.hair"
contains "$tmp/err" "missing.txt"
printf 'Load false\nFrobnicate 3\n' > "$scene/bad1.txt"
expect 1 "$hk" groom "$scene/bad1.txt" -o "$tmp/x.hair"
contains "$tmp/err" "bad1.txt:2:.*unknown key 'Frobnicate'"
printf 'HairstyleInfo hairstyle.txt\nWickModel nowhere.obj\n' > "$scene/bad2.txt"
expect 1 "$hk" groom "$scene/bad2.txt" -o "$tmp/x.hair"
contains "$tmp/err" "bad2.txt:2:.*nowhere.obj"
printf 'Load true\n' > "$scene/bad3.txt"
expect 1 "$hk" groom "$scene/bad3.txt" -o "$tmp/x.hair"
contains "$tmp/err" "bad3.txt:1:.*LoadFile"
printf 'v 0 0 0\nv 1 0 0\nf 1 2 3\n' > "$scene/badwick.obj"
printf 'HairstyleInfo hairstyle.txt\nWickModel badwick.obj\n' > "$scene/bad4.txt"
expect 1 "$hk" groom "$scene/bad4.txt" -o "$tmp/x.hair"
contains "$tmp/err" "badwick.obj:3:"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"

# A truncated .hair file: a clear error, and the existing output is not touched.
head -c 200 "$tmp/one.hair" > "$tmp/cut.hair"
expect 1 "$hk" info "$tmp/cut.hair"
contains "$tmp/err" "cut.hair"
printf 'Load true\nLoadFile %s\n' "$tmp/cut.hair" > "$scene/cut.txt"
cp "$tmp/one.hair" "$tmp/keep.hair"
expect 1 "$hk" groom "$scene/cut.txt" -o "$tmp/keep.hair"
cmp -s "$tmp/one.hair" "$tmp/keep.hair" || fail "a failed groom damaged the existing output"

# Bad bytes (issue 13). A wick vertex at 1e39 made area x HairDensity overflow a long
# and the groom crash (SIGSEGV): now refused at its line.
awk '/^v / && !done { print "v 1e39 0.146 0.031"; done = 1; next } { print }' "$src/assets/wick.obj" > "$scene/huge.obj"
sed 's|^WickModel .*|WickModel huge.obj|' "$scene/setup.txt" > "$scene/huge.txt"
expect 1 "$hk" groom "$scene/huge.txt" -o "$tmp/x.hair"
contains "$tmp/err" "huge.obj:2: '1e39' is out of range (value 1 of 'v')"
printf 'v 0 0 0\nv 0x10 0 0\nv 0 1 0\nf 1 2 3\n' > "$scene/hex.obj"
sed 's|^WickModel .*|WickModel hex.obj|' "$scene/setup.txt" > "$scene/hex.txt"
expect 1 "$hk" groom "$scene/hex.txt" -o "$tmp/x.hair"
contains "$tmp/err" "hex.obj:2: '0x10' is not a decimal number"

# A 128-byte .hair whose header says 2,147,483,646 strands, 0 points and no segments
# array: refused from the header at once (it was 8.4 GB allocated and filled for 24 s)
# by every command that reads .hair files, naming the field that is wrong.
{ printf 'HAIR\376\377\377\177\0\0\0\0\2\0\0\0'; head -c 112 /dev/zero; } > "$tmp/lie.hair"
[ "$(wc -c < "$tmp/lie.hair")" -eq 128 ] || fail "lie.hair is not 128 bytes"
lie="strand count 2147483646 in the header needs at least 25769803880 bytes but the file has 128"
expect 1 "$hk" info "$tmp/lie.hair"
contains "$tmp/err" "lie.hair: $lie"
expect 1 "$hk" render "$tmp/lie.hair" --head "$src/assets/head.obj" --visuality "$scene/visuality.txt" -o "$tmp/x.png"
contains "$tmp/err" "$lie"
printf 'Load true\nLoadFile %s\n' "$tmp/lie.hair" > "$scene/lie.txt"
expect 1 "$hk" groom "$scene/lie.txt" -o "$tmp/x.hair"
contains "$tmp/err" "$lie"
expect 1 "$hk" helicoid fit "$tmp/lie.hair" -o "$tmp/x.txt"
contains "$tmp/err" "$lie"
expect 1 "$hk" helicoid reconstruct "$tmp/lie.hair" -o "$tmp/x.hair"
contains "$tmp/err" "$lie"
{ printf 'HAIR\377\377\377\377\0\0\0\0\2\0\0\0'; head -c 112 /dev/zero; } > "$tmp/lie2.hair"
expect 1 "$hk" info "$tmp/lie2.hair"
contains "$tmp/err" "strand count 4294967295 in the header needs at least"
grep -q "refusing to allocate" "$tmp/err" && fail "a lying header reported as an allocation: $(cat "$tmp/err")"

# The memory budget: HairDensity 17,000 on the default head (8.4 million strands, about
# 8.5 GB with their .hair) is refused before anything is grown, with the numbers; the
# limit moves with HAIRKIT_MEMORY_LIMIT (here down, to refuse the light scene).
sed 's/^HairDensity .*/HairDensity 17000/' "$scene/hairstyle.txt" > "$scene/dense.txt"
sed 's|^HairstyleInfo .*|HairstyleInfo dense.txt|; /^Save /d' "$scene/setup.txt" > "$scene/dense-setup.txt"
expect 1 "$hk" groom "$scene/dense-setup.txt" -o "$tmp/x.hair"
contains "$tmp/err" "dense.txt, $src/assets/wick.obj: HairDensity 17000 over the wick's 493.2 cm^2: 83[0-9]* strands of 41 points"
contains "$tmp/err" "would take about 8.4[0-9] GB of memory, over the limit of 8 GB (HAIRKIT_MEMORY_LIMIT raises it"
expect 1 env HAIRKIT_MEMORY_LIMIT=1M "$hk" groom "$scene/setup.txt" -o "$tmp/x.hair"
contains "$tmp/err" "over the limit of 0.001 GB"
expect 1 env HAIRKIT_MEMORY_LIMIT=1M "$hk" info "$tmp/one.hair"
contains "$tmp/err" "one.hair ($strands strands, .* points) would take about"
expect 1 env HAIRKIT_MEMORY_LIMIT=lots "$hk" info "$tmp/one.hair"
contains "$tmp/err" "HAIRKIT_MEMORY_LIMIT='lots' is not a size"
expect 0 env HAIRKIT_MEMORY_LIMIT=16G "$hk" info "$tmp/one.hair"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"

finish "groom CLI"
