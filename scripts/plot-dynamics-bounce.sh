#!/usr/bin/env bash
# The accuracy figure of docs/dynamics.md: the tip height of the curly strand
# (examples/strand/curly.txt, damping on, still head, released from its natural shape)
# over 2 s with TR-BDF2 at dt = 1/30 s and 1 ms (the converged reference) and the linear
# Euler step at 1/30 s. Prints each curve's bounce frequency (upward crossings of the mean
# of the last second, after 0.05 s) and peak-to-peak tip motion over the first second, the
# analysis of tests/test_dynamics_stepping.c (bounce_frequency, peak_to_peak).
#
# Usage: scripts/plot-dynamics-bounce.sh [HAIRKIT [OUT.png]]
#   (defaults: build/hairkit, docs/images/dynamics-bounce.png)
#
# Needs gnuplot with the pngcairo terminal (Debian: apt-get install gnuplot-nox). Only this
# doc-image script uses gnuplot: scripts/install-deps.sh does not install it and no test
# needs it.
set -euo pipefail
cd "$(dirname "$0")/.."
hk=${1:-./build/hairkit}
out=${2:-docs/images/dynamics-bounce.png}
if ! command -v gnuplot > /dev/null 2>&1; then
    echo "plot-dynamics-bounce: needs gnuplot (apt-get install gnuplot-nox); only the doc images use it" >&2
    exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# name:dt:integrator:title
curves=("fine:0.001:trbdf2:TR-BDF2, dt = 1 ms (reference)"
        "coarse:0.03333333333333333:trbdf2:TR-BDF2, dt = 1/30 s"
        "euler:0.03333333333333333:euler:linear Euler, dt = 1/30 s")
for c in "${curves[@]}"; do
    IFS=: read -r name dt integrator title <<< "$c"
    "$hk" strand examples/strand/curly.txt --simulate 2 --dt "$dt" --integrator "$integrator" --damping on \
        --tip-csv "$tmp/$name.csv" --quiet > /dev/null
done

# Figures, as in tests/test_dynamics_stepping.c.
echo "curly strand, still head, damping on, tip height over 2 s:"
for c in "${curves[@]}"; do
    IFS=: read -r name dt integrator title <<< "$c"
    awk -F, -v title="$title" '
        BEGIN { n = 0 }
        NR > 1 { t[n] = $1 + 0; y[n] = $3 + 0; n++ }
        END {
            mean = 0; for (i = int(n / 2); i < n; i++) mean += y[i]; mean /= n - int(n / 2)
            crossings = 0
            for (i = 1; i < n; i++)
                if (y[i - 1] < mean && y[i] >= mean && t[i] > 0.05) {
                    tc = t[i - 1] + (mean - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1])
                    if (!crossings) first = tc
                    last = tc; crossings++
                }
            lo = 1e30; hi = -1e30
            for (i = 0; i < n && t[i] <= 1 + 1e-9; i++) { if (y[i] < lo) lo = y[i]; if (y[i] > hi) hi = y[i] }
            f = crossings > 1 ? (crossings - 1) / (last - first) : 0
            printf("  %-34s bounce %.3f Hz, first-second peak-to-peak %.2f mm\n", title, f, 1e3 * (hi - lo))
        }' "$tmp/$name.csv"
done

gnuplot <<EOF
set terminal pngcairo size 900,400 enhanced font "sans,11"
set output "$out"
set datafile separator ","
set key top right box opaque
set grid lc rgb "#dddddd"
set xlabel "time (s)"
set ylabel "tip height y (mm)"
set title "curly strand (examples/strand/curly.txt), still head, damping on: tip height"
set xrange [0:2]
plot "$tmp/fine.csv" skip 1 using 1:(\$3*1000) with lines lw 3 lc rgb "#999999" title "TR-BDF2, dt = 1 ms (reference)", \
     "$tmp/coarse.csv" skip 1 using 1:(\$3*1000) with linespoints lw 1.5 pt 7 ps 0.5 lc rgb "#1f5fbf" title "TR-BDF2, dt = 1/30 s", \
     "$tmp/euler.csv" skip 1 using 1:(\$3*1000) with linespoints lw 1.5 pt 5 ps 0.5 dt 2 lc rgb "#d04020" title "linear Euler, dt = 1/30 s"
EOF
echo "wrote $out"
