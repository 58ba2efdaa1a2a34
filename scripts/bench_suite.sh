#!/usr/bin/env bash
# The study measured: every build x walk on the bench suite's four scenes,
# then Embree on the same scenes straight after, and the summary with kdray's
# ratio to Embree (docs/benchmarks.md, "Every build and walk").
#
#   python3 -m venv /tmp/peers && /tmp/peers/bin/pip install embreex numpy
#   cargo build --release --locked
#   scripts/bench_suite.sh [OUT_DIR]          # default bench-suite
#
# Environment: KDRAY (default target/release/kdray), PY (a Python with
# embreex; default /tmp/peers/bin/python), REPEAT (timed frames per cell and
# Embree runs per scene, default 3). Without embreex the kdray part still
# runs and the summary says Embree was not measured.
set -euo pipefail
cd "$(dirname "$0")/.."

out=${1:-bench-suite}
kdray=${KDRAY:-target/release/kdray}
py=${PY:-/tmp/peers/bin/python}
repeat=${REPEAT:-3}

mkdir -p "$out"
{
    echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "uptime before: $(uptime)"
    echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores"
    echo "kdray: $kdray, checkout $(git rev-parse --short HEAD)"
} > "$out/machine.txt"

"$kdray" bench --suite --build all --traversal all --repeat "$repeat" --out "$out" > /dev/null
echo "uptime after kdray: $(uptime)" >> "$out/machine.txt"

if "$py" -c 'import embreex, numpy' 2> /dev/null; then
    "$py" scripts/peers/bench_embree.py "$out" --repeat "$repeat" --kdray "$kdray"
else
    echo "bench_suite.sh: no embreex in $py: Embree not measured" >&2
fi
echo "uptime after: $(uptime)" >> "$out/machine.txt"
cat "$out/summary.md"
