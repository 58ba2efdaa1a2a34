#!/usr/bin/env python3
"""Renders a kdray path scene with Mitsuba 3 (llvm_ad_rgb) once, as a
user would in one process, and says where the time went: for
scripts/equal_time.py, which runs it in the Python that has Mitsuba.

    python3 scripts/peers/mitsuba_timed.py SCENE --width W --height H --spp N --seed S \
        -o OUT.exr [--aov] [--variant V]

The scene is converted as scripts/peers/mitsuba_path.py converts it (its
PLY meshes and resampled sky written to OUT's folder); the conversion is
the comparison's own work, not Mitsuba's, and is timed apart (convert_s)
so that the caller can leave it out. With `--aov` the path integrator is
wrapped in Mitsuba's `aov` integrator, which also gathers each pixel's
albedo and shading normal (world space, turned to face the camera) at the
first hit, and those are written beside OUT as OUT's name with `.albedo.exr` and `.normal.exr`, the
inputs Open Image Denoise takes with the colour. Prints one JSON object:
import_s (importing Dr.Jit and Mitsuba), convert_s, load_s (mi.load_dict:
reading the meshes, building the BVH), render_s (every pass, compiling
included), jit_s (Dr.Jit's code generation and LLVM compilation of the
kernels the render launched, from its kernel history: part of render_s),
write_s (the EXRs), and the samples per pixel. Dr.Jit keeps compiled
kernels in $HOME/.drjit; the caller points HOME at an empty folder for a
run that compiles everything.
"""

import argparse
import json
import os
import sys
import time

started = time.perf_counter()

import numpy as np  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import kdray_scene  # noqa: E402
import mitsuba_path  # noqa: E402


def write_exr(mi, path, rgb):
    """(H, W, 3) float32 as an RGB EXR, atomically (Mitsuba's writer, synchronous)."""
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), f".{os.path.basename(path)}.tmp-{os.getpid()}.exr")
    mi.Bitmap(np.ascontiguousarray(rgb, dtype=np.float32)).write(tmp)
    os.replace(tmp, path)


def facing_camera(scene, normals):
    """Mitsuba's normals turned to face the camera (each pixel's against
    its centre's camera ray), as kdray gathers them for its denoiser: its
    AOV gives a surface's normal as the mesh winds it, either side."""
    h, w, _ = normals.shape
    scene.render["samples"] = 1
    _, dirs = kdray_scene.primary_rays(scene, w, h)
    away = np.sum(normals * dirs.reshape(h, w, 3), axis=-1, keepdims=True) > 0
    return np.where(away, -normals, normals)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--width", type=int, required=True)
    ap.add_argument("--height", type=int, required=True)
    ap.add_argument("--spp", type=int, required=True)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--aov", action="store_true", help="also write albedo and normal for a denoiser")
    ap.add_argument("--variant", default="llvm_ad_rgb")
    args = ap.parse_args()

    mitsuba_path._llvm_path()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    imported = time.perf_counter()
    scene = kdray_scene.load(args.scene)
    mesh_dir = os.path.dirname(os.path.abspath(args.output))
    d = mitsuba_path.scene_dict(mi, scene, args.width, args.height, args.spp, mesh_dir)
    if args.aov:
        d["integrator"] = {"type": "aov", "aovs": "albedo:albedo,nn:sh_normal", "integrator": d["integrator"]}
    converted = time.perf_counter()
    mscene = mi.load_dict(d)
    loaded = time.perf_counter()

    dr.set_flag(dr.JitFlag.KernelHistory, True)
    per_pass = max(1, min(args.spp, mitsuba_path.MAX_WAVEFRONT // (args.width * args.height)))
    total = None
    done = k = 0
    while done < args.spp:
        n = min(per_pass, args.spp - done)
        img = np.array(mi.render(mscene, spp=n, seed=args.seed * 100003 + k), dtype=np.float64)
        total = img * n if total is None else total + img * n
        done += n
        k += 1
    image = (total / args.spp).astype(np.float32)
    rendered = time.perf_counter()
    # Milliseconds in the history; kernels found in the cache have no backend time.
    jit_ms = sum(h.get("codegen_time", 0.0) + h.get("backend_time", 0.0) for h in dr.kernel_history())

    base, _ = os.path.splitext(args.output)
    if args.aov:
        # Channels: R, G, B, then the AOVs in the order asked for.
        write_exr(mi, base + ".albedo.exr", image[:, :, 3:6])
        write_exr(mi, base + ".normal.exr", facing_camera(scene, image[:, :, 6:9]))
    write_exr(mi, args.output, image[:, :, :3])
    written = time.perf_counter()
    print(
        json.dumps(
            {
                "renderer": f"mitsuba {mi.__version__} {mi.variant()}",
                "threads": dr.thread_count(),
                "spp": args.spp,
                "passes": k,
                "import_s": imported - started,
                "convert_s": converted - imported,
                "load_s": loaded - converted,
                "render_s": rendered - loaded,
                "jit_s": jit_ms / 1e3,
                "write_s": written - rendered,
            }
        )
    )


if __name__ == "__main__":
    main()
