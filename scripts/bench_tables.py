#!/usr/bin/env python3
"""Prints a table of docs/benchmarks.md from the bench.json files that
scripts/lavapipe_bench.sh keeps in DIR (default docs/results/lavapipe):

    python3 scripts/bench_tables.py summary [DIR]   # "Current results"
    python3 scripts/bench_tables.py walks [DIR]     # "The walks"
    python3 scripts/bench_tables.py sweep [FILE]    # "The sweep"
    python3 scripts/bench_tables.py seed [DIR]      # "Compared with the seed"

DIR defaults to docs/results/lavapipe; FILE, the sweep that
scripts/sweep.sh keeps, to docs/results/sweep.json (`seed` reads both).
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
        print(f"| {name} | {n:,} | {image} | {kd_text} | {brute_cell(brute)} | {ratio_cell(kd, brute)} |")


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


SWEEP = "docs/results/sweep.json"


def load_sweep(path):
    with open(path) as f:
        return json.load(f)


def sweep_rows(doc):
    """{n: {"kdtree": run, "brute": run}} of the sweep's runs, by size."""
    rows = {}
    for run in doc["runs"]:
        rows.setdefault(run["n"], {})[run["accel"]] = run
    return dict(sorted(rows.items()))


def brute_cell(run):
    """Brute force's frame, or why it was skipped; its loops cut short by
    llvmpipe's limit are said (the frame is then if anything too fast)."""
    if run is None:
        return ""
    note = run.get("note") or ""
    if run["status"] == "skipped":
        pred = re.search(r"predicted ([0-9.]+) s", note)
        if pred:
            return f"skipped ({pred.group(1)} s predicted)"
        if "llvmpipe's limit" in note or "loop limit" in note:
            return "skipped (past llvmpipe's loop limit)"
        return "skipped"
    if run["status"] != "ok":
        return ""
    text = ms(run["gpu_ms"])
    if run.get("loop_limited_pixels"):
        text += f" ({run['loop_limited_pixels']:,} pixels cut by the loop limit)"
    return text


def ratio_cell(kd, brute):
    """Brute force's frame over the tree's, a lower bound where brute
    force's loops were cut short."""
    if not (kd and brute and brute["status"] == "ok"):
        return ""
    more = " or more" if brute.get("loop_limited_pixels") else ""
    return f"**{brute['gpu_ms'] / kd['gpu_ms']:.1f}x**{more}"


def sweep(doc):
    print(provenance([doc]))
    print()
    print("| spheres | k-d build | upload | k-d tree (short stack) | brute force | tree vs brute |")
    print("| --: | --: | --: | --: | --: | --: |")
    for n, by in sweep_rows(doc).items():
        kd, brute = by.get("kdtree"), by.get("brute")
        build = f"{kd['build_ms']:,.1f} ms" if kd else ""
        upload = f"{kd['upload_ms']:,.1f} ms" if kd else ""
        print(f"| {n:,} | {build} | {upload} | {ms(kd['gpu_ms']) if kd else ''} | {brute_cell(brute)} "
              f"| {ratio_cell(kd, brute)} |")
    fits = {f["accel"]: f for f in doc["fits"]}
    parts = []
    if fits.get("brute", {}).get("linear_r2") is not None:
        b = fits["brute"]
        parts.append(f"brute force's frame fits {b['linear_intercept_ms']:.0f} ms + "
                     f"{b['linear_per_object_ms']:.3f} ms an object (r² {b['linear_r2']:.3f})")
    if fits.get("kdtree", {}).get("loglog_slope") is not None:
        parts.append(f"the tree's frame grows with slope {fits['kdtree']['loglog_slope']:.2f} on log-log axes")
    if parts:
        print()
        print("Fits: " + "; ".join(parts) + ".")


def seed(docs, sweep_doc):
    """The seed study's three measurements beside kdray's current ones."""
    seed_case = next(c for c in cases(docs) if c[0] == "`scenes/seed.toml`")
    seed_kd = seed_case[3][DEFAULT_WALK]
    rows = sweep_rows(sweep_doc)
    measured = [n for n, by in rows.items() if by.get("brute", {}).get("status") == "ok"]
    largest = max(measured)
    speedups = [(n, rows[n]["brute"]["gpu_ms"] / rows[n]["kdtree"]["gpu_ms"]) for n in measured]
    million = rows.get(1_000_000, {}).get("kdtree")
    b = {f["accel"]: f for f in sweep_doc["fits"]}["brute"]
    print(provenance(docs + [sweep_doc]))
    print()
    print("| the seed | what it measured | kdray here |")
    print("| --- | --- | --- |")
    print(f"| figure 6 | its scene in Python: 123 s an image with reflections, 106 s without (size not given) "
          f"| {ms(seed_kd['gpu_ms'])} at {seed_case[2]} with reflections (short stack) |")
    print(f"| figure 7 | time linear in the number of objects, naive loop "
          f"| brute force linear up to {largest:,} spheres: r² {b['linear_r2']:.3f} ([The sweep](#the-sweep)) |")
    spread = ", ".join(f"{x:.1f}x at {n:,}" for n, x in speedups)
    mil = f"; at 1,000,000 spheres the tree's frame is {ms(million['gpu_ms'])} and brute force cannot run on llvmpipe" if million else ""
    print(f"| figure 9 | the tree's speed-up over the loop grows with N "
          f"| {brute_ms_ratio(seed_case):.1f}x on the seed's {seed_case[1]} objects; {spread} spheres{mil} |")


def brute_ms_ratio(case):
    _, _, _, walks, brute = case
    return brute["gpu_ms"] / walks[DEFAULT_WALK]["gpu_ms"]


def main():
    modes = ("summary", "walks", "sweep", "seed")
    if len(sys.argv) < 2 or sys.argv[1] not in modes:
        sys.exit(__doc__)
    mode, arg = sys.argv[1], (sys.argv[2] if len(sys.argv) > 2 else None)
    if mode == "sweep":
        sweep(load_sweep(arg or SWEEP))
    elif mode == "seed":
        seed(load(arg or "docs/results/lavapipe"), load_sweep(SWEEP))
    else:
        docs = load(arg or "docs/results/lavapipe")
        (summary if mode == "summary" else walks_table)(docs)


if __name__ == "__main__":
    main()
