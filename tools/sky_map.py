#!/usr/bin/env python3
"""sky_map: writes scenes/sky/sky.hdr, the environment map of the repository's sky scenes: a
clear sky over a dark ground with a small, bright sun, as an equirectangular Radiance HDR in
vkrt's and Mitsuba's convention (docs/scene-format.md, environment-map: the top row is the
zenith, the left edge looks down -z).

    tools/sky_map.py [OUT.hdr] [--width 256]

Made, not downloaded, so that its licence is ours and its content is what a test of importance
sampling wants: nearly all of its power in a sun of a few texels (so light sampling must find
it), a smooth sky (so BSDF sampling finds it too) and a ground that is not black. Plain Python:
no packages needed."""
import argparse
import math
import os

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The sun: 35 degrees above the horizon, towards -x and +z; 2 degrees in radius, so that a
# 256-pixel-wide map draws it over a few texels; its irradiance on a surface facing it is about
# 6.9 (1800 times 0.0038 sr), the sky's on a horizontal surface about 1.6.
SUN_DIRECTION = (-0.6, math.sin(math.radians(35)), 0.55)
SUN_RADIUS_DEG = 2.0
SUN_RADIANCE = (1800.0, 1650.0, 1400.0)
ZENITH = (0.18, 0.32, 0.75)
HORIZON = (0.75, 0.85, 1.0)
GROUND = (0.12, 0.10, 0.08)


def normalised(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def radiance(d, sun):
    """Linear RGB radiance seen along unit direction d."""
    if sum(a * b for a, b in zip(d, sun)) > math.cos(math.radians(SUN_RADIUS_DEG)):
        return SUN_RADIANCE
    if d[1] < 0.0:
        return GROUND
    t = d[1] ** 0.5  # the horizon's band is wide and pale, the zenith deep
    return tuple(h + (z - h) * t for h, z in zip(HORIZON, ZENITH))


def rgbe(c):
    m = max(c)
    if m < 1e-32:
        return bytes(4)
    mantissa, exponent = math.frexp(m)
    scale = mantissa * 256.0 / m
    return bytes([min(255, int(c[0] * scale)), min(255, int(c[1] * scale)),
                  min(255, int(c[2] * scale)), exponent + 128])


def write(path, width):
    height = width // 2
    sun = normalised(SUN_DIRECTION)
    rows = []
    for y in range(height):
        row = bytearray()
        for x in range(width):
            # Four samples a texel, so that the sun's edge is anti-aliased as a mean.
            acc = [0.0, 0.0, 0.0]
            for sy in (0.25, 0.75):
                for sx in (0.25, 0.75):
                    th = math.pi * (y + sy) / height
                    phi = 2.0 * math.pi * (x + sx) / width
                    d = (math.sin(phi) * math.sin(th), math.cos(th), -math.cos(phi) * math.sin(th))
                    acc = [a + 0.25 * r for a, r in zip(acc, radiance(d, sun))]
            row += rgbe(acc)
        rows.append(bytes(row))
    with open(path, "wb") as f:
        f.write(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n")
        f.write(f"-Y {height} +X {width}\n".encode())
        for row in rows:
            f.write(row)


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("out", nargs="?", default=os.path.join(ROOT, "scenes", "sky", "sky.hdr"))
    p.add_argument("--width", type=int, default=256)
    a = p.parse_args()
    write(a.out, a.width)
    print(f"sky_map: wrote {a.out}")


if __name__ == "__main__":
    main()
