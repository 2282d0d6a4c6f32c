#!/usr/bin/env bash
# Command-line contract of `hairkit helicoid` (issue 7): trace, interpolate, fit and
# reconstruct on the examples, determinism, and errors. Usage: helicoid.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

ex="$src/examples/helicoid"
expect 0 "$hk" helicoid --help
contains "$tmp/out" "usage: hairkit helicoid trace"

# trace: one strand per helicoid strand, plus its wisp
expect 0 "$hk" helicoid trace "$ex/wisp.txt" -o "$tmp/wisp.hair" --quiet
expect 0 "$hk" info "$tmp/wisp.hair"
contains "$tmp/out" "strands:       257"
expect 0 "$hk" helicoid trace "$ex/curly.txt" -o "$tmp/curly.hair" --step 0.002 --quiet
cp "$tmp/curly.hair" "$tmp/curly1.hair"
expect 0 "$hk" helicoid trace "$ex/curly.txt" -o "$tmp/curly.hair" --step 0.002 --quiet --threads 1
cmp -s "$tmp/curly.hair" "$tmp/curly1.hair" || fail "trace differs between runs"

# waves out of step: a phase jitter draws each strand's phase from the seed, the same
# bytes whatever the threads; without it the seed changes nothing
sed 's/^Waviness.*/Waviness 0.002 120 0.5/' "$ex/wisp.txt" > "$tmp/jitter.txt"
expect 0 "$hk" helicoid trace "$tmp/jitter.txt" -o "$tmp/j1.hair" --quiet --threads 1
expect 0 "$hk" helicoid trace "$tmp/jitter.txt" -o "$tmp/j2.hair" --quiet --threads 2
cmp -s "$tmp/j1.hair" "$tmp/j2.hair" || fail "jittered waves differ between 1 and 2 threads"
expect 0 "$hk" helicoid trace "$tmp/jitter.txt" -o "$tmp/j3.hair" --quiet --seed 7
cmp -s "$tmp/j1.hair" "$tmp/j3.hair" && fail "--seed does not change the jittered phases"
expect 0 "$hk" helicoid trace "$ex/wisp.txt" -o "$tmp/j4.hair" --quiet --seed 7
cmp -s "$tmp/wisp.hair" "$tmp/j4.hair" || fail "--seed changed waves without jitter"
cmp -s "$tmp/wisp.hair" "$tmp/j1.hair" && fail "jitter changed nothing"

# fit: the traced strand back; CSV per strand and a summary line
expect 0 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/fit.txt" --quiet
[ "$(head -n 1 "$tmp/out")" = "strand,points,pieces,error_m,frechet_m" ] || fail "bad CSV header"
grep -q '^# strands=1 mean_error_m=' "$tmp/out" || fail "no summary line: $(tail -n 1 "$tmp/out")"
awk -F'[= ]' '/^# strands/ { exit !($5 < 0.002) }' "$tmp/out" || fail "fit error over 2 mm: $(tail -n 1 "$tmp/out")"
expect 0 "$hk" helicoid trace "$tmp/fit.txt" -o "$tmp/refit.hair" --quiet
grep -q "looks like" "$tmp/err" && fail "a unit warning on a groom in metres: $(cat "$tmp/err")"
# any hair format hairkit reads (the points are copied exactly: the same fit), and a
# warning with the fix when the extent looks like centimetres (a strand of 8.7 cm written in cm; issue 17)
expect 0 "$hk" convert "$tmp/curly.hair" "$tmp/curly.obj" --quiet
expect 0 "$hk" helicoid fit "$tmp/curly.obj" -o "$tmp/fit_obj.txt" --quiet
cmp -s "$tmp/fit.txt" "$tmp/fit_obj.txt" || fail "the fit of the same strand read from OBJ differs"
expect 0 "$hk" convert "$tmp/curly.hair" "$tmp/curly_cm.obj" --scale 100 --quiet
expect 0 "$hk" helicoid fit "$tmp/curly_cm.obj" -o "$tmp/fit_cm.txt" --max-pieces 1 --quiet
contains "$tmp/err" "curly_cm.obj: warning: .*looks like centimetres.*--scale 0.01"
# the paper's Nelder-Mead, and a fixed layout of 4 pieces
expect 0 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/fit_nm.txt" --method nelder-mead --quiet
awk -F'[= ]' '/^# strands/ { exit !($5 < 0.002) }' "$tmp/out" || fail "nelder-mead fit over 2 mm: $(tail -n 1 "$tmp/out")"
expect 0 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/fit4.txt" --pieces 4 --quiet
grep -q '^1,121,4,' "$tmp/out" || fail "--pieces 4 gave: $(sed -n 2p "$tmp/out")"
[ "$(grep -c '^Piece' "$tmp/fit4.txt")" = 4 ] || fail "--pieces 4 wrote $(grep -c '^Piece' "$tmp/fit4.txt") pieces"
expect 2 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/x.txt" --method simplex
contains "$tmp/err" "--method expects lm or nelder-mead"
expect 2 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/x.txt" --pieces 65
contains "$tmp/err" "--pieces expects"
expect 2 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/x.txt" --pieces 3 --max-pieces 5
contains "$tmp/err" "drop --max-pieces"
# more pieces than the strand holds: as many as it does (121 samples, 6 a piece: 24)
expect 0 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/fit40.txt" --pieces 40 --quiet
grep -q '^1,121,24,' "$tmp/out" || fail "--pieces 40 gave: $(sed -n 2p "$tmp/out")"

# --waves: the example's wavy strand (one piece with eq. 4's waves of 3 mm at 157 rad/m)
# fitted with waves of its own recovers them (a Waves line; without it the plain fitter
# needs about 9 pieces a turn), and traced back it lies on the strand (the reference: the
# example traced at its own step; docs/helicoid-fitting.md 5e)
expect 0 "$hk" helicoid trace "$src/examples/helicoid/wavy.txt" -o "$tmp/wavy.hair" --quiet
expect 0 "$hk" helicoid fit "$tmp/wavy.hair" -o "$tmp/wavyfit.txt" --waves --quiet
grep -q ' with_waves=1$' "$tmp/out" || fail "--waves kept no waves: $(tail -n 1 "$tmp/out")"
awk -F'[= ]' '/^# strands/ { exit !($5 < 0.0001) }' "$tmp/out" || fail "--waves fit over 0.1 mm: $(tail -n 1 "$tmp/out")"
awk '/^Waves/ { found = 1; if ($2 < 0.0029 || $2 > 0.0031 || $3 < 156 || $3 > 158) exit 1 } END { exit !found }' \
    "$tmp/wavyfit.txt" || fail "waves not recovered: $(grep '^Waves' "$tmp/wavyfit.txt")"
[ "$(grep -c '^Piece' "$tmp/wavyfit.txt")" -le 5 ] || fail "--waves wrote $(grep -c '^Piece' "$tmp/wavyfit.txt") pieces"
expect 0 "$hk" helicoid trace "$tmp/wavyfit.txt" -o "$tmp/wavyback.hair" --step 0.001 --quiet
# interpolation blends pieces only: guides with waves of their own are refused
expect 1 "$hk" helicoid interpolate "$tmp/wavyfit.txt" --surface "$src/assets/wick.obj" -o "$tmp/x.hair" --quiet
contains "$tmp/err" "has waves of its own"
expect 2 "$hk" helicoid reconstruct "$tmp/wavy.hair" -o "$tmp/x.hair" --waves
contains "$tmp/err" "--waves is for fit"
expect 2 "$hk" helicoid fit "$tmp/wavy.hair" -o "$tmp/x.txt" --waves --pieces 3
contains "$tmp/err" "--waves chooses its own layout"

# interpolate: random roots over the wick. Nine plain guides (the wavy 40 of the example
# would make the reconstruction below slow to fit): curly at the back, straight in front
nine="$tmp/nine.txt"
cat > "$nine" <<'EOF'
Step 0.002
Strand
Root  0.0 0.148 0.01
Frame 0 1 0   0 0 -1
Piece 10 0 0 0 0.1
Piece 8 0 0 0 0.1
Strand
Root  -0.06 0.12 -0.04
Frame -0.609208 0.507673 -0.609208   -0.358979 -0.861550 -0.358979
Piece 60 0 5 0.3 0.08
Piece 60 0 5 0.3 0.08
Strand
Root  0.06 0.12 -0.04
Frame 0.609208 0.507673 -0.609208   0.358979 -0.861550 -0.358979
Piece 60 0 -5 0.3 0.08
Piece 60 0 -5 0.3 0.08
Strand
Root  0 0.11 -0.08
Frame 0.000000 0.600000 -0.800000   0.000000 -0.800000 -0.600000
Piece 40 0 0 0.2 0.08
Piece 40 0 0 0.2 0.08
Strand
Root  -0.07 0.09 0.03
Frame -0.847998 0.423999 0.317999   -0.397003 -0.905663 0.148876
Piece 50 2 0 0.25 0.08
Piece 50 2 0 0.25 0.08
Strand
Root  0.07 0.09 0.03
Frame 0.847998 0.423999 0.317999   0.397003 -0.905663 0.148876
Piece 50 -2 0 0.25 0.08
Piece 50 -2 0 0.25 0.08
Strand
Root  -0.04 0.13 0.06
Frame -0.390360 0.780720 0.487950   -0.487712 -0.624881 0.609640
Piece 5 0 0 0 0.08
Piece 5 0 0 0 0.08
Strand
Root  0.04 0.13 0.06
Frame 0.390360 0.780720 0.487950   0.487712 -0.624881 0.609640
Piece 5 0 0 0 0.08
Piece 5 0 0 0 0.08
Strand
Root  0 0.14 0.07
Frame 0.000000 0.800000 0.600000   0.000000 -0.600000 0.800000
Piece 3 0 0 0 0.08
Piece 3 0 0 0 0.08
EOF
expect 0 "$hk" helicoid interpolate "$nine" --surface "$src/assets/wick.obj" --count 500 \
    -o "$tmp/interp.hair" --params "$tmp/interp.txt" --quiet
expect 0 "$hk" info "$tmp/interp.hair"
contains "$tmp/out" "strands:       500"
expect 0 "$hk" helicoid interpolate "$nine" --surface "$src/assets/wick.obj" --count 500 \
    -o "$tmp/interp2.hair" --threads 1 --quiet
cmp -s "$tmp/interp.hair" "$tmp/interp2.hair" || fail "interpolation depends on the threads"
# leaves_scalp PARAMS.txt: every strand leaves the scalp steeply (E_T . n > 0.5 against the
# outward normal of the head's cranium, the ellipsoid of assets/README.md, at its root): the
# root frames are averaged relative to the surface normal (paper 4.3). Averaged in space the
# nine guides' strands here come as low as 0.15; relative to the normal, 0.92.
leaves_scalp() {
    awk '$1 == "Root" { x = $2 + 0.001; y = $3 - 0.068; z = $4 - 0.010 }
         $1 == "Frame" {
             gx = x / 0.0064; gy = y / 0.0064; gz = z / 0.0121
             up = ($2 * gx + $3 * gy + $4 * gz) / sqrt(gx * gx + gy * gy + gz * gz)
             if (up < 0.5) { print "strand " NR ": E_T . n = " up; bad = 1 }
         }
         END { exit bad }' "$1" > "$tmp/up.log" || fail "strands not leaving the scalp in $1: $(head -n 3 "$tmp/up.log")"
}
leaves_scalp "$tmp/interp.txt"
# the example styles load and interpolate
for style in guides bob; do
    expect 0 "$hk" helicoid interpolate "$ex/$style.txt" --surface "$src/assets/wick.obj" --count 100 \
        -o "$tmp/style.hair" --quiet
done

# interpolate --follicles: one strand per follicle of the particle sampler (paper 4.3)
wick="$src/assets/wick.obj"
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --head "$src/assets/head.obj" \
    --follicles 0.02 -o "$tmp/fol.hair" --params "$tmp/fol.txt" --threads 2
contains "$tmp/err" "follicles 20 mm apart on .*wick.obj"
n=$(grep -c '^Root' "$tmp/fol.txt")
# a hexagonal packing of the wick's 493 cm^2 at 2 cm: 142, plus half the contour's row: 157
awk -v n="$n" 'BEGIN { exit !(n >= 130 && n <= 185) }' || fail "$n follicles at 2 cm (about 157 expected)"
expect 0 "$hk" info "$tmp/fol.hair"
contains "$tmp/out" "strands:       $n\$"
# the roots: on the wick (near its vertices), and follicles, not random points: no two
# closer than 0.6 spacing (the sampler keeps them at 0.85 or more)
awk 'FNR == NR && $1 == "v" { vx[++nv] = $2; vy[nv] = $3; vz[nv] = $4; next }
     FNR != NR && $1 == "Root" { rx[++nr] = $2; ry[nr] = $3; rz[nr] = $4 }
     END {
         for (i = 1; i <= nr; i++) {
             best = 1
             for (j = 1; j <= nv; j++) {
                 d = (rx[i]-vx[j])^2 + (ry[i]-vy[j])^2 + (rz[i]-vz[j])^2
                 if (d < best) best = d
             }
             if (best > 0.01^2) { print "root " i " is " sqrt(best) " m from the wick"; bad = 1 }
             for (j = 1; j < i; j++) {
                 d = (rx[i]-rx[j])^2 + (ry[i]-ry[j])^2 + (rz[i]-rz[j])^2
                 if (d < (0.6 * 0.02)^2) { print "roots " j " and " i " are " sqrt(d) " m apart"; bad = 1 }
             }
         }
         exit bad
     }' "$wick" "$tmp/fol.txt" > "$tmp/roots.log" || fail "follicle roots: $(head -n 3 "$tmp/roots.log")"
leaves_scalp "$tmp/fol.txt"
# the same bytes with one thread and two, and without the summary under --quiet
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --head "$src/assets/head.obj" \
    --follicles 0.02 -o "$tmp/fol1.hair" --params "$tmp/fol1.txt" --threads 1 --quiet
[ -s "$tmp/err" ] && fail "--quiet printed: $(cat "$tmp/err")"
cmp -s "$tmp/fol.hair" "$tmp/fol1.hair" || fail "--follicles: .hair differs between 1 and 2 threads"
cmp -s "$tmp/fol.txt" "$tmp/fol1.txt" || fail "--follicles: parameters differ between 1 and 2 threads"
# another seed, other follicles; no head, other follicles (the fit differs)
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --head "$src/assets/head.obj" \
    --follicles 0.02 -o "$tmp/fol2.hair" --seed 7 --quiet
cmp -s "$tmp/fol.hair" "$tmp/fol2.hair" && fail "--seed does not change the follicles"
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0.02 -o "$tmp/fol3.hair" --quiet
cmp -s "$tmp/fol.hair" "$tmp/fol3.hair" && fail "--head does not change the follicles"
# errors: bad spacings, conflicting options, missing files, too many follicles
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0 -o "$tmp/x.hair"
contains "$tmp/err" "--follicles expects a spacing"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 5mm -o "$tmp/x.hair"
contains "$tmp/err" "'5mm'"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles nan -o "$tmp/x.hair"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0.01 --count 10 -o "$tmp/x.hair"
contains "$tmp/err" "drop --count"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0.01 --density 5 -o "$tmp/x.hair"
contains "$tmp/err" "drop --density"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --head "$src/assets/head.obj" -o "$tmp/x.hair"
contains "$tmp/err" "--head .*--follicles"
expect 1 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0.01 \
    --head "$tmp/nohead.obj" -o "$tmp/x.hair"
contains "$tmp/err" "nohead.obj"
expect 1 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$wick" --follicles 0.0002 -o "$tmp/x.hair"
contains "$tmp/err" "wick.obj.*follicles, more than"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"

# reconstruct: from one strand in five
expect 0 "$hk" helicoid reconstruct "$tmp/interp.hair" --every 5 -o "$tmp/recon.hair" --quiet
grep -q '^# strands=500 fitted=100 ' "$tmp/out" || fail "reconstruct summary: $(cat "$tmp/out")"
# the head example without its waves: its strands lift off the scalp by 77 degrees in
# 8 mm. The default layout by length (a 1 cm root piece, then 3 cm) rebuilds these 600 to
# 11 mm (docs/helicoid-fitting.md); 4 equal pieces (9 cm), whose first piece must both lift
# off and fall, to 22 mm
sed 's/^Waviness.*//' "$ex/guides.txt" > "$tmp/smooth.txt"
expect 0 "$hk" helicoid interpolate "$tmp/smooth.txt" --surface "$wick" --count 600 -o "$tmp/smooth.hair" --quiet
expect 0 "$hk" helicoid reconstruct "$tmp/smooth.hair" -o "$tmp/smooth_rebuilt.hair" --quiet
awk -F'[= ]' '/^# strands/ { exit !($11 < 0.015) }' "$tmp/out" || fail "head rebuilt to over 15 mm: $(cat "$tmp/out")"
expect 0 "$hk" helicoid reconstruct "$tmp/smooth.hair" -o "$tmp/smooth_rebuilt4.hair" --pieces 4 --quiet
awk -F'[= ]' '/^# strands/ { exit !($11 > 0.015) }' "$tmp/out" || fail "4 equal pieces did well: $(cat "$tmp/out")"
expect 2 "$hk" helicoid reconstruct "$tmp/smooth.hair" -o "$tmp/x.hair" --pieces 4 --piece-length 0.03
contains "$tmp/err" "two layouts"
expect 2 "$hk" helicoid fit "$tmp/smooth.hair" -o "$tmp/x.txt" --root-piece 0.01
contains "$tmp/err" "give --piece-length"

# the same with 1 and 2 threads, byte for byte
expect 0 "$hk" helicoid reconstruct "$tmp/interp.hair" --every 5 -o "$tmp/recon1.hair" --quiet --threads 1
cmp -s "$tmp/recon.hair" "$tmp/recon1.hair" || fail "reconstruct differs between 1 and 2 threads"

# errors
expect 2 "$hk" helicoid
expect 2 "$hk" helicoid frobnicate x
expect 2 "$hk" helicoid trace "$ex/wisp.txt"
contains "$tmp/err" "-o FILE"
expect 2 "$hk" helicoid interpolate "$ex/guides.txt" -o "$tmp/x.hair"
contains "$tmp/err" "--surface"
expect 2 "$hk" helicoid trace "$ex/wisp.txt" -o "$tmp/x.hair" --step 0
expect 1 "$hk" helicoid trace "$tmp/missing.txt" -o "$tmp/x.hair"
contains "$tmp/err" "missing.txt"
printf 'Strand\nRoot 0 0 0\nFrame 1 0 0 1 1 0\nPiece 1 0 0 0 0.1\n' > "$tmp/bad.txt"
expect 1 "$hk" helicoid trace "$tmp/bad.txt" -o "$tmp/x.hair"
contains "$tmp/err" "bad.txt:3"
expect 1 "$hk" helicoid fit "$tmp/bad.txt" -o "$tmp/x.txt"
[ -e "$tmp/x.hair" ] && fail "output written despite an error"

# the benchmark runs (its figures are not checked), with rows of the real grooms when
# ../shared/hair-data is there and a line saying they are skipped when it is not
expect 0 "$hk" bench helicoid --quick --root "$src"
contains "$tmp/out" "fits/s"
if [ -f "$src/../shared/hair-data/SOURCES.md" ]; then
    contains "$tmp/out" "^  Bangs_100.hair  *10 "
    contains "$tmp/out" "helicoid reconstruction of Bangs_100.hair"
else
    contains "$tmp/out" "Bangs_100.hair  *skipped"
fi

finish helicoid
