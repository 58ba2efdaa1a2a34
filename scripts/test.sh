#!/usr/bin/env bash
# The README's test command: installs what the tests need on a Debian or
# Ubuntu machine without a GPU, then runs the test tiers (docs/testing.md):
#
#   scripts/test.sh [--dry-run] [all|lint|core|gpu|external] [cargo test arguments]
#
#   lint      cargo fmt --check and cargo clippy with warnings as errors
#   core      cargo test -p kdray-core: the GPU-free core; nothing to install
#   gpu       kdray's unit tests and tests/gpu/: lavapipe, llvmpipe GL,
#             SwiftShader's Vulkan, the kdray binary
#   external  tests/external/: Chromium, Slurm, Xvfb, out-of-memory runs
#   all       lint, core, then gpu and external side by side (the default;
#             what `.ci/run` runs)
#
# Extra arguments go to every `cargo test` it runs (not to the lint tier). --dry-run prints the
# packages it would install and the commands it would run, and does nothing.
# apt-get runs only when a package below is missing, with sudo when not
# root; on a machine without dpkg/apt-get it is skipped (install the
# equivalents yourself).
set -euo pipefail
cd "$(dirname "$0")/.."

dry_run=false
if [ "${1:-}" = --dry-run ]; then
    dry_run=true
    shift
fi
tier=all
case "${1:-}" in
    all | lint | core | gpu | external) tier=$1; shift ;;
esac

gpu_packages=(
    # lavapipe (Vulkan on the CPU), and EGL + llvmpipe for the GL fallback
    # (tests/gpu/gpu_faults.rs compares the two).
    mesa-vulkan-drivers libvulkan1 libegl1 libegl-mesa0 libgl1-mesa-dri
    # g++ builds nv-flip's C++ core (the golden-image tests).
    g++
    # scenes/bunny.toml's mesh, /usr/share/glmark2/models/bunny.obj (the
    # Stanford bunny), which the image tests render.
    glmark2-data
    # tests/gpu/textured_models.rs opens another project's textured models
    # (Khronos' BoxTextured, an OBJ with Windows-style image paths).
    assimp-testmodels
    # tests/gpu/swiftshader.rs runs on SwiftShader's Vulkan, which Debian's
    # chromium package ships.
    chromium
)
external_packages=(
    # gcc (cc) builds tests/common/device_memory_budget.c for
    # tests/external/gpu_memory.rs.
    gcc
    # tests/external/window.rs runs the window under Xvfb; winit loads these
    # at run time.
    xvfb xauth libxkbcommon-x11-0 libx11-xcb1 libxcursor1 libxi6 libxrandr2
    # tests/external/window_inspect.rs clicks and types in it through XTest.
    libxtst6
    # tests/external/web.rs traces the exported site in headless Chromium
    # (WebGPU on its SwiftShader), driven from node by tests/web's npm
    # packages (node and npm below, from Debian unless the machine has its own).
    python3
    # tests/external/farm.rs runs `kdray farm` on a one-node Slurm cluster
    # that scripts/slurm_cluster.sh starts on this machine (as root, no systemd).
    slurmctld slurmd slurm-client munge
)

packages=()
case $tier in
    gpu) packages=("${gpu_packages[@]}") ;;
    external | all) packages=("${gpu_packages[@]}" "${external_packages[@]}") ;;
esac
if [ "$tier" = external ] || [ "$tier" = all ]; then
    # Node.js may come from elsewhere (NodeSource's nodejs bundles npm and
    # conflicts with Debian's npm): Debian's packages only where there is none.
    command -v node >/dev/null || packages+=(nodejs)
    command -v npm >/dev/null || packages+=(npm)
fi

# One line per cargo command a tier runs.
tier_command() {
    case $1 in
        lint)
            echo "cargo fmt --all --check"
            echo "cargo clippy --locked --workspace --all-targets -- -D warnings"
            ;;
        core) echo "cargo test --locked -p kdray-core" ;;
        gpu) echo "cargo test --locked -p kdray --lib --bins --test gpu" ;;
        external) echo "cargo test --locked -p kdray --test external" ;;
    esac
}
if [ "$tier" = all ]; then tiers=(lint core gpu external); else tiers=("$tier"); fi

if $dry_run; then
    echo "packages: ${packages[*]}"
    for t in "${tiers[@]}"; do tier_command "$t"; done
    exit 0
fi

missing=()
if [ ${#packages[@]} -gt 0 ]; then
    if command -v dpkg-query >/dev/null && command -v apt-get >/dev/null; then
        for p in "${packages[@]}"; do
            status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
            [ "$status" = "install ok installed" ] || missing+=("$p")
        done
    else
        echo "scripts/test.sh: no dpkg/apt-get here; not installing: ${packages[*]}" >&2
    fi
fi

if [ ${#missing[@]} -gt 0 ]; then
    if [ "$(id -u)" = 0 ]; then
        sudo=()
    elif command -v sudo >/dev/null; then
        sudo=(sudo)
    else
        echo "scripts/test.sh: not root and no sudo: as root, run apt-get install ${missing[*]}" >&2
        exit 1
    fi
    echo "scripts/test.sh: installing ${missing[*]}" >&2
    export DEBIAN_FRONTEND=noninteractive
    "${sudo[@]}" apt-get update -qq
    "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# tests/web's driver (playwright-core), exactly as its lockfile says.
if { [ "$tier" = external ] || [ "$tier" = all ]; } && [ ! -d tests/web/node_modules/playwright-core ]; then
    npm ci --prefix tests/web --no-audit --no-fund >/dev/null
fi

# --- tests/external/denoise_oidn.rs ---------------------------------------
# Native Open Image Denoise 1.4.3 (the `oidn` wheel ships its library) and
# OpenEXR's Python binding, which scripts/oidn_denoise.py runs to check
# `kdray denoise` against; installed with pip only when missing.
if { [ "$tier" = external ] || [ "$tier" = all ]; } &&
    ! python3 -c 'import importlib.util, sys, OpenEXR; sys.exit(importlib.util.find_spec("oidn") is None)' 2>/dev/null; then
    # A Debian-managed python3 refuses plain pip installs (PEP 668).
    python3 -m pip install --quiet oidn==0.2.1 OpenEXR==3.5.3 ||
        python3 -m pip install --quiet --break-system-packages oidn==0.2.1 OpenEXR==3.5.3
fi
# --- end of tests/external/denoise_oidn.rs --------------------------------

# The debug build and its test binaries take a few GB under target/; a full
# disk shows up as a linker crash (signal 7, bus error), so say it first.
target_dir=${CARGO_TARGET_DIR:-target}
mkdir -p "$target_dir"
free_kib=$(df -Pk "$target_dir" | awk 'NR == 2 { print $4 }')
if [ -n "$free_kib" ] && [ "$free_kib" -lt $((3 * 1024 * 1024)) ]; then
    echo "scripts/test.sh: only $((free_kib / 1024)) MiB free for $target_dir; the test build needs a few GB" >&2
fi

test_args=("$@")

# Runs tier $1's commands (test arguments to all but the lint tier's).
run_tier() {
    local t=$1 start=$SECONDS command
    mapfile -t commands < <(tier_command "$t")
    for command in "${commands[@]}"; do
        echo "scripts/test.sh: the $t tier: $command" >&2
        # The command is plain words: split, not quoted; the lint tier's
        # commands take no test arguments.
        if [ "$t" = lint ]; then $command; else $command "${test_args[@]}"; fi
    done
    echo "scripts/test.sh: the $t tier passed in $((SECONDS - start)) s" >&2
}

if [ "$tier" != all ]; then
    run_tier "$tier"
    exit 0
fi

# Every tier: lint and core in turn; then, with the two tiers' test
# binaries built, the GPU and external tiers side by side. The GPU tier's
# tests share one device, whose queue thread compiles every kernel variant,
# so it keeps about one core of two busy; the external tier's processes
# (browsers, windows, Slurm jobs) take the other. Each line they print
# starts with its tier's name; either failing fails the run.
run_tier lint
run_tier core
start=$SECONDS
echo "scripts/test.sh: building the gpu and external tiers' tests" >&2
cargo test --locked -p kdray --lib --bins --test gpu --test external --no-run "${test_args[@]}"
pids=()
for t in gpu external; do
    (run_tier "$t" 2>&1 | sed -u "s/^/[$t] /") &
    pids+=($!)
done
failed=()
for i in 0 1; do
    wait "${pids[$i]}" || failed+=("$([ "$i" = 0 ] && echo gpu || echo external)")
done
if [ ${#failed[@]} -gt 0 ]; then
    echo "scripts/test.sh: the ${failed[*]} tier(s) failed" >&2
    exit 1
fi
echo "scripts/test.sh: the gpu and external tiers passed side by side in $((SECONDS - start)) s" >&2
