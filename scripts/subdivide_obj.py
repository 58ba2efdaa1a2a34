#!/usr/bin/env python3
"""Splits every triangle of an OBJ into four at its edge midpoints, LEVELS
times, and writes `v` and `f` lines only: a real mesh of 4^LEVELS times the
triangles, for measuring load and build at a million triangles and more
(docs/benchmarks.md). Midpoints are shared between neighbours, so the mesh
stays watertight where the input is.

    scripts/subdivide_obj.py /usr/share/glmark2/models/bunny.obj 2 /tmp/bunny-1m.obj
"""
import sys


def read_obj(path):
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                verts.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append((idx[0], idx[k], idx[k + 1]))
    return verts, faces


def subdivide(verts, faces):
    midpoint = {}

    def mid(a, b):
        key = (a, b) if a < b else (b, a)
        m = midpoint.get(key)
        if m is None:
            va, vb = verts[a], verts[b]
            verts.append(tuple((x + y) / 2 for x, y in zip(va, vb)))
            m = midpoint[key] = len(verts) - 1
        return m

    out = []
    for a, b, c in faces:
        ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
        out += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
    return out


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    verts, faces = read_obj(sys.argv[1])
    for _ in range(int(sys.argv[2])):
        faces = subdivide(verts, faces)
    with open(sys.argv[3], "w") as f:
        f.write("# %s subdivided %s times: %d triangles\n" % (sys.argv[1], sys.argv[2], len(faces)))
        f.writelines("v %.7g %.7g %.7g\n" % v for v in verts)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces)


if __name__ == "__main__":
    main()
