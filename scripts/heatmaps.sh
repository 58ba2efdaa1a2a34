#!/usr/bin/env bash
# The cost heatmaps of docs/benchmarks.md ("Where a walk spends its work"):
# the bunny (scenes/peers/bunny.toml, 480x270; needs `apt-get install
# glmark2-data`) and 10,000 random spheres (`kdray generate`, 480x360),
# with every walk, each on a fixed scale so that walks and runs compare.
# Writes docs/images/heatmap-{bunny,spheres}-WALK.png and OUT (default
# docs/results/heatmaps.json: every render's `--stats`, the machine, its
# load and the commit), and prints the table scripts/heatmap_table.py
# makes of it.
#
#   scripts/heatmaps.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/heatmaps.json "$@"

"$kdray" generate --kind spheres --count 10000 -o "$work/spheres.toml" 2>/dev/null
runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
# Fixed scales (nodes visited plus objects tested by a pixel's rays),
# chosen so that the restart walk's hot regions saturate: its largest
# pixels reach about 1,400 and 1,600, and a scale that high leaves most
# of the picture dark.
for walk in restart ropes short-stack; do
    json=$("$kdray" render scenes/peers/bunny.toml --width 480 --height 270 --traversal "$walk" \
        -o "$work/bunny.png" --stats \
        --heatmap "docs/images/heatmap-bunny-$walk.png" --heatmap-max 400)
    runs+=("{\"scene\": \"bunny\", \"walk\": \"$walk\", \"stats\": $json}")
    json=$("$kdray" render "$work/spheres.toml" --width 480 --height 360 --traversal "$walk" \
        -o "$work/spheres.png" --stats \
        --heatmap "docs/images/heatmap-spheres-$walk.png" --heatmap-max 500)
    runs+=("{\"scene\": \"10,000 spheres\", \"walk\": \"$walk\", \"stats\": $json}")
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/heatmap_table.py "$out"
