#!/usr/bin/env bash
# The same lavapipe made to compile the kernel differently (docs/
# benchmarks.md, "Other Mesa versions and CPUs"): `kdray bench --accel
# kdtree` of the gears (4,578 triangles, 640x480), 10,000 random spheres
# (640x480) and the bunny's camera and shadow rays (scenes/peers/bunny.toml
# at max_depth 1, 1920x1080), with llvmpipe as it is, without AVX-512
# (GALLIUM_OVERRIDE_CPU_CAPS=avx: what llvmpipe compiles for a CPU with
# AVX2 and no AVX-512), and at 4 and 16 lanes (LP_NATIVE_VECTOR_WIDTH 128
# and 512; 8 lanes of 256 bits is its default here). ROUNDS rounds
# (default 3), the settings alternating within each. Writes OUT (default
# docs/results/lavapipe-variants.json) with the machine, its load and the
# commit, and prints the table scripts/lavapipe_variants_table.py makes.
#
#   scripts/lavapipe_variants.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/lavapipe-variants.json "$@"
rounds=${ROUNDS:-3}

runs=()
# bench SETTING ENV... -- ARGS...: one `kdray bench` per scene, its records
# tagged with the setting and the adapter line it ran on.
bench() {
    local setting=$1
    shift
    local env=()
    while [ "$1" != -- ]; do
        env+=("$1")
        shift
    done
    shift
    env -u GALLIUM_OVERRIDE_CPU_CAPS -u LP_NATIVE_VECTOR_WIDTH "${env[@]}" \
        "$kdray" bench --accel kdtree --repeat 3 "$@" --out "$work/bench" >/dev/null 2>&1
    runs+=("$(python3 - "$work/bench/bench.json" "$setting" <<'PY'
import json, sys
doc = json.load(open(sys.argv[1]))
print(json.dumps({"setting": sys.argv[2], "adapter": doc["machine"]["adapter_line"], "runs": doc["runs"]}))
PY
)")
}
load_before=$(cut -d' ' -f1 /proc/loadavg)
for _ in $(seq "$rounds"); do
    for setting in default avx2 lanes4 lanes16; do
        case $setting in
            default) env=() ;;
            avx2) env=(GALLIUM_OVERRIDE_CPU_CAPS=avx) ;;
            lanes4) env=(LP_NATIVE_VECTOR_WIDTH=128) ;;
            lanes16) env=(LP_NATIVE_VECTOR_WIDTH=512) ;;
        esac
        bench "$setting" "${env[@]}" -- --kind gears --sizes 4578
        bench "$setting" "${env[@]}" -- --kind spheres --sizes 10000
        if [ -f /usr/share/glmark2/models/bunny.obj ]; then
            bench "$setting" "${env[@]}" -- --scene scenes/peers/bunny.toml --max-depth 1
        fi
    done
done
write_kept_results "$out" runs "$kdray" "$load_before" \
    -- "${runs[@]}"
python3 scripts/lavapipe_variants_table.py "$out"
