#!/usr/bin/env bash
# The page's frame time beside native kdray's, same machine, same run
# (docs/benchmarks.md, "In the browser"):
#   - the page (`kdray web`) in headless Chromium, WebGPU on SwiftShader:
#     every image pass's time (the first also compiles the pipeline),
#     driven by tests/web/bench_page.mjs;
#   - native `kdray bench` on lavapipe (Vulkan), and on SwiftShader's Vulkan
#     from Debian's chromium package (VK_ICD_FILENAMES): every frame after
#     one warm-up frame.
# Each is one sample per pixel of the seed scene and the bunny at 640x360
# with the short-stack walk. ROUNDS rounds (default 3) of the three, one
# after the other. Writes OUT (default docs/results/web.json) with the
# machine, the adapters, Chromium's version, its load and the commit, and
# prints the table scripts/web_table.py makes of it.
#
#   scripts/web_bench.sh [KDRAY] [OUT]   # KDRAY: default target/release/kdray
# Needs what scripts/test.sh installs (chromium, node and tests/web's npm
# packages, glmark2-data for the bunny). Environment: WEB_BENCH_SAMPLES
# (page passes per scene, a perfect square; default 9), WEB_BENCH_REPEAT
# (native timed frames; default 5).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/results_json.sh
measure_setup docs/results/web.json "$@"
rounds=${ROUNDS:-3}
samples=${WEB_BENCH_SAMPLES:-9}
repeat=${WEB_BENCH_REPEAT:-5}
width=640
height=360
swiftshader_icd=/usr/lib/chromium/vk_swiftshader_icd.json
scenes=(scenes/seed.toml scenes/bunny.toml)

[ -f "$swiftshader_icd" ] || { echo "web_bench.sh: no $swiftshader_icd (apt-get install chromium)" >&2; exit 1; }
[ -d tests/web/node_modules/playwright-core ] || npm ci --prefix tests/web --no-audit --no-fund >/dev/null
server_pid=
stop_server() { [ -z "$server_pid" ] || kill "$server_pid" 2>/dev/null || true; }
trap 'stop_server; rm -rf "$work"' EXIT

urls=()
for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .toml)
    "$kdray" web "$scene" -o "$work/site-$name" >/dev/null
    urls+=("site-$name/?width=$width&height=$height&samples=$samples&traversal=short-stack")
done

# One static server for every site, on a free port.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 -m http.server "$port" --bind 127.0.0.1 -d "$work" >/dev/null 2>&1 &
server_pid=$!
for _ in $(seq 100); do
    python3 -c "import socket; socket.create_connection(('127.0.0.1', $port))" 2>/dev/null && break
    sleep 0.1
done

native() { # NAME [ENV...]: kdray bench on both scenes into $work/NAME
    local name=$1
    shift
    local args=()
    for scene in "${scenes[@]}"; do args+=(--scene "$scene"); done
    rm -rf "${work:?}/$name"
    env "$@" "$kdray" bench "${args[@]}" --width "$width" --height "$height" \
        --accel kdtree --traversal short-stack --repeat "$repeat" --out "$work/$name" >/dev/null 2>&1
}

runs=()
load_before=$(cut -d' ' -f1 /proc/loadavg)
for round in $(seq "$rounds"); do
    echo "web_bench.sh: round $round: the page in headless Chromium, native on lavapipe and SwiftShader" >&2
    node tests/web/bench_page.mjs "${urls[@]/#/http://127.0.0.1:$port/}" >"$work/page.json"
    native lavapipe
    native swiftshader VK_ICD_FILENAMES=$swiftshader_icd WGPU_ADAPTER_NAME=SwiftShader
    # One round: per scene, the page's passes and the native runs' records.
    runs+=("$(python3 - "$work" <<'PY'
import json, sys
work = sys.argv[1]
page = json.load(open(f"{work}/page.json"))
for p in page:
    p["scene"] = p.pop("url").split("/site-")[1].split("/")[0] + ".toml"
native = {name: json.load(open(f"{work}/{name}/bench.json"))["runs"] for name in ("lavapipe", "swiftshader")}
print(json.dumps({"page": page, "lavapipe": native["lavapipe"], "swiftshader": native["swiftshader"]}))
PY
)")
done
stop_server
server_pid=

swiftshader_adapter=$(VK_ICD_FILENAMES=$swiftshader_icd WGPU_ADAPTER_NAME=SwiftShader "$kdray" info 2>/dev/null |
    grep '^\*' | sed 's/^\* //;s/"/\\"/g')
write_kept_results "$out" runs "$kdray" "$load_before" \
    swiftshader_adapter="$swiftshader_adapter" \
    chromium="$(chromium --version 2>/dev/null | sed 's/"/\\"/g')" \
    -- "${runs[@]}"
python3 scripts/web_table.py "$out"
