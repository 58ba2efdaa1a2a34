#!/usr/bin/env python3
"""Writes torus.obj and torus.mtl next to this script.

A torus centred at the origin with its axis along +y: major radius 1.0,
minor radius 0.35, 48 segments around the axis by 24 around the tube, written
as 48 x 24 quads (`f v//vn ...`, wound counter-clockwise seen from outside).
The rings of quads around the tube alternate between the materials `gold` and
`teal` from torus.mtl.

Regenerate with:  python3 scenes/models/make_torus.py
"""

import math
import os

MAJOR_RADIUS = 1.0
MINOR_RADIUS = 0.35
MAJOR_SEGMENTS = 48  # around the y axis
MINOR_SEGMENTS = 24  # around the tube

HERE = os.path.dirname(os.path.abspath(__file__))

MTL = """\
# torus.mtl: materials of torus.obj, written by make_torus.py
newmtl gold
Ka 0.10 0.08 0.02
Kd 0.75 0.58 0.16
Ks 0.60 0.55 0.40
Ns 128

newmtl teal
Ka 0.02 0.08 0.08
Kd 0.08 0.50 0.50
Ks 0.30 0.30 0.30
Ns 64
"""


def fmt(x):
    s = "%.6f" % x
    return "0.000000" if s == "-0.000000" else s


def main():
    lines = [
        "# torus.obj: written by make_torus.py (python3 scenes/models/make_torus.py)",
        "# Torus centred at the origin, axis +y, major radius %g, minor radius %g,"
        % (MAJOR_RADIUS, MINOR_RADIUS),
        "# %d x %d quads; rings alternate between materials gold and teal."
        % (MAJOR_SEGMENTS, MINOR_SEGMENTS),
        "mtllib torus.mtl",
        "o torus",
    ]

    def index(i, j):
        """1-based index of the vertex at major step i, minor step j."""
        return (i % MAJOR_SEGMENTS) * MINOR_SEGMENTS + (j % MINOR_SEGMENTS) + 1

    for i in range(MAJOR_SEGMENTS):
        u = 2.0 * math.pi * i / MAJOR_SEGMENTS
        for j in range(MINOR_SEGMENTS):
            v = 2.0 * math.pi * j / MINOR_SEGMENTS
            ring = MAJOR_RADIUS + MINOR_RADIUS * math.cos(v)
            p = (ring * math.cos(u), MINOR_RADIUS * math.sin(v), ring * math.sin(u))
            lines.append("v %s %s %s" % tuple(fmt(c) for c in p))
    for i in range(MAJOR_SEGMENTS):
        u = 2.0 * math.pi * i / MAJOR_SEGMENTS
        for j in range(MINOR_SEGMENTS):
            v = 2.0 * math.pi * j / MINOR_SEGMENTS
            n = (math.cos(v) * math.cos(u), math.sin(v), math.cos(v) * math.sin(u))
            lines.append("vn %s %s %s" % tuple(fmt(c) for c in n))

    lines.append("s 1")
    for i in range(MAJOR_SEGMENTS):
        lines.append("usemtl %s" % ("gold" if i % 2 == 0 else "teal"))
        for j in range(MINOR_SEGMENTS):
            # Along the tube first, then around the axis: outward normal.
            quad = (index(i, j), index(i, j + 1), index(i + 1, j + 1), index(i + 1, j))
            lines.append("f " + " ".join("%d//%d" % (k, k) for k in quad))

    with open(os.path.join(HERE, "torus.obj"), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(HERE, "torus.mtl"), "w", newline="\n") as f:
        f.write(MTL)


if __name__ == "__main__":
    main()
