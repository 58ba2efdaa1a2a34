#!/usr/bin/env python3
"""Writes sky.hdr: a 256 x 128 equirectangular sky of linear radiance in
Radiance RGBE (kdray's [environment] image convention: top row up, centre
column toward -z, u toward +x). A blue zenith fading to a pale, brighter
horizon, a grey-brown ground below it, and a sun disc of 2 degrees radius
and radiance about 2,000, 35 degrees above the horizon, 40 degrees from -z
toward +x. Deterministic; run `python3 make_sky.py` in this folder to remake
it.
"""

import math

WIDTH, HEIGHT = 256, 128
SUN_ELEVATION = math.radians(35.0)
SUN_AZIMUTH = math.radians(40.0)  # from -z toward +x
SUN_RADIUS = math.radians(2.0)  # the disc as drawn (texels are 1.4 degrees)
SUN_RADIANCE = (2000.0, 1900.0, 1700.0)


def direction(u, v):
    phi = (u - 0.5) * 2.0 * math.pi
    theta = v * math.pi
    return (math.sin(theta) * math.sin(phi), math.cos(theta), -math.sin(theta) * math.cos(phi))


def radiance(d):
    sun = (
        math.cos(SUN_ELEVATION) * math.sin(SUN_AZIMUTH),
        math.sin(SUN_ELEVATION),
        -math.cos(SUN_ELEVATION) * math.cos(SUN_AZIMUTH),
    )
    cos_sun = sum(a * b for a, b in zip(d, sun))
    if cos_sun > math.cos(SUN_RADIUS):
        return SUN_RADIANCE
    y = d[1]
    if y < 0.0:
        return (0.25, 0.22, 0.2)
    # Zenith blue to a bright, pale horizon; a glow around the sun.
    t = (1.0 - y) ** 3
    zenith, horizon = (0.25, 0.45, 1.0), (1.1, 1.15, 1.2)
    glow = 1.5 * max(cos_sun, 0.0) ** 32
    return tuple(z + (h - z) * t + glow for z, h in zip(zenith, horizon))


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    e = math.frexp(m)[1]
    scale = 256.0 / 2.0**e
    return bytes([int(c[0] * scale), int(c[1] * scale), int(c[2] * scale), e + 128])


def main():
    rows = []
    for j in range(HEIGHT):
        row = b"".join(rgbe(radiance(direction((i + 0.5) / WIDTH, (j + 0.5) / HEIGHT))) for i in range(WIDTH))
        rows.append(row)
    with open("sky.hdr", "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {HEIGHT} +X {WIDTH}\n".encode())
        for row in rows:
            f.write(row)


if __name__ == "__main__":
    main()
