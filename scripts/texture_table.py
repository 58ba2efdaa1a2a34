#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Textures" from the JSON
scripts/texture_cost.sh writes: per scene, the median (and range) of the
GPU milliseconds of its renders, the bytes of texture data in its buffers,
its rays, and its frame's ratio to the untextured scene's.

    python3 scripts/texture_table.py docs/results/textures.json
"""

import statistics
import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    scenes = results_table.grouped(doc["runs"], "scene", lambda run: run["stats"])
    print(results_table.provenance(doc))
    print()
    print("| floor | GPU ms, median (range) | renders | texture bytes | rays | vs untextured |")
    print("| --- | --: | --: | --: | --: | --: |")
    plain = statistics.median(r["gpu_ms"] for r in scenes["untextured"])
    for name, runs in scenes.items():
        ms = [r["gpu_ms"] for r in runs]
        r = runs[0]
        rays = r["primary_rays"] + r["shadow_rays"] + r["reflection_rays"]
        print(f"| {name} | {statistics.median(ms):.1f} ({min(ms):.1f} - {max(ms):.1f}) | {len(runs)} "
              f"| {r['texture_bytes']:,} | {rays:,} | {statistics.median(ms) / plain:.2f}x |")


if __name__ == "__main__":
    main()
