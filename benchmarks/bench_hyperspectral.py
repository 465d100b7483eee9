"""Hyperspectral benchmark: the render benchmark's scene as a spectral cube of 200 channels.

The scene of ``bench_render.py`` (1 M-triangle terrain, four land covers, uniform atmosphere,
1024 x 1024 nadir pixels, 16 sky rays per pixel) with its observer given a spectral grid
instead of bands: 0.40-2.39 um every 10 nm (200 channels) by default. The channels are
rendered in passes and written pass by pass to NetCDF and ENVI (as ``radscene render`` does),
or gathered in memory (``--in-memory``). Reported: wall time, passes, time per channel, peak
resident memory (VmHWM of this process), file sizes. Target: peak memory <= 4 GB.

Run ``python benchmarks/bench_hyperspectral.py`` (``--quick``: 256 x 256; ``--grid 4:13.95:0.05``
for 200 thermal channels). Figures go to ``out/bench/bench_hyperspectral.json``.
"""

from __future__ import annotations

import argparse
import json
import tempfile
import time
from pathlib import Path

from render_bench import OUT
from render_bench.report import machine, source_version
from render_bench.scene import TERRAIN_SIZE, scene_dict
from render_bench.timing import peak_rss_mib, reset_peak


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1024, help="pixels per side")
    parser.add_argument("--quick", action="store_true", help="256 x 256 on a quarter terrain")
    parser.add_argument("--grid", default="0.4:2.39:0.01", help="min:max:step [um]")
    parser.add_argument("--channels-per-pass", type=int, default=None,
                        help="default: from the pass memory budget")
    parser.add_argument("--in-memory", action="store_true",
                        help="gather the cube in memory instead of writing it")
    args = parser.parse_args()
    size = 256 if args.quick else args.size
    lo, hi, step = (float(v) for v in args.grid.split(":"))

    import radscene
    from radscene.io import write_spectral
    from radscene.pipeline import spectral_passes
    from radscene.render.hyperspectral import pass_size

    spec = scene_dict(size, 16, TERRAIN_SIZE * size / 1024)
    spec["observers"][0]["spectral"] = {"min": lo, "max": hi, "step": step}
    del spec["bands"]
    scene = radscene.load_scene(spec)
    grid = scene.observers[0].spectral
    per_pass = args.channels_per_pass or pass_size(grid, size * size)
    # compile the numba kernels and build the ray tracer once, untimed
    radscene.render_hyperspectral(scene, channels_per_pass=len(grid), grid=_first(grid, 2))

    held = peak_rss_mib()
    reset_peak()
    started = time.perf_counter()
    with tempfile.TemporaryDirectory(dir=OUT if OUT.exists() else None) as folder:
        if args.in_memory:
            cube = radscene.render_hyperspectral(scene, channels_per_pass=per_pass)
            sizes = {"cube in memory": cube["radiance"].nbytes}
        else:
            files = write_spectral(spectral_passes(scene, channels_per_pass=per_pass),
                                   Path(folder) / "cube.nc", grid, envi=Path(folder) / "cube.img")
            sizes = {f.name: f.stat().st_size for f in files}
        wall = time.perf_counter() - started
    figures = {
        "machine": machine(), "commit": source_version(), "pixels": [size, size],
        "channels": len(grid), "grid_um": [lo, float(grid.wavelength[-1]), step],
        "channels_per_pass": per_pass, "passes": -(-len(grid) // per_pass),
        "mode": "in memory" if args.in_memory else "NetCDF + ENVI, pass by pass",
        "wall_s": round(wall, 2), "s_per_channel": round(wall / len(grid), 3),
        "peak_rss_mib": round(peak_rss_mib(), 1), "rss_before_mib": round(held, 1),
        "bytes": sizes,
    }
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_hyperspectral.json").write_text(json.dumps(figures, indent=2))
    for key, value in figures.items():
        print(f"{key:>18}: {value}")
    print("target peak memory <= 4096 MiB:", "met" if figures["peak_rss_mib"] <= 4096 else "MISSED")


def _first(grid, n):
    """The first ``n`` channels of a grid (the warm-up render)."""
    from radscene.radiometry import ChannelGrid

    return ChannelGrid(grid.wavelength[:n], grid.step)


if __name__ == "__main__":
    main()
