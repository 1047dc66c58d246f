#!/usr/bin/env python3
"""equal_time.py: vkrt's path tracer against Mitsuba 3's `path` integrator at equal time per frame.

For one scene: a converged Mitsuba reference (--reference-spp), then vkrt and Mitsuba at a ladder of
samples per pixel, each image's relative MSE against the reference, mean over pixels and channels of
(x - ref)^2 / (ref^2 + 0.01), and each frame's time: vkrt's own ms/frame (GPU submission to
completion of a warm frame, `vkrt render --profile`), Mitsuba's mi.render wall time of the same call
made a second time (the first compiles its kernels). Mitsuba's relative MSE is interpolated, log-log, at each of
vkrt's times; the ratio vkrt / Mitsuba is what the issue asks to be at most 1/2. Writes
NAME-equal-time.csv and prints a table. Runs where Mitsuba runs: llvm_ad_rgb on a CPU, cuda_ad_rgb
on the GPU machine (the scene files and tools/mitsuba_scene.py are read as tools/reference reads them).
    usage: equal_time.py SCENE.cfg --vkrt VKRT --out DIR [--width W] [--spps 1,2,4,...]
                         [--reference-spp N] [--variant cuda_ad_rgb|llvm_ad_rgb]
"""
import argparse
import math
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools"))


def relmse(img, ref):
    import numpy as np
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + 0.01)))


def read_exr(mi, path):
    import numpy as np
    return np.array(mi.Bitmap(path))[..., :3].astype(np.float64)


def vkrt_render(vkrt, scene, out, width, height, spp):
    """Renders with vkrt; returns its frame's GPU ms from --profile (the median of 3 frames back
    to back after 300 ms of warm-up: a frame at the GPU's clocks, its kernels compiled)."""
    done = subprocess.run([vkrt, "render", scene, "-o", out, "--width", str(width), "--height",
                           str(height), "--spp", str(spp), "--integrator", "path",
                           "--profile-repeat", "3"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"equal_time: vkrt failed: {done.stderr}")
    m = re.search(r"frame ([0-9.]+) ms \(kernels", done.stderr)
    return float(m.group(1))


def at_time(points, t):
    """Log-log interpolation (or extrapolation from the nearest two) of relMSE at time t."""
    points = sorted(points)
    if len(points) < 2:
        return float("nan")
    for i in range(len(points) - 1):
        if points[i + 1][0] >= t or i == len(points) - 2:
            (t0, e0), (t1, e1) = points[i], points[i + 1]
            if t0 == t1:
                return e0
            a = (math.log(t) - math.log(t0)) / (math.log(t1) - math.log(t0))
            return math.exp(math.log(e0) + a * (math.log(e1) - math.log(e0)))
    return float("nan")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("--vkrt", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--width", type=int, default=256)
    p.add_argument("--spps", default="1,2,4,8,16,32,64")
    p.add_argument("--mitsuba-spps", default=None, help="default: --spps")
    p.add_argument("--reference-spp", type=int, default=1024)
    p.add_argument("--variant", default="cuda_ad_rgb")
    args = p.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    import mitsuba_scene
    os.makedirs(args.out, exist_ok=True)
    name = os.path.splitext(os.path.basename(args.scene))[0]
    cfg = mitsuba_scene.read_config(args.scene)
    width = args.width
    height = max(1, round(width * cfg.height / cfg.width))

    def mitsuba(spp, seed):
        scene, chosen, _ = mitsuba_scene.scene_dict(cfg, 0, width, height, spp, seed, None,
                                                    "path", [])
        loaded = mi.load_dict(scene)
        mi.render(loaded, spp=spp, seed=seed)  # compiles the kernels
        start = time.time()
        img = mi.render(loaded, spp=spp, seed=seed + 1)
        import numpy as np
        rgb = np.array(img)[..., :3].astype(np.float64)
        return (time.time() - start) * 1e3, rgb

    _, ref = mitsuba(args.reference_spp, 1000)
    rows = []
    for spp in [int(s) for s in args.spps.split(",")]:
        exr = os.path.join(args.out, f"{name}-vkrt-{spp}.exr")
        ms = vkrt_render(args.vkrt, args.scene, exr, width, height, spp)
        rows.append(("vkrt", spp, ms, relmse(read_exr(mi, exr), ref)))
    for spp in [int(s) for s in (args.mitsuba_spps or args.spps).split(",")]:
        ms, rgb = mitsuba(spp, 0)
        rows.append(("mitsuba", spp, ms, relmse(rgb, ref)))
    mits = [(ms, e) for who, _, ms, e in rows if who == "mitsuba"]
    with open(os.path.join(args.out, f"{name}-equal-time.csv"), "w") as f:
        f.write("renderer,spp,ms_per_frame,relmse,mitsuba_relmse_at_same_time,ratio\n")
        print(f"{name} {width}x{height}, reference {args.reference_spp} spp, {args.variant}")
        print(f"{'renderer':8} {'spp':>5} {'ms/frame':>10} {'relMSE':>10} {'Mitsuba at t':>13}"
              f" {'ratio':>7}")
        for who, spp, ms, e in rows:
            other = at_time(mits, ms) if who == "vkrt" else float("nan")
            ratio = e / other if who == "vkrt" else float("nan")
            f.write(f"{who},{spp},{ms:.3f},{e:.6g},{other:.6g},{ratio:.4g}\n")
            print(f"{who:8} {spp:5d} {ms:10.3f} {e:10.4g} {other:13.4g} {ratio:7.3f}")


if __name__ == "__main__":
    main()
