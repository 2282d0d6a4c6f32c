# Shared by the command-line tests (sourced): HAIRKIT and SRCDIR from the arguments, a
# private temporary folder, and the checks. Each test ends with `finish NAME`.
set -u
hk="$1"
src="$2"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }

# expect CODE CMD... : runs CMD, stdout to $tmp/out, stderr to $tmp/err, checks the exit code
expect() {
    local want=$1; shift
    "$@" >"$tmp/out" 2>"$tmp/err"
    local got=$?
    [ "$got" -eq "$want" ] || fail "exit $got (wanted $want): $* ; stderr: $(cat "$tmp/err")"
}
contains() { grep -q -- "$2" "$1" || fail "$1 lacks '$2': $(head -c 300 "$1")"; }

finish() {
    [ "$fails" -eq 0 ] || { echo "$1: $fails failure(s)" >&2; exit 1; }
    echo "$1: all checks passed"
}

# light_scene DIR [SETUP LINES...]: a light copy of the default scene in DIR (density
# 4 per cm^2: about 2,000 strands, quick under the sanitizers) whose setup.txt holds
# the given lines first, then the scene's files (the assets named by absolute path).
light_scene() {
    local dir=$1; shift
    mkdir -p "$dir"
    sed 's/^HairDensity .*/HairDensity 4/' "$src/examples/default/hairstyle.txt" > "$dir/hairstyle.txt"
    cp "$src/examples/default/collision.txt" "$src/examples/default/visuality.txt" "$dir/"
    {
        for line in "$@"; do echo "$line"; done
        echo "HairstyleInfo hairstyle.txt"
        echo "CollisionInfo collision.txt"
        echo "VisualityInfo visuality.txt"
        echo "HeadModel $src/assets/head.obj"
        echo "WickModel $src/assets/wick.obj"
    } > "$dir/setup.txt"
}
