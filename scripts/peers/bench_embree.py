#!/usr/bin/env python3
"""The Embree column of `kdray bench`: traces the primary and shadow rays of
every scene a bench run measured with Embree 4 (embreex) on one thread, and
writes OUT/embree.json; then `kdray bench --replot OUT` puts Embree's rays/s
and kdray's ratio to it in OUT/summary.md (a "vs Embree" column per scene).

    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install embreex numpy
    kdray bench --suite --build all --traversal all --out OUT   # writes OUT/scenes/*.json
    kdray bench --scene S.json --write-scenes --out OUT         # any scene: the same
    /tmp/peers/bin/python scripts/peers/bench_embree.py OUT [--repeat 3] [--kdray target/release/kdray]

Run it straight after the bench, on the same machine: the ratio is only
meaningful between runs on the same machine under the same load (uptime is
recorded before and after). Each scene is traced by embree_rays.py under
`taskset -c 0` (one core: embreex traces one ray at a time, and the pinning
keeps Embree's BVH build on one core too), from the scene file the bench
wrote (`scene_file` in bench.json: the same camera, image size, lights and
objects). Embree traces primary + shadow rays only, so compare with kdray
runs at max_depth 1 (the suite's triangle scenes; the summary shows each
scene's max_depth). embreex has no sphere geometry: scenes with spheres are
recorded as unsupported. Not a dependency of the crate.
"""

import argparse
import datetime
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))


def uptime():
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def embreex_version():
    try:
        from importlib.metadata import version

        return version("embreex")
    except Exception:  # noqa: BLE001 (any failure: unknown version)
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", help="the bench's output folder (bench.json, scenes/)")
    ap.add_argument("--repeat", type=int, default=3, help="timed runs per scene (default 3); the median is used")
    ap.add_argument(
        "--kdray",
        default=os.path.join(ROOT, "target", "release", "kdray"),
        help="kdray binary for the --replot (default target/release/kdray); 'none' skips it",
    )
    args = ap.parse_args()

    with open(os.path.join(args.out, "bench.json")) as f:
        bench = json.load(f)
    scenes = []
    for run in bench["runs"]:
        key = (run["scene"], run["n"])
        if key not in [(s["scene"], s["n"]) for s in scenes]:
            scenes.append({"scene": run["scene"], "n": run["n"], "scene_file": run.get("scene_file"),
                           "spheres": run["spheres"]})

    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    before = uptime()
    results = []
    for s in scenes:
        entry = {"scene": s["scene"], "n": s["n"]}
        if s["spheres"]:
            entry["unsupported"] = f"{s['spheres']} spheres: embreex exposes no sphere geometry"
            results.append(entry)
            continue
        if not s["scene_file"]:
            entry["unsupported"] = "the bench wrote no scene file (run it with --write-scenes, or --suite)"
            results.append(entry)
            continue
        path = os.path.join(args.out, s["scene_file"])
        print(f"embree: {s['scene']} N={s['n']} ({path})...", file=sys.stderr)
        proc = subprocess.run(
            ["taskset", "-c", "0", sys.executable, os.path.join(HERE, "embree_rays.py"), path,
             "--repeat", str(args.repeat)],
            capture_output=True,
            text=True,
        )
        if proc.returncode != 0:
            entry["unsupported"] = f"embree_rays.py failed ({proc.returncode}): {proc.stderr.strip()[-300:]}"
            results.append(entry)
            continue
        r = json.loads(proc.stdout)
        for key in ["primary_rays", "shadow_rays", "build_s", "repeat", "seconds_median",
                    "mrays_per_s_median", "seconds_best", "mrays_per_s_best", "primary_hits"]:
            entry[key] = r[key]
        print(f"  {r['mrays_per_s_median']} M rays/s", file=sys.stderr)
        results.append(entry)
    after = uptime()

    doc = {
        "renderer": "embree",
        "date_utc": started,
        "command": " ".join(["bench_embree.py"] + sys.argv[1:]),
        "uptime_before": before,
        "uptime_after": after,
        "embreex_version": embreex_version(),
        "threads": "1 (taskset -c 0; embreex traces one ray at a time)",
        "scenes": results,
    }
    target = os.path.join(args.out, "embree.json")
    tmp = target + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=2)
        f.write("\n")
    os.replace(tmp, target)
    print(f"wrote {target}", file=sys.stderr)

    if args.kdray != "none":
        subprocess.run([args.kdray, "bench", "--replot", args.out], check=True, stdout=subprocess.DEVNULL)
        print(f"rewrote {os.path.join(args.out, 'summary.md')} with the Embree column", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
