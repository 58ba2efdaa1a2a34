#!/usr/bin/env bash
# What glTF's optimised files and its material features cost
# (docs/benchmarks.md, "glTF files and materials"), on the Stanford bunny
# subdivided twice (scripts/subdivide_obj.py, 1,114,656 triangles) written as
# a GLB with normals, texture coordinates and a checker texture
# (scripts/obj_to_glb.py):
#   - loading: the GLB and what glTF Transform's CLI makes of it (quantize,
#     meshopt, draco), each opened as a model by `kdray bench --scene` at
#     32x18 (its `scene_ms`, the load; `peak_host_mib`, the peak resident set);
#   - the kernel: the same model plain, with a normal map, with an alpha
#     mask whose every texel is solid (the test's own cost) and with half its
#     texels holes, `kdray render --stats` (`gpu_ms`),
#     Whitted at 640x360 and path traced at 320x180 with 16 samples;
#   - with BASE=KDRAY2 (another build's binary): scenes/bunny.toml (Whitted,
#     640x360) and scenes/cornell_box.toml (path, 160x160, 16 samples), this
#     build and that one alternating, to show that scenes without these
#     features run as fast as before.
# ROUNDS rounds (default 3), the cases alternating within each. glTF
# Transform's CLI comes from npm into a scratch folder (network needed).
# Writes OUT (default docs/results/gltf-cost.json) with the machine, its
# load and the commit, and prints scripts/gltf_table.py's tables of it.
#
#   [BASE=OTHER_KDRAY] scripts/gltf_cost.sh [KDRAY] [OUT]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/gltf-cost.json "$@"
rounds=${ROUNDS:-3}
base=${BASE:-}
bunny=/usr/share/glmark2/models/bunny.obj
[ -f "$bunny" ] || { echo "gltf_cost.sh: no $bunny (apt-get install glmark2-data)" >&2; exit 1; }

python3 scripts/subdivide_obj.py "$bunny" 2 "$work/bunny.obj"
python3 scripts/obj_to_glb.py "$work/bunny.obj" "$work/plain.glb"
python3 scripts/obj_to_glb.py "$work/bunny.obj" "$work/normal.glb" --normal-map
python3 scripts/obj_to_glb.py "$work/bunny.obj" "$work/mask.glb" --mask
python3 scripts/obj_to_glb.py "$work/bunny.obj" "$work/solid.glb" --mask-solid
npm install --silent --no-audit --no-fund --prefix "$work/npm" @gltf-transform/cli@4.5.1 >/dev/null
for how in quantize meshopt draco; do
    "$work/npm/node_modules/.bin/gltf-transform" "$how" "$work/plain.glb" "$work/$how.glb" >/dev/null
done
# The kernel's scenes: the model under one light, seen as scenes/bunny.toml
# sees the bunny (the light bright enough for the path tracer's falloff).
for model in plain normal solid mask; do
    cat >"$work/$model.toml" <<EOF
[camera]
position = [2.6, 1.9, 4.4]
look_at  = [-0.2, 0.75, 0.0]
vfov     = 38.0

[render]
background = [0.3, 0.35, 0.45]

[[lights]]
position = [4.0, 6.0, 5.0]
diffuse  = [60, 60, 60]

[[meshes]]
path = "$model.glb"
EOF
done

runs=()
load() { # CASE FILE: one bench run's load and peak memory
    "$kdray" bench --scene "$2" --accel kdtree --width 32 --height 18 --repeat 1 \
        --out "$work/bench" >/dev/null 2>&1
    local record
    record=$(python3 -c 'import json, sys; r = json.load(open(sys.argv[1]))["runs"][0]; print(json.dumps({k: r[k] for k in ("scene_ms", "build_ms", "upload_ms", "peak_host_mib", "triangles")}))' \
        "$work/bench/bench.json")
    runs+=("{\"kind\": \"load\", \"case\": \"$1\", \"file_bytes\": $(stat -c %s "$2"), \"run\": $record}")
}
frame() { # KIND CASE KDRAY SCENE ARGS...: one render's --stats
    local kind=$1 case=$2 binary=$3 scene=$4
    shift 4
    local stats
    stats=$("$binary" render "$scene" -o "$work/frame.png" --stats "$@" 2>/dev/null | tail -1)
    local gpu_ms
    gpu_ms=$(python3 -c 'import json, sys; print(json.loads(sys.argv[1])["gpu_ms"])' "$stats")
    runs+=("{\"kind\": \"$kind\", \"case\": \"$case\", \"gpu_ms\": $gpu_ms}")
}
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    for how in plain quantize meshopt draco; do
        load "$how" "$work/$how.glb"
    done
    for model in plain normal solid mask; do
        frame kernel "$model, Whitted" "$kdray" "$work/$model.toml" --width 640 --height 360
        frame kernel "$model, path" "$kdray" "$work/$model.toml" --width 320 --height 180 \
            --integrator path --samples 16
    done
    if [ -n "$base" ]; then
        for which in this base; do
            binary=$kdray
            [ "$which" = base ] && binary=$base
            frame "$which" "bunny, Whitted" "$binary" scenes/bunny.toml --width 640 --height 360
            frame "$which" "Cornell box, path" "$binary" scenes/cornell_box.toml \
                --width 160 --height 160 --samples 16
        done
    fi
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    base="${BASE_COMMIT:-}" \
    -- "${runs[@]}"
python3 scripts/gltf_table.py "$out"
