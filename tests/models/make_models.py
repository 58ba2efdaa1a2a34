#!/usr/bin/env python3
"""Writes the small glTF test models of crates/kdray-core/tests/scene_parse/ and tests/gpu/cli.rs.

Also: sparse.gltf, the tetrahedron whose POSITION and NORMAL accessors are
sparse, moving vertex 3 (and its normal), and sparse_dense.gltf, the same
mesh written densely; wild.gltf, the tetrahedron asking for extensions and a
texture, which kdray warns about; gltf1.gltf and gltf1_no_asset.gltf, glTF
1.0 files, which kdray names as such.

A tetrahedron (4 vertices, 4 indexed triangles, per-vertex NORMALs) placed by
a two-node hierarchy: the root node has a translation and a rotation, its
child a scale and the mesh. The Rust tests restate these numbers (TETRA_* in
crates/kdray-core/tests/scene_parse/) and check the loaded triangles against an OBJ written
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


# The sparse tetrahedron: vertex 3 moves from (0, 0, 1) to (0, 0, 2) and its
# normal turns to (0, 0.6, 0.8), given as one sparse element each.
MOVED_VERTEX = 3
MOVED_POSITION = [0.0, 0.0, 2.0]
MOVED_NORMAL = [0.0, 0.6, 0.8]
SPARSE_BIN = (BIN + struct.pack("<B", MOVED_VERTEX) + b"\0\0\0"
              + struct.pack("<3f", *MOVED_POSITION) + struct.pack("<3f", *MOVED_NORMAL))


def data_uri_of(data):
    return "data:application/octet-stream;base64," + base64.b64encode(data).decode()


def sparse_document():
    doc = document(data_uri_of(SPARSE_BIN))
    doc["buffers"][0]["byteLength"] = len(SPARSE_BIN)
    doc["bufferViews"] += [
        {"buffer": 0, "byteOffset": 120, "byteLength": 1},
        {"buffer": 0, "byteOffset": 124, "byteLength": 24},
    ]
    for accessor, value_offset in ((0, 0), (1, 12)):
        doc["accessors"][accessor]["sparse"] = {
            "count": 1,
            "indices": {"bufferView": 3, "componentType": 5121},
            "values": {"bufferView": 4, "byteOffset": value_offset},
        }
    doc["accessors"][0]["max"] = [1, 1, 2]
    return doc


def dense_moved_document():
    positions = list(POSITIONS)
    normals = list(NORMALS)
    positions[3 * MOVED_VERTEX:3 * MOVED_VERTEX + 3] = MOVED_POSITION
    normals[3 * MOVED_VERTEX:3 * MOVED_VERTEX + 3] = MOVED_NORMAL
    data = (struct.pack("<12f", *positions) + struct.pack("<12f", *normals)
            + struct.pack("<12H", *INDICES))
    doc = document(data_uri_of(data))
    doc["accessors"][0]["max"] = [1, 1, 2]
    return doc


def wild_document():
    doc = document(data_uri_of(BIN))
    doc["extensionsUsed"] = ["KHR_materials_emissive_strength", "KHR_texture_transform"]
    doc["extensionsRequired"] = ["KHR_texture_transform"]
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    doc["materials"][0]["normalTexture"] = {"index": 0}
    doc["textures"] = [{"source": 0}]
    doc["images"] = [{"uri": "wood.png"}]
    return doc


GLTF1 = {
    "asset": {"version": "1.0"},
    "scene": "s",
    "scenes": {"s": {"nodes": ["n"]}},
    "nodes": {"n": {"meshes": ["m"]}},
    "meshes": {"m": {"primitives": [{"attributes": {"POSITION": "p"}, "mode": 4}]}},
    "accessors": {"p": {"bufferView": "v", "byteOffset": 0, "componentType": 5126,
                        "count": 3, "type": "VEC3"}},
    "bufferViews": {"v": {"buffer": "b", "byteOffset": 0, "byteLength": 36}},
    "buffers": {"b": {"uri": data_uri_of(struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)),
                      "byteLength": 36}},
}


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
    with open("sparse.gltf", "w") as f:
        json.dump(sparse_document(), f)
    with open("sparse_dense.gltf", "w") as f:
        json.dump(dense_moved_document(), f)
    with open("wild.gltf", "w") as f:
        json.dump(wild_document(), f)
    with open("gltf1.gltf", "w") as f:
        json.dump(GLTF1, f)
    no_asset = {k: v for k, v in GLTF1.items() if k != "asset"}
    with open("gltf1_no_asset.gltf", "w") as f:
        json.dump(no_asset, f)


if __name__ == "__main__":
    main()
