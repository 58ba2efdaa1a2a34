#!/usr/bin/env python3
"""Writes a kdray scene as JSON with `render.max_depth = 1` (primary and
shadow rays only, no reflections), and mesh paths made absolute so that the
copy works from any folder. Usage: direct_variant.py SCENE OUT.json
"""

import json
import os
import sys
import tomllib


def main():
    src, dst = sys.argv[1], sys.argv[2]
    with open(src, "rb") as f:
        data = f.read()
    doc = json.loads(data) if src.lower().endswith(".json") else tomllib.loads(data.decode())
    doc.setdefault("render", {})["max_depth"] = 1
    folder = os.path.dirname(os.path.abspath(src))
    for mesh in doc.get("meshes", []):
        mesh["path"] = os.path.join(folder, mesh["path"])  # an absolute path stays as it is
    with open(dst, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
