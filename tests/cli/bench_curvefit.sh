#!/usr/bin/env bash
# `hairkit bench curvefit` runs (figures are not checked: tests check correctness, not
# speed; the fitting itself is tested by tests/test_curvefit.c). Usage: bench_curvefit.sh HAIRKIT SRCDIR
source "$(dirname "$0")/lib/common.sh"

expect 0 "$hk" bench curvefit --quick
contains "$tmp/out" "fits/s"
contains "$tmp/out" "0.1 mm noise, single"
expect 0 "$hk" bench --help
contains "$tmp/out" "curvefit"

finish "bench curvefit CLI"
