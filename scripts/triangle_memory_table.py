#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Memory per triangle" from the
JSON scripts/triangle_memory.sh writes: per mesh, its triangles, the range
of the peak resident set over its runs, the scene's GPU arrays, their
bytes per triangle, the bytes each triangle past the mesh above it adds,
and the k-d tree's references per leaf.

    python3 scripts/triangle_memory_table.py docs/results/triangle-memory.json
"""

import sys

import results_table

NAMES = {0: "bunny", 1: "bunny, subdivided once", 2: "bunny, subdivided twice"}


def main():
    doc = results_table.load(sys.argv[1])
    meshes = results_table.grouped(doc["runs"], "subdivisions")
    print(results_table.provenance(doc))
    print()
    print("| mesh | triangles | peak resident set | GPU arrays | GPU bytes a triangle | bytes a triangle added | references per leaf | runs |")
    print("| --- | --: | --: | --: | --: | --: | --: | --: |")
    previous = None
    for level, runs in meshes.items():
        s = runs[0]["stats"]
        peaks = [r["peak_rss_kib"] / 2**20 for r in runs]
        gpu = s["gpu_scene_bytes"]
        name = NAMES.get(level, f"bunny, subdivided {level} times")
        added = "" if previous is None else f"{(gpu - previous[0]) / (s['triangles'] - previous[1]):.0f}"
        previous = (gpu, s["triangles"])
        print(f"| {name} | {s['triangles']:,} | {min(peaks):.2f} - {max(peaks):.2f} GiB | {gpu / 1e6:,.0f} MB "
              f"| {gpu / s['triangles']:.0f} | {added} | {s['kd_refs_per_leaf']:.1f} | {len(runs)} |")


if __name__ == "__main__":
    main()
