#!/usr/bin/env python3
"""Equal-samples error of kdray's and Mitsuba 3's path tracers on a scene of
many lights (docs/peers.md, "Light sampling against Mitsuba 3"). kdray's
next-event estimation picks a light by power; Mitsuba's `path` integrator
picks an emitter uniformly (each shape one emitter: a mesh is one, sampled
by area within; each sphere one; the sky one; each point or directional
light one). Run by hand, like mitsuba_path.py (its setup):

    python3 scripts/peers/light_sampling.py SCENE --kdray BIN [--spp 16 64]
        [--seeds 3] [--ref-spp 4096] [--save NAME]

It renders the reference, Mitsuba at --ref-spp samples (seed 1000), then at
each of --spp, --seeds images from each renderer (kdray `--seed 1..n`,
Mitsuba seeds 2000..), and prints one JSON object (`--save NAME` also
writes scripts/peers/results/NAME.json): per samples count, each image's
relative MSE against the reference,

    rel_mse = mean over channels c of  mean_pixels (x_c - ref_c)^2 / mean_pixels(ref_c)^2,

their mean per renderer, and kdray's mean over Mitsuba's. The reference's
own noise adds the same to both (independent images, E (x - ref)^2 =
var x + var ref, both renderers converging to the same image:
mitsuba_path.py compare checks that); `reference_noise_estimate` is
Mitsuba's figure at the most samples scaled by samples / ref_spp, what
the reference contributes.
"""

import argparse
import json
import os
import platform
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import kdray_scene  # noqa: E402
import mitsuba_path  # noqa: E402


def rel_mse(img, ref):
    """Mean over channels of MSE / (the reference's mean)^2."""
    img = img.astype(np.float64)
    ref = ref.astype(np.float64)
    per = [np.mean((img[:, :, c] - ref[:, :, c]) ** 2) / np.mean(ref[:, :, c]) ** 2 for c in range(3)]
    return float(np.mean(per))


def light_counts(scene):
    """What each renderer picks among: kdray's entries (each emissive
    triangle and sphere, each scene light, the sky image) and Mitsuba's
    emitters (a mesh of one material is one; a uniform sky is a `constant`
    emitter in Mitsuba, not an entry of kdray's)."""
    emissive = {n for n, m in scene.materials.items() if max(m.emission) > 0.0}
    spheres = sum(1 for n in scene.sphere_materials if n in emissive)
    tris = [n for n in scene.triangle_materials if n in emissive]
    sky_image = "image" in scene.environment
    sky_color = scene.environment.get("color", scene.render["background"])
    uniform_sky = not sky_image and max(sky_color) > 0.0
    lights = len(scene.lights)
    return {
        "scene_lights": lights,
        "emissive_spheres": spheres,
        "emissive_triangles": len(tris),
        "sky_image": sky_image,
        "kdray_entries": lights + spheres + len(tris) + int(sky_image),
        "mitsuba_emitters": lights + spheres + len(set(tris)) + int(sky_image) + int(uniform_sky),
    }


def machine():
    model = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return {"cpu": model, "cpus": os.cpu_count(), "system": platform.platform()}


def uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--kdray", default=os.environ.get("KDRAY", "kdray"), help="the kdray binary (default $KDRAY)")
    ap.add_argument("--spp", type=int, nargs="+", default=[16, 64], help="samples per pixel compared (default 16 64)")
    ap.add_argument("--seeds", type=int, default=3, help="images per renderer and samples count (default 3)")
    ap.add_argument("--ref-spp", type=int, default=4096, help="the Mitsuba reference's samples (default 4096)")
    ap.add_argument("--threads", type=int, help="Dr.Jit threads (default: one per core; 1 hung reading EXRs here)")
    ap.add_argument("--out", default="/tmp/light_sampling", help="folder for images and meshes")
    ap.add_argument("--save", help="also write scripts/peers/results/SAVE.json")
    args = ap.parse_args()

    mitsuba_path._llvm_path()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    if args.threads:
        dr.set_thread_count(args.threads)
    scene = kdray_scene.load(args.scene)
    width, height = scene.render["width"], scene.render["height"]
    name = args.save or os.path.splitext(os.path.basename(args.scene))[0]
    mesh_dir = os.path.join(args.out, name + "_meshes")
    os.makedirs(mesh_dir, exist_ok=True)
    try:
        d = mitsuba_path.scene_dict(mi, scene, width, height, args.ref_spp, mesh_dir)
    except mitsuba_path.Refused as e:
        sys.exit(f"refused: {e}")
    result = {
        "scene": os.path.relpath(os.path.abspath(args.scene), os.path.dirname(os.path.dirname(HERE))),
        "width": width,
        "height": height,
        "kdray_max_depth": int(scene.render["max_depth"]),
        "mitsuba_max_depth": int(scene.render["max_depth"]) + 1,
        "lights": light_counts(scene),
        "mitsuba": f"mitsuba {mi.__version__} {mi.variant()}, {dr.thread_count()} threads",
        "machine": machine(),
        "uptime_before": uptime(),
    }
    mscene = mi.load_dict(d)
    t0 = time.perf_counter()
    ref = mitsuba_path.mitsuba_render(mi, dr, mscene, width, height, args.ref_spp, seed=1000)
    result["reference"] = {
        "renderer": "mitsuba",
        "spp": args.ref_spp,
        "seed": 1000,
        "seconds": round(time.perf_counter() - t0, 3),
    }
    mi.Bitmap(ref).write(os.path.join(args.out, name + "_reference.exr"))

    runs = []
    for spp in args.spp:
        kd, ms, adapter = [], [], None
        for s in range(args.seeds):
            exr = os.path.join(args.out, f"{name}_kdray_{spp}_{s + 1}.exr")
            cmd = [args.kdray, "render", args.scene, "--samples", str(spp), "--seed", str(s + 1), "-o", exr]
            p = subprocess.run(cmd + ["--stats"], capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit(f"kdray failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}")
            for line in (p.stdout + "\n" + p.stderr).splitlines():
                if line.strip().startswith("{") and '"adapter"' in line:
                    adapter = json.loads(line)["adapter"]
            kd.append(rel_mse(np.array(mi.Bitmap(exr), dtype=np.float32)[:, :, :3], ref))
            m = mitsuba_path.mitsuba_render(mi, dr, mscene, width, height, spp, seed=2000 + s)
            ms.append(rel_mse(m, ref))
        runs.append(
            {
                "spp": spp,
                "kdray_rel_mse": [round(x, 6) for x in kd],
                "mitsuba_rel_mse": [round(x, 6) for x in ms],
                "kdray_mean": round(float(np.mean(kd)), 6),
                "mitsuba_mean": round(float(np.mean(ms)), 6),
                "kdray_over_mitsuba": round(float(np.mean(kd) / np.mean(ms)), 4),
            }
        )
        print(json.dumps(runs[-1]), file=sys.stderr, flush=True)
        result["kdray_adapter"] = adapter
    most = max(runs, key=lambda r: r["spp"])
    result["rel_mse"] = "mean over channels of mean (x - ref)^2 / mean(ref)^2, ref the reference"
    result["runs"] = runs
    result["reference_noise_estimate"] = round(most["mitsuba_mean"] * most["spp"] / args.ref_spp, 6)
    result["kdray_command"] = f"{args.kdray} render {args.scene} --samples N --seed S -o X.exr --stats"
    result["uptime_after"] = uptime()
    text = json.dumps(result, indent=1)
    print(text)
    if args.save:
        path = os.path.join(mitsuba_path.RESULTS, args.save + ".json")
        tmp = path + ".tmp"
        with open(tmp, "w") as f:
            f.write(text + "\n")
        os.replace(tmp, path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
