"""Reflected-background benchmark: its cost and its noise on the render benchmark scene.

The scene is the render benchmark's (``benchmarks/render_bench/scene.py``: procedural
terrain, 8 bands, nadir map camera, 16 sky samples) with a block of buildings on it. It is
rendered without the ``background_reflected`` term and with one bounce at 16 paths per pixel,
in alternating rounds (the median of each is reported, wall and CPU time); then, on a smaller
image, the term's noise against the paths per pixel N: the standard deviation of the
difference of two renders with different seeds, over √2, relative to the term's mean. It falls
as 1/√N or faster: σ·√N is constant for independent paths, lower where the paths take the
sky fan's stratified directions (N up to ``sky_samples``, 16 here).

Target (issue 15, on 2 cores): one bounce at 16 samples per pixel costs ≤ 3 x the render
without it.

Run ``python benchmarks/bench_background.py`` (``--quick`` for a 256 x 256 smoke run).
Figures go to ``out/bench/bench_background.json`` and a table to stdout.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import sys
import time

import numpy as np
from render_bench import OUT
from render_bench.report import machine, source_version
from render_bench.scene import TERRAIN_SIZE, scene_dict

#: Buildings: a grid of blocks [m] (width, depth, height) on the middle of the terrain.
BLOCK = (24.0, 36.0, 18.0)
STREET = 60.0
GRID = 12


def with_buildings(spec: dict, terrain_size: float) -> dict:
    """The scene with a block of concrete buildings over the middle third of the terrain
    (GRID x GRID on the full one)."""
    centre = terrain_size / 2.0
    grid = max(1, min(GRID, int(terrain_size / 3.0 / (BLOCK[1] + STREET))))
    offset = (np.arange(grid) - (grid - 1) / 2.0) * (BLOCK[1] + STREET)
    spec["objects"] = [
        {"name": f"building_{i}_{j}", "shape": {"type": "box", "size": list(BLOCK)},
         "position": [float(centre + x), float(centre + y), -1.0], "material": "concrete",
         "temperature": 305.0}
        for i, x in enumerate(offset) for j, y in enumerate(offset)]
    return spec


def _timed(scene):
    import radscene

    cpu0, t0 = time.process_time(), time.perf_counter()
    ds = radscene.render(scene, "nadir")
    return time.perf_counter() - t0, time.process_time() - cpu0, ds


def run(args) -> dict:
    import radscene

    size, terrain = (256, TERRAIN_SIZE / 4) if args.quick else (args.size, TERRAIN_SIZE)
    report = {"date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
              "load_average_at_start": os.getloadavg(), "radscene": source_version(),
              "machine": machine(), "command": " ".join(["python"] + sys.argv),
              "settings": {"size": size, "terrain_size_m": terrain, "buildings": len(with_buildings({}, terrain)["objects"]),
                           "background_samples": args.samples, "repeat": args.repeat}}
    scenes = {n: radscene.load_scene(with_buildings(scene_dict(size, 16, terrain,
                                                               background_samples=n), terrain))
              for n in (0, args.samples)}
    radscene.render(radscene.load_scene(with_buildings(  # untimed: imports, compilation
        scene_dict(32, 16, 400.0, background_samples=4), 400.0)))
    times = {0: [], args.samples: []}
    ds = None
    for _ in range(args.repeat):
        for n, scene in scenes.items():
            wall, cpu, ds = _timed(scene)
            times[n].append((wall, cpu))
    for n, runs in times.items():
        walls, cpus = zip(*runs, strict=True)
        report[f"samples_{n}"] = {"walls_s": walls, "cpu_s": cpus,
                                  "median_wall_s": float(np.median(walls)),
                                  "median_cpu_s": float(np.median(cpus))}
    off, on = report["samples_0"], report[f"samples_{args.samples}"]
    report["ratio_wall"] = on["median_wall_s"] / off["median_wall_s"]
    report["ratio_cpu"] = on["median_cpu_s"] / off["median_cpu_s"]
    bg = ds["background_reflected"]
    report["background_over_radiance"] = {
        str(b): float(bg.sel(band=b).mean() / ds["radiance"].sel(band=b).mean())
        for b in ds["band"].values}

    # noise against N on a quarter of the image (the buildings' block)
    noise = {}
    small, side = size // 4, terrain / 4
    for n in args.noise_samples:
        pair = []
        for seed in (1, 2):
            spec = with_buildings(scene_dict(small, 16, terrain, seed=seed,
                                             background_samples=n), terrain)
            cam = spec["observers"][0]
            cam["center"], cam["gsd"] = [terrain / 2, terrain / 2], side / small
            pair.append(radscene.render(radscene.load_scene(spec), "nadir")["background_reflected"])
        diff = (pair[0] - pair[1]) / np.sqrt(2.0)
        mean = 0.5 * (pair[0] + pair[1]).mean(("y", "x"))
        noise[n] = {str(b): float(diff.sel(band=b).std() / mean.sel(band=b))
                    for b in ("red", "lwir")}
    report["relative_noise"] = noise
    return report


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024, help="image side [pixels]")
    parser.add_argument("--samples", type=int, default=16, help="paths per pixel")
    parser.add_argument("--repeat", type=int, default=3, help="timed rounds")
    parser.add_argument("--noise-samples", type=int, nargs="+", default=[1, 4, 16, 64])
    parser.add_argument("--quick", action="store_true", help="256 x 256 smoke run")
    args = parser.parse_args(argv)
    report = run(args)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_background.json").write_text(json.dumps(report, indent=1))
    off, on = report["samples_0"], report[f"samples_{args.samples}"]
    print("| render | wall [s], median | CPU [s], median |\n|---|---|---|")
    print(f"| without the background | {off['median_wall_s']:.2f} | {off['median_cpu_s']:.2f} |")
    print(f"| one bounce, {args.samples} paths/pixel | {on['median_wall_s']:.2f} | "
          f"{on['median_cpu_s']:.2f} |")
    print(f"| ratio (target <= 3) | {report['ratio_wall']:.2f} | {report['ratio_cpu']:.2f} |")
    print("\n| paths/pixel N | relative noise red | lwir | red x sqrt(N) | lwir x sqrt(N) |")
    print("|---|---|---|---|---|")
    for n, row in report["relative_noise"].items():
        print(f"| {n} | {row['red']:.4f} | {row['lwir']:.4f} | {row['red'] * np.sqrt(n):.3f}"
              f" | {row['lwir'] * np.sqrt(n):.3f} |")


if __name__ == "__main__":
    main()
