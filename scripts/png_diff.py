#!/usr/bin/env python3
"""Compares two 8-bit RGB PNGs (kdray's output) pixel by pixel, with the
standard library alone, and prints a JSON object: the pixels that differ
and the largest difference of a channel, in levels.

    python3 scripts/png_diff.py A.png B.png
"""

import json
import struct
import sys
import zlib


def rgb(path):
    """(width, height, bytes) of an 8-bit RGB PNG, not interlaced."""
    data = open(path, "rb").read()
    at, idat = 8, b""
    while at < len(data):
        (n,) = struct.unpack(">I", data[at:at + 4])
        kind, chunk = data[at + 4:at + 8], data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", chunk[:10])
            if (depth, colour, chunk[12]) != (8, 2, 0):
                sys.exit(f"{path}: not an 8-bit RGB PNG without interlacing")
        elif kind == b"IDAT":
            idat += chunk
        at += 12 + n
    raw, stride = zlib.decompress(idat), width * 3
    out, above, pos = bytearray(), bytearray(stride), 0
    for _ in range(height):
        kind, line = raw[pos], bytearray(raw[pos + 1:pos + 1 + stride])
        pos += 1 + stride
        for x in range(stride):
            a = line[x - 3] if x >= 3 else 0
            b, c = above[x], (above[x - 3] if x >= 3 else 0)
            if kind == 1:
                line[x] = (line[x] + a) & 255
            elif kind == 2:
                line[x] = (line[x] + b) & 255
            elif kind == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif kind == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out += line
        above = line
    return width, height, bytes(out)


def main():
    wa, ha, a = rgb(sys.argv[1])
    wb, hb, b = rgb(sys.argv[2])
    if (wa, ha) != (wb, hb):
        sys.exit(f"sizes differ: {wa}x{ha} and {wb}x{hb}")
    worst, pixels = 0, 0
    for i in range(0, len(a), 3):
        d = max(abs(a[i + k] - b[i + k]) for k in range(3))
        worst = max(worst, d)
        pixels += d > 0
    print(json.dumps({"differing_pixels": pixels, "largest_difference": worst}))


if __name__ == "__main__":
    main()
