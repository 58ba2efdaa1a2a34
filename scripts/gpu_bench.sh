#!/usr/bin/env bash
# Run the benchmark suite on a machine with a GPU (docs/benchmarks.md, "On a
# GPU"). Two steps, so that the GPU machine needs no network:
#
#   scripts/gpu_bench.sh prepare          # on a machine with network
#       a release build (stripped), the Stanford bunny, the Vulkan and EGL
#       loader .deb files and the Python wheels of embreex and Mitsuba 3,
#       in .gpu-bench/ and .gpu-bench-mitsuba/ (both kept out of git through
#       .git/info/exclude). Mitsuba's wheel alone is about 60 MB, so it
#       travels in two parts: the first in .gpu-bench-mitsuba/, the rest
#       with everything else in .gpu-bench/; each folder with the checkout
#       stays under 64 MiB, for machines that take at most that per copy.
#       Copy .gpu-bench-mitsuba/ to the GPU machine first, then .gpu-bench/.
#
#   scripts/gpu_bench.sh run [OUT_DIR]    # on the GPU machine, offline
#       installs the loaders and wheels locally where they are missing
#       (joining Mitsuba's two parts where both are there), writes
#       `kdray info` and refuses a CPU or software adapter (llvmpipe,
#       lavapipe, SwiftShader), then measures, each step bounded by
#       `timeout` and the whole run by GPU_BENCH_BUDGET_S (default 450 s):
#         - the bench's random scenes with every walk: the gears and 10,000
#           spheres against brute force, 1,000 -> 1,000,000 spheres;
#         - the study's suite (`kdray bench --suite`) with every walk;
#         - the path tracer: the Cornell box at 1024x1024, 64 samples, with
#           every walk (samples and rays per second in each --stats JSON),
#           and the bunny under the sky image at 1920x1080, 16 samples;
#         - the denoiser on a 1920x1080 image with albedo and normal
#           (`kdray denoise --stats`);
#         - the bunny's camera and shadow rays at 1920x1080 and 3840x2160
#           with every walk, Embree 4 on one CPU core at 1920x1080, and
#           Mitsuba 3's `cuda_ad_rgb` variant on the same frames where it
#           loads.
#       Everything goes into OUT_DIR (default: $OUT, else gpu-bench-results):
#       info.txt, log.txt and one folder per step.
#
# Environment: GPU_PYTHON_VERSION (the GPU machine's Python, for the wheels;
# default 3.12), PY (the Python that runs the peers; default python3),
# GPU_BENCH_BUDGET_S (the run's time bound in seconds).
set -uo pipefail
cd "$(dirname "$0")/.."

stash=.gpu-bench
mitsuba_part=.gpu-bench-mitsuba
# Bytes of Mitsuba's wheel that travel in $mitsuba_part (the rest in $stash).
first_part_bytes=$((52 * 1024 * 1024))

prepare() {
    set -e
    cargo build --release --locked
    rm -rf "$stash" "$mitsuba_part"
    mkdir -p "$stash/bin" "$stash/models" "$stash/debs" "$stash/wheels" "$mitsuba_part"
    for d in "$stash" "$mitsuba_part"; do
        grep -qx "/$d/" .git/info/exclude 2>/dev/null || echo "/$d/" >>.git/info/exclude
    done
    cp target/release/kdray "$stash/bin/kdray"
    strip "$stash/bin/kdray"
    # The bunny of scenes/peers/bunny.toml (apt-get install glmark2-data).
    cp /usr/share/glmark2/models/bunny.obj "$stash/models/bunny.obj"
    # The Vulkan and EGL loaders; the GPU's own driver brings the rest.
    local o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/gpu-bench-apt'
    mkdir -p /tmp/gpu-bench-apt/partial
    # shellcheck disable=SC2086
    apt-get $o update >/dev/null
    # shellcheck disable=SC2086
    (cd "$stash/debs" && apt-get $o download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
    # Wheels for the GPU machine's Python (numpy is assumed there).
    local py=${GPU_PYTHON_VERSION:-3.12}
    python3 -m pip download -q --no-deps --only-binary=:all: --python-version "$py" \
        --implementation cp --platform manylinux_2_28_x86_64 --platform manylinux_2_17_x86_64 \
        --platform manylinux2014_x86_64 -d "$stash/wheels" embreex mitsuba drjit
    # Mitsuba's wheel in two parts, joined again by `run`.
    local wheel
    wheel=$(ls "$stash"/wheels/mitsuba-*.whl)
    head -c "$first_part_bytes" "$wheel" >"$mitsuba_part/$(basename "$wheel").part1"
    tail -c +$((first_part_bytes + 1)) "$wheel" >"$stash/wheels/$(basename "$wheel").part2"
    rm "$wheel"
    du -sh "$stash" "$mitsuba_part"
}

out=${2:-${OUT:-gpu-bench-results}}
budget=${GPU_BENCH_BUDGET_S:-450}
start=$SECONDS

# step NAME SECONDS COMMAND...: runs COMMAND under `timeout`, bounded by
# SECONDS and by what is left of the run's budget; logs how it ended.
step() {
    local name=$1 limit=$2
    shift 2
    local left=$((budget - (SECONDS - start)))
    if [ "$left" -lt 10 ]; then
        echo "== $name: skipped, the run's budget of ${budget} s is spent"
        return 1
    fi
    [ "$limit" -gt "$left" ] && limit=$left
    echo "== $name (at most ${limit} s)"
    local t0=$SECONDS
    timeout --kill-after=5 "$limit" "$@"
    local rc=$?
    if [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ]; then
        echo "== $name: stopped after ${limit} s"
    else
        echo "== $name: exit $rc after $((SECONDS - t0)) s"
    fi
    return "$rc"
}

install_offline() {
    # The loaders, where the machine has none: unpacked over /.
    if ! ldconfig -p | grep -q libvulkan.so.1 && ls "$stash"/debs/*.deb >/dev/null 2>&1; then
        for f in "$stash"/debs/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    # NVIDIA's Vulkan driver manifest, where the loader does not find it itself.
    if [ -z "${VK_DRIVER_FILES:-}" ] && [ -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]; then
        export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
    fi
    if [ ! -f "$bunny" ] && [ -f "$stash/models/bunny.obj" ]; then
        mkdir -p "$(dirname "$bunny")" && cp "$stash/models/bunny.obj" "$bunny"
    fi
    # Mitsuba's wheel, where both its parts came.
    local part2 part1
    for part2 in "$stash"/wheels/mitsuba-*.whl.part2; do
        part1=$mitsuba_part/$(basename "$part2" .part2).part1
        [ -f "$part2" ] && [ -f "$part1" ] && cat "$part1" "$part2" >"${part2%.part2}"
    done
    if ls "$stash"/wheels/*.whl >/dev/null 2>&1 &&
        ! "$py" -c 'import embreex, mitsuba' 2>/dev/null; then
        "$py" -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade \
            --target /tmp/gpu-bench-site "$stash"/wheels/*.whl &&
            export PYTHONPATH=/tmp/gpu-bench-site${PYTHONPATH:+:$PYTHONPATH}
    fi
}

# Exits unless the adapter kdray uses (the line `kdray info` marks with *)
# is a real GPU.
require_gpu() {
    local chosen
    chosen=$(grep '^\*' "$out/info.txt" || true)
    if [ -z "$chosen" ]; then
        echo "gpu_bench.sh: kdray found no adapter (see $out/info.txt)" >&2
        exit 3
    fi
    if echo "$chosen" | grep -Eiq 'llvmpipe|lavapipe|swiftshader|softpipe|, Cpu,'; then
        echo "gpu_bench.sh: the adapter is a CPU or software renderer, not a GPU:" >&2
        echo "  $chosen" >&2
        echo "gpu_bench.sh: refusing to record its figures as GPU figures" >&2
        exit 3
    fi
}

run() {
    kdray=target/release/kdray
    [ -x "$stash/bin/kdray" ] && kdray=$stash/bin/kdray
    py=${PY:-python3}
    bunny=/usr/share/glmark2/models/bunny.obj
    install_offline

    {
        echo "uptime: $(uptime)"
        echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
        echo "checkout: $(git rev-parse --short HEAD 2>/dev/null || echo unknown)"
        nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || true
        "$kdray" info
    } >"$out/info.txt" 2>&1
    cat "$out/info.txt"
    require_gpu

    # The bench's random scenes (the figures of docs/benchmarks.md).
    step gears 60 "$kdray" bench --kind gears --sizes 4578 --traversal all --repeat 5 \
        --out "$out/gears" >/dev/null
    step spheres 60 "$kdray" bench --kind spheres --sizes 10000 --traversal all --repeat 5 \
        --budget-s 120 --out "$out/spheres" >/dev/null
    step growth 75 "$kdray" bench --kind spheres --sizes 1000,10000,1000000 --accel kdtree \
        --traversal all --repeat 5 --out "$out/growth" >/dev/null
    step suite 100 "$kdray" bench --suite --traversal all --repeat 5 --out "$out/suite" >/dev/null

    # The path tracer: incoherent rays, every walk.
    mkdir -p "$out/path"
    local walk
    for walk in restart ropes short-stack; do
        step "path-cornell-$walk" 40 "$kdray" render scenes/cornell_box.toml --width 1024 \
            --height 1024 --samples 64 --traversal "$walk" --stats \
            -o "$out/path/cornell-$walk.exr" >"$out/path/cornell-$walk.json"
    done
    # The kernel's shape: one loop per pixel against a queue of the same
    # rays traced alone (what a wavefront's frame costs at least).
    step wavefront-bound 40 "$kdray" bench --wavefront-bound --scene scenes/cornell_box.toml \
        --width 1024 --height 1024 --repeat 5 --out "$out/path" >/dev/null

    # The denoiser at 1920x1080: its inputs from one path-traced sample of
    # the Cornell box, then `kdray denoise --stats` (set-up, and the image's
    # denoise, in ms). The images stay in /tmp (about 25 MB each); the
    # figures go to OUT_DIR.
    local images
    images=$(mktemp -d)
    step denoise-inputs 40 "$kdray" render scenes/cornell_box.toml --width 1920 --height 1080 \
        --samples 1 --denoise -o "$images/cornell.exr" >/dev/null &&
        step denoise-1080p 60 "$kdray" denoise "$images/cornell.noisy.exr" \
            --albedo "$images/cornell.albedo.exr" --normal "$images/cornell.normal.exr" \
            -o "$images/denoised.exr" --stats >"$out/denoise-1080p.json"
    rm -rf "$images"

    # The bunny's camera and shadow rays, the peers' frame (docs/peers.md).
    if [ ! -f "$bunny" ]; then
        echo "gpu_bench.sh: no bunny at $bunny: its frames are not measured"
        return 0
    fi
    local direct=$out/bunny-direct.json
    python3 scripts/peers/direct_variant.py scenes/peers/bunny.toml "$direct" || return 0
    step bunny-1080p 40 "$kdray" bench --scene "$direct" --accel kdtree --traversal all \
        --width 1920 --height 1080 --repeat 5 --write-scenes --out "$out/bunny-1080p" >/dev/null
    step bunny-2160p 50 "$kdray" bench --scene "$direct" --accel kdtree --traversal all \
        --width 3840 --height 2160 --repeat 5 --out "$out/bunny-2160p" >/dev/null
    step path-bunny-sky 40 "$kdray" render scenes/bunny_sky.toml --width 1920 --height 1080 \
        --samples 16 --stats -o "$out/path/bunny-sky.exr" >"$out/path/bunny-sky.json"
    if "$py" -c 'import embreex, numpy' 2>/dev/null; then
        step embree-1080p 30 taskset -c 0 "$py" scripts/peers/bench_embree.py "$out/bunny-1080p" \
            --repeat 5 --kdray "$kdray"
    else
        echo "gpu_bench.sh: no embreex: Embree not measured"
    fi
    if "$py" -c 'import mitsuba' 2>/dev/null; then
        step mitsuba-1080p 40 "$py" scripts/peers/mitsuba_frame.py "$direct" --variant cuda_ad_rgb \
            --width 1920 --height 1080 --repeat 5 >"$out/mitsuba-cuda-1080p.json"
        step mitsuba-2160p 40 "$py" scripts/peers/mitsuba_frame.py "$direct" --variant cuda_ad_rgb \
            --width 3840 --height 2160 --repeat 5 >"$out/mitsuba-cuda-2160p.json"
    else
        echo "gpu_bench.sh: no mitsuba: Mitsuba 3 not measured"
    fi
    echo "== done in $((SECONDS - start)) s; results in $out"
    ls -l "$out"
}

case "${1:-}" in
prepare) prepare ;;
run)
    mkdir -p "$out"
    run 2>&1 | tee "$out/log.txt"
    exit "${PIPESTATUS[0]}"
    ;;
*)
    sed -n '2,35p' "$0" >&2
    exit 2
    ;;
esac
