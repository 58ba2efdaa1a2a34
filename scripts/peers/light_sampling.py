#!/usr/bin/env python3
"""Equal-samples error of kdray's and Mitsuba 3's path tracers on a scene of
many lights (docs/peers.md, "Light sampling against Mitsuba 3"). kdray's
next-event estimation picks a light by power, an emitter among the emitters
by its light tree; Mitsuba's `path` integrator
picks an emitter uniformly (each shape one emitter: a mesh is one, sampled
by area within; each sphere one; the sky one; each point or directional
light one). Run by hand, like mitsuba_path.py (its setup):

    python3 scripts/peers/light_sampling.py SCENE --kdray BIN [--spp 16 64]
        [--seeds 3] [--ref-spp 4096] [--save NAME]

It renders the reference, Mitsuba at --ref-spp samples (seed 1000), then at
each of --spp, --seeds images from each renderer (kdray `--seed 1..n`,
Mitsuba seeds 2000..; and Mitsuba with each emitter's `sampling_weight`
set to its power as kdray weighs it, seeds 3000..), and prints one JSON object (`--save NAME` also
writes scripts/peers/results/NAME.json): per samples count, each image's
relative MSE against the reference,

    rel_mse = mean over channels c of  mean_pixels (x_c - ref_c)^2 / mean_pixels(ref_c)^2,

their mean per renderer, and kdray's mean over Mitsuba's; and the same
means over the pixels that show no emitter directly (`surface_*`: the
reference's luminance below SURFACE_LUMINANCE), where only the light
sampling differs. The reference's
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


def rel_mse(img, ref, mask=None):
    """Mean over channels of MSE / (the reference's mean)^2, over the
    pixels of `mask` (all by default)."""
    img = img.astype(np.float64)
    ref = ref.astype(np.float64)
    if mask is not None:
        img, ref = img[mask][:, None, :], ref[mask][:, None, :]
    per = [np.mean((img[:, :, c] - ref[:, :, c]) ** 2) / np.mean(ref[:, :, c]) ** 2 for c in range(3)]
    return float(np.mean(per))


# Pixels whose reference luminance is below this show no emitter directly
# (the city's dimmest lamp has a luminance of 0.78): their error is the
# light sampling's, while a lamp a few pixels wide seen directly carries the
# noise of where in the pixel the camera ray falls, the same for any light
# sampling, and in the city most of the squared error.
SURFACE_LUMINANCE = 0.5


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


def luminance(c):
    """Rec. 709 luminance, as kdray's layout/light_picks.rs weighs power."""
    return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]


def with_power_weights(mi, d, scene):
    """A copy of Mitsuba scene dict d (mitsuba_path.scene_dict's) with each
    emitter's `sampling_weight` set to its power as kdray weighs it
    (crates/kdray-core/src/layout/light_picks.rs): point 4 pi I,
    directional E pi R^2, sphere pi 4 pi r^2 L, a mesh the sum of its
    triangles' pi A L, the sky image pi 4 pi R^2 times its mean radiance;
    R the radius of the sphere around the scene's box. Mitsuba then picks
    its emitters as kdray picks its blocks (within a mesh, by area, as
    kdray's equal-radiance triangles by power)."""
    # Copies of the entries changed (the rest, Mitsuba objects among them, shared).
    d = {k: (dict(v, **({"emitter": dict(v["emitter"])} if "emitter" in v else {})) if isinstance(v, dict) else v)
         for k, v in d.items()}
    lo = np.full(3, np.inf)
    hi = np.full(3, -np.inf)
    if len(scene.sphere_radii):
        lo = np.minimum(lo, (scene.sphere_centers - scene.sphere_radii[:, None]).min(axis=0))
        hi = np.maximum(hi, (scene.sphere_centers + scene.sphere_radii[:, None]).max(axis=0))
    if len(scene.triangles):
        lo = np.minimum(lo, scene.triangles.reshape(-1, 3).min(axis=0))
        hi = np.maximum(hi, scene.triangles.reshape(-1, 3).max(axis=0))
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    for i, light in enumerate(scene.lights):
        lum = luminance(light["diffuse"])
        w = 4 * np.pi * lum if light["kind"] == "point" else lum * np.pi * radius**2
        d[f"light{i}"]["sampling_weight"] = float(w)
    for i, (r, name) in enumerate(zip(scene.sphere_radii, scene.sphere_materials)):
        if "emitter" in d[f"sphere{i}"]:
            L = luminance(scene.materials[name].emission)
            d[f"sphere{i}"]["emitter"]["sampling_weight"] = float(np.pi * 4 * np.pi * r * r * L)
    names = np.array(scene.triangle_materials)
    for i, name in enumerate(sorted(set(scene.triangle_materials))):
        if "emitter" in d[f"mesh{i}"]:
            t = scene.triangles[names == name]
            area = 0.5 * np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1).sum()
            L = luminance(scene.materials[name].emission)
            d[f"mesh{i}"]["emitter"]["sampling_weight"] = float(np.pi * area * L)
    if "image" in scene.environment:
        texels = mitsuba_path.sky_texels(mi, os.path.join(scene.folder, scene.environment["image"]))
        h = texels.shape[0]
        rows = np.arange(h)
        solid = 2 * np.pi / texels.shape[1] * (np.cos(rows / h * np.pi) - np.cos((rows + 1) / h * np.pi))
        mean = float((luminance(texels.transpose(2, 0, 1)).sum(axis=1) * solid).sum() / (4 * np.pi))
        mean *= float(scene.environment.get("intensity", 1.0))
        d["sky"]["sampling_weight"] = np.pi * 4 * np.pi * radius**2 * mean
    return d


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
    # Mitsuba with each emitter's sampling_weight set to kdray's power.
    mscene_power = mi.load_dict(with_power_weights(mi, d, scene))
    t0 = time.perf_counter()
    ref = mitsuba_path.mitsuba_render(mi, dr, mscene, width, height, args.ref_spp, seed=1000)
    result["reference"] = {
        "renderer": "mitsuba",
        "spp": args.ref_spp,
        "seed": 1000,
        "seconds": round(time.perf_counter() - t0, 3),
    }
    mi.Bitmap(ref).write(os.path.join(args.out, name + "_reference.exr"))

    ref_luminance = 0.2126 * ref[:, :, 0] + 0.7152 * ref[:, :, 1] + 0.0722 * ref[:, :, 2]
    surface = np.asarray(ref_luminance) < SURFACE_LUMINANCE
    runs = []
    for spp in args.spp:
        kd, ms, mp, adapter = [], [], [], None
        kd_surface, ms_surface = [], []
        for s in range(args.seeds):
            exr = os.path.join(args.out, f"{name}_kdray_{spp}_{s + 1}.exr")
            cmd = [args.kdray, "render", args.scene, "--samples", str(spp), "--seed", str(s + 1), "-o", exr]
            p = subprocess.run(cmd + ["--stats"], capture_output=True, text=True)
            if p.returncode != 0:
                sys.exit(f"kdray failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}")
            for line in (p.stdout + "\n" + p.stderr).splitlines():
                if line.strip().startswith("{") and '"adapter"' in line:
                    adapter = json.loads(line)["adapter"]
            k = np.array(mi.Bitmap(exr), dtype=np.float32)[:, :, :3]
            kd.append(rel_mse(k, ref))
            kd_surface.append(rel_mse(k, ref, surface))
            m = mitsuba_path.mitsuba_render(mi, dr, mscene, width, height, spp, seed=2000 + s)
            ms.append(rel_mse(m, ref))
            ms_surface.append(rel_mse(m, ref, surface))
            m = mitsuba_path.mitsuba_render(mi, dr, mscene_power, width, height, spp, seed=3000 + s)
            mp.append(rel_mse(m, ref))
        runs.append(
            {
                "spp": spp,
                "kdray_rel_mse": [round(x, 6) for x in kd],
                "mitsuba_rel_mse": [round(x, 6) for x in ms],
                "kdray_mean": round(float(np.mean(kd)), 6),
                "mitsuba_mean": round(float(np.mean(ms)), 6),
                "kdray_over_mitsuba": round(float(np.mean(kd) / np.mean(ms)), 4),
                "mitsuba_power_weights_rel_mse": [round(x, 6) for x in mp],
                "mitsuba_power_weights_mean": round(float(np.mean(mp)), 6),
                "surface_pixels": int(surface.sum()),
                "kdray_surface_mean": round(float(np.mean(kd_surface)), 6),
                "mitsuba_surface_mean": round(float(np.mean(ms_surface)), 6),
                "kdray_over_mitsuba_surface": round(float(np.mean(kd_surface) / np.mean(ms_surface)), 4),
            }
        )
        print(json.dumps(runs[-1]), file=sys.stderr, flush=True)
        result["kdray_adapter"] = adapter
    most = max(runs, key=lambda r: r["spp"])
    result["rel_mse"] = "mean over channels of mean (x - ref)^2 / mean(ref)^2, ref the reference"
    result["surface"] = f"the same over the pixels whose reference luminance is below {SURFACE_LUMINANCE}"
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
