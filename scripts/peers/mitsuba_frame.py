#!/usr/bin/env python3
"""Renders a kdray scene's frame with Mitsuba 3 (llvm_ad_rgb: Dr.Jit's LLVM
backend on the CPU) and prints one JSON object: the frame time after a
warm-up, the rays it traced, M rays/s, and the scene load time separately.

    apt-get install -y libllvm19
    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install mitsuba numpy
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM-19.so \\
        /tmp/peers/bin/python scripts/peers/mitsuba_frame.py SCENE [--threads N] [--repeat N]

The frame: kdray's camera (same position, look-at, up, vertical field of
view and size), one sample per pixel (the scene's samples), and Mitsuba's
`direct` integrator with one emitter sample and no BSDF sample: one primary
ray per sample and, at each hit, one shadow ray to a light (one light chosen
per hit when there are several; kdray traces one per light with L . N > 0).
So it is the work of a kdray render at max_depth 1: no reflection rays.
The look differs: materials become two-sided diffuse (kdray's diffuse
colour), lights are Mitsuba point lights (which fall off with distance; kdray's
do not: their intensity is scaled to agree at the camera's look-at point), and Mitsuba jitters its sample inside the pixel. Triangles are flat
(no vertex normals), as in kdray; spheres are Mitsuba spheres.

`--variant cuda_ad_rgb` renders the same frame on an NVIDIA GPU (Dr.Jit's
CUDA backend). `--threads` sets Dr.Jit's thread pool (default: one per core). The frame time
is `mi.render` plus the wait for its result, after one untimed warm-up
render that compiles and caches the kernels. The ray count: primary rays are
the samples; shadow rays are the primary hits (counted with
`scene.ray_intersect` on the sensor's rays after timing).
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


def bsdf_for(material):
    # Mitsuba's diffuse reflectance must lie in [0, 1].
    rgb = [min(max(c, 0.0), 1.0) for c in material.diffuse]
    return {
        "type": "twosided",
        "material": {"type": "diffuse", "reflectance": {"type": "rgb", "value": rgb}},
    }


def mesh_for(mi, dr, name, triangles, bsdf):
    """One Mitsuba mesh of unshared vertices (3 per triangle), flat normals."""
    count = len(triangles)
    props = mi.Properties()
    props["bsdf"] = mi.load_dict(bsdf)
    mesh = mi.Mesh(name, 3 * count, count, props, False, False)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(triangles.astype(np.float32).reshape(-1))
    params["faces"] = mi.UInt32(np.arange(3 * count, dtype=np.uint32))
    params.update()
    return mesh


def scene_dict(mi, dr, scene, width, height, spp):
    cam = scene.camera
    d = {
        "type": "scene",
        "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
        "sensor": kdray_scene.mitsuba_sensor(mi, cam, width, height, spp),
    }
    target = np.array(cam["look_at"], dtype=np.float64)
    for i, light in enumerate(scene.lights):
        # Mitsuba's point lights fall off as 1 / r^2, kdray's do not: scale
        # the intensity so that the two agree at the camera's look-at point.
        r2 = float(np.sum((np.array(light["position"]) - target) ** 2))
        d[f"light{i}"] = {
            "type": "point",
            "position": light["position"],
            "intensity": {"type": "rgb", "value": [c * r2 for c in light["diffuse"]]},
        }
    for i, (c, r, m) in enumerate(
        zip(scene.sphere_centers, scene.sphere_radii, scene.sphere_materials)
    ):
        d[f"sphere{i}"] = {
            "type": "sphere",
            "center": c.tolist(),
            "radius": float(r),
            "bsdf": bsdf_for(scene.materials[m]),
        }
    names = np.array(scene.triangle_materials)
    for i, m in enumerate(sorted(set(scene.triangle_materials))):
        d[f"mesh{i}"] = mesh_for(
            mi, dr, f"mesh{i}", scene.triangles[names == m], bsdf_for(scene.materials[m])
        )
    return d


def primary_hits(mi, dr, mscene, width, height, spp):
    """How many of the frame's primary rays hit something."""
    sensor = mscene.sensors()[0]
    n = width * height * spp
    idx = dr.arange(mi.UInt32, n) // spp
    pos = mi.Vector2f(mi.Float(idx % width), mi.Float(idx // width))
    sample = (pos + 0.5) / mi.Vector2f(width, height)
    rays, _ = sensor.sample_ray(0.0, 0.5, sample, mi.Point2f(0.5, 0.5))
    si = mscene.ray_intersect(rays)
    return int(dr.count(si.is_valid())[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument(
        "--variant",
        default="llvm_ad_rgb",
        help="Mitsuba variant (default llvm_ad_rgb, the CPU; cuda_ad_rgb on an NVIDIA GPU)",
    )
    ap.add_argument("--threads", type=int, help="Dr.Jit worker threads (default: one per core)")
    ap.add_argument("--repeat", type=int, default=3, help="timed renders (default 3)")
    ap.add_argument("-o", "--output", help="also write the last frame (EXR, or PNG by extension)")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    if args.threads:
        dr.set_thread_count(args.threads)

    scene = kdray_scene.load(args.scene)
    width = args.width or scene.render["width"]
    height = args.height or scene.render["height"]
    spp = scene.render["samples"]

    t0 = time.perf_counter()
    mscene = mi.load_dict(scene_dict(mi, dr, scene, width, height, spp))
    load_s = time.perf_counter() - t0

    t0 = time.perf_counter()
    image = mi.render(mscene, spp=spp, seed=0)
    dr.eval(image)
    dr.sync_thread()
    warmup_s = time.perf_counter() - t0

    seconds = []
    for i in range(args.repeat):
        t0 = time.perf_counter()
        image = mi.render(mscene, spp=spp, seed=i + 1)
        dr.eval(image)
        dr.sync_thread()
        seconds.append(time.perf_counter() - t0)
    if args.output:
        mi.util.write_bitmap(args.output, image)

    primary = width * height * spp
    shadow = primary_hits(mi, dr, mscene, width, height, spp)
    best = min(seconds)
    median = statistics.median(seconds)
    print(
        json.dumps(
            {
                "renderer": f"mitsuba {mi.__version__} {args.variant}",
                "scene": args.scene,
                "width": width,
                "height": height,
                "spp": spp,
                "triangles": len(scene.triangles),
                "spheres": len(scene.sphere_radii),
                "threads": dr.thread_count(),
                "cpu_affinity": sorted(os.sched_getaffinity(0)),
                "load_s": round(load_s, 4),
                "warmup_s": round(warmup_s, 4),
                "primary_rays": primary,
                "shadow_rays": shadow,
                "repeat": args.repeat,
                "seconds": [round(x, 4) for x in seconds],
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
