#!/usr/bin/env python3
"""Prints the results of `vkrt bench --json` as a Markdown table, so the numbers in docs/ are
copied from the measurement, never typed in. Usage: bench_table.py RESULTS.json"""
import json
import os
import sys


def rate(x):
    """Mrays/s: whole numbers from 100 up, three significant digits below."""
    return f"{x:.0f}" if x >= 100 else f"{x:.3g}"


def main():
    with open(sys.argv[1], encoding="utf-8") as f:
        run = json.load(f)
    print(f"Device: {run['device']} (Vulkan {run['api_version']}); median of "
          f"{run['timed_runs']} back-to-back timed runs.\n")
    # Runs before the diffuse bounce rays were measured have no such column.
    diffuse = all("diffuse_mrays_per_s" in r for r in run["results"])
    print("| scene | triangles | rays | accel | build ms | MiB | primary Mrays/s | "
          "shadow Mrays/s | " + ("diffuse Mrays/s | " if diffuse else "") + "hits | shadowed |")
    print("|---|---:|---|---|---:|---:|---:|---:|" + ("---:|" if diffuse else "") + "---:|---:|")
    for r in run["results"]:
        scene = os.path.basename(os.path.dirname(r["scene"])) if r["scene"].endswith(
            "scene.cfg") else os.path.splitext(os.path.basename(r["scene"]))[0]
        rays = f"{r['width']}x{r['height']}"
        if r["primary_rays_timed"] < r["width"] * r["height"]:
            rays += f" ({r['primary_rays_timed']} timed)"
        print(f"| {scene} | {r['triangles']} | {rays} | {r['accel']} | {r['build_ms']:.1f} | "
              f"{r['bytes'] / 2**20:.2f} | {rate(r['primary_mrays_per_s'])} | "
              f"{rate(r['shadow_mrays_per_s'])} | " +
              (f"{rate(r['diffuse_mrays_per_s'])} | " if diffuse else "") +
              f"{r['hits']} | {r['blocked']} |")


if __name__ == "__main__":
    main()
