#!/usr/bin/env python3
"""Prints the Markdown table of docs/benchmarks.md's "Wavefront or one loop"
from the JSON scripts/wavefront_bound.sh writes: per case and walk, the
path-traced frame's M rays/s (the megakernel: one loop per pixel), the
same kind of rays traced from a queue alone (the least a wavefront's
frame costs), and their ratio.

    python3 scripts/wavefront_table.py docs/results/wavefront-bound.json
"""

import json
import sys


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    adapter = doc["cases"][0]["report"]["adapter"] if doc["cases"] else "?"
    print(f"Commit {doc['commit']}; {adapter}; {doc['machine']}; "
          f"load after: {doc['uptime_after'].split('load average:')[-1].strip()}.")
    print()
    print("| case | walk | one loop per pixel, M rays/s | queue alone, M rays/s | loop / queue |")
    print("| --- | --- | ---: | ---: | ---: |")
    for case in doc["cases"]:
        for scene in case["report"]["scenes"]:
            for w in scene["walks"]:
                print(f"| {case['case']} ({scene['width']}x{scene['height']}) | {w['traversal']} | "
                      f"{w['megakernel_mrays_per_s']:.2f} | {w['queue_mrays_per_s']:.2f} | {w['ratio']:.2f} |")


if __name__ == "__main__":
    main()
