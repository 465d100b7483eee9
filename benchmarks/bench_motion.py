"""Motion benchmark: a frame sequence of the demo with one moving vehicle, frame by frame
against a single render; and one object moving over the render benchmark's ~1 M-triangle
terrain, refit against rebuild.

**Sequence** (the default). The bundled ``demo`` with its truck driven along its heading at
10 m/s (a ``trajectory``, attitude along the path, on the terrain), rendered as a sequence of
``--frames`` frames 40 ms apart (stepped as :func:`radscene.render_sequence` steps them, each
frame let go once timed, so 100 frames fit in memory; every frame renders both observers: the
map and the oblique camera), twice: with incremental frames (the default:
each frame after the first traces only the rays that something moved through,
:mod:`radscene.render.frame_cache`, and with key frames, ``render.key_frames: true`` set here
(off by default), shades only the pixels something moved through between key frames,
:mod:`radscene.render.key_frames`) and
with full frames (``incremental=False``). With ``--compare-key-frames`` the incremental
sequence is stepped together with one without key frames (``render.key_frames: false``):
both frame times, and per observer the largest and 99th-percentile relative difference of
radiance between them. Reported:
the single render of the same scene (``radscene.render_all`` after its heat balance, the second
of two: warm), each sequence's first frame (its heat balance included) and the median and 90th
percentile of the later frames, and their ratio to the single render (the goal: at most 0.3
after the first frame), and the largest difference between the two sequences' frames. The same with
``radscene.Simulation(scene, realtime=True)`` (``--realtime-frames`` frames; real-time frames
take no supersampling, so both the single render and the frames of that part are of the demo
with ``supersample: 1``).

**Refit** (``--refit``). Per frame the object moves 5 m east and the map camera renders. Two
ways of bringing the ray engine up to date are timed:

* **refit** — :class:`radscene.Simulation`: ``set_pose`` writes the object's 12 triangles into
  a dynamic tracer and Embree refits that mesh's BVH and the top level only;
* **rebuild** — a new :class:`radscene.geometry.RayTracer` of every mesh after the move (what a
  render of the moved scene from scratch pays before its first ray).

Reported (median over the frames): the geometry update alone, and the whole frame (update and
a render of every observer) each way.

The machine's load average is recorded before and after. Figures go to
``out/bench/bench_motion.json`` (``bench_motion_refit.json`` with ``--refit``).

Run ``python benchmarks/bench_motion.py`` (``--frames 10`` for a quicker sequence;
``--refit``, with ``--quick`` for a 1/4-size terrain; ``--help``).
"""

from __future__ import annotations

import argparse
import json
import os
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


#: Time between frames [s], and the truck's speed [m s-1].
STEP, SPEED = 0.04, 10.0


def demo_scene(frames: int, supersample: int | None = None) -> tuple[dict, object]:
    """The demo's document with its truck driven along its heading, and the folder its files
    resolve against; ``supersample`` for every observer when given."""
    import numpy as np
    import yaml

    import radscene
    from radscene.radiometry.units import parse_quantity

    path = radscene.example_path("demo")
    scene = yaml.safe_load(path.read_text())
    truck = next(o for o in scene["objects"] if o["name"] == "truck")
    x, y, z = (float(parse_quantity(v, "length")) for v in truck["position"])
    heading = np.radians(float(parse_quantity(truck["rotation"][0], "angle")))
    duration = frames * STEP + 1.0
    end = [x + SPEED * duration * np.sin(heading), y + SPEED * duration * np.cos(heading)]
    truck["trajectory"] = {"waypoints": [[0.0, x, y, z], [duration, *end, z]], "attitude": "path"}
    truck["rotation"] = [0, 0, 0]  # the path gives the heading
    scene.setdefault("render", {})["key_frames"] = True  # off by default: the goal's mode
    if supersample is not None:
        for observer in scene["observers"]:
            observer["supersample"] = supersample
    return scene, path.parent


def _single(scene, base) -> tuple[float, float]:
    """The heat balance, then the warm single render of every observer [s]."""
    import radscene
    from radscene.pipeline import apply_thermal, thermal_active

    loaded = radscene.load_scene(scene, base_dir=base)
    t0 = time.perf_counter()
    if thermal_active(loaded):
        apply_thermal(loaded, progress=False)
    thermal = time.perf_counter() - t0
    radscene.render_all(loaded, progress=False)  # compiles the kernels, builds the tables
    t0 = time.perf_counter()
    radscene.render_all(loaded, progress=False)
    return thermal, time.perf_counter() - t0


def _frames(times: list[float], single: float) -> dict:
    later = sorted(times[1:])
    median = statistics.median(later)
    mean = statistics.fmean(later)
    return {"frames": len(times), "first_frame_s": round(times[0], 3), "frame_median_s": round(median, 4),
            "frame_p90_s": round(later[int(0.9 * (len(later) - 1))], 4),
            "frame_mean_s": round(mean, 4), "frame_over_single": round(median / single, 3),
            "mean_over_single": round(mean / single, 3),
            "frame_s": [round(t, 3) for t in times]}


def _schedule(sim, frames: int, look_ahead: bool) -> None:
    """Tell ``sim`` the sequence's frame times, as :func:`radscene.render_sequence` does (the
    key frames rendered ahead, the frames between interpolated); not with ``look_ahead``
    False (the frames between extrapolated, as the live step API makes them)."""
    if look_ahead:
        sim.schedule([k * STEP for k in range(frames)])


def _lockstep(scene, base, frames: int, look_ahead: bool = True):
    """Two incremental sequences of ``scene`` stepped together, with key frames
    (:mod:`radscene.render.key_frames`) and without (``render.key_frames: false``,
    every pixel shaded at its own instant): (each frame's wall time [s] of each, and per
    observer and frame the largest and the 99th-percentile relative difference of radiance
    between the two). The label maps must match exactly (an error otherwise)."""
    import copy

    import numpy as np

    import radscene

    sims, times = [], ([], [])
    for flag in (True, False):
        document = copy.deepcopy(scene)
        document.setdefault("render", {})["key_frames"] = flag
        sims.append(radscene.Simulation(radscene.load_scene(document, base_dir=base)))
        _schedule(sims[-1], frames, look_ahead)
    errors = {}
    for k in range(frames):
        shown = []
        for sim, spent in zip(sims, times, strict=True):
            t = time.perf_counter()
            shown.append(sim.render() if k == 0 else sim.step(STEP))
            spent.append(time.perf_counter() - t)
        for name, got in shown[0].radiance.items():
            want = shown[1].radiance[name]
            for var in ("object_id", "material_id", "range", "latitude", "longitude"):
                if var in want and not np.array_equal(got[var].values, want[var].values,
                                                      equal_nan=True):
                    raise AssertionError(f"frame {k}, {name}: {var} differs")
            x, y = want.radiance.values, got.radiance.values
            rel = (np.abs(y - x) / np.maximum(np.abs(x), 1e-30))[x > 0]
            errors.setdefault(name, []).append((float(rel.max()), float(np.quantile(rel, 0.99))))
        print(f"frame {k}: {times[0][-1]:.2f} s with key frames, {times[1][-1]:.2f} s without;",
              {n: f"{e[-1][0]:.1e} (p99 {e[-1][1]:.1e})" for n, e in errors.items()}, flush=True)
        del shown
    return times, errors


def _stepped(loaded, frames: int, incremental: bool, keep: bool, look_ahead: bool = True):
    """The frames of a sequence as :func:`radscene.render_sequence` renders them (a
    :class:`radscene.Simulation` at the first instant, then a step of ``STEP`` per frame),
    each let go once timed: (each frame's wall time [s], per observer the radiance and the
    label maps of every frame when ``keep``, else None). A sequence held whole takes about
    0.6 GB a frame of the demo; stepped, a run of 100 frames fits in memory."""
    import numpy as np

    import radscene

    sim = radscene.Simulation(loaded, incremental=incremental)
    _schedule(sim, frames, look_ahead)
    times, kept = [], {}
    for k in range(frames):
        t = time.perf_counter()
        frame = sim.render() if k == 0 else sim.step(STEP)
        times.append(time.perf_counter() - t)
        if keep:
            for name, ds in frame.radiance.items():
                maps = kept.setdefault(name, {var: [] for var in
                                              ("radiance", "object_id", "material_id")})
                for var in maps:
                    maps[var].append(ds[var].values)
    if not keep:
        return times, None
    return times, {name: {var: np.stack(v) for var, v in maps.items()}
                   for name, maps in kept.items()}


def _largest_difference(a, b) -> float:
    """The largest relative difference of radiance between two sequences' frames
    (:func:`_kept_maps`) [-]; the label maps must match exactly (an error otherwise)."""
    import numpy as np

    worst = 0.0
    for name, maps in a.items():
        other = b[name]
        for var in ("object_id", "material_id"):
            if not np.array_equal(maps[var], other[var]):
                raise AssertionError(f"{name}: {var} differs between the sequences")
        x, y = maps["radiance"], other["radiance"]
        worst = max(worst, float(np.max(np.abs(x - y) / np.maximum(np.abs(x), 1e-30))))
    return worst


def run_sequence(args) -> dict:
    import radscene

    load_before = os.getloadavg()
    scene, base = demo_scene(args.frames)
    thermal, single = _single(scene, base)
    result = {"machine": machine(), "source": source_version(), "load_before": load_before,
              "look_ahead": not args.no_look_ahead,
              "step_s": STEP, "heat_balance_s": round(thermal, 2), "single_render_s": round(single, 3)}
    runs = {}
    if args.compare_key_frames:  # with key frames and without, their differences
        (keyed, every), errors = _lockstep(scene, base, args.frames, not args.no_look_ahead)
        result["sequence_key_frames"] = _frames(keyed, single)
        result["sequence_no_key_frames"] = _frames(every, single)
        result["key_frames_max_rel"] = {n: max(e[0] for e in v) for n, v in errors.items()}
        result["key_frames_p99_rel"] = {n: max(e[1] for e in v) for n, v in errors.items()}
        result["load_after_compare"] = os.getloadavg()
    for key, incremental in (("sequence", True), ("sequence_full_frames", False)):
        if key == "sequence_full_frames" and args.no_full_frames or (
                key == "sequence" and args.compare_key_frames):
            continue
        loaded = radscene.load_scene(scene, base_dir=base)
        times, runs[key] = _stepped(loaded, args.frames, incremental,
                                    keep=not args.no_full_frames,
                                    look_ahead=not args.no_look_ahead)
        result[key] = _frames(times, single)
        result[f"load_after_{key}"] = os.getloadavg()
        print(key, result[key], result[f"load_after_{key}"], flush=True)
    if args.single_after:  # the single render again, at the load the frames ran at
        _, after = _single(scene, base)
        result["single_render_after_s"] = round(after, 3)
        for key in ("sequence", "sequence_full_frames"):
            if key in result:
                result[key]["mean_over_single_after"] = round(
                    result[key]["frame_mean_s"] / after, 3)
    if len(runs) == 2 and None not in runs.values():
        result["incremental_vs_full_max_rel"] = _largest_difference(*runs.values())
    if args.realtime_frames:
        scene, base = demo_scene(args.realtime_frames, supersample=1)
        _, single1 = _single(scene, base)
        sim = radscene.Simulation(radscene.load_scene(scene, base_dir=base), realtime=True)
        times = []
        for k in range(args.realtime_frames):
            t0 = time.perf_counter()
            if k == 0:
                sim.render()
            else:
                sim.step(STEP)
            times.append(time.perf_counter() - t0)
        result.update({"single_render_supersample_1_s": round(single1, 3),
                       "realtime": _frames(times, single1)})
    result["load_after"] = os.getloadavg()
    return result


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
            render_observer(scene, setup.name, tables=tables)
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
    parser.add_argument("--refit", action="store_true",
                        help="refit against rebuild over the 1 M-triangle terrain, not the sequence")
    parser.add_argument("--quick", action="store_true", help="--refit: a 1/4-size terrain (62 k triangles)")
    parser.add_argument("--size", type=int, default=256, help="--refit: image side [pixels]")
    parser.add_argument("--sky-samples", type=int, default=16, help="--refit: sky samples")
    parser.add_argument("--frames", type=int, default=None,
                        help="frames of the sequence (default 100; --refit: 10)")
    parser.add_argument("--no-full-frames", action="store_true",
                        help="the incremental sequence only, not the one of full frames")
    parser.add_argument("--compare-key-frames", action="store_true",
                        help="the incremental sequence with key frames and without, stepped "
                        "together: each one's frame times and their largest differences")
    parser.add_argument("--no-look-ahead", action="store_true",
                        help="the frames between key frames extrapolated from the last two (as "
                        "the live step API makes them), not interpolated between the key frame "
                        "behind and one rendered ahead (as render_sequence makes them)")
    parser.add_argument("--single-after", action="store_true",
                        help="time the single render again after the sequences (the machine's "
                        "load may have changed while they ran)")
    parser.add_argument("--realtime-frames", type=int, default=100,
                        help="frames of the real-time part of the sequence (0: none)")
    args = parser.parse_args()
    if args.frames is None:
        args.frames = 10 if args.refit else 100
    if args.frames < 2 or args.realtime_frames == 1:
        parser.error("at least 2 frames (--realtime-frames 0: no real-time part)")
    result = run(args) if args.refit else run_sequence(args)
    OUT.mkdir(parents=True, exist_ok=True)
    name = "bench_motion_refit.json" if args.refit else "bench_motion.json"
    (OUT / name).write_text(json.dumps(result, indent=2))
    for key, value in result.items():
        if key not in ("machine", "source"):
            print(f"{key:>30}: {value}")


if __name__ == "__main__":
    main()
