#!/usr/bin/env python3
"""Prints the tables of docs/benchmarks.md's "glTF files and materials"
from what scripts/gltf_cost.sh kept (default docs/results/gltf-cost.json):
the load and peak memory of each file, the kernel's GPU time with each
material feature against the plain model, and, where measured, this build
against another on scenes without those features. Medians over the rounds.

    python3 scripts/gltf_table.py [RESULTS]
"""

import json
import statistics
import sys


def median(runs, kind, case, key):
    values = [r[key] if key in r else r["run"][key]
              for r in runs if r["kind"] == kind and r["case"] == case]
    return statistics.median(values) if values else None


def main():
    path = sys.argv[1] if len(sys.argv) > 1 else "docs/results/gltf-cost.json"
    with open(path) as f:
        results = json.load(f)
    runs = results["runs"]
    rounds = sum(1 for r in runs if r["kind"] == "load" and r["case"] == "plain")
    print(f"Commit {results['commit']}; {results['adapter']}; {results['machine']}; "
          f"load {results['load']}; medians of {rounds} rounds.")
    print()
    print("| file | bytes | load | peak resident set | load vs the plain GLB |")
    print("| --- | --: | --: | --: | --: |")
    plain_ms = median(runs, "load", "plain", "scene_ms")
    for case, name in [("plain", "GLB, float attributes"), ("quantize", "quantized"),
                       ("meshopt", "meshopt"), ("draco", "Draco")]:
        size = next(r["file_bytes"] for r in runs if r["kind"] == "load" and r["case"] == case)
        ms = median(runs, "load", case, "scene_ms")
        mib = median(runs, "load", case, "peak_host_mib")
        print(f"| {name} | {size:,} | {ms:.0f} ms | {mib:.0f} MiB | {ms / plain_ms:.2f}x |")
    print()
    print("| model | Whitted, 640x360 | vs plain | path, 320x180, 16 samples | vs plain |")
    print("| --- | --: | --: | --: | --: |")
    base_w = median(runs, "kernel", "plain, Whitted", "gpu_ms")
    base_p = median(runs, "kernel", "plain, path", "gpu_ms")
    for case, name in [("plain", "textured"), ("normal", "textured, normal map"),
                       ("solid", "textured, MASK, every texel solid"),
                       ("mask", "textured, MASK, half the texels holes")]:
        w = median(runs, "kernel", f"{case}, Whitted", "gpu_ms")
        p = median(runs, "kernel", f"{case}, path", "gpu_ms")
        print(f"| {name} | {w:.0f} ms | {w / base_w:.2f}x | {p:.0f} ms | {p / base_p:.2f}x |")
    if any(r["kind"] == "base" for r in runs):
        print()
        print(f"| scene | this build | build {results['base']} | this / that |")
        print("| --- | --: | --: | --: |")
        for case in ["bunny, Whitted", "Cornell box, path"]:
            this = median(runs, "this", case, "gpu_ms")
            that = median(runs, "base", case, "gpu_ms")
            print(f"| {case} | {this:.0f} ms | {that:.0f} ms | {this / that:.2f} |")


if __name__ == "__main__":
    main()
