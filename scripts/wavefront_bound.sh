#!/usr/bin/env bash
# The path tracer's kernel shape, measured (docs/design.md, "One loop per
# pixel"; docs/benchmarks.md, "Wavefront or one loop"): `kdray bench
# --wavefront-bound` on the Cornell box (128x128) and the bunny under the
# sky (160x90), each at max_depth 1 (every lane traces a camera ray and a
# shadow ray: no path outlives its neighbours) and at its own depth (paths
# of every length side by side). Writes OUT (default
# docs/results/wavefront-bound.json) with the machine, adapter and commit,
# and prints the table scripts/wavefront_table.py makes of it.
#
#   scripts/wavefront_bound.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
kdray=${1:-target/release/kdray}
out=${2:-docs/results/wavefront-bound.json}
repeat=${REPEAT:-5}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cases=()
run() { # NAME SCENE WIDTH HEIGHT DEPTH
    "$kdray" bench --wavefront-bound --scene "$2" --width "$3" --height "$4" --max-depth "$5" \
        --repeat "$repeat" --out "$work/$1" >/dev/null
    cases+=("{\"case\": \"$1\", \"max_depth\": $5, \"report\": $(cat "$work/$1/wavefront-bound.json")}")
}
run "cornell depth 1" scenes/cornell_box.toml 128 128 1
run "cornell depth 8" scenes/cornell_box.toml 128 128 8
if [ -f /usr/share/glmark2/models/bunny.obj ]; then
    run "bunny_sky depth 1" scenes/bunny_sky.toml 160 90 1
    run "bunny_sky depth 6" scenes/bunny_sky.toml 160 90 6
fi

write_results_json "$out" cases \
    machine="$(cpu_cores)" \
    commit="$(git rev-parse --short HEAD)" \
    uptime_after="$(uptime | sed 's/^ *//')" \
    -- "${cases[@]}"
python3 scripts/wavefront_table.py "$out"
