#!/bin/sh
# The cost heatmaps of docs/benchmarks.md ("Where a walk spends its work"):
# the bunny (scenes/peers/bunny.toml, 480x270; needs `apt-get install
# glmark2-data`) and 10,000 random spheres (`kdray generate`, 480x360), with
# the restart and ropes walks, each on a fixed scale so that runs compare.
#
#   scripts/heatmaps.sh [SUFFIX]
#
# writes docs/images/heatmap-{bunny,spheres}-{restart,ropes}[-SUFFIX].png and
# prints one `--stats` JSON line per image (the figures the page quotes).
# Run it again after a change to the tree or the walks with a suffix (e.g.
# `after-clipping`) to get the "after" pictures beside the "before" ones.
set -eu
cd "$(dirname "$0")/.."
suffix=${1:+-$1}
cargo build --release --locked --quiet
kdray=./target/release/kdray
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
$kdray generate --kind spheres --count 10000 -o "$work/spheres.toml" 2>/dev/null
# Fixed scales, so that walks and builds compare: chosen so that the
# restart walk's hot regions saturate (its largest pixels reach
# about 1,400 and 1,600; a scale that high leaves most of the picture dark).
for walk in restart ropes; do
    $kdray render scenes/peers/bunny.toml --width 480 --height 270 --traversal "$walk" \
        -o "$work/bunny.png" --stats \
        --heatmap "docs/images/heatmap-bunny-$walk$suffix.png" --heatmap-max 400
    $kdray render "$work/spheres.toml" --width 480 --height 360 --traversal "$walk" \
        -o "$work/spheres.png" --stats \
        --heatmap "docs/images/heatmap-spheres-$walk$suffix.png" --heatmap-max 500
done
