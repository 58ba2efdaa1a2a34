#!/usr/bin/env bash
# How long `kdray render` takes to its first pixel (docs/benchmarks.md,
# "Start-up"): each scene rendered at 8x8 pixels, one sample (one dispatch,
# so the first pixel is the last), the process's wall time from start to
# exit, and its --stats parts: the tree's build, the upload (flattening and
# the buffers) and the GPU's time. What is left of the wall time is reading
# the scene, opening the adapter and compiling the kernel variant (llvmpipe
# compiles at the first dispatch). Each round runs each scene twice in a
# row, so that a driver that keeps compiled pipelines between processes
# shows a faster second run. ROUNDS rounds (default 3). Writes OUT (default
# docs/results/startup.json) with the machine, its load and the commit, and
# prints the table scripts/startup_table.py makes of it.
#
#   scripts/startup_time.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/startup.json "$@"
rounds=${ROUNDS:-3}
[ -f /usr/share/glmark2/models/bunny.obj ] || { echo "startup_time.sh: no bunny (apt-get install glmark2-data)" >&2; exit 1; }
scenes=(scenes/seed.toml scenes/bunny.toml scenes/cornell_box.toml)

now_ms() { echo $(($(date +%s%N) / 1000000)); }
runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for round in $(seq "$rounds"); do
    for scene in "${scenes[@]}"; do
        name=$(basename "$scene" .toml)
        for run in first second; do
            t=$(now_ms)
            stats=$("$kdray" render "$scene" --width 8 --height 8 --samples 1 --stats \
                -o "$work/$name.png" 2>/dev/null | tail -1)
            wall=$(($(now_ms) - t))
            runs+=("{\"scene\": \"$name\", \"run\": \"$run\", \"round\": $round, \"wall_ms\": $wall, \"stats\": $stats}")
        done
    done
done
# target/release/kdray or target/debug/kdray: which build was timed.
write_kept_results "$out" runs "$kdray" "$load_before" \
    build="$(basename "$(dirname "$kdray")")" \
    -- "${runs[@]}"
python3 scripts/startup_table.py "$out"
