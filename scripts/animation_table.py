#!/usr/bin/env python3
"""Prints a table from the JSON scripts/animation_cost.sh writes:

- `ways` (docs/benchmarks.md, "Animation and the farm"): per way of
  rendering the animation, the median wall time over the rounds (and its
  range), per frame, against one process, and whether the ways wrote the
  same PNGs;
- `tasks` (docs/farm.md, "What a task costs beyond its frames"): the parts
  of a farm task's time from the tasks' own reports, medians and ranges
  over every task of every round, and the frames a task needs to come
  within 10% of one process by the rule F >= 10 O / r.

    python3 scripts/animation_table.py ways docs/results/animation.json
    python3 scripts/animation_table.py tasks docs/results/animation.json
"""

import statistics
import sys

import results_table


def spread(values, scale=1.0, digits=2):
    values = [v * scale for v in values]
    return f"{statistics.median(values):.{digits}f} ({min(values):.{digits}f} - {max(values):.{digits}f})"


def heading(doc):
    print(results_table.provenance(doc))
    print()


def ways(doc):
    by_way = results_table.grouped(doc["runs"], "way")
    heading(doc)
    one = statistics.median(r["wall_ms"] for r in by_way["one process"])
    labels = {
        "one process": "one process, `kdray render --all-frames`",
        "one process per frame": "one process per frame, `kdray render --frame K`",
    }
    print("| how | frames | wall time, s | per frame, s | vs one process |")
    print("| --- | --: | --: | --: | --: |")
    for way, runs in by_way.items():
        frames = runs[0]["frames"]
        wall = [r["wall_ms"] for r in runs]
        if way == "farm":
            tasks = len(runs[0]["tasks"])
            label = (f"`kdray farm --tasks {tasks}`, the tasks run one after the other "
                     f"({frames // tasks} frames each)")
        else:
            label = labels[way]
        print(f"| {label} | {frames} | {spread(wall, 1e-3)} | {statistics.median(wall) / frames / 1e3:.3f} "
              f"| {statistics.median(wall) / one:.2f}x |")
    farms = by_way["farm"]
    same = sum(r["same_pngs"] for r in farms)
    print()
    print(f"The three ways wrote the same PNGs, frame for frame, in {same} of {len(farms)} rounds "
          "(the ways alternating within each).")


def tasks(doc):
    reports = [t for run in doc["runs"] if run["way"] == "farm" for t in run["tasks"]]
    heading(doc)
    per_frame = [t["report"]["render_ms"] / len(t["report"]["rendered"]) for t in reports]
    rows = [
        ("reading the plan and the scene, hashing the inputs (`load_ms`)", "load_ms"),
        ("opening the adapter (`adapter_ms`)", "adapter_ms"),
        ("building the k-d tree, flattening, uploading, compiling the kernel (`prepare_ms`)", "prepare_ms"),
    ]
    print("| part of a task | ms, median (range) |")
    print("| --- | --: |")
    for label, key in rows:
        print(f"| {label} | {spread([t['report'][key] for t in reports], digits=0)} |")
    print(f"| rendering and writing one frame (`render_ms` over the frames) | {spread(per_frame, digits=0)} |")
    fixed = statistics.median(sum(t["report"][k] for _, k in rows) for t in reports)
    frame = statistics.median(per_frame)
    frames = {len(t["report"]["rendered"]) for t in reports}
    print()
    print(f"{len(reports)} tasks of {'/'.join(str(f) for f in sorted(frames))} frames. "
          f"Fixed cost O = {fixed / 1e3:.2f} s, r = {frame / 1e3:.2f} s a frame (medians): "
          f"F >= 10 O / r = {10 * fixed / frame:.0f} frames a task.")


def main():
    doc = results_table.load(sys.argv[2])
    {"ways": ways, "tasks": tasks}[sys.argv[1]](doc)


if __name__ == "__main__":
    main()
