#!/usr/bin/env bash
# `hairkit bench io` runs (figures are not checked: tests check correctness, not speed;
# the readers and writers are tested by tests/test_hair_formats.c and test_hair_data.c).
# Usage: bench_io.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

expect 0 "$hk" bench io --quick --root "$src"
contains "$tmp/out" "hk_hair_save / fwrite + fsync"
contains "$tmp/out" "hk_hair_load / malloc + fread"
if [ -f "$src/../shared/hair-data/SOURCES.md" ]; then
    contains "$tmp/out" "Sintel .tfx -> .hair (11,400 strands"
else
    contains "$tmp/out" "skipped"
fi
# Without the shared data the conversion is skipped, saying so.
expect 0 "$hk" bench io --quick --root "$tmp"
contains "$tmp/out" "Sintel .tfx -> .hair: skipped"
expect 0 "$hk" bench --help
contains "$tmp/out" "io "

finish "bench io CLI"
