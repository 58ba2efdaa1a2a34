#!/usr/bin/env bash
# How long the denoiser takes (docs/benchmarks.md, "Denoising"): kdray's
# GPU denoiser (`kdray denoise --stats`) beside native Open Image Denoise
# 1.4.3 on the CPU (scripts/oidn_denoise.py --stats, through the `oidn`
# wheel), on the same inputs, in one run on this machine. The inputs are
# the Cornell box path traced at 1 sample a pixel with its albedo and
# normal (`render --denoise -o X.exr`) at each size of SIZES (default
# 640x360 1280x720 1920x1080); the content does not change the work. Each
# tool denoises colour, albedo and normal ROUNDS times (default 3),
# alternating. kdray's figure is the image's denoise after a warm-up
# denoise that compiles its pipelines; OIDN's, the filter's execution after
# its commit. Writes OUT (default docs/results/denoise-time.json) and
# prints the table scripts/denoise_time_table.py makes of it.
#
#   pip install oidn==0.2.1 OpenEXR==3.5.3
#   scripts/denoise_time.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/denoise-time.json "$@"
rounds=${ROUNDS:-3}
sizes=(${SIZES:-640x360 1280x720 1920x1080})

runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for size in "${sizes[@]}"; do
    w=${size%x*}
    h=${size#*x}
    in="$work/$size.exr"
    "$kdray" render scenes/cornell_box.toml --width "$w" --height "$h" --samples 1 \
        --denoise -o "$in" >/dev/null
    inputs=("$work/$size.noisy.exr" --albedo "$work/$size.albedo.exr" --normal "$work/$size.normal.exr")
    for round in $(seq "$rounds"); do
        k=$("$kdray" denoise "${inputs[@]}" -o "$work/kdray.exr" --stats | tail -1)
        o=$(python3 scripts/oidn_denoise.py "${inputs[@]}" -o "$work/oidn.exr" --stats | tail -1)
        runs+=("{\"size\": \"$size\", \"round\": $round, \"tool\": \"kdray\", \"stats\": $k}")
        runs+=("{\"size\": \"$size\", \"round\": $round, \"tool\": \"oidn\", \"stats\": $o}")
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    build="$(basename "$(dirname "$kdray")")" \
    oidn="Open Image Denoise 1.4.3 (oidn wheel 0.2.1), CPU device" \
    -- "${runs[@]}"
python3 scripts/denoise_time_table.py "$out"
