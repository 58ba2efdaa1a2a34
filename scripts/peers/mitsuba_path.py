#!/usr/bin/env python3
"""Holds kdray's path tracer (`[render] integrator = "path"`) against
Mitsuba 3's `path` integrator: the same scene, resolution and samples per
pixel rendered by both, compared by block means (noise-aware), or timed.
Run by hand; Mitsuba (a 60 MB wheel) is no part of the test run.

    apt-get install -y libllvm19          # Dr.Jit's LLVM backend (llvm_ad_rgb)
    python3 -m pip install mitsuba numpy  # Mitsuba 3.9 was used
    python3 scripts/peers/mitsuba_path.py compare SCENE --kdray BIN [--spp N] [--save NAME]
    python3 scripts/peers/mitsuba_path.py speed SCENE --kdray BIN [--spp N] [--save NAME]

`compare` renders SCENE with `BIN render SCENE --samples N -o X.exr` (linear
radiance) and twice with Mitsuba (seeds 0 and 1, N samples each). It prints
one JSON object: per channel, kdray against Mitsuba seed 0 and, as the noise
floor, Mitsuba seed 1 against seed 0 (the same statistics between two
images that differ by noise alone). `--save NAME` also writes it to
scripts/peers/results/NAME.json. Images (EXR, and a PNG of kdray | Mitsuba |
relative difference of block means) go to --out (default /tmp/mitsuba_path).

`speed` times, in one run: kdray (its --stats: gpu_ms, samples/s, rays;
then the same render without --stats, by the wall clock), then
Mitsuba llvm_ad_rgb on one thread and on every thread (after an untimed
warm-up render that compiles the kernels), with `uptime` before and after.

The conversion (refused, with a message, where Mitsuba cannot express
kdray's material exactly):
- camera: Mitsuba `perspective`, fov = kdray's vfov, fov_axis "y", the same
  look_at; a box pixel filter (radius 0.5: each sample falls in its own
  pixel, at a uniformly random position in it, as in kdray);
- integrator: Mitsuba `path` with max_depth = kdray's max_depth + 1 (kdray
  counts scattering hits, Mitsuba the path's segments, the last one to the
  emitter included);
- Lambertian `diffuse` -> `diffuse`; reflection 1 -> `conductor` with
  material "none" (a perfect mirror); 0 < reflection < 1 with a Lambertian
  rest -> `blendbsdf` (kdray's mixture is linear, as blendbsdf's); glass
  (transmission 1, reflection 0) -> `dielectric` int_ior = ior, ext_ior = 1
  (untinted, exact Fresnel: kdray's glass); metal/rough with metallic 1 and
  base_color [1, 1, 1] -> `roughconductor` material "none", ggx,
  alpha = roughness^2 (kdray's GGX alpha; with F0 = 1 Schlick's Fresnel is 1,
  as "none" is). Mitsuba's Smith masking is the separable
  G1(wi) G1(wo), kdray's the height-correlated one, which is larger
  (brighter) at grazing angles: the two rough metals differ by that alone.
  Every opaque BSDF is wrapped in `twosided` (kdray shades both sides).
- emission -> an `area` emitter on the sphere (outward) or on the triangles
  (front side: (v1 - v0) x (v2 - v0), which is Mitsuba's face normal too);
  `[environment] color` (or render.background) -> `constant`; point lights ->
  `point` (intensity in W/sr: radiance I / d^2 in both); directional lights
  -> `directional` (irradiance in W/m^2, the same direction of travel);
  `[environment] image` -> `envmap` (mitsuba_sky_image and envmap_of: the
  image resampled so that Mitsuba's bilinear lookup gives kdray's nearest
  texel but near texel edges; `compare` then records how far the two skies
  differ). Spot lights and `reference_distance` are refused.
Triangles of one material become one PLY mesh of unshared vertices and face
normals (flat, as kdray shades a `smooth = false` mesh).
"""

import argparse
import glob
import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import kdray_scene  # noqa: E402

RESULTS = os.path.join(HERE, "results")
# Mitsuba's LLVM variant renders one wavefront per pass: at most this many
# samples in one (memory grows with it; about 1 KB per sample).
MAX_WAVEFRONT = 1 << 22


class Refused(Exception):
    """A scene feature Mitsuba cannot express exactly."""


def _llvm_path():
    # Dr.Jit looks for libLLVM; Debian's libllvm19 does not put it on its path.
    if "DRJIT_LIBLLVM_PATH" in os.environ:
        return
    for pattern in (
        "/usr/lib/x86_64-linux-gnu/libLLVM-19.so",
        "/usr/lib/x86_64-linux-gnu/libLLVM*.so*",
        "/usr/lib/llvm-*/lib/libLLVM*.so*",
    ):
        found = sorted(glob.glob(pattern))
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[-1]
            return


def _rgb(v):
    return {"type": "rgb", "value": [float(c) for c in v]}


def bsdf_for(name, m):
    """The Mitsuba BSDF dict of kdray material m, or Refused."""
    r, t = m.reflection, m.transmission
    where = f"material {name!r}"
    if t > 0.0:
        if t < 1.0 or r > 0.0:
            raise Refused(
                f"{where}: glass mixed with another lobe (reflection {r}, transmission {t}); "
                "Mitsuba's blendbsdf cannot hold a two-sided dielectric beside an opaque BSDF"
            )
        return {"type": "dielectric", "int_ior": float(m.ior), "ext_ior": 1.0}
    mirror = {"type": "conductor", "material": "none"}
    if r >= 1.0:
        return {"type": "twosided", "material": mirror}
    if m.model == "lambertian":
        if max(m.diffuse) > 1.0:
            raise Refused(f"{where}: diffuse {m.diffuse} above 1 (Mitsuba clamps albedo)")
        model = {"type": "diffuse", "reflectance": _rgb(m.diffuse)}
    else:
        if m.metallic != 1.0 or tuple(m.diffuse) != (1.0, 1.0, 1.0):
            raise Refused(
                f"{where}: metal/rough with metallic {m.metallic} and base_color {m.diffuse}; "
                "Mitsuba has no Schlick-Fresnel GGX (only metallic 1 with base_color [1, 1, 1], "
                "whose Fresnel is 1, maps exactly)"
            )
        model = {
            "type": "roughconductor",
            "material": "none",
            "distribution": "ggx",
            # kdray's alpha, floored as in shaders/bsdf.wgsl (MIN_ALPHA).
            "alpha": max(m.roughness**2, 1e-3),
        }
    if r > 0.0:
        # blendbsdf: (1 - weight) * first + weight * second.
        model = {"type": "blendbsdf", "weight": float(r), "a": model, "b": mirror}
    return {"type": "twosided", "material": model}


def _write_ply(path, triangles):
    """Binary PLY of unshared vertices: 3 per triangle, in order."""
    count = len(triangles)
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {3 * count}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {count}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    faces = np.zeros(count, dtype=[("n", "u1"), ("i", "<i4", (3,))])
    faces["n"] = 3
    faces["i"] = np.arange(3 * count, dtype=np.int32).reshape(-1, 3)
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(triangles.astype("<f4").reshape(-1, 3).tobytes())
        f.write(faces.tobytes())


# The sky image is resampled this many times finer for Mitsuba (below).
SKY_UPSAMPLE = 8


def read_hdr_flat(path):
    """A Radiance HDR of flat (not run-length coded) RGBE scanlines, top row
    first, decoded as kdray's reader (the image crate) does: mantissa times
    2^(exponent - 136), 0 where the exponent byte is 0. (H, W, 3) float64."""
    data = open(path, "rb").read()
    end = data.index(b"\n\n") + 2
    line_end = data.index(b"\n", end)
    size = data[end:line_end].split()
    if len(size) != 4 or size[0] != b"-Y" or size[2] != b"+X":
        raise Refused(f"{path}: resolution line {data[end:line_end]!r} (only -Y H +X W is read here)")
    h, w = int(size[1]), int(size[3])
    pixels = np.frombuffer(data[line_end + 1 :], dtype=np.uint8)
    if pixels.size != h * w * 4:
        raise Refused(f"{path}: run-length coded scanlines (only flat RGBE is decoded here)")
    rgbe = pixels.reshape(h, w, 4).astype(np.float64)
    e = rgbe[:, :, 3:]
    return np.where(e > 0, rgbe[:, :, :3] * np.exp2(e - 136.0), 0.0)


def sky_texels(mi, path):
    if path.lower().endswith(".hdr"):
        return read_hdr_flat(path)
    if path.lower().endswith(".exr"):
        return np.array(mi.Bitmap(path), dtype=np.float64)[:, :, :3]
    raise Refused(f"{path}: not a .hdr or .exr sky image")


def mitsuba_sky_image(texels, k=SKY_UPSAMPLE):
    """kdray reads the nearest texel: texel (col, row) covers u in
    [col, col + 1) / W and v in [row, row + 1) / H. Mitsuba's `envmap`
    interpolates bilinearly between values it places at u = (J + 1/2) / W'
    (columns) and v = j / (H' - 1) (rows; measured with its `eval`). So
    Mitsuba gets the image k times finer, each value the kdray texel its
    position reads: the two skies then differ only within 1/k of a texel
    of texel edges (`sky_mismatch` measures it)."""
    h, w, _ = texels.shape
    wk, hk = w * k, h * k + 1
    cols = np.minimum(((np.arange(wk) + 0.5) / wk * w).astype(int), w - 1)
    rows = np.minimum((np.arange(hk) / (hk - 1) * h).astype(int), h - 1)
    return texels[rows][:, cols]


def kdray_sky_radiance(texels, intensity, rotation_degrees, d):
    """kdray's sky along unit directions d (N, 3), in numpy: `texel_of`
    of crates/kdray-core/src/scene/environment.rs."""
    h, w, _ = texels.shape
    s, c = np.sin(np.radians(rotation_degrees)), np.cos(np.radians(rotation_degrees))
    x = c * d[:, 0] - s * d[:, 2]
    z = s * d[:, 0] + c * d[:, 2]
    u = 0.5 + np.arctan2(x, -z) / (2 * np.pi)
    v = np.arccos(np.clip(d[:, 1], -1, 1)) / np.pi
    col = np.minimum((u * w).astype(int), w - 1)
    row = np.minimum((v * h).astype(int), h - 1)
    return texels[row, col] * intensity


def envmap_of(mi, scene):
    """`[environment] image` -> Mitsuba `envmap`: the image resampled
    (mitsuba_sky_image), `scale` = intensity, and to_world a turn about +y
    by rotation + 180 degrees (kdray's u = 1/2 + atan2(x, -z) / 2 pi,
    Mitsuba's atan2(x, -z) / 2 pi: half a turn apart)."""
    env = scene.environment
    path = os.path.join(scene.folder, env["image"])
    texels = sky_texels(mi, path)
    intensity = float(env.get("intensity", 1.0))
    rotation = float(env.get("rotation", 0.0))
    emitter = {
        "type": "envmap",
        "bitmap": mi.Bitmap(mitsuba_sky_image(texels).astype(np.float32)),
        "scale": intensity,
        "to_world": mi.ScalarTransform4f().rotate(axis=[0, 1, 0], angle=rotation + 180.0),
    }
    return emitter, texels, intensity, rotation


def sky_mismatch(mi, dr, emitter_dict, texels, intensity, rotation, n=200_000):
    """Mitsuba's sky against kdray's over n uniformly random directions:
    the relative difference of their means, and the mean absolute
    difference over the mean (per channel)."""
    em = mi.load_dict(emitter_dict)
    rng = np.random.default_rng(3)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    si = dr.zeros(mi.SurfaceInteraction3f, n)
    si.wi = mi.Vector3f(-d[:, 0], -d[:, 1], -d[:, 2])
    ms = np.array(em.eval(si), dtype=np.float64)
    if ms.shape[0] == 3 and ms.shape[1] == n:
        ms = ms.T
    kd = kdray_sky_radiance(texels, intensity, rotation, d)
    mean = kd.mean(axis=0)
    return {
        "directions": n,
        "mean_rel_diff": [round(float(x), 6) for x in (ms.mean(axis=0) - mean) / mean],
        "mean_abs_diff_over_mean": [round(float(x), 6) for x in np.abs(ms - kd).mean(axis=0) / mean],
    }


def sky_of(mi, scene):
    """The Mitsuba sky emitter dict of the scene, or None (a black sky)."""
    env = scene.environment
    if "image" in env:
        return envmap_of(mi, scene)[0]
    color = [float(c) for c in env.get("color", scene.render["background"])]
    if max(color) > 0.0:
        return {"type": "constant", "radiance": _rgb(color)}
    return None


def light_of(i, light):
    """A kdray scene light -> a Mitsuba emitter dict, or Refused."""
    where = f"light {i}"
    if light["reference_distance"] is not None:
        raise Refused(f"{where}: reference_distance (a Whitted-matching intensity scale; give diffuse in W/sr)")
    if light["kind"] == "point":
        return {"type": "point", "position": light["position"], "intensity": _rgb(light["diffuse"])}
    if light["kind"] == "directional":
        # Both: `direction` is the way the light travels, `diffuse` and
        # `irradiance` the irradiance (W/m^2) of a surface facing it.
        return {"type": "directional", "direction": light["direction"], "irradiance": _rgb(light["diffuse"])}
    raise Refused(
        f"{where}: a {light['kind']} light (Mitsuba's spot falloff is not glTF's s^2 of kdray's)"
    )


def scene_dict(mi, scene, width, height, spp, mesh_dir):
    """kdray scene -> Mitsuba scene dict (module docstring: the mapping)."""
    if scene.render["integrator"] != "path":
        raise Refused(f"{scene.path}: not a path scene (integrator = {scene.render['integrator']!r})")
    cam = scene.camera
    d = {
        "type": "scene",
        "integrator": {
            "type": "path",
            "max_depth": int(scene.render["max_depth"]) + 1,
            "hide_emitters": False,
        },
        "sensor": kdray_scene.mitsuba_sensor(mi, cam, width, height, spp),
    }
    sky = sky_of(mi, scene)
    if sky is not None:
        d["sky"] = sky
    for i, light in enumerate(scene.lights):
        d[f"light{i}"] = light_of(i, light)

    def emitter(m):
        if max(m.emission) > 0.0:
            return {"emitter": {"type": "area", "radiance": _rgb(m.emission)}}
        return {}

    for i, (c, r, name) in enumerate(zip(scene.sphere_centers, scene.sphere_radii, scene.sphere_materials)):
        m = scene.materials[name]
        d[f"sphere{i}"] = {
            "type": "sphere",
            "center": c.tolist(),
            "radius": float(r),
            "bsdf": bsdf_for(name, m),
            **emitter(m),
        }
    names = np.array(scene.triangle_materials)
    for i, name in enumerate(sorted(set(scene.triangle_materials))):
        m = scene.materials[name]
        path = os.path.join(mesh_dir, f"mesh{i}.ply")
        _write_ply(path, scene.triangles[names == name])
        d[f"mesh{i}"] = {
            "type": "ply",
            "filename": path,
            "face_normals": True,
            "bsdf": bsdf_for(name, m),
            **emitter(m),
        }
    return d


def mitsuba_render(mi, dr, mscene, width, height, spp, seed):
    """Mean of spp samples per pixel, (H, W, 3) float32, rendered in passes of
    at most MAX_WAVEFRONT samples, each pass with its own seed."""
    per_pass = max(1, min(spp, MAX_WAVEFRONT // (width * height)))
    total = np.zeros((height, width, 3), dtype=np.float64)
    done = 0
    k = 0
    while done < spp:
        n = min(per_pass, spp - done)
        img = mi.render(mscene, spp=n, seed=seed * 100003 + k)
        total += np.array(img, dtype=np.float64)[:, :, :3] * n
        done += n
        k += 1
    return (total / spp).astype(np.float32)


def run_kdray(binary, scene_path, spp, exr, stats=True):
    cmd = [binary, "render", scene_path, "--samples", str(spp), "-o", exr] + (["--stats"] if stats else [])
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"kdray failed ({p.returncode}): {' '.join(cmd)}\n{p.stdout}\n{p.stderr}")
    stats = None
    for text in (p.stdout, p.stderr):
        for line in text.splitlines():
            line = line.strip()
            if line.startswith("{"):
                try:
                    stats = json.loads(line)
                except json.JSONDecodeError:
                    pass
    return {"command": " ".join(cmd), "wall_s": round(wall, 3), "stats": stats}


def _blocks(img, b):
    """(H, W, C) -> (H/b, W/b, C, b*b): each block's pixels (edges cropped)."""
    h, w, c = img.shape
    img = img[: h - h % b, : w - w % b]
    return img.reshape(h // b, b, w // b, b, c).transpose(0, 2, 4, 1, 3).reshape(h // b, w // b, c, b * b)


def compare_images(test, ref, b):
    """Per channel: the image's mean ratio test / ref and, over b x b blocks,
    the relative difference of block means |T - R| / R (mean and largest,
    with the largest's block as [row, column] of its top-left pixel), its
    signed mean (a bias shows there; noise averages out) and z = the block's
    mean of (test - ref) over that mean's standard error, estimated from the
    pixel differences in the block (the images' signal cancels in them, noise
    is independent from pixel to pixel). Blocks whose reference mean is below
    1e-3 of the image's are left out of the relative figures."""
    tb = _blocks(test.astype(np.float64), b)
    rb = _blocks(ref.astype(np.float64), b)
    diff = tb - rb
    out = {}
    for ch, name in enumerate("rgb"):
        t_mean = tb[:, :, ch].mean(axis=-1)
        r_mean = rb[:, :, ch].mean(axis=-1)
        d = diff[:, :, ch]
        se = d.std(axis=-1, ddof=1) / np.sqrt(d.shape[-1])
        z = np.where(se > 0, d.mean(axis=-1) / np.where(se > 0, se, 1.0), 0.0)
        valid = r_mean > 1e-3 * ref[:, :, ch].mean()
        rel = np.where(valid, (t_mean - r_mean) / np.where(valid, r_mean, 1.0), 0.0)
        arel = np.abs(rel)
        worst = np.unravel_index(np.argmax(arel), arel.shape)
        out[name] = {
            "image_ratio": round(float(test[:, :, ch].astype(np.float64).sum() / ref[:, :, ch].astype(np.float64).sum()), 5),
            "block_rel_mean": round(float(arel[valid].mean()), 5),
            "block_rel_max": round(float(arel.max()), 5),
            "block_rel_max_at": [int(worst[0] * b), int(worst[1] * b)],
            "block_rel_max_ref": round(float(r_mean[worst]), 5),
            "block_rel_signed_mean": round(float(rel[valid].mean()), 5),
            "z_rms": round(float(np.sqrt(np.mean(z[valid] ** 2))), 3),
            "z_max_abs": round(float(np.abs(z[valid]).max()), 3),
            "blocks_abs_z_over_3": round(float(np.mean(np.abs(z[valid]) > 3)), 4),
            "blocks": int(valid.sum()),
        }
    return out


def _png(path, kd, ms, b):
    """kdray | Mitsuba | |relative difference of block means| (x5, grey)."""
    import mitsuba as mi

    rel = np.abs(
        _blocks(kd.astype(np.float64), b).mean(-1) / np.maximum(_blocks(ms.astype(np.float64), b).mean(-1), 1e-6) - 1
    ).mean(-1)
    h, w = kd.shape[:2]
    heat = np.kron(np.minimum(rel * 5, 1), np.ones((b, b)))
    heat_img = np.zeros_like(kd)
    heat_img[: heat.shape[0], : heat.shape[1]] = heat[:, :, None]
    mi.util.write_bitmap(path, np.concatenate([kd, ms, heat_img], axis=1).astype(np.float32), write_async=False)


def cmd_compare(args, mi, dr):
    scene = kdray_scene.load(args.scene)
    width, height = scene.render["width"], scene.render["height"]
    spp = args.spp or scene.render["samples"]
    name = args.save or os.path.splitext(os.path.basename(args.scene))[0]
    os.makedirs(args.out, exist_ok=True)
    mesh_dir = os.path.join(args.out, name + "_meshes")
    os.makedirs(mesh_dir, exist_ok=True)
    try:
        d = scene_dict(mi, scene, width, height, spp, mesh_dir)
    except Refused as e:
        sys.exit(f"refused: {e}")
    kd_exr = os.path.join(args.out, name + "_kdray.exr")
    kd = run_kdray(args.kdray, args.scene, spp, kd_exr)
    kd_img = np.array(mi.Bitmap(kd_exr), dtype=np.float32)[:, :, :3]
    if kd_img.shape[:2] != (height, width):
        sys.exit(f"kdray wrote {kd_img.shape[:2]}, expected {(height, width)}")

    mscene = mi.load_dict(d)
    t0 = time.perf_counter()
    m0 = mitsuba_render(mi, dr, mscene, width, height, spp, seed=0)
    m_seconds = time.perf_counter() - t0
    m1 = mitsuba_render(mi, dr, mscene, width, height, spp, seed=1)
    # Written synchronously: mi.util.write_bitmap's background writer hung here.
    mi.Bitmap(m0).write(os.path.join(args.out, name + "_mitsuba.exr"))
    mi.Bitmap(m1).write(os.path.join(args.out, name + "_mitsuba_seed1.exr"))
    _png(os.path.join(args.out, name + ".png"), kd_img, m0, args.block)

    both = (m0.astype(np.float64) + m1) / 2
    result = {
        "scene": os.path.relpath(os.path.abspath(args.scene), os.path.dirname(os.path.dirname(HERE))),
        "width": width,
        "height": height,
        "spp": spp,
        "kdray_max_depth": int(scene.render["max_depth"]),
        "mitsuba_max_depth": int(scene.render["max_depth"]) + 1,
        "block": args.block,
        "mitsuba": f"mitsuba {mi.__version__} {mi.variant()}",
        "kdray": kd,
        "mitsuba_seconds_per_image": round(m_seconds, 3),
        "kdray_vs_mitsuba": compare_images(kd_img, m0, args.block),
        "noise_floor_mitsuba_seed1_vs_seed0": compare_images(m1, m0, args.block),
        "image_ratio_kdray_vs_mitsuba_both_seeds": [
            round(float(kd_img[:, :, c].sum(dtype=np.float64) / both[:, :, c].sum()), 5) for c in range(3)
        ],
    }
    if "image" in scene.environment:
        _, texels, intensity, rotation = envmap_of(mi, scene)
        result["sky_mismatch_mitsuba_vs_kdray"] = sky_mismatch(mi, dr, d["sky"], texels, intensity, rotation)
    result["within_noise"] = verdict(result)
    _emit(result, args.save)


def verdict(result):
    """True where, in every channel, kdray's block differences are no larger
    than 1.5 times the noise floor's (+0.5%), and its image ratio is within
    1% or 3 times the noise floor's ratio deviation of 1. A rule of thumb,
    not a test: the figures themselves are the result."""
    ok = True
    for ch in "rgb":
        k = result["kdray_vs_mitsuba"][ch]
        n = result["noise_floor_mitsuba_seed1_vs_seed0"][ch]
        ok &= k["block_rel_mean"] <= 1.5 * n["block_rel_mean"] + 0.005
        ok &= abs(k["image_ratio"] - 1) <= max(0.01, 3 * abs(n["image_ratio"] - 1))
    return bool(ok)


def _emit(result, save):
    text = json.dumps(result, indent=1)
    print(text)
    if save:
        os.makedirs(RESULTS, exist_ok=True)
        with open(os.path.join(RESULTS, save + ".json"), "w") as f:
            f.write(text + "\n")


def _uptime():
    return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()


def cmd_speed(args, mi, dr):
    scene = kdray_scene.load(args.scene)
    width, height = scene.render["width"], scene.render["height"]
    spp = args.spp or scene.render["samples"]
    samples = width * height * spp
    os.makedirs(args.out, exist_ok=True)
    mesh_dir = os.path.join(args.out, "speed_meshes")
    os.makedirs(mesh_dir, exist_ok=True)
    mscene = mi.load_dict(scene_dict(mi, scene, width, height, spp, mesh_dir))
    result = {
        "scene": os.path.relpath(os.path.abspath(args.scene), os.path.dirname(os.path.dirname(HERE))),
        "width": width,
        "height": height,
        "spp": spp,
        "kdray_max_depth": int(scene.render["max_depth"]),
        "mitsuba_max_depth": int(scene.render["max_depth"]) + 1,
        "cpus": os.cpu_count(),
        "uptime_before": _uptime(),
    }
    kd = run_kdray(args.kdray, args.scene, spp, os.path.join(args.out, "speed_kdray.exr"))
    result["kdray"] = kd
    # --stats also counts the walk's work (nodes, leaves, objects per ray),
    # which costs time: the same render without it, timed by the wall clock
    # (start-up, scene build, shader compilation and EXR writing included).
    plain = run_kdray(args.kdray, args.scene, spp, os.path.join(args.out, "speed_kdray_plain.exr"), stats=False)
    result["kdray_without_stats"] = {"command": plain["command"], "wall_s": plain["wall_s"]}
    runs = []
    for threads in (1, os.cpu_count()):
        dr.set_thread_count(threads)
        t0 = time.perf_counter()
        mitsuba_render(mi, dr, mscene, width, height, spp, seed=9)  # warm-up: compiles
        warm = time.perf_counter() - t0
        seconds = []
        for i in range(args.repeat):
            t0 = time.perf_counter()
            mitsuba_render(mi, dr, mscene, width, height, spp, seed=10 + i)
            seconds.append(time.perf_counter() - t0)
        best = min(seconds)
        runs.append(
            {
                "renderer": f"mitsuba {mi.__version__} {mi.variant()}",
                "threads": dr.thread_count(),
                "warmup_s": round(warm, 3),
                "seconds": [round(s, 3) for s in seconds],
                "msamples_per_s_best": round(samples / best / 1e6, 4),
            }
        )
    result["mitsuba"] = runs
    stats = kd["stats"] or {}
    if "gpu_ms" in stats:
        result["kdray_msamples_per_s_from_gpu_ms"] = round(samples / (stats["gpu_ms"] / 1e3) / 1e6, 4)
    result["kdray_msamples_per_s_from_wall"] = round(samples / kd["wall_s"] / 1e6, 4)
    result["uptime_after"] = _uptime()
    _emit(result, args.save)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("mode", choices=["compare", "speed"])
    ap.add_argument("scene")
    ap.add_argument("--kdray", default=os.environ.get("KDRAY", "kdray"), help="the kdray binary (default $KDRAY)")
    ap.add_argument("--spp", type=int, help="samples per pixel (default: the scene's)")
    ap.add_argument("--variant", default="llvm_ad_rgb", help="llvm_ad_rgb (default) or scalar_rgb")
    ap.add_argument(
        "--threads",
        type=int,
        help="compare: Dr.Jit threads (default: one per core; with 1, mi.Bitmap hung reading an EXR here)",
    )
    ap.add_argument("--block", type=int, default=16, help="block size in pixels (default 16)")
    ap.add_argument("--repeat", type=int, default=2, help="speed: timed Mitsuba renders per thread count")
    ap.add_argument("--out", default="/tmp/mitsuba_path", help="folder for images and meshes")
    ap.add_argument("--save", help="also write scripts/peers/results/SAVE.json")
    args = ap.parse_args()

    _llvm_path()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    if args.threads:
        dr.set_thread_count(args.threads)
    if args.mode == "compare":
        cmd_compare(args, mi, dr)
    else:
        cmd_speed(args, mi, dr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
