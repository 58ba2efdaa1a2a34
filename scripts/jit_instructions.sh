#!/bin/bash
# Instructions the CPU runs in lavapipe's compiled shaders for one
# `kdray render`: a count that does not move with the machine's load, for
# comparing two builds of the kernel on a shared machine where GPU times
# move by 10 - 30% (docs/benchmarks.md, "A count that does not move with the
# load").
#
# usage: scripts/jit_instructions.sh KDRAY SCENE [render options...]
#   e.g. scripts/jit_instructions.sh target/release/kdray /tmp/direct.json --width 480 --height 270
#
# Needs valgrind (apt-get install valgrind). It runs the render twice under
# callgrind, llvmpipe on the calling thread (LP_NUM_THREADS=0) and one build
# thread, and prints the second run's count: llvmpipe's shader cache is keyed
# on the CPU's features, which valgrind reports differently, so the first run
# under valgrind compiles the kernel and fills the cache for the second.
# Shader code is what callgrind finds in no mapped file; the compiler's own
# work lies in libLLVM and lavapipe, so it is not counted.
#
# Instructions are not time: a private register add counts as much as a
# load that misses the cache. Nor is this the kernel a plain run executes:
# valgrind hides AVX-512, so llvmpipe compiles an AVX2 kernel here, which
# spills where the AVX-512 one does not and ran 1.9 - 2.4x slower natively
# (GALLIUM_OVERRIDE_CPU_CAPS=avx makes a plain run compile it too). Check a
# change that the count favours with alternating timed runs
# (docs/benchmarks.md, "the kernel that runs is not the kernel valgrind counts").
set -euo pipefail
if [ $# -lt 2 ]; then
    sed -n '2,10p' "$0" >&2
    exit 2
fi
kdray=$1
scene=$2
shift 2
command -v valgrind >/dev/null || { echo "jit_instructions.sh: valgrind is not installed" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for run in 1 2; do
    RAYON_NUM_THREADS=1 LP_NUM_THREADS=0 valgrind --tool=callgrind \
        --callgrind-out-file="$work/callgrind.out" \
        "$kdray" render "$scene" -o "$work/image.png" "$@" >"$work/log" 2>&1 ||
        { cat "$work/log" >&2; exit 1; }
done
# callgrind_annotate names code outside every mapped file "[???]".
callgrind_annotate --threshold=100 "$work/callgrind.out" |
    awk '/\[\?\?\?\]$/ { gsub(",", "", $1); n += $1 } END { printf "%d instructions in shader code\n", n }'
