#!/usr/bin/env bash
# The page's frame time beside native kdray's, same machine, same run
# (docs/benchmarks.md, "In the browser"):
#   - the page (`kdray web`) in headless Chromium, WebGPU on SwiftShader:
#     the median image pass after the first (which also compiles the
#     pipeline), driven by tests/web/bench_page.mjs;
#   - native `kdray bench` on lavapipe (Vulkan), and on SwiftShader's Vulkan
#     from Debian's chromium package (VK_ICD_FILENAMES): the median frame
#     after one warm-up frame.
# Each is one sample per pixel of the seed scene and the bunny at 640x360
# with the short-stack walk; the ratios are page / native.
#
# Usage: scripts/web_bench.sh [OUT_DIR]   (default: web-bench-results)
# Needs what scripts/test.sh installs (chromium, node and tests/web's npm
# packages, glmark2-data for the bunny) and a release build, made here.
# Environment: WEB_BENCH_SAMPLES (page passes per scene, a perfect square;
# default 9), WEB_BENCH_REPEAT (native timed frames; default 5), KDRAY (a
# kdray binary to use instead of building target/release/kdray).
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:-web-bench-results}
samples=${WEB_BENCH_SAMPLES:-9}
repeat=${WEB_BENCH_REPEAT:-5}
width=640
height=360
swiftshader_icd=/usr/lib/chromium/vk_swiftshader_icd.json
scenes=(scenes/seed.toml scenes/bunny.toml)

[ -f "$swiftshader_icd" ] || { echo "web_bench.sh: no $swiftshader_icd (apt-get install chromium)" >&2; exit 1; }
[ -d tests/web/node_modules/playwright-core ] || npm ci --prefix tests/web --no-audit --no-fund >/dev/null

if [ -z "${KDRAY:-}" ]; then
    cargo build --release --locked --quiet
    KDRAY=$PWD/target/release/kdray
fi
kdray=$(realpath "$KDRAY")
mkdir -p "$out"
out=$(cd "$out" && pwd)
{
    echo "# $(uname -srm), $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
    echo "# chromium: $(chromium --version 2>/dev/null || echo unknown)"
    "$kdray" info
    VK_ICD_FILENAMES=$swiftshader_icd "$kdray" info
} >"$out/machine.txt" 2>&1

server_pid=
stop_server() { [ -z "$server_pid" ] || kill "$server_pid" 2>/dev/null || true; }
trap stop_server EXIT

urls=()
for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .toml)
    rm -rf "$out/site-$name"
    "$kdray" web "$scene" -o "$out/site-$name"
    urls+=("site-$name/?width=$width&height=$height&samples=$samples&traversal=short-stack")
done

# One static server for every site, on a free port.
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
python3 -m http.server "$port" --bind 127.0.0.1 -d "$out" >/dev/null 2>&1 &
server_pid=$!
for _ in $(seq 100); do
    python3 -c "import socket; socket.create_connection(('127.0.0.1', $port))" 2>/dev/null && break
    sleep 0.1
done

echo "web_bench.sh: the page in headless Chromium" >&2
node tests/web/bench_page.mjs "${urls[@]/#/http://127.0.0.1:$port/}" >"$out/page.json"
stop_server
server_pid=

native() { # native NAME [ENV...]: kdray bench on both scenes into $out/NAME
    local name=$1
    shift
    echo "web_bench.sh: native kdray, $name" >&2
    local args=()
    for scene in "${scenes[@]}"; do args+=(--scene "$scene"); done
    env "$@" "$kdray" bench "${args[@]}" --width "$width" --height "$height" \
        --accel kdtree --traversal short-stack --repeat "$repeat" --out "$out/$name" >"$out/$name.log" 2>&1
}
native lavapipe
native swiftshader VK_ICD_FILENAMES=$swiftshader_icd WGPU_ADAPTER_NAME=SwiftShader

python3 - "$out" <<'PY' | tee "$out/summary.md"
import json, statistics, sys
out = sys.argv[1]

def runs(name):
    data = json.load(open(f"{out}/{name}/bench.json"))["runs"]
    found = {}
    def walk(v):
        if isinstance(v, dict):
            if v.get("scene") and v.get("frame_wall_ms") is not None:
                found[v["scene"]] = v
            for x in v.values():
                walk(x)
        elif isinstance(v, list):
            for x in v:
                walk(x)
    walk(data)
    return found

lavapipe, swiftshader = runs("lavapipe"), runs("swiftshader")
page = json.load(open(f"{out}/page.json"))
print("| scene | page (Chromium, SwiftShader) | native, SwiftShader's Vulkan | native, lavapipe | page / native SwiftShader | page / native lavapipe |")
print("|---|---|---|---|---|---|")
for p in page:
    name = p["url"].split("/site-")[1].split("/")[0] + ".toml"
    if "failure" in p or not p.get("pass_ms"):
        print(f"| {name} | failed: {p.get('failure') or p.get('title')} | | | | |")
        continue
    steady = p["pass_ms"][1:] or p["pass_ms"]
    page_ms = statistics.median(steady)
    ss = swiftshader.get(name, {}).get("frame_wall_ms")
    lp = lavapipe.get(name, {}).get("frame_wall_ms")
    fmt = lambda ms: f"{ms:.0f} ms" if ms else "n/a"
    ratio = lambda ms: f"{page_ms / ms:.2f}" if ms else "n/a"
    print(f"| {name} | {fmt(page_ms)} (first pass {p['pass_ms'][0]:.0f} ms) | {fmt(ss)} | {fmt(lp)} | {ratio(ss)} | {ratio(lp)} |")
print()
print("page adapter: " + "; ".join(sorted({p.get('adapter', '?') for p in page})))
PY
