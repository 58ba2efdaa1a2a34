#!/usr/bin/env bash
# What a triangle costs in memory (docs/benchmarks.md, "Memory per
# triangle"): scenes/bunny.toml (smooth-shaded) with its mesh subdivided
# LEVELS times by scripts/subdivide_obj.py, rendered at 320x240 under
# `/usr/bin/time -v` with `kdray render --stats`: the peak resident set
# (the kernel's), and the bytes of the scene's GPU arrays (`gpu_scene_bytes`).
# LEVELS is a space-separated list (default "0 1 2 3": 69,666 to 4,458,624
# triangles of the bunny), ROUNDS rounds (default 3), the sizes alternating
# within each. Writes OUT (default docs/results/triangle-memory.json) with
# the machine, its load and the commit, and prints the table
# scripts/triangle_memory_table.py makes of it.
#
#   scripts/triangle_memory.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/triangle-memory.json "$@"
rounds=${ROUNDS:-3}
levels=${LEVELS:-0 1 2 3}
bunny=/usr/share/glmark2/models/bunny.obj
[ -f "$bunny" ] || { echo "triangle_memory.sh: no $bunny (apt-get install glmark2-data)" >&2; exit 1; }

for level in $levels; do
    if [ "$level" = 0 ]; then
        cp "$bunny" "$work/bunny-$level.obj"
    else
        python3 scripts/subdivide_obj.py "$bunny" "$level" "$work/bunny-$level.obj"
    fi
    sed "s|^path *= *\"$bunny\"|path      = \"bunny-$level.obj\"|" scenes/bunny.toml >"$work/bunny-$level.toml"
    grep -q "\"bunny-$level.obj\"" "$work/bunny-$level.toml"
done

runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    for level in $levels; do
        /usr/bin/time -v -o "$work/time.txt" "$kdray" render "$work/bunny-$level.toml" \
            --width 320 --height 240 --stats -o "$work/out.png" >"$work/stats.json"
        peak_kib=$(sed -n 's/^\s*Maximum resident set size (kbytes): //p' "$work/time.txt")
        runs+=("{\"subdivisions\": $level, \"peak_rss_kib\": $peak_kib, \"stats\": $(cat "$work/stats.json")}")
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/triangle_memory_table.py "$out"
