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
    scripts/make_forest.py --count 1000 -o /tmp/forest.glb
    kdray render /tmp/forest.glb -o forest.png

A .glb output (or --format glb) is one glTF file instead: the mesh (read
from the OBJ, with area-weighted vertex normals) placed by one node's
EXT_mesh_gpu_instancing (its TRANSLATION, ROTATION and SCALE accessors, one
element per instance, all in one material), and the ground by another node;
the model view of `kdray render` frames and lights it.

The mesh defaults to Debian glmark2-data's bunny (x, y in [-1, 1], its feet at
y = -0.991), whose feet stand on the ground; give --mesh and --lift (how far
its origin sits above its lowest point) for another. The renderer flattens
instances before tracing, so the scene needs the memory of COUNT copies.
"""
import argparse
import json
import math
import random
import struct

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


def read_obj(path):
    """The OBJ's vertices and triangles (polygons fanned), 0-based."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def area_normals(verts, faces):
    """Each vertex's normal: the sum of its faces' area-weighted normals, made unit."""
    sums = [[0.0, 0.0, 0.0] for _ in verts]
    for a, b, c in faces:
        u = [verts[b][k] - verts[a][k] for k in range(3)]
        v = [verts[c][k] - verts[a][k] for k in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        for i in (a, b, c):
            for k in range(3):
                sums[i][k] += n[k]
    out = []
    for n in sums:
        length = math.sqrt(sum(x * x for x in n))
        out.append([x / length for x in n] if length > 0 else [0.0, 1.0, 0.0])
    return out


def glb(doc, mesh):
    """The forest as one binary glTF: the mesh instanced by EXT_mesh_gpu_instancing."""
    verts, faces = read_obj(mesh)
    normals = area_normals(verts, faces)
    ground_tris = doc["shapes"]["ground"]["triangles"]
    ground_verts = [p for tri in ground_tris for p in tri]
    copies = doc["instances"][1:]
    rotations = []
    for c in copies:
        half = math.radians(c["rotate"][1]) / 2
        rotations.append([0.0, math.sin(half), 0.0, math.cos(half)])
    chunks = [
        ("VEC3", 5126, len(verts), b"".join(struct.pack("<3f", *v) for v in verts)),
        ("VEC3", 5126, len(normals), b"".join(struct.pack("<3f", *n) for n in normals)),
        ("SCALAR", 5125, 3 * len(faces), b"".join(struct.pack("<3I", *f) for f in faces)),
        ("VEC3", 5126, len(ground_verts), b"".join(struct.pack("<3f", *v) for v in ground_verts)),
        ("VEC3", 5126, len(copies), b"".join(struct.pack("<3f", *c["translate"]) for c in copies)),
        ("VEC4", 5126, len(copies), b"".join(struct.pack("<4f", *q) for q in rotations)),
        ("VEC3", 5126, len(copies), b"".join(struct.pack("<3f", *c["scale"]) for c in copies)),
    ]
    binary, views, accessors = b"", [], []
    for kind, component, count, data in chunks:
        views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data)})
        accessor = {"bufferView": len(views) - 1, "componentType": component,
                    "count": count, "type": kind}
        if len(accessors) in (0, 3):
            points = verts if len(accessors) == 0 else ground_verts
            accessor["min"] = [min(p[k] for p in points) for k in range(3)]
            accessor["max"] = [max(p[k] for p in points) for k in range(3)]
        accessors.append(accessor)
        binary += data + b"\0" * ((4 - len(data) % 4) % 4)
    colour = lambda name: doc["materials"][name]["diffuse"] + [1.0]
    gltf = {
        "asset": {"version": "2.0", "generator": "kdray scripts/make_forest.py"},
        "extensionsUsed": ["EXT_mesh_gpu_instancing"],
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"mesh": 1, "extensions": {"EXT_mesh_gpu_instancing": {
                "attributes": {"TRANSLATION": 4, "ROTATION": 5, "SCALE": 6}}}},
        ],
        "meshes": [
            {"primitives": [{"attributes": {"POSITION": 3}, "material": 0}]},
            {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                             "material": 1}]},
        ],
        "materials": [
            {"name": "ground", "pbrMetallicRoughness": {
                "baseColorFactor": colour("ground"), "metallicFactor": 0.0}},
            {"name": "model", "pbrMetallicRoughness": {
                "baseColorFactor": colour("sand"), "metallicFactor": 0.0}},
        ],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": views,
        "accessors": accessors,
    }
    text = json.dumps(gltf, separators=(",", ":")).encode()
    text += b" " * ((4 - len(text) % 4) % 4)
    body = (struct.pack("<I4s", len(text), b"JSON") + text
            + struct.pack("<I4s", len(binary), b"BIN\0") + binary)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


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
    p.add_argument("--format", choices=("toml", "json", "glb"), default=None,
                   help="default: by the output's extension")
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args()
    doc = scene(args.count, args.seed, args.mesh, args.lift)
    ext = args.output.lower().rsplit(".", 1)[-1]
    fmt = args.format or (ext if ext in ("json", "glb") else "toml")
    if fmt == "glb":
        with open(args.output, "wb") as f:
            f.write(glb(doc, args.mesh))
        return
    with open(args.output, "w") as f:
        if fmt == "json":
            json.dump(doc, f)
        else:
            f.write(toml(doc))


if __name__ == "__main__":
    main()
