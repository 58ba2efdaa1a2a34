#!/usr/bin/env python3
"""Prints the table of docs/benchmarks.md's "The window" from the JSON
scripts/window_bench.sh writes: per case, medians over its runs of the
frame rate the window reports for its frames (still or moving), their mean
time with the longest frame left out (the longest is the one that waited
for the kernel's compilation), the longest frame, the resolution divisor
while moving, the time to refine to every sample (still), and the reloads
the window reported.

    python3 scripts/window_table.py docs/results/window.json
"""

import statistics
import sys

import results_table


def figures(stats):
    """(kind, fps, mean ms without the longest frame, longest ms)."""
    kind = "still" if stats["still_frames"] > 0 else "moving"
    frames, ms, longest = stats[f"{kind}_frames"], stats[f"{kind}_ms"], stats[f"{kind}_longest_ms"]
    rest = (frames * ms - longest) / max(frames - 1, 1)
    return kind, stats[f"{kind}_fps"], rest, longest


def main():
    doc = results_table.load(sys.argv[1])
    cases = results_table.grouped(doc["runs"], "case")
    print(results_table.provenance(doc))
    print()
    print("| case | window | frames | frame rate | mean frame, longest left out | longest frame "
          "| resolution while moving | all samples in | reloads | runs |")
    print("| --- | --- | --- | --: | --: | --: | --: | --: | --: | --: |")
    for name, runs in cases.items():
        s = runs[0]["stats"]
        kinds, fps, rest, longest = zip(*(figures(r["stats"]) for r in runs))
        kind = kinds[0]
        scale = "" if kind == "still" else f"1/{statistics.median(r['stats']['moving_scale'] for r in runs):.0f}"
        refine = [r["stats"]["refine_seconds"] for r in runs if r["stats"]["refine_seconds"] is not None]
        refine = f"{statistics.median(refine):.2f} s ({s['samples']} samples)" if refine else ""
        reloads = "-".join(sorted({str(r["reloads"]) for r in runs}))
        print(f"| {name} | {s['width']}x{s['height']} | {statistics.median(r['stats'][kind + '_frames'] for r in runs):.0f} {kind} "
              f"| {statistics.median(fps):.1f} fps | {statistics.median(rest):.1f} ms "
              f"| {statistics.median(longest):,.0f} ms | {scale} | {refine} | {reloads} | {len(runs)} |")


if __name__ == "__main__":
    main()
