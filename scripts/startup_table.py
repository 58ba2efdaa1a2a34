#!/usr/bin/env python3
"""Prints docs/benchmarks.md's "Start-up" table from the JSON
scripts/startup_time.sh writes: per scene and run (the first of a pair,
then the second at once after it), the median over the rounds of the wall
time to the first pixel (and its range), and of its parts from --stats:
before the tree's build (starting, reading the scene, opening the
adapter: the wall time less --stats' total), the build, the upload
(flattening, the buffers, the renderer), the first dispatch less the GPU's
time in it (llvmpipe compiles the kernel variant there) and the GPU's
time.

    python3 scripts/startup_table.py docs/results/startup.json
"""

import statistics
import sys

import results_table


def median_ms(runs, value):
    return statistics.median(value(r) for r in runs)


def main(path):
    doc = results_table.load(path)
    print(f"{results_table.provenance(doc)} kdray's {doc['build']} build.")
    print()
    print("| scene | run | to the first pixel, s | before the build, s | tree build, s | upload, s "
          "| compiling, s | GPU, s |")
    print("| --- | --- | --: | --: | --: | --: | --: | --: |")
    groups = results_table.grouped(doc["runs"], "scene")
    for scene, runs in groups.items():
        for run, these in results_table.grouped(runs, "run").items():
            wall = [r["wall_ms"] / 1e3 for r in these]
            parts = [
                median_ms(these, lambda r: r["wall_ms"] - r["stats"]["total_ms"]),
                median_ms(these, lambda r: r["stats"]["build_ms"]),
                median_ms(these, lambda r: r["stats"]["upload_ms"]),
                median_ms(these, lambda r: r["stats"]["total_ms"] - r["stats"]["build_ms"]
                          - r["stats"]["upload_ms"] - r["stats"]["gpu_ms"]),
                median_ms(these, lambda r: r["stats"]["gpu_ms"]),
            ]
            cells = " | ".join(f"{p / 1e3:.2f}" for p in parts)
            print(f"| {scene} | {run} | {statistics.median(wall):.2f} ({min(wall):.2f} - {max(wall):.2f}) "
                  f"| {cells} |")


if __name__ == "__main__":
    main(sys.argv[1])
