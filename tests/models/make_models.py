#!/usr/bin/env python3
"""Writes the small glTF test models of crates/kdray-core/tests/scene_parse/ and tests/gpu/cli_bad_input.rs.

Also: sparse.gltf, the tetrahedron whose POSITION and NORMAL accessors are
sparse, moving vertex 3 (and its normal), and sparse_dense.gltf, the same
mesh written densely; wild.gltf, the tetrahedron asking for extensions and a
texture, which kdray warns about; tetra_quantized_i16.gltf and
tetra_quantized_u8.gltf, the tetrahedron in KHR_mesh_quantization's integer
types with texture coordinates and a 2x2 texture; requires_basisu.gltf, one
requiring an extension kdray refuses; gltf1.gltf and gltf1_no_asset.gltf, glTF
1.0 files, which kdray names as such; instanced.gltf, the tetrahedron
placed by two nodes and by a node's EXT_mesh_gpu_instancing (three copies),
and as a second mesh by one node.

A tetrahedron (4 vertices, 4 indexed triangles, per-vertex NORMALs) placed by
a two-node hierarchy: the root node has a translation and a rotation, its
child a scale and the mesh. The Rust tests restate these numbers (TETRA_* in
crates/kdray-core/tests/scene_parse/) and check the loaded triangles against an OBJ written
from them, so change both together. Run from this folder: python3 make_models.py
"""
import base64
import json
import struct
import zlib

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
    doc["extensionsUsed"] = ["KHR_materials_sheen", "KHR_texture_transform"]
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    doc["materials"][0]["normalTexture"] = {"index": 0}
    doc["textures"] = [{"source": 0}]
    doc["images"] = [{"uri": "wood.png"}]
    return doc


# Texture coordinates of the quantized tetrahedra (any values; exact in
# every component type used below).
UVS = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 1.0]


def png_2x2():
    """A 2x2 RGB PNG (red, green / blue, white), written without a library."""
    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff))
    rows = b"\0\xff\0\0\0\xff\0" + b"\0\0\0\xff\xff\xff\xff"
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def quantized_document(kind):
    """The tetrahedron in KHR_mesh_quantization's types, interleaved with
    byteStrides that keep each element 4-byte aligned:
    - "i16": POSITION normalized SHORT and NORMAL normalized BYTE in one view
      (stride 12), TEXCOORD_0 normalized UNSIGNED_SHORT (stride 4);
    - "u8": POSITION UNSIGNED_BYTE (stride 4), NORMAL normalized SHORT
      (stride 8), TEXCOORD_0 BYTE (stride 4), UNSIGNED_BYTE indices."""
    def snorm(x, bits):
        return round(x * ((1 << (bits - 1)) - 1))
    data = b""
    views = []
    accessors = []
    def view(payload, stride=None):
        nonlocal data
        v = {"buffer": 0, "byteOffset": len(data), "byteLength": len(payload)}
        if stride:
            v["byteStride"] = stride
        data += pad(payload, b"\0")
        views.append(v)
        return len(views) - 1
    if kind == "i16":
        vertices = b""
        for i in range(4):
            vertices += struct.pack("<3hxx", *(snorm(p, 16) for p in POSITIONS[3 * i:3 * i + 3]))
            vertices += struct.pack("<3bx", *(snorm(n, 8) for n in NORMALS[3 * i:3 * i + 3]))
        v = view(vertices, 12)
        accessors.append({"bufferView": v, "componentType": 5122, "normalized": True,
                          "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [32767] * 3})
        accessors.append({"bufferView": v, "byteOffset": 8, "componentType": 5120,
                          "normalized": True, "count": 4, "type": "VEC3"})
        uvs = b"".join(struct.pack("<HH", round(UVS[2 * i] * 65535), round(UVS[2 * i + 1] * 65535))
                       for i in range(4))
        accessors.append({"bufferView": view(uvs, 4), "componentType": 5123,
                          "normalized": True, "count": 4, "type": "VEC2"})
        indices = struct.pack("<12H", *INDICES)
        index_type = 5123
    else:
        positions = b"".join(struct.pack("<3Bx", *POSITIONS[3 * i:3 * i + 3]) for i in range(4))
        accessors.append({"bufferView": view(positions, 4), "componentType": 5121,
                          "count": 4, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]})
        normals = b"".join(struct.pack("<3hxx", *(snorm(n, 16) for n in NORMALS[3 * i:3 * i + 3]))
                           for i in range(4))
        accessors.append({"bufferView": view(normals, 8), "componentType": 5122,
                          "normalized": True, "count": 4, "type": "VEC3"})
        uvs = b"".join(struct.pack("<bbxx", int(UVS[2 * i]), int(UVS[2 * i + 1])) for i in range(4))
        accessors.append({"bufferView": view(uvs, 4), "componentType": 5120,
                          "count": 4, "type": "VEC2"})
        indices = struct.pack("<12B", *INDICES)
        index_type = 5121
    accessors.append({"bufferView": view(indices), "componentType": index_type,
                      "count": 12, "type": "SCALAR"})
    doc = document(data_uri_of(data))
    doc["buffers"][0]["byteLength"] = len(data)
    doc["bufferViews"] = views
    doc["accessors"] = accessors
    doc["meshes"][0]["primitives"][0]["attributes"] = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}
    doc["meshes"][0]["primitives"][0]["indices"] = 3
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] = {"index": 0}
    doc["textures"] = [{"source": 0}]
    doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png_2x2()).decode()}]
    doc["extensionsUsed"] = ["KHR_mesh_quantization"]
    doc["extensionsRequired"] = ["KHR_mesh_quantization"]
    return doc


def required_document():
    """The tetrahedron requiring an extension kdray does not read."""
    doc = document(data_uri_of(BIN))
    doc["extensionsUsed"] = ["KHR_texture_basisu"]
    doc["extensionsRequired"] = ["KHR_texture_basisu"]
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


# instanced.gltf: the tetrahedron as mesh 0, placed by two nodes (one moved
# and turned, one mirrored in x and moved) and by a third node's
# EXT_mesh_gpu_instancing (three copies, each moved, turned and scaled);
# and as mesh 1, placed by one node.
COPY_TRANSLATIONS = [0, 0, 0, 2, 0, 0, 0, 3, 1]
COPY_ROTATIONS = [0, 0, 0, 1, 0, 0.38268343, 0, 0.92387953, 0.70710678, 0, 0, 0.70710678]
COPY_SCALES = [1, 1, 1, 0.5, 0.5, 0.5, 1, 2, -1]
COPIES_BIN = (struct.pack("<9f", *COPY_TRANSLATIONS) + struct.pack("<12f", *COPY_ROTATIONS)
              + struct.pack("<9f", *COPY_SCALES))


def instanced_document():
    doc = document(data_uri_of(BIN))
    doc["extensionsUsed"] = ["EXT_mesh_gpu_instancing"]
    doc["scenes"] = [{"nodes": [0, 2, 3, 4]}]
    doc["nodes"] = [
        {"translation": TRANSLATION, "rotation": ROTATION, "children": [1]},
        {"scale": SCALE, "mesh": 0},
        {"translation": [-3, 0, 0], "scale": [-1, 1, 1], "mesh": 0},
        {"translation": [0, -4, 0], "mesh": 0,
         "extensions": {"EXT_mesh_gpu_instancing": {
             "attributes": {"TRANSLATION": 3, "ROTATION": 4, "SCALE": 5}}}},
        {"translation": [5, 0, 0], "mesh": 1},
    ]
    doc["meshes"].append({"primitives": doc["meshes"][0]["primitives"]})
    doc["buffers"].append({"byteLength": len(COPIES_BIN), "uri": data_uri_of(COPIES_BIN)})
    doc["bufferViews"] += [
        {"buffer": 1, "byteOffset": 0, "byteLength": 36},
        {"buffer": 1, "byteOffset": 36, "byteLength": 48},
        {"buffer": 1, "byteOffset": 84, "byteLength": 36},
    ]
    doc["accessors"] += [
        {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"},
        {"bufferView": 4, "componentType": 5126, "count": 3, "type": "VEC4"},
        {"bufferView": 5, "componentType": 5126, "count": 3, "type": "VEC3"},
    ]
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
    with open("sparse.gltf", "w") as f:
        json.dump(sparse_document(), f)
    with open("sparse_dense.gltf", "w") as f:
        json.dump(dense_moved_document(), f)
    with open("wild.gltf", "w") as f:
        json.dump(wild_document(), f)
    for kind in ("i16", "u8"):
        with open(f"tetra_quantized_{kind}.gltf", "w") as f:
            json.dump(quantized_document(kind), f)
    with open("instanced.gltf", "w") as f:
        json.dump(instanced_document(), f)
    with open("requires_basisu.gltf", "w") as f:
        json.dump(required_document(), f)
    with open("gltf1.gltf", "w") as f:
        json.dump(GLTF1, f)
    no_asset = {k: v for k, v in GLTF1.items() if k != "asset"}
    with open("gltf1_no_asset.gltf", "w") as f:
        json.dump(no_asset, f)


if __name__ == "__main__":
    main()
