#!/usr/bin/env bash
# The sweep of docs/benchmarks.md ("The sweep"): `kdray bench` on random
# spheres from 1 to 1,000,000 (its default sizes), the k-d tree (short
# stack) and brute force where its predicted frame fits the budget, three
# timed frames each. Keeps the run's bench.json as OUT (default
# docs/results/sweep.json) with the commit, its plots as docs/images/bench-*.png and
# the images at 1,000 and 1,000,000 spheres; scripts/bench_tables.py sweep
# makes the table from it.
#
#   scripts/sweep.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/sweep.json "$@"

"$kdray" bench --budget-s 120 --repeat "${REPEAT:-3}" --out "$work" --save-images >/dev/null
keep_bench_json "$work/bench.json" "$out"
for plot in time speedup build; do
    cp "$work/bench-$plot.png" "docs/images/bench-$plot.png"
done
for n in 1000 1000000; do
    cp "$work/render-spheres-$n-sah-short-stack.png" "docs/images/bench-render-$n.png"
done
python3 scripts/bench_tables.py sweep "$out"
