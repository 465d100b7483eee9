"""Heat-balance exposure benchmark: shadows at many sun positions and the hemisphere (sky view
and view factors) of many elements, from the ray engine.

A procedural terrain of about ``--elements`` cells (one element per cell, two faces each) with
a block of buildings; shadows for every element at ``--suns`` sun positions through a summer
day (:func:`radscene.thermal.exposure.sunlit_fraction`, Embree packets of eight where the
library allows), and the hemisphere with ``--samples`` rays per element
(:func:`radscene.thermal.exposure.hemisphere_exposure`). Best of ``--repeat`` runs.

Run ``python benchmarks/bench_thermal_exposure.py``; figures go to
``out/bench/bench_thermal_exposure.json`` and a Markdown table to stdout.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import platform
import time
from pathlib import Path

import numpy as np

from radscene.geometry import Heightfield, RayTracer, box, procedural_terrain
from radscene.thermal.elements import build_elements
from radscene.thermal.exposure import hemisphere_exposure, sunlit_fraction
from radscene.thermal.solve import sun_vectors

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "bench"


def _scene(n_elements):
    side = int(round(np.sqrt(n_elements))) + 1
    spacing = 2.0
    hf, _ = procedural_terrain(size=(side * spacing, side * spacing), spacing=spacing, relief=20.0, seed=1)
    hf = Heightfield(hf.elevation[:side, :side], origin=(0.0, 0.0), spacing=(spacing, spacing))
    ground = hf.to_mesh()
    rng = np.random.default_rng(0)
    blocks = []
    for _ in range(40):
        x, y = rng.uniform(0.2, 0.8, 2) * side * spacing
        blocks.append(box((12.0, 12.0, rng.uniform(4.0, 15.0))).transformed(translation=(x, y, hf.height_at(x, y) - 1.0)))
    meshes = [ground, *blocks]
    mats = [np.zeros(len(m.faces), np.int64) for m in meshes]
    elements = build_elements(meshes, mats, [True] + [False] * len(blocks), terrain=0, heightfield=hf)
    return RayTracer(meshes), elements


def _best(fn, repeat):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=100_000)
    parser.add_argument("--suns", type=int, default=96)
    parser.add_argument("--samples", type=int, default=64)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    tracer, elements = _scene(args.elements)
    # a June day at 45 deg N, every 15 min from sunrise to sunset (zenith < 90 deg)
    hours = np.linspace(4.5, 19.5, args.suns)
    declination, latitude = np.radians(23.4), np.radians(45.0)
    hour_angle = np.radians(15.0 * (hours - 12.0))
    cos_z = np.sin(latitude) * np.sin(declination) + np.cos(latitude) * np.cos(declination) * np.cos(hour_angle)
    zenith = np.degrees(np.arccos(np.clip(cos_z, -1.0, 1.0)))
    azimuth = np.where(hours < 12.0, 90.0, 270.0) + np.where(hours < 12.0, -1.0, 1.0) * 45.0 * np.cos(hour_angle)
    suns = sun_vectors(np.minimum(zenith, 89.0), azimuth)
    shadows = _best(lambda: sunlit_fraction(tracer, elements, suns), args.repeat)
    hemisphere = _best(lambda: hemisphere_exposure(tracer, elements, args.samples), args.repeat)
    n_rays_shadow = int((elements.face_element >= 0).sum()) * args.suns
    figures = {
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "machine": platform.processor() or platform.machine(),
        "elements": elements.size,
        "faces": int((elements.face_element >= 0).sum()),
        "sun_positions": args.suns,
        "shadows_s": shadows,
        "shadow_rays_per_s": n_rays_shadow / shadows,
        "hemisphere_samples": args.samples,
        "hemisphere_s": hemisphere,
        "hemisphere_rays_per_s": elements.size * args.samples / hemisphere,
        "packets": tracer.packets is not None,
    }
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_thermal_exposure.json").write_text(json.dumps(figures, indent=2))
    print("| what | figure |\n|---|---|")
    for key, value in figures.items():
        print(f"| {key} | {value:.3g} |" if isinstance(value, float) else f"| {key} | {value} |")


if __name__ == "__main__":
    main()
