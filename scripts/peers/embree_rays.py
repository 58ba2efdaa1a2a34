#!/usr/bin/env python3
"""Traces kdray's primary and shadow rays for a scene with Embree 4
(through embreex) on one CPU thread, and prints one JSON object: rays
traced, seconds, M rays/s, and the BVH build time separately.

    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install embreex numpy
    taskset -c 0 /tmp/peers/bin/python scripts/peers/embree_rays.py SCENE [--width W --height H] [--repeat N]

The rays are kdray's (docs/scene-format.md, shaders/trace.wgsl): one primary
ray per pixel centre (k x k per pixel when samples = k * k) from the camera,
and at each primary hit one shadow ray per light with L . N > 0, from the
hit point moved off the surface by kdray's spawn offset, to the light
(an occlusion query on that segment). No reflection rays: compare with a
kdray render whose max_depth is 1.

One thread: embreex traces one ray at a time (rtcIntersect1 and
rtcOccluded1 in a loop on the calling thread), so tracing is single-threaded
by construction; run the script under `taskset -c 0` so that Embree's BVH
build (TBB threads) is on one core too. Times are of the `run` calls only
(the loop over rays in embreex's Cython wrapper, including its per-ray copy
into Embree's ray struct); making the ray arrays in numpy is not counted.

Spheres: embreex exposes triangle meshes only, so a scene with spheres is
reported as unsupported (exit code 3).
"""

import argparse
import json
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import kdray_scene  # noqa: E402


def spawn_offset(p, magnitude):
    """kdray's offset along N for secondary rays (shaders/intersect.wgsl)."""
    return np.maximum(
        1e-4 * np.maximum(np.abs(p).max(axis=1), 1.0), magnitude * (1.0 / 4194304.0)
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--repeat", type=int, default=3, help="timed runs (default 3); the best and median are reported")
    args = ap.parse_args()

    from embreex import mesh_construction, rtcore_scene

    scene = kdray_scene.load(args.scene)
    if len(scene.sphere_radii):
        print(
            json.dumps(
                {
                    "scene": args.scene,
                    "unsupported": f"{len(scene.sphere_radii)} spheres: embreex exposes no sphere geometry",
                }
            )
        )
        return 3
    tris = scene.triangles.astype(np.float32)
    width = args.width or scene.render["width"]
    height = args.height or scene.render["height"]
    origins, dirs = kdray_scene.primary_rays(scene, width, height)
    lights = np.array([l["position"] for l in scene.lights], dtype=np.float32)
    # Per triangle: the largest vertex coordinate magnitude (the spawn
    # offset's `magnitude` for a triangle).
    magnitude = np.abs(tris).reshape(len(tris), -1).max(axis=1)

    # Build: mesh upload and BVH commit (embreex commits lazily, on the first
    # query, so one ray forces it).
    t0 = time.perf_counter()
    emb = rtcore_scene.EmbreeScene()
    mesh_construction.TriangleMesh(emb, tris)
    emb.run(origins[:1], dirs[:1])
    build_s = time.perf_counter() - t0

    primary_s, shadow_s = [], []
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        hit = emb.run(origins, dirs, output=1)
        primary_s.append(time.perf_counter() - t0)

        prim = hit["primID"]
        is_hit = prim >= 0
        t = hit["tfar"][is_hit].astype(np.float32)
        d = dirs[is_hit]
        p = origins[is_hit] + t[:, None] * d
        n = hit["Ng"][is_hit]
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        n[(n * d).sum(axis=1) > 0] *= -1.0  # face the incoming ray
        origin = p + spawn_offset(p, magnitude[prim[is_hit]])[:, None] * n
        s_orig, s_dir, s_len = [], [], []
        for light in lights:
            to_light = light[None, :] - p
            dist = np.linalg.norm(to_light, axis=1)
            lit = (dist > 0) & ((to_light * n).sum(axis=1) > 0)
            from_origin = light[None, :] - origin[lit]
            length = np.linalg.norm(from_origin, axis=1)
            ok = length > 0
            s_orig.append(origin[lit][ok])
            s_dir.append(from_origin[ok] / length[ok][:, None])
            s_len.append(length[ok])
        s_orig = np.ascontiguousarray(np.concatenate(s_orig), dtype=np.float32)
        s_dir = np.ascontiguousarray(np.concatenate(s_dir), dtype=np.float32)
        s_len = np.ascontiguousarray(np.concatenate(s_len), dtype=np.float32)

        t0 = time.perf_counter()
        occluded = emb.run(s_orig, s_dir, dists=s_len, query="OCCLUDED") >= 0
        shadow_s.append(time.perf_counter() - t0)

    primary = len(dirs)
    shadow = len(s_dir)
    total_s = [a + b for a, b in zip(primary_s, shadow_s)]
    best = min(total_s)
    median = statistics.median(total_s)
    print(
        json.dumps(
            {
                "renderer": "embree",
                "scene": args.scene,
                "width": width,
                "height": height,
                "triangles": len(tris),
                "threads": "1 (embreex traces one ray at a time on the calling thread)",
                "cpu_affinity": sorted(os.sched_getaffinity(0)),
                "build_s": round(build_s, 4),
                "primary_rays": primary,
                "primary_hits": int(is_hit.sum()),
                "shadow_rays": shadow,
                "shadow_occluded": int(occluded.sum()),
                "repeat": args.repeat,
                "primary_s": [round(x, 4) for x in primary_s],
                "shadow_s": [round(x, 4) for x in shadow_s],
                "seconds_best": round(best, 4),
                "seconds_median": round(median, 4),
                "mrays_per_s_best": round((primary + shadow) / best / 1e6, 3),
                "mrays_per_s_median": round((primary + shadow) / median / 1e6, 3),
            }
        )
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
