#!/usr/bin/env bash
# A misspelt option, command, subcommand, benchmark or value gets the nearest valid name
# by edit distance (issue 18, item 2), exit 2; a word near nothing gets no guess.
# Usage: did_you_mean.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

g200="$src/examples/guides200/setup.txt"
# suggests WANTED ARGS...: exit 2, and stderr says "did you mean WANTED?"
suggests() {
    local want=$1; shift
    expect 2 "$hk" "$@"
    contains "$tmp/err" "did you mean $want?"
}
suggests --frames simulate "$g200" --frams 3 --fps 30 -o "$tmp/x"
suggests --frames simulate "$g200" --frmes=3 --fps 30 -o "$tmp/x"
suggests --shadow-map run "$g200" --shadowmap 256 -o "$tmp/x.png"
suggests --width render x.hair --widht 64 -o "$tmp/x.png"
suggests --from info --form ply x.ply
suggests --root bench --rot .
suggests --tolerance helicoid fit x.hair --tolerence 0.001 -o "$tmp/x.txt"
suggests --screenshot view x.hair --screnshot "$tmp/x.png"
suggests simulate simulat
suggests render rendr x.hair
suggests trace helicoid trase x.txt
suggests reconstruct helicoid reconstuct x.hair
suggests render bench rendr
suggests shake strand "$src/examples/strand/wavy.txt" --simulate 0.1 --motion shak
suggests groom help gromm
[ -e "$tmp/x" ] && fail "an output was made"

# Nothing near: the plain message, no guess.
expect 2 "$hk" run "$g200" --zzzzzzzz -o "$tmp/x.png"
contains "$tmp/err" "unknown option '--zzzzzzzz'"
grep -q "did you mean" "$tmp/err" && fail "a guess for --zzzzzzzz: $(cat "$tmp/err")"
expect 2 "$hk" xyzzyplugh
grep -q "did you mean" "$tmp/err" && fail "a guess for xyzzyplugh: $(cat "$tmp/err")"
expect 2 "$hk" helicoid wibble x
contains "$tmp/err" "unknown action 'wibble' (trace, interpolate, fit or reconstruct)"

finish did_you_mean
