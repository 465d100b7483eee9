"""Motion benchmark: one small object moving over the render benchmark's ~1 M-triangle terrain.

Per frame the object moves 5 m east and the map camera renders. Two ways of bringing the ray
engine up to date are timed:

* **refit** — :class:`radscene.Simulation`: ``set_pose`` writes the object's 12 triangles into
  a dynamic tracer and Embree refits that mesh's BVH and the top level only;
* **rebuild** — a new :class:`radscene.geometry.RayTracer` of every mesh after the move (what a
  render of the moved scene from scratch pays before its first ray).

Reported (median over the frames): the geometry update alone, and the whole frame (update and
a render of every observer) each way. Figures go to ``out/bench/bench_motion.json``.

Run ``python benchmarks/bench_motion.py`` (``--quick``: a 1/4-size terrain; ``--help``).
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

from render_bench import OUT
from render_bench.report import machine, source_version
from render_bench.scene import TERRAIN_SIZE, scene_dict


def _scene(args) -> dict:
    terrain_size = TERRAIN_SIZE / 4 if args.quick else TERRAIN_SIZE
    scene = scene_dict(args.size, args.sky_samples, terrain_size)
    cx, cy = scene["observers"][0]["center"]
    scene["objects"] = [{"name": "vehicle", "shape": {"type": "box", "size": [2.5, 5.0, 2.0]},
                         "position": [cx, cy, 0.0], "material": "painted_metal", "temperature": 310.0}]
    return scene


def run(args) -> dict:
    import radscene
    from radscene.geometry import RayTracer
    from radscene.render import render as render_observer
    from radscene.render.integrator import scene_tables

    sim = radscene.Simulation(_scene(args))
    scene = sim.scene
    name = "vehicle"
    k = next(i for i, o in enumerate(scene.objects) if o.name == name)
    faces = sum(len(o.mesh.faces) for o in scene.objects)
    start, attitude = sim.pose(name)
    sim.step(0.04)  # compiles the kernels
    refit_update, refit_frame, rebuild_update, rebuild_frame = [], [], [], []
    for i in range(1, args.frames + 1):
        position = start + [5.0 * i, 0.0, 0.0]
        t0 = time.perf_counter()
        sim.set_pose(name, position=position)
        t1 = time.perf_counter()
        sim.step(0.04)
        t2 = time.perf_counter()
        refit_update.append(t1 - t0)
        refit_frame.append(t2 - t0)
        # the same moved scene, its ray engine built from scratch
        t0 = time.perf_counter()
        tracer = RayTracer([o.mesh for o in scene.objects])
        t1 = time.perf_counter()
        tables = scene_tables(scene, tracer)
        for setup in scene.observers:
            render_observer(scene, setup.name, _tables=tables)
        t2 = time.perf_counter()
        rebuild_update.append(t1 - t0)
        rebuild_frame.append(t2 - t0)
        scene_tables(scene, sim.tracer)  # back to the simulation's tracer

    def median(values):
        return round(statistics.median(values), 4)

    return {
        "machine": machine(), "source": source_version(), "faces": faces,
        "moving_faces": len(scene.objects[k].mesh.faces), "image": [args.size, args.size],
        "sky_samples": args.sky_samples, "frames": args.frames,
        "refit_update_s": median(refit_update), "rebuild_update_s": median(rebuild_update),
        "refit_frame_s": median(refit_frame), "rebuild_frame_s": median(rebuild_frame),
        "update_speedup": round(statistics.median(rebuild_update) / statistics.median(refit_update), 1),
        "frame_speedup": round(statistics.median(rebuild_frame) / statistics.median(refit_frame), 2),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a 1/4-size terrain (62 k triangles)")
    parser.add_argument("--size", type=int, default=256, help="image side [pixels]")
    parser.add_argument("--sky-samples", type=int, default=16)
    parser.add_argument("--frames", type=int, default=10)
    args = parser.parse_args()
    result = run(args)
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "bench_motion.json").write_text(json.dumps(result, indent=2))
    for key, value in result.items():
        if key not in ("machine", "source"):
            print(f"{key:>18}: {value}")


if __name__ == "__main__":
    main()
