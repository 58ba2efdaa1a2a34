#!/usr/bin/env python3
"""Prints the Markdown table of docs/benchmarks.md's "Wavefront or one loop"
from the JSON scripts/wavefront_bound.sh writes: per case and walk, the
path-traced frame's M rays/s (the megakernel: one loop per pixel), the
same kind of rays traced from a queue alone (the least a wavefront's
frame costs), and their ratio; under the table, the ratio's range at
depth 1 (every lane traces one camera and one shadow ray) and at each
scene's own depth (paths of every length share a SIMD group).

    python3 scripts/wavefront_table.py docs/results/wavefront-bound.json
"""

import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    adapter = doc["cases"][0]["report"]["adapter"] if doc["cases"] else "?"
    print(f"Commit {doc['commit']}; {adapter}; {doc['machine']}; "
          f"load after: {doc['uptime_after'].split('load average:')[-1].strip()}.")
    print()
    print("| case | walk | one loop per pixel, M rays/s | queue alone, M rays/s | loop / queue |")
    print("| --- | --- | ---: | ---: | ---: |")
    ratios = {"depth 1": [], "own depth": []}
    for case in doc["cases"]:
        for scene in case["report"]["scenes"]:
            for w in scene["walks"]:
                print(f"| {case['case']} ({scene['width']}x{scene['height']}) | {w['traversal']} | "
                      f"{w['megakernel_mrays_per_s']:.2f} | {w['queue_mrays_per_s']:.2f} | {w['ratio']:.2f} |")
                ratios["depth 1" if " depth 1 " in f" {case['case']} " else "own depth"].append(w["ratio"])
    print()
    print("Loop / queue: " + "; ".join(
        f"{k} {min(v):.2f} - {max(v):.2f}" for k, v in ratios.items() if v) + ".")


if __name__ == "__main__":
    main()
