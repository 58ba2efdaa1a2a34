#!/usr/bin/env bash
# kdray, Embree and Mitsuba 3 on one scene, primary + shadow rays, in one run
# on this machine (docs/peers.md). Writes each tool's JSON and summary.md
# into OUT_DIR (default /tmp/kdray-peers).
#
#   apt-get install -y glmark2-data libllvm19        # the bunny; Mitsuba's LLVM
#   python3 -m venv /tmp/peers && /tmp/peers/bin/pip install embreex mitsuba numpy
#   cargo build --release --locked
#   PY=/tmp/peers/bin/python scripts/peers/measure.sh [SCENE] [OUT_DIR]
#
# Environment: PY (a Python with embreex and mitsuba; default python3),
# REPEAT (timed runs of each, default 3), KDRAY (default target/release/kdray),
# DRJIT_LIBLLVM_PATH (default Debian's libLLVM-19).
set -euo pipefail
cd "$(dirname "$0")/../.."

scene=${1:-scenes/peers/bunny.toml}
out=${2:-/tmp/kdray-peers}
py=${PY:-python3}
repeat=${REPEAT:-3}
kdray=${KDRAY:-target/release/kdray}
export DRJIT_LIBLLVM_PATH=${DRJIT_LIBLLVM_PATH:-/usr/lib/x86_64-linux-gnu/libLLVM-19.so}
here=scripts/peers

mkdir -p "$out"
rm -rf "$out"/*.jsonl "$out"/*.json "$out"/summary.md "$out"/kdray-bench "$out"/kdray-bench-1thread
# kdray follows a path up to max_depth hits: at 1 it traces primary and
# shadow rays only, which is what the peers trace.
direct="$out/direct.json"
python3 "$here/direct_variant.py" "$scene" "$direct"

{
    echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "uptime before: $(uptime)"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
    echo "kdray: $kdray, built $(date -u -r "$kdray" '+%Y-%m-%d %H:%M UTC'); checkout at $(git rev-parse --short HEAD)"
} > "$out/machine.txt"

# kdray's frames are timed by `kdray bench`: a warm-up frame that counts the
# walk's work, then REPEAT frames of the kernel a plain `kdray render` runs,
# which counts nothing (`render --stats` would time the counting kernel,
# 1 - 3% slower: docs/design.md, "Counting only when asked").
echo "kdray (lavapipe, all cores)..." >&2
"$kdray" render "$direct" -o "$out/kdray.png"
"$kdray" bench --scene "$direct" --accel kdtree --repeat "$repeat" --out "$out/kdray-bench" >/dev/null
echo "kdray (lavapipe, LP_NUM_THREADS=1, taskset -c 0)..." >&2
LP_NUM_THREADS=1 taskset -c 0 "$kdray" bench --scene "$direct" --accel kdtree --repeat "$repeat" \
    --out "$out/kdray-bench-1thread" >/dev/null
echo "Embree (taskset -c 0)..." >&2
taskset -c 0 "$py" "$here/embree_rays.py" "$direct" --repeat "$repeat" > "$out/embree.json" || true
echo "Mitsuba 3 (1 thread, taskset -c 0)..." >&2
taskset -c 0 "$py" "$here/mitsuba_frame.py" "$direct" --threads 1 --repeat "$repeat" > "$out/mitsuba_1thread.json"
echo "Mitsuba 3 (all cores)..." >&2
"$py" "$here/mitsuba_frame.py" "$direct" --repeat "$repeat" -o "$out/mitsuba.png" > "$out/mitsuba.json"

echo "uptime after: $(uptime)" >> "$out/machine.txt"
python3 "$here/summarize.py" "$out" | tee "$out/summary.md"
