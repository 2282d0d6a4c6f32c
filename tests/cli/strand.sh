#!/usr/bin/env bash
# Command-line contract of `hairkit strand` (DESIGN.md): output format, options, and
# clear errors with the right exit codes for bad input. Usage: strand.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

expect 0 "$hk" --help
contains "$tmp/out" "strand"
expect 0 "$hk" strand --help
contains "$tmp/out" "usage: hairkit strand HAIRSTYLE.txt"
expect 2 "$hk"
expect 2 "$hk" frobnicate

# The curly example: header line, CSV header, rows every VisualityStep (1 mm over 20 cm).
expect 0 "$hk" strand "$src/examples/strand/curly.txt" --quiet
head -n 1 "$tmp/out" | grep -Eq '^# energy=-?[0-9.]+e[-+][0-9]+ iterations=[0-9]+ evaluations=[0-9]+ solver=newton$' \
    || fail "bad first line: $(head -n 1 "$tmp/out")"
[ "$(sed -n 2p "$tmp/out")" = "s,x,y,z" ] || fail "bad CSV header"
[ "$(wc -l < "$tmp/out")" -eq 203 ] || fail "expected 201 samples, got $(( $(wc -l < "$tmp/out") - 2 ))"
[ "$(sed -n 3p "$tmp/out")" = "0,0,0,0" ] || fail "first row is not the root: $(sed -n 3p "$tmp/out")"
tail -n 1 "$tmp/out" | grep -Eq '^0\.2(0*)?,' || fail "last row is not the tip s = L: $(tail -n 1 "$tmp/out")"
[ -s "$tmp/err" ] && fail "--quiet printed to stderr: $(cat "$tmp/err")"
cp "$tmp/out" "$tmp/first"

# Deterministic: the same input gives the same bytes.
expect 0 "$hk" strand "$src/examples/strand/curly.txt" --quiet
cmp -s "$tmp/out" "$tmp/first" || fail "two runs differ"

# Root, direction, solver, collisions and the plot.
expect 0 "$hk" strand "$src/examples/strand/straight.txt" --root 1,2,3 --dir 0,-1,0 --quiet
[ "$(sed -n 3p "$tmp/out")" = "0,1,2,3" ] || fail "--root not honoured: $(sed -n 3p "$tmp/out")"
expect 0 "$hk" strand "$src/examples/thesis/hairstyle.txt" --collision "$src/examples/thesis/collision.txt" \
    --root 0,0.151,0 --dir 0,0,1 --solver rosenbrock --plot "$tmp/plot.png" --quiet
contains "$tmp/out" "solver=rosenbrock"
[ "$(head -c 4 "$tmp/plot.png" | od -An -c | tr -d ' ')" = "211PNG" ] || fail "--plot did not write a PNG"
ls "$tmp" | grep -q 'tmp-' && fail "temporary file left behind"

# Bad input: exit 1 and a message naming the file (and line when there is one).
expect 1 "$hk" strand "$tmp/missing.txt"
contains "$tmp/err" "missing.txt"
[ -s "$tmp/out" ] && fail "output written despite an error"
sed 's/^Young .*/Young -3/' "$src/examples/strand/curly.txt" > "$tmp/bad.txt"
expect 1 "$hk" strand "$tmp/bad.txt"
contains "$tmp/err" "bad.txt:[0-9]*:.*Young"
printf 'HairLengths 0.1\n\0\1\2binary' > "$tmp/binary.txt"
expect 1 "$hk" strand "$tmp/binary.txt"
contains "$tmp/err" "binary.txt"
: > "$tmp/empty.txt"
expect 1 "$hk" strand "$tmp/empty.txt"
contains "$tmp/err" "empty.txt"
expect 1 "$hk" strand "$src/examples/strand/curly.txt" --collision "$src/examples/strand/curly.txt"
contains "$tmp/err" "curly.txt:[0-9]*:"

# Usage errors: exit 2.
expect 2 "$hk" strand
expect 2 "$hk" strand "$src/examples/strand/curly.txt" --root 1,2
expect 2 "$hk" strand "$src/examples/strand/curly.txt" --dir 0,0,0
expect 2 "$hk" strand "$src/examples/strand/curly.txt" --solver simplex
expect 2 "$hk" strand "$src/examples/strand/curly.txt" --envelope 2
expect 2 "$hk" strand "$src/examples/strand/curly.txt" --bogus
expect 2 "$hk" strand "$src/examples/strand/curly.txt" extra.txt

# The benchmark runs (figures are not checked: tests check correctness, not speed).
expect 0 "$hk" bench statics --quick
contains "$tmp/out" "newton"
expect 0 "$hk" bench dynamics --quick --root "$src"
contains "$tmp/out" "frames/s"
contains "$tmp/out" "N = 10 on 2 threads, ms a frame in each of 2 runs"
expect 0 "$hk" bench stability --quick --root "$src"
contains "$tmp/out" "still, undamped"
contains "$tmp/out" "linear Euler"
expect 0 "$hk" bench long-heads --quick --root "$src"
contains "$tmp/out" "30  shake      ran "

finish "strand CLI"
