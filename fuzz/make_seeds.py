#!/usr/bin/env python3
"""Writes the hand-made fuzz seeds that reach the loaders' texture, glass,
sparse-accessor and animation paths (fuzz/corpus/<target>/seed_*): small
files, a few hundred bytes to a few KB each. Run from anywhere; it
overwrites only the files it names.

The glTF seeds are one unit quad (4 positions, 2 triangles) with texture
coordinates and a base-colour texture, in the containers and encodings
kdray reads: image in a data URI (PNG, JPEG), in a .glb buffer view;
texture coordinates as floats, normalized bytes, or sparse; a sampler
with NEAREST and the clamp and mirror wraps; the two glass extensions;
vertex colours, tangents and a second set of coordinates.
"""

import base64
import json
import os
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def corpus(target, name, data):
    folder = os.path.join(HERE, "corpus", target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, name), "wb") as f:
        f.write(data)


def png(width, height, rgb_rows):
    """An 8-bit RGB PNG, written by hand (signature, IHDR, IDAT, IEND)."""

    def chunk(kind, body):
        crc = zlib.crc32(kind + body) & 0xFFFFFFFF
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", crc)

    raw = b"".join(b"\x00" + bytes(row) for row in rgb_rows)
    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", header)
        + chunk(b"IDAT", zlib.compress(raw, 9))
        + chunk(b"IEND", b"")
    )


# A 2x2 image whose four texels differ.
PNG_2X2 = png(2, 2, [[200, 30, 90, 40, 30, 90], [200, 230, 90, 40, 230, 90]])

# A 2x2 baseline JPEG (quality 50) of the same texels, as the image crate's
# JpegEncoder writes it.
JPEG_2X2 = base64.b64decode(
    "/9j/4AAQSkZJRgABAgAAAQABAAD/wAARCAACAAIDAREAAhEBAxEB/9sAQwAQCwwODAoQDg0OEhEQExgo"
    "GhgWFhgxIyUdKDozPTw5Mzg3QEhcTkBEV0U3OFBtUVdfYmdoZz5NcXlwZHhcZWdj/9sAQwEREhIYFRgv"
    "GhovY0I4QmNjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2NjY2Nj/8QA"
    "HwAAAQUBAQEBAQEAAAAAAAAAAAECAwQFBgcICQoL/8QAtRAAAgEDAwIEAwUFBAQAAAF9AQIDAAQRBRIh"
    "MUEGE1FhByJxFDKBkaEII0KxwRVS0fAkM2JyggkKFhcYGRolJicoKSo0NTY3ODk6Q0RFRkdISUpTVFVW"
    "V1hZWmNkZWZnaGlqc3R1dnd4eXqDhIWGh4iJipKTlJWWl5iZmqKjpKWmp6ipqrKztLW2t7i5usLDxMXG"
    "x8jJytLT1NXW19jZ2uHi4+Tl5ufo6erx8vP09fb3+Pn6/8QAHwEAAwEBAQEBAQEBAQAAAAAAAAECAwQF"
    "BgcICQoL/8QAtREAAgECBAQDBAcFBAQAAQJ3AAECAxEEBSExBhJBUQdhcRMiMoEIFEKRobHBCSMzUvAV"
    "YnLRChYkNOEl8RcYGRomJygpKjU2Nzg5OkNERUZHSElKU1RVVldYWVpjZGVmZ2hpanN0dXZ3eHl6goOE"
    "hYaHiImKkpOUlZaXmJmaoqOkpaanqKmqsrO0tba3uLm6wsPExcbHyMnK0tPU1dbX2Nna4uPk5ebn6Onq"
    "8vP09fb3+Pn6/9oADAMBAAIRAxEAPwDobextPs8f+iwfcH/LMeleHOrU5n7z+83w9ar7KPvPZdfI/9k="
)

POSITIONS = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
UVS = [(0, 1), (1, 1), (1, 0), (0, 0)]
INDICES = [0, 1, 2, 0, 2, 3]


def pad4(data):
    return data + b"\x00" * (-len(data) % 4)


def data_uri(mime, data):
    return "data:%s;base64,%s" % (mime, base64.b64encode(data).decode())


class Quad:
    """The quad's glTF JSON and its one buffer, built view by view."""

    def __init__(self):
        self.buffer = b""
        self.views = []
        self.accessors = []

    def view(self, data):
        self.views.append(
            {"buffer": 0, "byteOffset": len(self.buffer), "byteLength": len(data)}
        )
        self.buffer += pad4(data)
        return len(self.views) - 1

    def accessor(self, view, component, count, kind, **extra):
        a = {"componentType": component, "count": count, "type": kind}
        if view is not None:
            a["bufferView"] = view
        a.update(extra)
        self.accessors.append(a)
        return len(self.accessors) - 1

    def positions(self):
        data = b"".join(struct.pack("<3f", *p) for p in POSITIONS)
        return self.accessor(
            self.view(data), 5126, 4, "VEC3", min=[-1, -1, 0], max=[1, 1, 0]
        )

    def indices(self):
        data = struct.pack("<6H", *INDICES)
        return self.accessor(self.view(data), 5123, 6, "SCALAR")

    def float_uvs(self):
        data = b"".join(struct.pack("<2f", *uv) for uv in UVS)
        return self.accessor(self.view(data), 5126, 4, "VEC2")

    def byte_uvs(self):
        data = b"".join(struct.pack("<2B", u * 255, v * 255) for u, v in UVS)
        return self.accessor(self.view(data), 5121, 4, "VEC2", normalized=True)

    def sparse_uvs(self):
        """No bufferView (all zeros) but for two elements set sparsely, as
        normalized shorts."""
        idx = self.view(struct.pack("<2B", 1, 2))
        values = self.view(struct.pack("<4H", 65535, 65535, 65535, 0))
        return self.accessor(
            None,
            5123,
            4,
            "VEC2",
            normalized=True,
            sparse={
                "count": 2,
                "indices": {"bufferView": idx, "componentType": 5121},
                "values": {"bufferView": values},
            },
        )

    def document(self, uv_accessor, tex_coord, material, textures, images, samplers):
        position = self.positions()
        index = self.indices()
        attributes = {"POSITION": position}
        if uv_accessor is not None:
            attributes["TEXCOORD_%d" % tex_coord] = uv_accessor
        doc = {
            "asset": {"version": "2.0", "generator": "kdray fuzz/make_seeds.py"},
            "scene": 0,
            "scenes": [{"nodes": [0]}],
            "nodes": [{"mesh": 0}],
            "meshes": [
                {
                    "primitives": [
                        {"attributes": attributes, "indices": index, "material": 0}
                    ]
                }
            ],
            "materials": [material],
            "accessors": self.accessors,
            "bufferViews": self.views,
        }
        for key, value in [
            ("textures", textures),
            ("images", images),
            ("samplers", samplers),
        ]:
            if value:
                doc[key] = value
        return doc


def textured_material(tex_coord=0):
    info = {"index": 0}
    if tex_coord:
        info["texCoord"] = tex_coord
    return {
        "name": "textured",
        "pbrMetallicRoughness": {
            "baseColorFactor": [1, 1, 1, 1],
            "baseColorTexture": info,
        },
    }


def gltf_text(doc, quad):
    doc["buffers"] = [
        {
            "byteLength": len(quad.buffer),
            "uri": data_uri("application/octet-stream", quad.buffer),
        }
    ]
    return json.dumps(doc, separators=(",", ":"))


def glb(doc, quad):
    doc["buffers"] = [{"byteLength": len(quad.buffer)}]
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    body = pad4(quad.buffer)
    chunks = (
        struct.pack("<I4s", len(text), b"JSON")
        + text
        + struct.pack("<I4s", len(body), b"BIN\x00")
        + body
    )
    return struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks


def gltf_seeds():
    # PNG in a data URI; TEXCOORD_0 floats; NEAREST, clamp along u, mirror along v.
    q = Quad()
    doc = q.document(
        q.float_uvs(),
        0,
        textured_material(),
        [{"source": 0, "sampler": 0}],
        [{"uri": data_uri("image/png", PNG_2X2), "name": "two by two"}],
        [{"magFilter": 9728, "minFilter": 9728, "wrapS": 33071, "wrapT": 33648}],
    )
    corpus("gltf", "seed_texture_png_data_uri.gltf", gltf_text(doc, q))

    # JPEG in a data URI; TEXCOORD_1 named by texCoord; no sampler.
    q = Quad()
    doc = q.document(
        q.float_uvs(),
        1,
        textured_material(1),
        [{"source": 0}],
        [{"uri": data_uri("image/jpeg", JPEG_2X2)}],
        None,
    )
    corpus("gltf", "seed_texture_jpeg_data_uri.gltf", gltf_text(doc, q))

    # A .glb: PNG in a buffer view; normalized-byte coordinates; LINEAR, repeat.
    q = Quad()
    uvs = q.byte_uvs()
    image_view = q.view(PNG_2X2)
    doc = q.document(
        uvs,
        0,
        textured_material(),
        [{"source": 0, "sampler": 0}],
        [{"bufferView": image_view, "mimeType": "image/png"}],
        [{"magFilter": 9729, "wrapS": 10497, "wrapT": 10497}],
    )
    corpus("gltf", "seed_texture_png_buffer_view.glb", glb(doc, q))

    # Sparse coordinates (no bufferView); the texture's image shared by two
    # textures with different samplers.
    q = Quad()
    doc = q.document(
        q.sparse_uvs(),
        0,
        textured_material(),
        [{"source": 0, "sampler": 0}, {"source": 0, "sampler": 1}],
        [{"uri": data_uri("image/png", PNG_2X2)}],
        [{"wrapS": 33071}, {"magFilter": 9728}],
    )
    doc["materials"].append(
        {"pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}
    )
    doc["meshes"][0]["primitives"].append(
        dict(doc["meshes"][0]["primitives"][0], material=1)
    )
    corpus("gltf", "seed_sparse_texcoords.gltf", gltf_text(doc, q))

    # Glass: KHR_materials_transmission and KHR_materials_ior, untextured.
    q = Quad()
    glass = {
        "name": "glass",
        "pbrMetallicRoughness": {"baseColorFactor": [0.9, 1, 0.95, 1]},
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 0.9},
            "KHR_materials_ior": {"ior": 1.33},
        },
    }
    doc = q.document(None, 0, glass, None, None, None)
    doc["extensionsUsed"] = ["KHR_materials_transmission", "KHR_materials_ior"]
    corpus("gltf", "seed_glass_extensions.gltf", gltf_text(doc, q))

    # Vertex attributes: COLOR_0 as normalized unsigned shorts, TANGENT as
    # floats, a normal map on TEXCOORD_1 and an occlusion map with a
    # texture transform (two channels of coordinates).
    q = Quad()
    uvs = q.float_uvs()
    second = q.byte_uvs()
    colours = q.accessor(
        q.view(struct.pack("<16H", *([65535, 32768, 0, 65535] * 4))), 5123, 4, "VEC4",
        normalized=True,
    )
    tangents = q.accessor(q.view(struct.pack("<16f", *([1, 0, 0, -1] * 4))), 5126, 4, "VEC4")
    material = textured_material()
    material["normalTexture"] = {"index": 0, "texCoord": 1, "scale": 0.5}
    material["occlusionTexture"] = {
        "index": 0,
        "strength": 0.5,
        "extensions": {"KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.3}},
    }
    doc = q.document(
        uvs,
        0,
        material,
        [{"source": 0}],
        [{"uri": data_uri("image/png", PNG_2X2)}],
        None,
    )
    attributes = doc["meshes"][0]["primitives"][0]["attributes"]
    attributes.update({"TEXCOORD_1": second, "COLOR_0": colours, "TANGENT": tangents})
    doc["extensionsUsed"] = ["KHR_texture_transform"]
    corpus("gltf", "seed_vertex_attributes.gltf", gltf_text(doc, q))


OBJ_TEXTURED = """\
# A textured quad: vt and vn, its material in an MTL file
mtllib quad.mtl
o quad
v -1 -1 0
v 1 -1 0
v 1 1 0
v -1 1 0
vt 0 0
vt 1 0 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl textured
f 1/1/1 2/2/1 3/3/1
f -4/-4/-1 -2/-2/-1 -1/-1/-1
usemtl missing
f 1/1 2/2 4/4
f 1//1 3//1 4//1
"""

MTL_FULL = """\
# Every statement the MTL reader reads, and some it skips
newmtl textured
Ka 0.1 0.1 0.1
Kd 0.8 0.7 0.6
Ks 1
Ns 50
illum 2
map_Kd -clamp on -s 2 2 1 -o 0.5 0 0 -bm 1 tex.png
map_Ks spec.png
bump -bm 0.5 bump.png

newmtl glass
Kd 1 1 1
d -halo 0.2
Ni 1.45
Tr 0.8

newmtl windows
Kd 0.5 0.5 0.5
map_Kd .\\textures\\wood.jpg
d 1
Ni 0

newmtl textured
Kd 0 0 1
"""

TOML_ANIMATION = """\
[camera]
position = [0.0, 0.5, 3.0]
look_at = [0.0, 0.0, 0.0]
vfov = 50.0

[render]
width = 32
height = 24

[animation]
frames = 12
fps = 30
orbit = -90

[[animation.keys]]
frame = 0
vfov = 40

[[animation.keys]]
frame = 3
position = [2.0, 1.0, 2.0]
up = [0.0, 1.0, 0.1]

[[animation.keys]]
frame = 7
look_at = [0.5, 0.0, 0.0]
vfov = 70

[[animation.keys]]
frame = 11
position = [0.0, 3.0, 0.5]

[[lights]]
position = [3.0, 3.0, 3.0]

[materials.glass]
diffuse = [0.1, 0.1, 0.1]
transmission = 0.9
ior = 1.5

[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 0.5
material = "glass"
"""

TOML_ORBIT_ONLY = """\
[camera]
position = [0.0, 0.0, 2.0]
look_at = [0.0, 0.0, 0.0]

[animation]
frames = 1
orbit = 720

[[triangles]]
vertices = [[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [0.0, 1.0, 0.0]]
"""

JSON_ANIMATION = json.dumps(
    {
        "camera": {"position": [0, 0, 2], "look_at": [0, 0, 0]},
        "animation": {
            "frames": 5,
            "orbit": 45,
            "keys": [{"frame": 2, "position": [1, 1, 2]}, {"frame": 4, "vfov": 30}],
        },
        "spheres": [{"center": [0, 0, 0], "radius": 0.5}],
    },
    indent=1,
)


def main():
    gltf_seeds()
    corpus("obj", "seed_textured_quad.obj", OBJ_TEXTURED)
    corpus("mtl", "seed_all_statements.mtl", MTL_FULL)
    corpus("scene_toml", "seed_animation_keys.toml", TOML_ANIMATION)
    corpus("scene_toml", "seed_animation_orbit.toml", TOML_ORBIT_ONLY)
    corpus("scene_json", "seed_animation_keys.json", JSON_ANIMATION)


if __name__ == "__main__":
    main()
