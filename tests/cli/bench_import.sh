#!/usr/bin/env bash
# `hairkit bench import` runs: with ../shared/hair-data it prints the Sintel import's
# stages and the still-head drift; without it (a root whose ../shared/hair-data is
# absent) it says it skipped (figures are not checked: tests check correctness, not
# speed; the import itself is tested by tests/test_import_data.c). Usage:
# bench_import.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

mkdir -p "$tmp/root/src"
expect 0 "$hk" bench import --quick --root "$tmp/root/src"
contains "$tmp/out" "skipped: .* is absent"
if [ -f "$src/../shared/hair-data/SintelHairOriginal-sintel_hair.16points.tfx" ]; then
    expect 0 "$hk" bench import --quick --root "$src"
    contains "$tmp/out" "head's field"
    contains "$tmp/out" "writing"
    contains "$tmp/out" "drift from the capture"
else
    echo "bench_import.sh: ../shared/hair-data absent, the import itself not run"
fi
expect 0 "$hk" bench --help
contains "$tmp/out" "import"

finish "bench import CLI"
