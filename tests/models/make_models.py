#!/usr/bin/env python3
"""Writes the small glTF test models of tests/scene_parse.rs and tests/cli.rs.

A tetrahedron (4 vertices, 4 indexed triangles, per-vertex NORMALs) placed by
a two-node hierarchy: the root node has a translation and a rotation, its
child a scale and the mesh. The Rust tests restate these numbers (TETRA_* in
tests/scene_parse.rs) and check the loaded triangles against an OBJ written
from them, so change both together. Run from this folder: python3 make_models.py
"""
import base64
import json
import struct

POSITIONS = [0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]
NORMALS = [-0.57735026, -0.57735026, -0.57735026, 1, 0, 0, 0, 1, 0, 0, 0, 1]
INDICES = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]
TRANSLATION = [1.0, 2.0, 3.0]
ROTATION = [0.0, 0.38268343, 0.0, 0.92387953]  # 45 degrees about y, (x, y, z, w)
SCALE = [2.0, 1.0, 0.5]

BIN = (struct.pack("<12f", *POSITIONS) + struct.pack("<12f", *NORMALS)
       + struct.pack("<12H", *INDICES))


def document(uri, material=True, normals=True, indexed=True, mode=4):
    buffer = {"byteLength": len(BIN)}
    if uri is not None:
        buffer["uri"] = uri
    attributes = {"POSITION": 0}
    if normals:
        attributes["NORMAL"] = 1
    primitive = {"attributes": attributes, "mode": mode}
    if indexed:
        primitive["indices"] = 2
    if material:
        primitive["material"] = 0
    doc = {
        "asset": {"version": "2.0", "generator": "kdray tests/models/make_models.py"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [
            {"translation": TRANSLATION, "rotation": ROTATION, "children": [1]},
            {"scale": SCALE, "mesh": 0},
        ],
        "meshes": [{"primitives": [primitive]}],
        "buffers": [buffer],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 48},
            {"buffer": 0, "byteOffset": 48, "byteLength": 48},
            {"buffer": 0, "byteOffset": 96, "byteLength": 24},
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
             "min": [0, 0, 0], "max": [1, 1, 1]},
            {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
            {"bufferView": 2, "componentType": 5123, "count": 12, "type": "SCALAR"},
        ],
    }
    if material:
        doc["materials"] = [{
            "name": "gold",
            "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.75, 0.25, 1.0],
                                     "metallicFactor": 1.0, "roughnessFactor": 0.5},
        }]
    return doc


def pad(data, fill):
    return data + fill * ((4 - len(data) % 4) % 4)


def glb(doc, binary):
    text = pad(json.dumps(doc, separators=(",", ":")).encode(), b" ")
    binary = pad(binary, b"\0")
    body = (struct.pack("<I4s", len(text), b"JSON") + text
            + struct.pack("<I4s", len(binary), b"BIN\0") + binary)
    return b"glTF" + struct.pack("<II", 2, 12 + len(body)) + body


def main():
    data_uri = "data:application/octet-stream;base64," + base64.b64encode(BIN).decode()
    with open("tetra.glb", "wb") as f:
        f.write(glb(document(None), BIN))
    with open("tetra_embedded.gltf", "w") as f:
        json.dump(document(data_uri), f)
    with open("tetra_external.gltf", "w") as f:
        json.dump(document("tetra.bin"), f)
    with open("tetra.bin", "wb") as f:
        f.write(BIN)
    # No material, no normals, not indexed (the first 4 positions as one triangle and a spare).
    doc = document(data_uri, material=False, normals=False, indexed=False)
    doc["accessors"][0]["count"] = 3
    with open("plain.gltf", "w") as f:
        json.dump(doc, f)
    lines = document(data_uri, material=False, normals=False, indexed=False, mode=1)
    with open("lines.gltf", "w") as f:
        json.dump(lines, f)


if __name__ == "__main__":
    main()
