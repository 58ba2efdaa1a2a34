#!/usr/bin/env python3
"""Prints a table of docs/benchmarks.md from the bench.json files that
scripts/lavapipe_bench.sh keeps in DIR (default docs/results/lavapipe):

    python3 scripts/bench_tables.py summary [DIR]   # "Current results"
    python3 scripts/bench_tables.py walks [DIR]     # "The walks"

Each table starts with the line naming the commit, adapter, machine, its
load and the date of the runs it comes from. Figures are the median GPU
milliseconds of each run's timed frames (`gpu_ms`).
"""

import json
import os
import re
import sys

FILES = ["spheres", "gears", "scenes", "seed"]
DEFAULT_WALK = "short-stack"
WALKS = ["restart", "ropes", "short-stack"]


def load(folder):
    docs = []
    for name in FILES:
        path = os.path.join(folder, name + ".json")
        if os.path.exists(path):
            with open(path) as f:
                docs.append(json.load(f))
    if not docs:
        sys.exit(f"bench_tables.py: no bench.json files in {folder}")
    return docs


def provenance(docs):
    first = docs[0]
    m = first["machine"]
    commits = sorted({d.get("commit", "?") for d in docs})
    loads = [d["machine"][k] for d in docs for k in ("load_average_start", "load_average_end")]
    dates = sorted(d["date_utc"][:10] for d in docs)
    return (f"Commit {', '.join(commits)}; {m['adapter_line']}; {m['host_cpu']}, "
            f"{m['host_threads']} threads; load {min(loads):.1f} - {max(loads):.1f}; {dates[0]}.")


def label(run):
    scene = run["scene"]
    if scene == "spheres":
        return "random spheres (bench)"
    if scene == "gears":
        return "gears (bench)"
    if scene == "bunny-direct.json":
        return "the bunny, camera and shadow rays (`scenes/peers/bunny.toml` at `max_depth` 1)"
    if scene == "bunny.toml":
        return "`scenes/peers/bunny.toml` (mirror, reflections)"
    return f"`scenes/{scene}`"


def ms(x):
    return f"{x:,.0f} ms" if x >= 100 else f"{x:.1f} ms"


def cases(docs):
    """(label, n, image, {walk: run}, brute run or None), in file order."""
    out = []
    for doc in docs:
        keyed = {}
        for run in doc["runs"]:
            key = (run["scene"], run["n"])
            entry = keyed.setdefault(key, {"walks": {}, "brute": None, "first": run})
            if run["accel"] == "brute":
                entry["brute"] = run
            elif run.get("build", "sah") == "sah" and run["status"] == "ok":
                entry["walks"][run["traversal"]] = run
        for (scene, n), e in keyed.items():
            r = e["first"]
            out.append((label(r), n, f"{r['width']}x{r['height']}", e["walks"], e["brute"]))
    return out


def summary(docs):
    print(provenance(docs))
    print()
    print("| scene | objects | image | k-d tree (short stack) | brute force | tree vs brute |")
    print("| --- | --: | --- | --: | --: | --: |")
    for name, n, image, walks, brute in cases(docs):
        kd = walks.get(DEFAULT_WALK)
        kd_text = ms(kd["gpu_ms"]) if kd else ""
        brute_text, ratio = "", ""
        if brute is not None:
            note = brute.get("note") or ""
            if brute["status"] == "skipped":
                pred = re.search(r"predicted ([0-9.]+) s", note)
                if pred:
                    brute_text = f"skipped ({pred.group(1)} s predicted)"
                elif "llvmpipe's limit" in note or "loop limit" in note:
                    brute_text = "skipped (past llvmpipe's loop limit)"
                else:
                    brute_text = "skipped"
            elif brute["status"] == "ok" and brute.get("loop_limited_pixels"):
                # Loops cut short: brute force's frame is if anything too fast.
                brute_text = f"{ms(brute['gpu_ms'])} ({brute['loop_limited_pixels']:,} pixels cut by the loop limit)"
                if kd:
                    ratio = f"**{brute['gpu_ms'] / kd['gpu_ms']:.1f}x** or more"
            elif brute["status"] == "ok":
                brute_text = ms(brute["gpu_ms"])
                if kd:
                    ratio = f"**{brute['gpu_ms'] / kd['gpu_ms']:.1f}x**"
        print(f"| {name} | {n:,} | {image} | {kd_text} | {brute_text} | {ratio} |")


def walks_table(docs):
    print(provenance(docs))
    print()
    print("| scene | objects | restart | ropes | short stack | fastest |")
    print("| --- | --: | --: | --: | --: | --- |")
    for name, n, image, walks, _ in cases(docs):
        if not walks:
            continue
        cells = [f"{walks[w]['gpu_ms']:,.1f}" if w in walks else "" for w in WALKS]
        best = min(walks, key=lambda w: walks[w]["gpu_ms"])
        print(f"| {name} ({image}) | {n:,} | {' | '.join(cells)} | {best} |")


def main():
    if len(sys.argv) < 2 or sys.argv[1] not in ("summary", "walks"):
        sys.exit(__doc__)
    folder = sys.argv[2] if len(sys.argv) > 2 else "docs/results/lavapipe"
    docs = load(folder)
    (summary if sys.argv[1] == "summary" else walks_table)(docs)


if __name__ == "__main__":
    main()
