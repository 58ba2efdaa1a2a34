#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "Other Mesa versions and CPUs"
from the JSON scripts/lavapipe_variants.sh writes: per scene, the median
over the rounds of each setting's median GPU milliseconds (the k-d tree,
short stack), and each setting's ratio to llvmpipe as it is.

    python3 scripts/lavapipe_variants_table.py docs/results/lavapipe-variants.json
"""

import json
import statistics
import sys

SETTINGS = {
    "default": "as it is",
    "avx2": "without AVX-512 (`GALLIUM_OVERRIDE_CPU_CAPS=avx`)",
    "lanes4": "4 lanes (`LP_NATIVE_VECTOR_WIDTH=128`)",
    "lanes16": "16 lanes (`LP_NATIVE_VECTOR_WIDTH=512`)",
}


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    # (scene, objects, image) -> setting -> GPU ms, one a round
    cells = {}
    adapters = {}
    for entry in doc["runs"]:
        adapters.setdefault(entry["setting"], entry["adapter"])
        for r in entry["runs"]:
            if r["status"] != "ok" or r["gpu_ms"] is None:
                continue
            scene = r["scene"]
            if scene.endswith(".toml"):
                scene = f"`{scene}` at `max_depth` {r['max_depth']}"
            key = (scene, r["n"], f"{r['width']}x{r['height']}")
            cells.setdefault(key, {}).setdefault(entry["setting"], []).append(r["gpu_ms"])
    settings = [s for s in SETTINGS if s in adapters]
    print(f"Commit {doc['commit']}; {doc['machine']}; load {doc['load']}. "
          + "; ".join(f"{SETTINGS[s]}: {adapters[s]}" for s in settings) + ".")
    print()
    print("| scene | objects | image | " + " | ".join(f"{SETTINGS[s]}, ms" for s in settings) + " |")
    print("| --- | --: | --- | " + " | ".join("--:" for _ in settings) + " |")
    for (scene, n, image), by_setting in cells.items():
        base = statistics.median(by_setting["default"])
        figures = []
        for s in settings:
            ms = statistics.median(by_setting[s])
            figures.append(f"{ms:,.0f}" if s == "default" else f"{ms:,.0f} ({ms / base:.2f}x)")
        print(f"| {scene} | {n:,} | {image} | " + " | ".join(figures) + " |")


if __name__ == "__main__":
    main()
