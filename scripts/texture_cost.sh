#!/usr/bin/env bash
# What a texture costs (docs/benchmarks.md, "Textures"): `kdray render
# --stats` of scenes/textured.toml (a floor painted by a checker texture,
# bilinear, under two spheres) and of the same scene with the floor's
# material replaced by an untextured one of the MTL's colours, at
# 1280x720, alternating, ROUNDS rounds (default 5). Writes OUT (default
# docs/results/textures.json) with the machine, its load and the commit,
# and prints the table scripts/texture_table.py makes of it.
#
#   scripts/texture_cost.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/textures.json "$@"
rounds=${ROUNDS:-5}

# The floor without its texture: scenes/models/board.mtl's colours, no map_Kd.
{
    sed "s|^path  = \"models/board.obj\"|path  = \"$PWD/scenes/models/board.obj\"\nmaterial = \"untextured\"|" \
        scenes/textured.toml
    printf '\n[materials.untextured]\nambient   = [0.15, 0.15, 0.15]\ndiffuse   = [0.9, 0.9, 0.9]\n'
    printf 'specular  = [0.3, 0.3, 0.3]\nshininess = 40.0\n'
} >"$work/untextured.toml"
grep -q '^material = "untextured"' "$work/untextured.toml"
grep -q '^Kd 0.9 0.9 0.9$' scenes/models/board.mtl

runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    for scene in textured untextured; do
        if [ "$scene" = textured ]; then file=scenes/textured.toml; else file=$work/untextured.toml; fi
        json=$("$kdray" render "$file" --width 1280 --height 720 --stats -o "$work/out.png")
        runs+=("{\"scene\": \"$scene\", \"stats\": $json}")
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/texture_table.py "$out"
