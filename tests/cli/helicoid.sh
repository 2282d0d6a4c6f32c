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

# fit: the traced strand back; CSV per strand and a summary line
expect 0 "$hk" helicoid fit "$tmp/curly.hair" -o "$tmp/fit.txt" --quiet
[ "$(head -n 1 "$tmp/out")" = "strand,points,pieces,error_m,frechet_m" ] || fail "bad CSV header"
grep -q '^# strands=1 mean_error_m=' "$tmp/out" || fail "no summary line: $(tail -n 1 "$tmp/out")"
awk -F'[= ]' '/^# strands/ { exit !($5 < 0.002) }' "$tmp/out" || fail "fit error over 2 mm: $(tail -n 1 "$tmp/out")"
expect 0 "$hk" helicoid trace "$tmp/fit.txt" -o "$tmp/refit.hair" --quiet

# interpolate: the example guides over the wick
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$src/assets/wick.obj" --count 500 \
    -o "$tmp/interp.hair" --params "$tmp/interp.txt" --quiet
expect 0 "$hk" info "$tmp/interp.hair"
contains "$tmp/out" "strands:       500"
expect 0 "$hk" helicoid interpolate "$ex/guides.txt" --surface "$src/assets/wick.obj" --count 500 \
    -o "$tmp/interp2.hair" --threads 1 --quiet
cmp -s "$tmp/interp.hair" "$tmp/interp2.hair" || fail "interpolation depends on the threads"

# reconstruct: from one strand in five
expect 0 "$hk" helicoid reconstruct "$tmp/interp.hair" --every 5 -o "$tmp/recon.hair" --quiet
grep -q '^# strands=500 fitted=100 ' "$tmp/out" || fail "reconstruct summary: $(cat "$tmp/out")"

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

# the benchmark runs (its figures are not checked)
expect 0 "$hk" bench helicoid --quick
contains "$tmp/out" "fits/s"

finish helicoid
