#!/usr/bin/env python3
"""Prints the Markdown table of docs/benchmarks.md's "The path tracer" from
the JSON scripts/path_bench.sh writes: per case, the median over its runs
of GPU milliseconds, M samples/s and M rays/s (all rays: camera, shadow
and bounce), the pixels llvmpipe's loop limit may have cut short (their
figures are too fast and not a reference), and the machine, adapter and
commit it came from. Under the table, per scene, the fastest walk and how
much slower the slowest is, and brute force against the fastest walk.

    python3 scripts/path_table.py docs/results/path-bench.json
"""

import statistics
import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    cases = results_table.grouped(doc["runs"], "case", lambda run: run["stats"])
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
    print()
    for line in findings(cases):
        print(f"- {line}")


WALKS = ("restart", "ropes", "short-stack")


def findings(cases):
    """A line per scene and integrator: the walks' spread, and brute force."""
    medians = {name: statistics.median(r["gpu_ms"] for r in runs) for name, runs in cases.items()}
    groups = {}
    for name, ms in medians.items():
        scene, integrator, accel = name.rsplit(" ", 2)
        groups.setdefault((scene, integrator), {})[accel] = (ms, cases[name])
    lines = []
    for (scene, integrator), by in groups.items():
        walks = {w: by[w][0] for w in WALKS if w in by}
        if not walks:
            continue
        fast = min(walks, key=walks.get)
        slow = max(walks, key=walks.get)
        line = (f"{scene}, {integrator}: {fast} fastest, {slow} "
                f"{walks[slow] / walks[fast] - 1:.0%} slower")
        if "brute" in by:
            ms, runs = by["brute"]
            cut = max(r["loop_limited_pixels"] for r in runs)
            line += f"; brute force takes {ms / walks[fast]:.2f}x the fastest walk's time"
            if cut:
                line += " (its loops cut short, so if anything too little)"
        lines.append(line + ".")
    return lines


if __name__ == "__main__":
    main()
