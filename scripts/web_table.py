#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "In the browser" from the JSON
scripts/web_bench.sh writes: per scene, the page's median image pass after
the first (WebGPU on SwiftShader in headless Chromium) and its first pass,
native kdray's median frame (`frame_wall_ms`) on SwiftShader's Vulkan and
on lavapipe, and the page's ratio to each; every figure the median over
the rounds of each round's figure, the ratios' range over the rounds
beside them.

    python3 scripts/web_table.py docs/results/web.json
"""

import json
import statistics
import sys


def median_range(values, digits):
    m = statistics.median(values)
    if len(values) == 1:
        return f"{m:.{digits}f}"
    return f"{m:.{digits}f} ({min(values):.{digits}f} - {max(values):.{digits}f})"


def main():
    with open(sys.argv[1]) as f:
        doc = json.load(f)
    # scene -> figure -> one value a round
    scenes = {}
    page_adapters = set()
    for run in doc["runs"]:
        native = {
            kind: {r["scene"]: r["frame_wall_ms"] for r in run[kind] if r.get("frame_wall_ms") is not None}
            for kind in ("lavapipe", "swiftshader")
        }
        for p in run["page"]:
            s = scenes.setdefault(p["scene"], {"page": [], "first": [], "swiftshader": [], "lavapipe": [],
                                               "failures": []})
            if "failure" in p or not p.get("pass_ms"):
                s["failures"].append(p.get("failure") or p.get("title"))
                continue
            page_adapters.add(p.get("adapter", "?"))
            steady = statistics.median(p["pass_ms"][1:] or p["pass_ms"])
            s["page"].append(steady)
            s["first"].append(p["pass_ms"][0])
            for kind in ("swiftshader", "lavapipe"):
                s[kind].append(native[kind].get(p["scene"]))
    print(f"Commit {doc['commit']}; {doc['machine']}; load {doc['load']}. "
          f"Native: {doc['adapter']}, and {doc['swiftshader_adapter']}. "
          f"Page: {doc['chromium']}, {'; '.join(sorted(page_adapters))}.")
    print()
    print("| scene | page (Chromium, SwiftShader) | page's first pass | native, SwiftShader's Vulkan "
          "| native, lavapipe | page / native SwiftShader | page / native lavapipe | rounds |")
    print("| --- | --: | --: | --: | --: | --: | --: | --: |")
    for name, s in scenes.items():
        if not s["page"]:
            print(f"| {name} | failed: {s['failures'][0]} | | | | | | {len(s['failures'])} |")
            continue
        ms = lambda values: f"{statistics.median(values):,.0f} ms"
        ratio = lambda kind: median_range([p / n for p, n in zip(s["page"], s[kind])], 2)
        print(f"| {name} | {ms(s['page'])} | {ms(s['first'])} | {ms(s['swiftshader'])} | {ms(s['lavapipe'])} "
              f"| {ratio('swiftshader')} | {ratio('lavapipe')} | {len(s['page'])} |")


if __name__ == "__main__":
    main()
