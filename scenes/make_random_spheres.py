#!/usr/bin/env python3
"""Writes random_spheres.toml: 400 random spheres resting on a floor.

Deterministic (fixed seed), so the file and its golden image never drift.
Run from this folder: python3 make_random_spheres.py
"""
import random

rng = random.Random(20261121)
palette = {
    "red": (0.8, 0.15, 0.1), "orange": (0.9, 0.5, 0.1), "yellow": (0.85, 0.8, 0.2),
    "green": (0.2, 0.7, 0.25), "blue": (0.15, 0.3, 0.85), "violet": (0.55, 0.2, 0.75),
    "white": (0.8, 0.8, 0.8),
}
out = [__doc__.strip().replace("\n", "\n# ").join(["# ", "\n"]),
       "[camera]\nposition = [0.0, 3.2, 9.0]\nlook_at = [0.0, 0.3, 0.0]\nvfov = 45.0\n",
       "[render]\nwidth = 1280\nheight = 720\nbackground = [0.05, 0.07, 0.12]\nmax_depth = 6\n",
       "[[lights]]\nposition = [6.0, 10.0, 8.0]\nambient = [0.25, 0.25, 0.25]\n",
       "[[lights]]\nposition = [-8.0, 6.0, 2.0]\nambient = [0.0, 0.0, 0.0]\ndiffuse = [0.35, 0.35, 0.45]\nspecular = [0.3, 0.3, 0.3]\n"]
for name, (r, g, b) in palette.items():
    for finish, (spec, shin, refl) in {"matte": (0.1, 8, 0.0), "shiny": (0.8, 200, 0.35)}.items():
        out.append(f"[materials.{name}_{finish}]\nambient = [{r*0.2:.3f}, {g*0.2:.3f}, {b*0.2:.3f}]\n"
                   f"diffuse = [{r:.3f}, {g:.3f}, {b:.3f}]\nspecular = [{spec}, {spec}, {spec}]\n"
                   f"shininess = {shin}.0\nreflection = {refl}\n")
out.append("[materials.floor]\nambient = [0.08, 0.08, 0.08]\ndiffuse = [0.5, 0.5, 0.5]\n"
           "specular = [0.2, 0.2, 0.2]\nshininess = 40.0\nreflection = 0.25\n")
out.append("[[spheres]]\ncenter = [0.0, -1000.0, 0.0]\nradius = 1000.0\nmaterial = \"floor\"\n")
for _ in range(400):
    radius = rng.uniform(0.08, 0.3)
    x, z = rng.uniform(-7.0, 7.0), rng.uniform(-12.0, 4.0)
    name = rng.choice(list(palette)) + "_" + rng.choice(["matte", "shiny"])
    out.append(f"[[spheres]]\ncenter = [{x:.4f}, {radius:.4f}, {z:.4f}]\nradius = {radius:.4f}\nmaterial = \"{name}\"\n")
with open("random_spheres.toml", "w") as f:
    f.write("\n".join(out))
