#!/usr/bin/env bash
# Loading and building big scenes (docs/benchmarks.md, "OBJ load"):
# `kdray bench --scene FILE --accel kdtree` at 32x18 (a warm-up and one
# timed frame of a few hundred pixels, so that the run is the load, the
# tree's build and the upload), which records each as `scene_ms`,
# `build_ms` and `upload_ms`, and the peak resident set. The scenes:
#   - the Stanford bunny subdivided twice (scripts/subdivide_obj.py,
#     1,114,656 triangles) in a TOML scene that names one material;
#   - the same OBJ opened as a model file (`kdray render MESH.obj`: its
#     smooth normals, a floor and a framing camera are made at load);
#   - a million random spheres (`kdray generate`) as JSON and as TOML.
# ROUNDS rounds (default 3), the scenes alternating within each. Writes OUT
# (default docs/results/obj-load.json) with the machine, its load and the
# commit, and prints the table scripts/obj_load_table.py makes of it.
#
#   scripts/obj_load.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/obj-load.json "$@"
rounds=${ROUNDS:-3}
bunny=/usr/share/glmark2/models/bunny.obj
[ -f "$bunny" ] || { echo "obj_load.sh: no $bunny (apt-get install glmark2-data)" >&2; exit 1; }

python3 scripts/subdivide_obj.py "$bunny" 2 "$work/bunny-1m.obj"
cat >"$work/bunny-1m.toml" <<'EOF'
[camera]
position = [2.6, 1.9, 4.4]
look_at  = [-0.2, 0.75, 0.0]
vfov     = 38.0

[[lights]]
position = [4.0, 6.0, 5.0]

[materials.bunny]
diffuse = [0.75, 0.68, 0.6]

[[meshes]]
path     = "bunny-1m.obj"
material = "bunny"
EOF
"$kdray" generate --kind spheres --count 1000000 -o "$work/spheres-1m.json" >/dev/null 2>&1
"$kdray" generate --kind spheres --count 1000000 -o "$work/spheres-1m.toml" >/dev/null 2>&1

runs=()
measure() { # NAME SCENE FILE: one bench run's record, tagged with FILE's size
    "$kdray" bench --scene "$2" --accel kdtree --width 32 --height 18 --repeat 1 \
        --out "$work/bench" >/dev/null 2>&1
    local record
    record=$(python3 -c 'import json, sys; print(json.dumps(json.load(open(sys.argv[1]))["runs"][0]))' \
        "$work/bench/bench.json")
    runs+=("{\"case\": \"$1\", \"file_bytes\": $(stat -c %s "$3"), \"run\": $record}")
}
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    measure "bunny subdivided twice, OBJ in a TOML scene" "$work/bunny-1m.toml" "$work/bunny-1m.obj"
    measure "bunny subdivided twice, OBJ opened as a model" "$work/bunny-1m.obj" "$work/bunny-1m.obj"
    measure "random spheres, JSON" "$work/spheres-1m.json" "$work/spheres-1m.json"
    measure "random spheres, TOML" "$work/spheres-1m.toml" "$work/spheres-1m.toml"
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/obj_load_table.py "$out"
