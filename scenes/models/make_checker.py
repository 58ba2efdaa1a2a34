#!/usr/bin/env python3
"""Writes checker.png (a 64 x 64 checkerboard of 8 x 8 squares, warm and
cool, with a gradient so that every square differs) and board.obj/board.mtl
(a unit square in the x-z plane, texture coordinates repeating the image
4 times across it, map_Kd checker.png): the textured floor of
scenes/textured.toml. Standard library only (zlib for the PNG)."""
import struct
import zlib

W = H = 64


def texel(x, y):
    dark = ((x // 8) + (y // 8)) % 2 == 0
    base = (200, 170, 120) if dark else (70, 110, 170)
    g = 40 * x // (W - 1)
    return (min(255, base[0] + g // 2), base[1], min(255, base[2] + (40 - g) // 2))


def png(path):
    rows = b"".join(b"\x00" + bytes(c for x in range(W) for c in texel(x, y)) for y in range(H))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", W, H, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(rows, 9)))
        f.write(chunk(b"IEND", b""))


png("checker.png")
with open("board.mtl", "w") as f:
    f.write("# The textured floor of scenes/textured.toml (make_checker.py).\n")
    f.write("newmtl checker\nKa 0.15 0.15 0.15\nKd 0.9 0.9 0.9\nKs 0.3 0.3 0.3\nNs 40\nmap_Kd checker.png\n")
with open("board.obj", "w") as f:
    f.write("# A unit square in the x-z plane, its texture repeated 4 times (make_checker.py).\n")
    f.write("mtllib board.mtl\n")
    for x, z in [(-0.5, 0.5), (0.5, 0.5), (0.5, -0.5), (-0.5, -0.5)]:
        f.write(f"v {x} 0 {z}\n")
    for u, v in [(0, 0), (4, 0), (4, 4), (0, 4)]:
        f.write(f"vt {u} {v}\n")
    f.write("usemtl checker\nf 1/1 2/2 3/3 4/4\n")
