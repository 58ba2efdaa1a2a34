#!/usr/bin/env python3
"""Prints the Markdown table of a scripts/peers/measure.sh run: each
renderer's rays, median time, M rays/s, and its ratio to Embree's.
Usage: summarize.py OUT_DIR
"""

import json
import os
import statistics
import sys


def main():
    out = sys.argv[1]
    rows = []
    for folder, threads in [("kdray-bench", "all (lavapipe)"), ("kdray-bench-1thread", "1 (LP_NUM_THREADS=1)")]:
        path = os.path.join(out, folder, "bench.json")
        if not os.path.exists(path):
            continue
        bench = json.load(open(path))
        (r,) = [x for x in bench["runs"] if x["accel"] == "kdtree"]
        assert r["reflection_rays"] == 0, "kdray traced reflections: max_depth is not 1"
        rays = r["primary_rays"] + r["shadow_rays"]
        seconds = r["gpu_ms"] / 1e3  # the median of the timed frames
        rows.append(
            {
                "renderer": f"kdray ({bench['machine']['adapter']}, {bench['machine']['backend']})",
                "threads": threads,
                "primary": r["primary_rays"],
                "shadow": r["shadow_rays"],
                "seconds": seconds,
                "mrays": rays / seconds / 1e6,
                "setup": f"tree {r['build_ms']:.0f} ms, upload {r['upload_ms']:.0f} ms; "
                f"frames {min(r['gpu_ms_samples']):.0f} - {max(r['gpu_ms_samples']):.0f} ms",
                "runs": len(r["gpu_ms_samples"]),
            }
        )
    embree = None
    path = os.path.join(out, "embree.json")
    if os.path.exists(path) and os.path.getsize(path):
        e = json.load(open(path))
        if "unsupported" in e:
            print(f"Embree: scene unsupported ({e['unsupported']})\n")
        else:
            embree = e["mrays_per_s_median"]
            rows.append(
                {
                    "renderer": "Embree 4 (embreex, rtcIntersect1/rtcOccluded1)",
                    "threads": "1 (taskset -c 0)",
                    "primary": e["primary_rays"],
                    "shadow": e["shadow_rays"],
                    "seconds": e["seconds_median"],
                    "mrays": e["mrays_per_s_median"],
                    "setup": f"BVH build {e['build_s'] * 1e3:.0f} ms",
                    "runs": e["repeat"],
                }
            )
    for name in ["mitsuba_1thread.json", "mitsuba.json"]:
        path = os.path.join(out, name)
        if not os.path.exists(path):
            continue
        m = json.load(open(path))
        rows.append(
            {
                "renderer": f"{m['renderer']} (`direct`, 1 spp)",
                "threads": f"{m['threads']}" + (" (taskset -c 0)" if m["cpu_affinity"] == [0] else ""),
                "primary": m["primary_rays"],
                "shadow": m["shadow_rays"],
                "seconds": m["seconds_median"],
                "mrays": m["mrays_per_s_median"],
                "setup": f"scene load {m['load_s'] * 1e3:.0f} ms, first frame {m['warmup_s'] * 1e3:.0f} ms",
                "runs": m["repeat"],
            }
        )
    print("| renderer | threads | primary rays | shadow rays | frame (median) | M rays/s | vs Embree | setup, not timed |")
    print("| --- | --- | --: | --: | --: | --: | --: | --- |")
    for r in rows:
        ratio = f"{r['mrays'] / embree:.2f}x" if embree else "n/a"
        print(
            f"| {r['renderer']} | {r['threads']} | {r['primary']:,} | {r['shadow']:,} | "
            f"{r['seconds'] * 1e3:.0f} ms (of {r['runs']}) | {r['mrays']:.2f} | {ratio} | {r['setup']} |"
        )
    print()
    with open(os.path.join(out, "machine.txt")) as f:
        for line in f:
            print(f"- {line.strip()}")


if __name__ == "__main__":
    main()
