#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Against an earlier build" from
the JSON scripts/compare_builds.sh writes: per scene, the median GPU
milliseconds of this build and of the base build over the rounds, their
ratio, in how many rounds the two wrote the same PNG bytes, and the most
pixels that differed in a round, with the largest difference in levels.

    python3 scripts/compare_builds_table.py docs/results/build-compare.json
"""

import statistics
import sys

import results_table


def main():
    doc = results_table.load(sys.argv[1])
    times, same, diffs = {}, {}, {}
    for run in doc["runs"]:
        if run["build"] == "both":
            same.setdefault(run["scene"], []).append(run["same_png"])
            diffs.setdefault(run["scene"], []).append(run["diff"])
        else:
            times.setdefault(run["scene"], {}).setdefault(run["build"], []).append(run["gpu_ms"])
    print(results_table.provenance(doc) + f" Base build: {doc['base']}.")
    print()
    print(f"| scene (640x360, Whitted) | this build, ms | build {doc['base']}, ms | this / that "
          "| same PNG bytes | pixels differing (largest, levels) |")
    print("| --- | --: | --: | --: | --: | --: |")
    for scene, by in times.items():
        this, base = statistics.median(by["this"]), statistics.median(by["base"])
        pixels = max(d["differing_pixels"] for d in diffs[scene])
        worst = max(d["largest_difference"] for d in diffs[scene])
        print(f"| {scene} | {this:,.1f} | {base:,.1f} | {this / base:.2f} | "
              f"{sum(same[scene])} of {len(same[scene])} | {pixels:,} ({worst}) |")


if __name__ == "__main__":
    main()
