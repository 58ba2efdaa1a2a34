#!/usr/bin/env bash
# This build against another (docs/benchmarks.md, "Against an earlier
# build"): `kdray render --stats` of Whitted scenes that every build since
# the seed renders (the seed, its mirrors, the torus, the bunny, 10,000
# random spheres) with this build and BASE, alternating, ROUNDS rounds
# (default 5), whether the two wrote the same PNG bytes, and if not how
# many pixels differ and by how much (scripts/png_diff.py). Writes OUT
# (default docs/results/build-compare.json) with the machine, its load,
# both commits, and prints the table scripts/compare_builds_table.py makes.
#
#   BASE=OTHER_KDRAY BASE_COMMIT=abc1234 scripts/compare_builds.sh [KDRAY] [OUT]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/build-compare.json "$@"
base=${BASE:?BASE=another build of kdray}
rounds=${ROUNDS:-5}

# Written by the base build, whose scene files this build reads too (a newer
# build may write keys an older one does not know).
"$base" generate --kind spheres --count 10000 -o "$work/spheres.toml" 2>/dev/null
scenes=(scenes/seed.toml scenes/mirrors.toml scenes/torus.toml scenes/bunny.toml "$work/spheres.toml")
runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for round in $(seq "$rounds"); do
    for scene in "${scenes[@]}"; do
        name=$(basename "$scene" .toml)
        for which in this base; do
            binary=$kdray
            [ "$which" = base ] && binary=$base
            stats=$("$binary" render "$scene" --width 640 --height 360 --stats \
                -o "$work/$name-$which.png" 2>/dev/null | tail -1)
            gpu_ms=$(python3 -c 'import json, sys; print(json.loads(sys.argv[1])["gpu_ms"])' "$stats")
            runs+=("{\"scene\": \"$name\", \"build\": \"$which\", \"round\": $round, \"gpu_ms\": $gpu_ms}")
        done
        same=false
        cmp -s "$work/$name-this.png" "$work/$name-base.png" && same=true
        diff=$(python3 scripts/png_diff.py "$work/$name-this.png" "$work/$name-base.png")
        runs+=("{\"scene\": \"$name\", \"build\": \"both\", \"round\": $round, \"same_png\": $same, \"diff\": $diff}")
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    base="${BASE_COMMIT:-}" \
    -- "${runs[@]}"
python3 scripts/compare_builds_table.py "$out"
