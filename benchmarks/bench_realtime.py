"""Real-time benchmark: 256 x 256 pixels, 4 bands, 10 000 moving polygons, frame after frame.

The scene: a 500 m procedural terrain (5 m grid, 20 000 triangles) under the render
benchmark's uniform atmosphere, the sun of 21 June 09:00 UTC at 45 N, a nadir map camera of
256 x 256 pixels (1.875 m) and four bands (green, NIR, MWIR, LWIR), the reflected background
on (one bounce, 16 paths a pixel: the defaults). On it 100 vehicles,
capped 25-sided cylinders of 100 triangles each (10 000 moving polygons), each driving a
circle of 12 m radius at 10 m/s and turning with it, on the terrain.

Every frame the caller moves all 100 vehicles (:meth:`radscene.Simulation.set_poses`, one
ray-engine commit) and steps a 40 ms clock of ``radscene.Simulation(scene, realtime=True)``.
Reported: the key frame; per frame the median, 99th percentile and worst time and the
frames per second they give, over ``--frames`` frames (default 1 000); where the time goes
(moving the vehicles, the frame's own tracing and shading, the rest of ``step``); the pixels
traced again per frame; and the last frame's difference to full renders
(``radscene.Simulation(scene)``) of its poses, under the key frame's sun and at its own
instant, with that render's time. The machine's load average
is recorded before and after: figures from a shared machine vary with it.

Run ``python benchmarks/bench_realtime.py`` (``--frames 100`` for a quick run, ``--profile``
for the functions that take the time; ``--help``).
Figures go to ``out/bench/bench_realtime.json``.
"""

from __future__ import annotations

import argparse
import json
import os
import time

import numpy as np
from render_bench import OUT
from render_bench.report import machine, source_version
from render_bench.scene import ATMOSPHERE

SIZE = 256  # image side [pixels]
TERRAIN = 500.0  # terrain side [m]
VEHICLES = 10  # per side: 10 x 10 vehicles of 100 triangles
SPEED, RADIUS, DT = 10.0, 12.0, 0.04  # [m/s], [m], [s]
BANDS = [{"name": "green", "min": 0.52, "max": 0.60}, {"name": "nir", "min": 0.76, "max": 0.90},
         {"name": "mwir", "min": 3.0, "max": 5.0}, {"name": "lwir", "min": 8.0, "max": 12.0}]


def scene_dict(sky_samples: int) -> dict:
    spacing = TERRAIN / VEHICLES
    vehicles = [{"name": f"vehicle{i}", "material": "painted_metal", "temperature": 310.0,
                 "shape": {"type": "cylinder", "radius": 2.0, "height": 3.0, "sections": 25},
                 "position": [spacing * (i % VEHICLES + 0.5), spacing * (i // VEHICLES + 0.5), 0]}
                for i in range(VEHICLES**2)]
    return {
        "name": "bench_realtime",
        "environment": {"time": "2026-06-21T09:00:00Z",
                        "location": {"latitude": 45.0, "longitude": 5.0},
                        "atmosphere": ATMOSPHERE},
        "terrain": {"type": "procedural", "size": [TERRAIN, TERRAIN], "spacing": 5.0,
                    "relief": 20.0, "seed": 3, "material": "dry_grass", "temperature": 300.0},
        "objects": vehicles,
        "bands": BANDS,
        "observers": [{"name": "map", "type": "orthographic", "center": [TERRAIN / 2] * 2,
                       "gsd": TERRAIN / SIZE * 0.96, "shape": [SIZE, SIZE], "altitude": 1000.0}],
        "render": {"sky_samples": sky_samples, "seed": 1},  # background: 1 bounce, 16 paths
    }


class Fleet:
    """The vehicles' poses at a time: circles about their start, heading along the path."""

    def __init__(self, sim):
        self.names = [o.name for o in sim.scene.objects if o.name.startswith("vehicle")]
        start = np.array([sim.pose(n)[0] for n in self.names])
        self.centre = start[:, :2] - [RADIUS, 0.0]  # each starts on its circle's east point
        self.phase = np.linspace(0.0, 2 * np.pi, len(self.names), endpoint=False)
        self.terrain = sim.scene.heightfield

    def poses(self, t: float) -> dict:
        angle = self.phase + SPEED / RADIUS * t
        x = self.centre[:, 0] + RADIUS * np.cos(angle)
        y = self.centre[:, 1] + RADIUS * np.sin(angle)
        z = self.terrain.height_at(x, y)
        yaw = np.degrees(-angle) % 360.0  # counter-clockwise circle: heading along the path
        return {n: ((x[i], y[i], z[i]), (yaw[i], 0.0, 0.0)) for i, n in enumerate(self.names)}


def difference(fast, full) -> dict:
    """Per band the relative difference of the radiance: mean, max, share of pixels > 0.1 %."""
    error = np.abs(fast.radiance.values - full.radiance.values) / full.radiance.values
    return {band: {"mean": float(f"{error[b].mean():.3g}"), "max": float(f"{error[b].max():.3g}"),
                   "pixels_over_0.1%": float(f"{np.mean(error[b] > 1e-3):.3g}")}
            for b, band in enumerate(full.band.values.tolist())}


def run(args) -> dict:
    import radscene

    load_before = os.getloadavg()
    sim = radscene.Simulation(scene_dict(args.sky_samples), realtime=True)
    fleet = Fleet(sim)
    faces = [len(o.mesh.faces) for o in sim.scene.objects]
    t0 = time.perf_counter()
    sim.set_poses(fleet.poses(0.0))
    sim.render()  # the key frame (and the kernels' compilation)
    key_frame = time.perf_counter() - t0
    move, frame, render, traced = [], [], [], []
    for k in range(1, args.frames + 1):
        t0 = time.perf_counter()
        sim.set_poses(fleet.poses(k * DT))
        t1 = time.perf_counter()
        images = sim.step(DT).radiance["map"]
        t2 = time.perf_counter()
        move.append(t1 - t0)
        frame.append(t2 - t0)
        render.append(images.attrs["render_seconds"])
        traced.append(images.attrs["pixels_traced"])
    load_after = os.getloadavg()
    # the last frame's poses rendered in full: under the key frame's sun (the frozen sky, path
    # nodes and background alone), then at the last frame's own instant (the sun moved too)
    full = radscene.Simulation(scene_dict(args.sky_samples))
    full.set_poses(fleet.poses(args.frames * DT))
    same_sun = full.render().radiance["map"]
    t0 = time.perf_counter()
    reference = full.step(args.frames * DT).radiance["map"]
    full_seconds = time.perf_counter() - t0
    def ms(values, q=50):
        return round(1e3 * float(np.percentile(values, q)), 2)

    frame = np.array(frame)
    return {
        "machine": machine(), "source": source_version(),
        "load_average_before": [round(v, 2) for v in load_before],
        "load_average_after": [round(v, 2) for v in load_after],
        "image": [SIZE, SIZE], "bands": len(BANDS), "frames": args.frames,
        "faces": sum(faces), "moving_faces": sum(faces) - faces[0], "sky_samples": args.sky_samples,
        "key_frame_s": round(key_frame, 3),
        "frame_median_ms": ms(frame), "frame_p99_ms": ms(frame, 99), "frame_max_ms": ms(frame, 100),
        "fps_median": round(1.0 / float(np.median(frame)), 1),
        "fps_p99": round(1.0 / float(np.percentile(frame, 99)), 1),
        "fps_sustained": round(len(frame) / float(frame.sum()), 1),
        "move_median_ms": ms(move), "render_median_ms": ms(render),
        "step_rest_median_ms": ms(frame - np.array(move) - np.array(render)),
        "pixels_traced_median": int(np.median(traced)),
        "frames_all_pixels": int(np.sum(np.array(traced) == SIZE * SIZE)),  # the clipping box grew
        "full_render_s": round(full_seconds, 2),
        "difference_same_sun": difference(images, same_sun),
        "difference_same_instant": difference(images, reference),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1000)
    parser.add_argument("--sky-samples", type=int, default=16, help="of the key frame")
    parser.add_argument("--profile", action="store_true",
                        help="print the 15 functions that take the most time (cProfile)")
    args = parser.parse_args()
    if args.profile:
        import cProfile
        import pstats

        with cProfile.Profile() as profile:
            result = run(args)
        pstats.Stats(profile).sort_stats("tottime").print_stats(15)
    else:
        result = run(args)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_realtime.json").write_text(json.dumps(result, indent=2))
    for key, value in result.items():
        if key not in ("machine", "source"):
            print(f"{key:>26}: {value}")


if __name__ == "__main__":
    main()
