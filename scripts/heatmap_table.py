#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Where a walk spends its work"
from the JSON scripts/heatmaps.sh writes: per scene and walk, the work of
a ray (k-d nodes visited, leaves visited, objects tested, as the kernel
counts them) and the nodes a ray read against the short stack's.

    python3 scripts/heatmap_table.py docs/results/heatmaps.json
"""

import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    nodes = {(r["scene"], r["walk"]): r["stats"]["nodes_visited_per_ray"] for r in doc["runs"]}
    print(results_table.provenance(doc))
    print()
    print("| scene | walk | nodes a ray | leaves a ray | objects tested a ray | nodes vs short stack |")
    print("| --- | --- | --: | --: | --: | --: |")
    scenes = list(dict.fromkeys(r["scene"] for r in doc["runs"]))
    for run in sorted(doc["runs"], key=lambda r: scenes.index(r["scene"])):
        s = run["stats"]
        base = nodes.get((run["scene"], "short-stack"))
        ratio = f"{s['nodes_visited_per_ray'] / base:.2f}x" if base else ""
        print(f"| {run['scene']} | {run['walk']} | {s['nodes_visited_per_ray']:.1f} | "
              f"{s['leaves_visited_per_ray']:.1f} | {s['objects_tested_per_ray']:.1f} | {ratio} |")


if __name__ == "__main__":
    main()
