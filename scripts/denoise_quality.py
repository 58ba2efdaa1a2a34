#!/usr/bin/env python3
"""How much the denoiser gains (docs/benchmarks.md, "Denoising"): each
scene path traced at a few samples per pixel with `render --denoise`, its
noisy and its denoised image both held against a high-sample reference of
the same scene (another seed), by relative MSE and HDR-FLIP.

    pip install OpenEXR==3.5.3 flip-evaluator numpy
    python3 scripts/denoise_quality.py [--kdray BIN] [--out JSON] [--reference-spp N] [--spp N ...]

The scenes: scenes/cornell_box.toml at 128 x 128, scenes/bunny_sky.toml at
192 x 108 (the bunny from glmark2-data), and a textured glTF, Khronos'
BoxTextured from Debian's assimp-testmodels, turned on a matte floor under
scenes/models/sky.hdr, at 128 x 128. Relative MSE is the mean over pixels
and channels of (x - r)^2 / (r^2 + 0.01) (the 0.01 keeps black pixels from
dominating); FLIP is NVIDIA's HDR-FLIP (flip-evaluator), its mean over the
image. The reference's own noise is in both figures alike; at N samples
its variance is N / spp times below the noisy image's. Writes OUT (default
docs/results/denoise-quality.json) with the machine, adapter, commit and
load, and prints the table scripts/denoise_quality_table.py makes of it.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import OpenEXR

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

BOX_TEXTURED = "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf"

BOX_SCENE = f"""
[camera]
position = [2.2, 1.6, 2.6]
look_at  = [0.0, 0.45, 0.0]
vfov     = 40.0

[render]
width      = 128
height     = 128
integrator = "path"
samples    = 16
max_depth  = 6
exposure   = -1.0

[environment]
image     = "{ROOT}/scenes/models/sky.hdr"
intensity = 1.0
rotation  = 200.0

[materials.floor]
diffuse = [0.5, 0.5, 0.5]

[[meshes]]
path      = "{BOX_TEXTURED}"
rotate    = [0.0, 30.0, 0.0]
translate = [0.0, 0.5, 0.0]

[[triangles]]
vertices = [[-100.0, 0.0, -100.0], [100.0, 0.0, -100.0], [100.0, 0.0, 100.0]]
material = "floor"

[[triangles]]
vertices = [[-100.0, 0.0, -100.0], [100.0, 0.0, 100.0], [-100.0, 0.0, 100.0]]
material = "floor"
"""


def read_rgb(path):
    with OpenEXR.File(path, separate_channels=True) as f:
        channels = f.channels()
        return np.stack([channels[c].pixels for c in "RGB"], axis=-1).astype(np.float64)


def relative_mse(x, r):
    return float(np.mean((x - r) ** 2 / (r * r + 0.01)))


def flip_hdr(x, r):
    import flip_evaluator as flip
    _, mean, _ = flip.evaluate(r.astype(np.float32), x.astype(np.float32), "HDR", applyMagma=False)
    return float(mean)


def render(kdray, scene, size, spp, seed, out, denoise):
    args = [kdray, "render", scene, "--width", str(size[0]), "--height", str(size[1]),
            "--samples", str(spp), "--seed", str(seed), "-o", out]
    if denoise:
        args.append("--denoise")
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def provenance(kdray):
    cpu = next(l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name"))
    info = subprocess.run([kdray, "info"], capture_output=True, text=True).stdout
    adapter = next((l[2:] for l in info.splitlines() if l.startswith("* ")), "unknown")
    commit = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True, text=True,
                            cwd=ROOT).stdout.strip()
    return {"machine": f"{cpu}, {os.cpu_count()} cores", "adapter": adapter, "commit": commit}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kdray", default=os.path.join(ROOT, "target/release/kdray"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs/results/denoise-quality.json"))
    parser.add_argument("--reference-spp", type=int, default=4096)
    parser.add_argument("--spp", type=int, nargs="+", default=[4, 16])
    args = parser.parse_args()
    kdray = os.path.abspath(args.kdray)
    load_before = open("/proc/loadavg").read().split()[0]
    runs = []
    with tempfile.TemporaryDirectory() as work:
        box = os.path.join(work, "box_textured.toml")
        with open(box, "w") as f:
            f.write(BOX_SCENE)
        scenes = [
            ("cornell_box", os.path.join(ROOT, "scenes/cornell_box.toml"), (128, 128)),
            ("bunny_sky", os.path.join(ROOT, "scenes/bunny_sky.toml"), (192, 108)),
            ("box_textured", box, (128, 128)),
        ]
        for name, scene, size in scenes:
            ref_path = os.path.join(work, f"{name}.ref.exr")
            render(kdray, scene, size, args.reference_spp, 1, ref_path, False)
            reference = read_rgb(ref_path)
            for spp in args.spp:
                out = os.path.join(work, f"{name}.{spp}.exr")
                render(kdray, scene, size, spp, 2, out, True)
                noisy = read_rgb(os.path.join(work, f"{name}.{spp}.noisy.exr"))
                denoised = read_rgb(out)
                run = {"scene": name, "width": size[0], "height": size[1], "spp": spp,
                       "noisy": {"rel_mse": relative_mse(noisy, reference), "flip": flip_hdr(noisy, reference)},
                       "denoised": {"rel_mse": relative_mse(denoised, reference),
                                    "flip": flip_hdr(denoised, reference)}}
                print(json.dumps(run), file=sys.stderr)
                runs.append(run)
    doc = provenance(kdray)
    doc["reference_spp"] = args.reference_spp
    doc["load"] = f"{load_before} - {open('/proc/loadavg').read().split()[0]}"
    doc["runs"] = runs
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1)
    os.replace(tmp, args.out)
    subprocess.run([sys.executable, os.path.join(HERE, "denoise_quality_table.py"), args.out], check=True)


if __name__ == "__main__":
    main()
