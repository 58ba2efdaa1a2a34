#!/usr/bin/env python3
"""Writes the light-sampling scenes of docs/peers.md ("Light sampling
against Mitsuba 3") into scenes/peers/: kdray path scenes that
scripts/peers/light_sampling.py renders with kdray and Mitsuba 3. Run from
anywhere; the output is deterministic (fixed random seeds).

    python3 scripts/peers/make_light_scenes.py

Writes:
- lights_torus.obj: a torus of 64 x 40 quads (5,120 triangles), wound so
  that each face's front side, (v1 - v0) x (v2 - v0), points outward;
- lights_sky.hdr: a 128 x 64 equirectangular sky (Radiance RGBE, flat
  scanlines): a smooth blue gradient with a bright, soft sun;
- lights_mixed.toml: ground, two balls, a point light, a directional light
  and the emissive torus;
- lights_sky_mesh.toml: the sky image and the emissive torus over ground
  and a ball;
- lights_city.toml: 400 small emissive spheres of different sizes and
  brightness among dark blocks ("city at night");
- lights_one_bright.toml: one bright emissive sphere and 200 dim ones.
"""

import math
import os

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
OUT = os.path.join(ROOT, "scenes", "peers")

HEADER = """# Light sampling against Mitsuba 3 (docs/peers.md; written by
# scripts/peers/make_light_scenes.py: edit that, not this file). {what}
"""


def torus_obj(path, major=0.5, minor=0.14, around=64, across=40):
    """A torus around the z axis (a ring in the xy plane), centred at the
    origin: 2 * around * across triangles, fronts facing out."""
    lines = ["# written by scripts/peers/make_light_scenes.py"]
    for i in range(around):
        a = 2 * math.pi * i / around
        for j in range(across):
            b = 2 * math.pi * j / across
            r = major + minor * math.cos(b)
            lines.append(f"v {r * math.cos(a):.6f} {r * math.sin(a):.6f} {minor * math.sin(b):.6f}")

    def idx(i, j):
        return (i % around) * across + (j % across) + 1

    for i in range(around):
        for j in range(across):
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            # (v1 - v0) x (v2 - v0) along the outward normal: the tube's
            # angle b grows toward +z on the outside, the ring's a
            # counter-clockwise about +z.
            lines.append(f"f {a} {b} {c}")
            lines.append(f"f {a} {c} {d}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def torus_faces_point_out(path):
    """Checks the winding: every face normal points away from the tube's
    centre line."""
    v, f = [], []
    for line in open(path):
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:]])
        elif line.startswith("f "):
            f.append([int(x) - 1 for x in line.split()[1:]])
    v, f = np.array(v), np.array(f)
    t = v[f]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    c = t.mean(axis=1)
    ring = c.copy()
    ring[:, 2] = 0
    ring = ring / np.linalg.norm(ring, axis=1, keepdims=True) * 0.5
    assert len(f) == 5120, len(f)
    assert np.all(np.einsum("ij,ij->i", n, c - ring) > 0), "a torus face points inward"


def write_hdr(path, img):
    """Radiance RGBE, flat scanlines (no run-length coding), top row first."""
    h, w, _ = img.shape
    img = img.astype(np.float64)
    m = img.max(axis=2)
    e = np.zeros_like(m, dtype=np.int32)
    mant, e_ = np.frexp(m)
    e[m > 1e-32] = e_[m > 1e-32]
    scale = np.where(m > 1e-32, mant * 256.0 / np.where(m > 1e-32, m, 1.0), 0.0)
    rgbe = np.zeros((h, w, 4), dtype=np.uint8)
    rgbe[:, :, :3] = np.clip(np.floor(img * scale[:, :, None]), 0, 255).astype(np.uint8)
    rgbe[:, :, 3] = np.where(m > 1e-32, e + 128, 0).astype(np.uint8)
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {h} +X {w}\n".encode("ascii"))
        f.write(rgbe.tobytes())


def sky_image(w=128, h=64):
    """A sky of linear radiance, smooth from texel to texel (neighbours differ
    by a few percent: kdray reads the nearest texel, Mitsuba interpolates):
    a blue gradient, a dim ground below the horizon and a soft sun."""
    v = (np.arange(h) + 0.5) / h
    u = (np.arange(w) + 0.5) / w
    theta = v[:, None] * math.pi
    phi = (u[None, :] - 0.5) * 2 * math.pi
    d = np.stack(
        [np.sin(theta) * np.sin(phi), np.cos(theta) * np.ones_like(phi), -np.sin(theta) * np.cos(phi)], axis=-1
    )
    up = np.clip(d[..., 1], 0, 1)[..., None]
    sky = np.array([0.25, 0.35, 0.6]) * (0.4 + 0.6 * up) + np.array([0.15, 0.12, 0.1]) * (1 - up)
    sun_dir = np.array([0.5, 0.6, -0.62])
    sun_dir /= np.linalg.norm(sun_dir)
    cos_sun = d @ sun_dir
    # A Gaussian lobe about 10 degrees wide (5 texels): bright, but smooth.
    sun = 40.0 * np.exp(-(1 - cos_sun) / (1 - math.cos(math.radians(10))))
    return sky + sun[..., None] * np.array([1.0, 0.9, 0.75])


def ground(material, half=6.0, y=0.0):
    return f"""
[[triangles]]
vertices = [[-{half}, {y}, -{half}], [-{half}, {y}, {half}], [{half}, {y}, {half}]]
material = "{material}"
[[triangles]]
vertices = [[-{half}, {y}, -{half}], [{half}, {y}, {half}], [{half}, {y}, -{half}]]
material = "{material}"
"""


def box(material, lo, hi):
    """An axis-aligned box of 12 triangles, fronts facing out."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    p = [[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0], [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]]
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 4, 7, 3), (1, 2, 6, 5), (3, 7, 6, 2), (0, 1, 5, 4)]
    out = []
    for a, b, c, d in quads:
        for tri in ((a, b, c), (a, c, d)):
            vs = ", ".join("[" + ", ".join(f"{x:.4f}" for x in p[k]) + "]" for k in tri)
            out.append(f'[[triangles]]\nvertices = [{vs}]\nmaterial = "{material}"')
    return "\n".join(out) + "\n"


def value(v):
    """A TOML value as the scenes spell it: floats as Python writes them."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return f'"{v}"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(value(x) for x in v) + "]"
    return repr(v)


def table(header, keys):
    """A TOML table (`header` with its brackets) of `keys` in order, each
    `=` aligned one space past the longest key, after a blank line."""
    width = max(len(k) for k in keys)
    return f"\n{header}\n" + "".join(f"{k.ljust(width)} = {value(v)}\n" for k, v in keys.items())


# Every scene's [render]: the path tracer, small and quick.
RENDER = {"width": 80, "height": 60, "integrator": "path", "samples": 64, "max_depth": 4}


def material(diffuse, emission=None):
    keys = {"diffuse": diffuse}
    if emission is not None:
        keys["emission"] = emission
    return keys


def sphere(center, radius, name):
    return {"center": center, "radius": radius, "material": name}


def city():
    """The city's generated parts: 400 lamps along a grid of streets among
    dark blocks, radii 0.02 - 0.08, emission 1 - 40 (log-uniform): powers
    over three orders of magnitude."""
    rng = np.random.default_rng(7)
    parts = []
    colours = [[1.0, 0.75, 0.4], [1.0, 0.9, 0.8], [0.7, 0.8, 1.0], [1.0, 0.5, 0.25]]
    # Lamp materials: one per (colour, brightness step), 4 x 10.
    steps = np.geomspace(1.0, 40.0, 10)
    for k, c in enumerate(colours):
        for s, e in enumerate(steps):
            rgb = ", ".join(f"{x * e:.4f}" for x in c)
            parts.append(f"[materials.lamp{k}_{s}]\ndiffuse = [0.0, 0.0, 0.0]\nemission = [{rgb}]\n")
    parts.append(ground("street", half=8.0))
    # Blocks: 6 x 6 cells of 1.2, each a box 0.8 wide of random height.
    for i in range(6):
        for j in range(6):
            x, z = -3.6 + 1.2 * i + 0.2, -3.6 + 1.2 * j + 0.2
            hgt = float(rng.uniform(0.2, 1.2))
            parts.append(box("block", (x, 0.0, z), (x + 0.8, hgt, z + 0.8)))
    # Lamps along the streets between blocks (x or z on a street line).
    lamps = 0
    while lamps < 400:
        line = -3.6 + 1.2 * int(rng.integers(0, 7))
        along = float(rng.uniform(-3.6, 3.6))
        r = float(rng.uniform(0.02, 0.08))
        x, z = (line, along) if rng.random() < 0.5 else (along, line)
        y = r if rng.random() < 0.5 else float(rng.uniform(0.3, 1.5))
        k = int(rng.integers(0, 4))
        s = int(rng.integers(0, 10))
        parts.append(f'[[spheres]]\ncenter = [{x:.4f}, {y:.4f}, {z:.4f}]\nradius = {r:.4f}\nmaterial = "lamp{k}_{s}"\n')
        lamps += 1
    return parts


def one_bright():
    """The dim lights beside the bright one (radius 0.25, radiance 40):
    200 of radius 0.04 and radiance 2, kept clear of the bright one and the
    ball; the bright one has 81% of the power (luminance)."""
    rng = np.random.default_rng(11)
    parts = [ground("ground")]
    dim = 0
    while dim < 200:
        x, z = rng.uniform(-3.0, 3.0), rng.uniform(-3.5, 1.5)
        y = rng.uniform(0.04, 2.0)
        if math.dist((x, y, z), (-0.5, 0.5, 0.0)) < 0.6 or math.dist((x, y, z), (0.8, 1.4, -0.8)) < 0.35:
            continue
        parts.append(f'[[spheres]]\ncenter = [{x:.4f}, {y:.4f}, {z:.4f}]\nradius = 0.04\nmaterial = "dim"\n')
        dim += 1
    return parts


# The scenes written by hand: what the header says of each, its camera
# (position, look_at, vfov) and its tables after [render], in order. The
# generated parts of a scene (ground, blocks, lamps) are its `parts`
# function's, set apart from each other by `sep`.
SCENES = {
    "lights_mixed.toml": {
        "what": "A ground, two Lambertian balls, a point\n# light, a directional light "
        "and an emissive torus of 5,120 triangles.",
        "camera": ([0.0, 1.5, 4.2], [0.0, 0.6, 0.0], 45.0),
        "tables": [
            ("[[lights]]", {"position": [-2.0, 3.0, 2.0], "diffuse": [5.0, 5.0, 5.0]}),
            ("[[lights]]", {"kind": "directional", "direction": [1.0, -2.0, -0.5], "diffuse": [0.25, 0.25, 0.22]}),
            ("[materials.ground]", material([0.6, 0.6, 0.6])),
            ("[materials.red]", material([0.8, 0.3, 0.2])),
            ("[materials.white]", material([0.8, 0.8, 0.8])),
            ("[materials.glow]", material([0.0, 0.0, 0.0], [6.0, 3.5, 1.5])),
            ("[[spheres]]", sphere([-1.0, 0.45, 0.3], 0.45, "red")),
            ("[[spheres]]", sphere([1.1, 0.35, 0.6], 0.35, "white")),
            (
                "[[meshes]]",
                {"path": "lights_torus.obj", "material": "glow", "smooth": False, "translate": [0.1, 0.8, -0.6]},
            ),
        ],
        "parts": lambda: [ground("ground")],
        "sep": "",
    },
    "lights_sky_mesh.toml": {
        "what": "A sky image (lights_sky.hdr) and an emissive\n# torus lying flat, over ground and a ball.",
        "camera": ([0.0, 1.6, 4.0], [0.0, 0.5, 0.0], 50.0),
        "tables": [
            ("[environment]", {"image": "lights_sky.hdr", "intensity": 0.8}),
            ("[materials.ground]", material([0.5, 0.5, 0.45])),
            ("[materials.ball]", material([0.7, 0.7, 0.75])),
            ("[materials.glow]", material([0.0, 0.0, 0.0], [3.0, 6.0, 3.0])),
            ("[[spheres]]", sphere([-0.6, 0.5, 0.0], 0.5, "ball")),
            (
                "[[meshes]]",
                {
                    "path": "lights_torus.obj",
                    "material": "glow",
                    "smooth": False,
                    "rotate": [-90.0, 0.0, 0.0],
                    "translate": [0.8, 0.2, 0.4],
                },
            ),
        ],
        "parts": lambda: [ground("ground")],
        "sep": "",
    },
    "lights_city.toml": {
        "what": "City at night: 400 small emissive spheres\n# (radius 0.02 - 0.08, radiance 1 - 40) "
        "among dark blocks, no sky.",
        "camera": ([0.0, 4.0, 7.0], [0.0, 0.0, 0.0], 50.0),
        "tables": [
            ("[materials.street]", material([0.3, 0.3, 0.3])),
            ("[materials.block]", material([0.5, 0.45, 0.4])),
        ],
        "parts": city,
        "sep": "\n",
    },
    "lights_one_bright.toml": {
        "what": "One bright light among many dim ones: a\n# sphere of radius 0.25 and radiance 40, "
        "200 of radius 0.04 and radiance 2; no sky.",
        "camera": ([0.0, 2.5, 5.0], [0.0, 0.5, 0.0], 48.0),
        "tables": [
            ("[materials.ground]", material([0.6, 0.6, 0.6])),
            ("[materials.ball]", material([0.3, 0.6, 0.8])),
            ("[materials.bright]", material([0.0, 0.0, 0.0], [40.0, 36.0, 30.0])),
            ("[materials.dim]", material([0.0, 0.0, 0.0], [2.0, 1.6, 1.2])),
            ("[[spheres]]", sphere([0.8, 1.4, -0.8], 0.25, "bright")),
            ("[[spheres]]", sphere([-0.5, 0.5, 0.0], 0.5, "ball")),
        ],
        "parts": one_bright,
        "sep": "\n",
    },
}


def scene_text(spec):
    """A scene of SCENES: its header, camera, [render] and tables, then its
    generated parts."""
    position, look_at, vfov = spec["camera"]
    written = [
        HEADER.format(what=spec["what"]),
        table("[camera]", {"position": position, "look_at": look_at, "vfov": vfov}),
        table("[render]", RENDER),
        "".join(table(header, keys) for header, keys in spec["tables"]),
    ]
    return spec["sep"].join(written + spec["parts"]())


def write(name, text):
    path = os.path.join(OUT, name)
    with open(path, "w") as f:
        f.write(text)
    print(path)


def main():
    os.makedirs(OUT, exist_ok=True)
    torus = os.path.join(OUT, "lights_torus.obj")
    torus_obj(torus)
    torus_faces_point_out(torus)
    print(torus)
    write_hdr(os.path.join(OUT, "lights_sky.hdr"), sky_image())
    print(os.path.join(OUT, "lights_sky.hdr"))
    for name, spec in SCENES.items():
        write(name, scene_text(spec))


if __name__ == "__main__":
    main()
