#!/usr/bin/env python3
"""Writes an OBJ's `v` and `f` lines (triangles) as a binary glTF, for
measuring what glTF files and their material features cost
(scripts/gltf_cost.sh, docs/benchmarks.md "glTF files and materials"):
POSITION, smooth NORMALs (area-weighted), TEXCOORD_0 (a planar projection
on x and y, eight repeats across the model) and 32-bit indices, one
material with a 64 x 64 checker base-colour texture, and as asked:

    --normal-map   a 64 x 64 normal map of bumps (normalTexture)
    --mask         the checker's dark squares at alpha 0, alphaMode MASK
    --mask-solid   alphaMode MASK with every texel solid (the test, no hole)

    python3 scripts/obj_to_glb.py IN.obj OUT.glb [--normal-map] [--mask | --mask-solid]

numpy does the arithmetic; the PNGs are written with zlib.
"""

import json
import struct
import sys
import zlib

import numpy as np


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                vertices.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                faces.append([int(w.split("/")[0]) - 1 for w in line.split()[1:4]])
    return np.array(vertices, dtype=np.float32), np.array(faces, dtype=np.uint32)


def smooth_normals(p, f):
    a, b, c = p[f[:, 0]], p[f[:, 1]], p[f[:, 2]]
    n = np.cross(b - a, c - a)  # area-weighted
    out = np.zeros_like(p)
    for k in range(3):
        np.add.at(out, f[:, k], n)
    length = np.linalg.norm(out, axis=1, keepdims=True)
    return (out / np.where(length > 0, length, 1)).astype(np.float32)


def png(width, height, rgba):
    """An RGBA8 PNG of `rgba` (height x width x 4 uint8)."""
    raw = b"".join(b"\0" + rgba[y].tobytes() for y in range(height))

    def chunk(kind, data):
        c = kind + data
        return struct.pack(">I", len(data)) + c + struct.pack(">I", zlib.crc32(c))

    header = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker(mask):
    side = 64
    y, x = np.mgrid[0:side, 0:side]
    dark = ((x // 8 + y // 8) % 2) == 1
    rgba = np.full((side, side, 4), 255, dtype=np.uint8)
    rgba[dark, :3] = (90, 70, 60)
    rgba[~dark, :3] = (220, 200, 170)
    if mask:
        rgba[dark, 3] = 0
    return png(side, side, rgba)


def bumps():
    side = 64
    y, x = np.mgrid[0:side, 0:side] + 0.5
    dx = np.cos(x / side * 8 * np.pi) * 0.5
    dy = np.cos(y / side * 8 * np.pi) * 0.5
    n = np.stack([-dx, -dy, np.ones_like(dx)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    rgba = np.full((side, side, 4), 255, dtype=np.uint8)
    rgba[..., :3] = np.round((n * 0.5 + 0.5) * 255).astype(np.uint8)
    return png(side, side, rgba)


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    flags = {a for a in sys.argv[1:] if a.startswith("--")}
    if len(args) != 2 or flags - {"--normal-map", "--mask", "--mask-solid"}:
        sys.exit(__doc__)
    p, f = read_obj(args[0])
    n = smooth_normals(p, f)
    lo, hi = p.min(axis=0), p.max(axis=0)
    uv = ((p[:, :2] - lo[:2]) / (hi[:2] - lo[:2]).max() * 8).astype(np.float32)
    uv[:, 1] = -uv[:, 1]

    images = [checker("--mask" in flags)]
    material = {
        "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                 "metallicFactor": 0, "roughnessFactor": 0.6},
    }
    if "--normal-map" in flags:
        images.append(bumps())
        material["normalTexture"] = {"index": 1}
    if flags & {"--mask", "--mask-solid"}:
        material["alphaMode"] = "MASK"

    blob = bytearray()
    views = []

    def add(data):
        while len(blob) % 4:
            blob.append(0)
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
        blob.extend(data)
        return len(views) - 1

    accessors = [
        {"bufferView": add(p.tobytes()), "componentType": 5126, "count": len(p),
         "type": "VEC3", "min": lo.tolist(), "max": hi.tolist()},
        {"bufferView": add(n.tobytes()), "componentType": 5126, "count": len(n), "type": "VEC3"},
        {"bufferView": add(uv.tobytes()), "componentType": 5126, "count": len(uv), "type": "VEC2"},
        {"bufferView": add(f.astype(np.uint32).tobytes()), "componentType": 5125,
         "count": f.size, "type": "SCALAR"},
    ]
    image_views = [add(i) for i in images]
    document = {
        "asset": {"version": "2.0", "generator": "kdray scripts/obj_to_glb.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0}]}],
        "materials": [material],
        "textures": [{"source": i, "sampler": 0} for i in range(len(images))],
        "samplers": [{"magFilter": 9729, "minFilter": 9987}],
        "images": [{"bufferView": v, "mimeType": "image/png"} for v in image_views],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(blob)}],
    }
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    while len(blob) % 4:
        blob.append(0)
    total = 12 + 8 + len(text) + 8 + len(blob)
    with open(args[1], "wb") as out:
        out.write(struct.pack("<4sII", b"glTF", 2, total))
        out.write(struct.pack("<I4s", len(text), b"JSON") + text)
        out.write(struct.pack("<I4s", len(blob), b"BIN\0") + bytes(blob))


if __name__ == "__main__":
    main()
