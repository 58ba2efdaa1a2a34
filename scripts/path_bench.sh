#!/usr/bin/env bash
# The path tracer's speed on this machine's adapter (docs/benchmarks.md,
# "The path tracer"): samples and rays per second of GPU time, every walk
# and brute force, on incoherent rays, and the Whitted frames of the same
# scenes beside them. Each figure is one `kdray render --stats` JSON; the
# runs alternate walk by walk, REPEAT times, so that a change in load hits
# every walk alike. Writes OUT (default docs/results/path-bench.json) and
# prints the table scripts/path_table.py makes of it.
#
#   scripts/path_bench.sh [KDRAY] [OUT]     # KDRAY: default target/release/kdray
#
# Scenes: the Cornell box (14 objects, 256x256, 32 samples), the bench's
# gears (4,578 long thin triangles, `kdray generate --kind gears`) in path
# mode under a uniform sky (256x256, 4 samples: brute force over 4,578
# objects stays under llvmpipe's loop limit only at a few samples a
# dispatch), and the bunny under the sky image (69,668 triangles,
# 320x180, 8 samples; no brute force: 69,668 tests a ray exceed llvmpipe's
# loop limit).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
kdray=${1:-target/release/kdray}
out=${2:-docs/results/path-bench.json}
repeat=${REPEAT:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

"$kdray" generate --kind gears --count 4578 -o "$work/gears.toml" >/dev/null
printf '\n[environment]\ncolor = [0.8, 0.85, 1.0]\n' >>"$work/gears.toml"
sed -i 's/^background = .*$//' "$work/gears.toml"

runs=()
measure() { # NAME ARGS...: one render's --stats JSON, tagged
    local name=$1
    shift
    local json
    json=$("$kdray" render "$@" --stats -o "$work/out.png")
    runs+=("{\"case\": \"$name\", \"stats\": $json}")
}

for _ in $(seq "$repeat"); do
    for walk in restart ropes short-stack brute; do
        if [ "$walk" = brute ]; then a=(--accel brute); else a=(--traversal "$walk"); fi
        measure "cornell path $walk" scenes/cornell_box.toml --width 256 --height 256 --samples 32 "${a[@]}"
        measure "gears path $walk" "$work/gears.toml" --integrator path --width 256 --height 256 \
            --samples 4 "${a[@]}"
        measure "gears whitted $walk" "$work/gears.toml" --width 256 --height 256 --samples 4 "${a[@]}"
        if [ "$walk" != brute ] && [ -f /usr/share/glmark2/models/bunny.obj ]; then
            measure "bunny_sky path $walk" scenes/bunny_sky.toml --width 320 --height 180 \
                --samples 8 "${a[@]}"
        fi
    done
done

write_results_json "$out" runs \
    machine="$(cpu_cores)" \
    adapter="$(adapter_name "$kdray")" \
    commit="$(git rev-parse --short HEAD)" \
    uptime_after="$(uptime | sed 's/^ *//')" \
    -- "${runs[@]}"
python3 scripts/path_table.py "$out"
