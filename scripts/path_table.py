#!/usr/bin/env python3
"""Prints the Markdown table of docs/benchmarks.md's "The path tracer" from
the JSON scripts/path_bench.sh writes: per case, the median over its runs
of GPU milliseconds, M samples/s and M rays/s (all rays: camera, shadow
and bounce), the pixels llvmpipe's loop limit may have cut short (their
figures are too fast and not a reference), and the machine, adapter and
commit it came from.

    python3 scripts/path_table.py docs/results/path-bench.json
"""

import json
import statistics
import sys


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    cases = {}
    for run in doc["runs"]:
        cases.setdefault(run["case"], []).append(run["stats"])
    print(f"Commit {doc['commit']}; {doc['adapter']}; {doc['machine']}; "
          f"load after: {doc['uptime_after'].split('load average:')[-1].strip()}.")
    print()
    print("| case | objects | image | samples | GPU ms (median) | M samples/s | M rays/s | loop-limited pixels | runs |")
    print("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name, runs in cases.items():
        ms = statistics.median(r["gpu_ms"] for r in runs)
        s = runs[0]
        samples = s["width"] * s["height"] * s["samples"]
        rays = statistics.median(r["primary_rays"] + r["shadow_rays"] + r["reflection_rays"] for r in runs)
        print(f"| {name} | {s['spheres'] + s['triangles']:,} | {s['width']}x{s['height']} | {s['samples']} "
              f"| {ms:,.0f} | {samples / ms / 1e3:.3f} | {rays / ms / 1e3:.3f} "
              f"| {max(r['loop_limited_pixels'] for r in runs):,} | {len(runs)} |")


if __name__ == "__main__":
    main()
