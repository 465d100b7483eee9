"""Volumes and sheets benchmark: the cost of the volume pass and of a sheet's second pass.

A 512 x 512 nadir map of a 600 m grey plate in two bands (0.5-0.6 um, 8-12 um), no
atmosphere and no reflected background, rendered alone, with an ellipsoid of smoke (uniform,
Gaussian, and uniform with single-scattering albedo 0.9), and with a transmissive net over a
quarter of it. Each scene is rendered once to warm up, then timed (wall and CPU).

Run ``python benchmarks/bench_volumes.py``; a table goes to stdout.
"""

from __future__ import annotations

import copy
import time

import radscene

BASE = {
    "name": "bench_volumes",
    "environment": {"sun": {"zenith": 30.0, "azimuth": 180.0}, "atmosphere": {"type": "none"}},
    "materials": {"grey": {"reflectance": 0.3},
                  "net": {"reflectance": 0.2, "transmittance": 0.5}},
    "objects": [{"name": "plate", "shape": {"type": "plate", "width": 600, "length": 600},
                 "material": "grey", "temperature": "300 K"}],
    "bands": [{"name": "vis", "min": 0.5, "max": 0.6}, {"name": "lwir", "min": 8, "max": 12}],
    "observers": [{"name": "nadir", "type": "orthographic", "center": [0, 0], "gsd": 1.0,
                   "shape": [512, 512], "altitude": 1000}],
    "render": {"background_bounces": 0},
}
SMOKE = {"name": "smoke", "shape": {"type": "ellipsoid", "radii": [150, 150, 40]},
         "position": [0, 0, 60], "optical_depth": 0.8, "temperature": "330 K"}
NET = {"name": "net", "shape": {"type": "plate", "width": 300, "length": 300},
       "position": [0, 0, 3], "material": "net", "temperature": "310 K", "transmissive": True}


def cases() -> dict:
    out = {"plate alone": BASE}
    for name, volume in (("uniform ellipsoid", SMOKE),
                         ("gaussian ellipsoid", {**SMOKE, "profile": {"type": "gaussian",
                                                                      "sigma": 60}}),
                         ("uniform, albedo 0.9", {**SMOKE, "single_scattering_albedo": 0.9})):
        scene = copy.deepcopy(BASE)
        scene["volumes"] = [volume]
        out[name] = scene
    scene = copy.deepcopy(BASE)
    scene["objects"].append(NET)
    out["net over a quarter"] = scene
    return out


def main() -> None:
    for name, spec in cases().items():
        scene = radscene.load_scene(spec)
        radscene.render(scene)
        wall, cpu = time.perf_counter(), time.process_time()
        radscene.render(scene)
        print(f"{name:24s} wall {time.perf_counter() - wall:6.2f} s   "
              f"cpu {time.process_time() - cpu:6.2f} s")


if __name__ == "__main__":
    main()
