#!/usr/bin/env bash
# What an animation costs rendered three ways (docs/benchmarks.md,
# "Animation and the farm"; docs/farm.md, "What a task costs beyond its
# frames"): scenes/bunny.toml given an orbit of FRAMES frames (default 12;
# `[animation] frames = FRAMES, orbit = 360`) at 640x360,
#   - in one process: `kdray render --all-frames`;
#   - one process per frame: `kdray render --frame K`, K = 0 .. FRAMES - 1;
#   - as a farm of 3 tasks (`kdray farm --tasks 3`), the tasks run by hand
#     one after the other (`sh render.sbatch I`), each printing its report
#     (load, adapter, tree and upload, frames) as one JSON line.
# Each way's wall time; and whether the three ways wrote the same PNGs.
# ROUNDS rounds (default 3), the ways alternating within each. Writes OUT
# (default docs/results/animation.json) with the machine, its load and the
# commit, and prints the table scripts/animation_table.py makes of it.
#
#   scripts/animation_cost.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/animation.json "$@"
rounds=${ROUNDS:-3}
frames=${FRAMES:-12}
tasks=3
[ -f /usr/share/glmark2/models/bunny.obj ] || { echo "animation_cost.sh: no bunny (apt-get install glmark2-data)" >&2; exit 1; }
scene=$work/bunny-orbit.toml
{
    cat scenes/bunny.toml
    printf '\n[animation]\nframes = %s\norbit  = 360\n' "$frames"
} >"$scene"
size=(--width 640 --height 360)

now_ms() { echo $(($(date +%s%N) / 1000000)); }
runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    rm -rf "$work/one" "$work/each" "$work/farm"

    t=$(now_ms)
    "$kdray" render "$scene" "${size[@]}" --all-frames -o "$work/one" 2>/dev/null
    runs+=("{\"way\": \"one process\", \"frames\": $frames, \"wall_ms\": $(($(now_ms) - t))}")

    mkdir "$work/each"
    t=$(now_ms)
    for k in $(seq 0 $((frames - 1))); do
        "$kdray" render "$scene" "${size[@]}" --frame "$k" -o "$(printf '%s/each/%04d.png' "$work" "$k")" 2>/dev/null
    done
    runs+=("{\"way\": \"one process per frame\", \"frames\": $frames, \"wall_ms\": $(($(now_ms) - t))}")

    "$kdray" farm "$scene" "${size[@]}" --out "$work/farm" --tasks "$tasks" >/dev/null
    reports=()
    t=$(now_ms)
    for i in $(seq 0 $((tasks - 1))); do
        ti=$(now_ms)
        report=$(sh "$work/farm/render.sbatch" "$i" 2>/dev/null | grep '^{')
        reports+=("{\"wall_ms\": $(($(now_ms) - ti)), \"report\": $report}")
    done
    wall=$(($(now_ms) - t))
    same=true
    for f in "$work"/one/*.png; do
        name=$(basename "$f")
        cmp -s "$f" "$work/each/$name" && cmp -s "$f" "$work/farm/$name" || same=false
    done
    [ "$(ls "$work"/one/*.png | wc -l)" = "$frames" ] || same=false
    tasks_json=$(IFS=,; echo "${reports[*]}")
    runs+=("{\"way\": \"farm\", \"frames\": $frames, \"wall_ms\": $wall, \"tasks\": [$tasks_json], \"same_pngs\": $same}")
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/animation_table.py ways "$out"
