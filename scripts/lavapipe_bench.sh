#!/usr/bin/env bash
# The figures of docs/benchmarks.md's "Current results" and "The walks":
# `kdray bench` on the random spheres (1,000, 10,000 and 1,000,000, against
# brute force where its predicted frame fits the budget), the gears, and
# the scene files (the bunny's camera and shadow rays at 1920x1080, the
# bunny with its mirror, the torus, the mixed scene, the seed at
# 1920x1080), every walk, the default build. Each run's bench.json goes
# into OUT (default docs/results/lavapipe) with the machine, its load and
# the command; scripts/bench_tables.py makes the tables from them.
#
#   scripts/lavapipe_bench.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/lavapipe "$@"
repeat=${REPEAT:-3}

keep() { # NAME: the run's bench.json into OUT/NAME.json
    keep_bench_json "$work/$1/bench.json" "$out/$1.json"
}

"$kdray" bench --kind spheres --sizes 1000,10000,1000000 --traversal all --repeat "$repeat" \
    --budget-s 120 --out "$work/spheres" >/dev/null
keep spheres
"$kdray" bench --kind gears --sizes 4578 --traversal all --repeat "$repeat" --budget-s 120 \
    --out "$work/gears" >/dev/null
keep gears
bunny=/usr/share/glmark2/models/bunny.obj
scenes=()
if [ -f "$bunny" ]; then
    python3 scripts/peers/direct_variant.py scenes/peers/bunny.toml "$work/bunny-direct.json"
    scenes+=(--scene "$work/bunny-direct.json" --scene scenes/peers/bunny.toml)
fi
"$kdray" bench "${scenes[@]}" --scene scenes/torus.toml --scene scenes/mixed.toml \
    --accel kdtree --traversal all --repeat "$repeat" --out "$work/scenes" >/dev/null
keep scenes
"$kdray" bench --scene scenes/seed.toml --width 1920 --height 1080 --traversal all \
    --repeat "$repeat" --out "$work/seed" >/dev/null
keep seed
python3 scripts/bench_tables.py summary "$out"
python3 scripts/bench_tables.py walks "$out"
