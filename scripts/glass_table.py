#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Glass" from the JSON
scripts/glass_cost.sh writes: per scene, the median GPU milliseconds of its
renders, its shadow rays and its reflection and refraction rays, and the
glass frame's ratio to the seed's.

    python3 scripts/glass_table.py docs/results/glass.json
"""

import statistics
import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    scenes = results_table.grouped(doc["runs"], "scene", lambda run: run["stats"])
    print(results_table.provenance(doc))
    print()
    print("| scene | GPU ms (median) | renders | shadow rays | reflection and refraction rays | vs seed |")
    print("| --- | --: | --: | --: | --: | --: |")
    seed = statistics.median(r["gpu_ms"] for r in scenes["seed"])
    for name, runs in scenes.items():
        ms = statistics.median(r["gpu_ms"] for r in runs)
        r = runs[0]
        print(f"| {name} | {ms:.1f} | {len(runs)} | {r['shadow_rays']:,} | {r['reflection_rays']:,} | "
              f"{ms / seed:.2f}x |")


if __name__ == "__main__":
    main()
