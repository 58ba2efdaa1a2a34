#!/usr/bin/env bash
# Issue 9's targets on a lent GPU (the workplace's `device` tool), in one
# call: the adapter, the three brute-force ratios, the growth from 1,000 to
# 1,000,000 spheres, and the bunny against Embree on that machine's CPU
# (docs/benchmarks.md, "On a GPU"). The device machine reaches nothing
# outside it, so everything it needs travels with the working tree:
#
#   here:    scripts/device_targets.sh prepare
#            (a release build, the bunny and Vulkan's loader packages and the
#            embreex wheel, into .device/, .gl/ and .whl/, which
#            .git/info/exclude keeps out of git; 33 MiB on 2026-11-26)
#   there:   run(command="scripts/device_targets.sh run", carry=[".device", ".gl", ".whl"],
#                timeout_s=480)
#
# `run` writes at most eight files into $OUT (the device tool's limit):
# info.txt, gears.md, spheres.md, growth.md, bunny.md, embree.json and
# log.txt. On lavapipe (`OUT=/tmp/x scripts/device_targets.sh run` here) it
# runs the same commands, for a rehearsal; the brute-force frames then take
# minutes instead of seconds.
set -uo pipefail
cd "$(dirname "$0")/.."

prepare() {
    set -e
    cargo build --release --locked
    mkdir -p .device .gl .whl
    for folder in .device .gl .whl; do
        grep -qx "/$folder/" .git/info/exclude 2>/dev/null || echo "/$folder/" >>.git/info/exclude
    done
    cp target/release/kdray .device/kdray
    cp /usr/share/glmark2/models/bunny.obj .device/bunny.obj # apt-get install glmark2-data
    # The Vulkan and EGL loaders (the device tool's README, "Headless rendering").
    local o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
    mkdir -p /tmp/amd64/partial
    # shellcheck disable=SC2086
    apt-get $o update >/dev/null
    # shellcheck disable=SC2086
    (cd .gl && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    # embreex for the machine's Python 3.12 (numpy is there already).
    python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 \
        --implementation cp --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 \
        --platform manylinux2014_x86_64 -d .whl embreex==4.4.0.post1
    du -sh .device .gl .whl
}

out=${OUT:-/tmp/device-targets}

run() {
    # The loaders, where the machine has none (unpacked over /, as the tool's README says).
    if ! ldconfig -p | grep -q libvulkan.so.1 && ls .gl/*.deb >/dev/null 2>&1; then
        for f in .gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    # Where the loader finds no NVIDIA driver by itself.
    if [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ] && [ -z "${VK_DRIVER_FILES:-}" ]; then
        export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    fi
    local kdray=target/release/kdray
    [ -x .device/kdray ] && kdray=.device/kdray
    local bunny=/usr/share/glmark2/models/bunny.obj
    if [ ! -f "$bunny" ] && [ -f .device/bunny.obj ]; then
        mkdir -p "$(dirname "$bunny")" && cp .device/bunny.obj "$bunny"
    fi
    local py=${PY:-python3}
    if ! "$py" -c "import embreex" 2>/dev/null && ls .whl/*.whl >/dev/null 2>&1; then
        "$py" -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
            --target /tmp/site .whl/*.whl && export PYTHONPATH=/tmp/site
    fi
    local work=/tmp/device-targets-work
    rm -rf "$work" && mkdir -p "$work"

    {
        date -u '+%Y-%m-%d %H:%M UTC'
        uptime
        grep -m1 'model name' /proc/cpuinfo
        nproc
        nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || true
        "$kdray" info
    } >"$out/info.txt" 2>&1
    cat "$out/info.txt"

    # The commands of docs/benchmarks.md's targets table.
    "$kdray" bench --kind gears --sizes 4578 --repeat 3 --out "$work/gears" >/dev/null &&
        cp "$work/gears/summary.md" "$out/gears.md"
    "$kdray" bench --kind spheres --sizes 10000 --repeat 3 --budget-s 120 --out "$work/spheres" >/dev/null &&
        cp "$work/spheres/summary.md" "$out/spheres.md"
    "$kdray" bench --kind spheres --sizes 1000,10000,1000000 --accel kdtree --repeat 3 \
        --out "$work/growth" >/dev/null &&
        cp "$work/growth/summary.md" "$out/growth.md"
    # The bunny's camera and shadow rays, every walk, then Embree on one core.
    if [ -f "$bunny" ]; then
        "$py" scripts/peers/direct_variant.py scenes/peers/bunny.toml "$work/direct.json" &&
            "$kdray" bench --scene "$work/direct.json" --accel kdtree --traversal all --repeat 5 \
                --write-scenes --out "$work/bunny" >/dev/null &&
            { "$py" scripts/peers/bench_embree.py "$work/bunny" --repeat 5 --kdray "$kdray" || true; } &&
            cp "$work/bunny/summary.md" "$out/bunny.md" &&
            { cp "$work/bunny/embree.json" "$out/embree.json" 2>/dev/null || true; }
    else
        echo "no bunny at $bunny: the bunny's row is not measured"
    fi
    ls -l "$out"
}

case "${1:-}" in
prepare) prepare ;;
run)
    mkdir -p "$out"
    run 2>&1 | tee "$out/log.txt"
    ;;
*)
    sed -n '2,19p' "$0" >&2
    exit 2
    ;;
esac
