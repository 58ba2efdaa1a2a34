#!/usr/bin/env bash
# What glass costs (docs/benchmarks.md, "Glass"): `kdray render --stats` of
# the seed scene and of scenes/glass.toml (the seed with a glass ball) at
# 1280x720, alternating, ROUNDS rounds (default 5). Writes OUT (default
# docs/results/glass.json) with the machine, its load and the commit, and
# prints the table scripts/glass_table.py makes of it.
#
#   scripts/glass_cost.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/glass.json "$@"
rounds=${ROUNDS:-5}

runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    for scene in seed glass; do
        json=$("$kdray" render "scenes/$scene.toml" --width 1280 --height 720 --stats -o "$work/out.png")
        runs+=("{\"scene\": \"$scene\", \"stats\": $json}")
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/glass_table.py "$out"
