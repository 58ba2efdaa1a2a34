#!/usr/bin/env python3
"""Writes a scene of many instances of one mesh on a hilly ground: a forest
of the bunny by default, for demos and benchmarks of instancing
(docs/scene-format.md, "[shapes.NAME] and [[instances]]").

The mesh is one `[shapes.model]`; each of COUNT `[[instances]]` stands it on
the ground at a random spot of a square grid (jittered), turned about y by a
random angle, scaled by 0.4 to 1 (one in five mirrored in x), in one of four
colours (a material override). The ground is a 48 x 48 grid of triangles
whose height is a sum of sines. Deterministic for a given --seed.

    scripts/make_forest.py --count 1000 -o /tmp/forest.toml
    scripts/make_forest.py --count 100000 --format json -o /tmp/forest.json
    kdray render /tmp/forest.toml -o forest.png

The mesh defaults to Debian glmark2-data's bunny (x, y in [-1, 1], its feet at
y = -0.991), whose feet stand on the ground; give --mesh and --lift (how far
its origin sits above its lowest point) for another. The renderer flattens
instances before tracing, so the scene needs the memory of COUNT copies.
"""
import argparse
import json
import math
import random

GRID = 48
COLOURS = {
    "moss": [0.35, 0.55, 0.3],
    "sand": [0.75, 0.65, 0.45],
    "rust": [0.7, 0.35, 0.2],
    "slate": [0.4, 0.45, 0.55],
}


def height(x, z, side):
    """The ground's height at (x, z): gentle hills about a tenth of the side high."""
    k = 2 * math.pi / side
    return side * 0.04 * (math.sin(1.3 * k * x) * math.cos(0.9 * k * z)
                          + 0.5 * math.sin(2.7 * k * (x + z)))


def ground(side):
    """The ground's triangles: a GRID x GRID square of quads, two triangles each."""
    half = side / 2
    step = side / GRID
    point = lambda i, j: [-half + i * step, height(-half + i * step, -half + j * step, side),
                          -half + j * step]
    triangles = []
    for i in range(GRID):
        for j in range(GRID):
            a, b, c, d = point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1)
            triangles += [[a, c, b], [a, d, c]]
    return triangles


def scene(count, seed, mesh, lift):
    rng = random.Random(seed)
    cells = max(1, math.ceil(math.sqrt(count)))
    spacing = 2.5
    side = cells * spacing
    instances = []
    for n in range(count):
        i, j = n % cells, n // cells
        x = -side / 2 + (i + 0.5 + rng.uniform(-0.3, 0.3)) * spacing
        z = -side / 2 + (j + 0.5 + rng.uniform(-0.3, 0.3)) * spacing
        s = rng.uniform(0.4, 1.0)
        instances.append({
            "shape": "model",
            "material": rng.choice(sorted(COLOURS)),
            "scale": [-s if rng.random() < 0.2 else s, s, s],
            "rotate": [0, round(rng.uniform(0, 360), 3), 0],
            "translate": [round(x, 4), round(height(x, z, side) + lift * s, 4), round(z, 4)],
        })
    eye = [side * 0.55, side * 0.35 + 3, side * 0.75]
    return {
        "camera": {"position": eye, "look_at": [0, 0, 0], "vfov": 45},
        "render": {"width": 960, "height": 540, "max_depth": 3,
                   "background": [0.55, 0.65, 0.8]},
        "lights": [{"position": [side, side * 1.5, side * 0.5], "ambient": [0.2, 0.2, 0.2]}],
        "materials": dict({name: {"diffuse": c, "ambient": [x * 0.3 for x in c]}
                           for name, c in COLOURS.items()},
                          ground={"diffuse": [0.45, 0.5, 0.35], "ambient": [0.1, 0.12, 0.08]}),
        "shapes": {
            "model": {"path": mesh, "material": "moss", "smooth": True},
            "ground": {"triangles": ground(side), "material": "ground"},
        },
        "instances": [{"shape": "ground"}] + instances,
    }


def toml_value(v):
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    return "[" + ", ".join(toml_value(x) for x in v) + "]"


def toml(doc):
    out = []
    for table in ("camera", "render"):
        out.append(f"[{table}]")
        out += [f"{k} = {toml_value(v)}" for k, v in doc[table].items()]
        out.append("")
    for light in doc["lights"]:
        out.append("[[lights]]")
        out += [f"{k} = {toml_value(v)}" for k, v in light.items()]
        out.append("")
    for group in ("materials", "shapes"):
        for name, table in doc[group].items():
            out.append(f"[{group}.{name}]")
            out += [f"{k} = {toml_value(v)}" for k, v in table.items()]
            out.append("")
    for instance in doc["instances"]:
        out.append("[[instances]]")
        out += [f"{k} = {toml_value(v)}" for k, v in instance.items()]
        out.append("")
    return "\n".join(out)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--count", type=int, default=100, help="instances of the mesh (default 100)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--mesh", default="/usr/share/glmark2/models/bunny.obj",
                   help="the mesh file (absolute, or relative to the scene's folder)")
    p.add_argument("--lift", type=float, default=0.991233,
                   help="the height of the mesh's origin above its lowest point")
    p.add_argument("--format", choices=("toml", "json"), default=None,
                   help="default: by the output's extension")
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args()
    doc = scene(args.count, args.seed, args.mesh, args.lift)
    fmt = args.format or ("json" if args.output.lower().endswith(".json") else "toml")
    with open(args.output, "w") as f:
        if fmt == "json":
            json.dump(doc, f)
        else:
            f.write(toml(doc))


if __name__ == "__main__":
    main()
