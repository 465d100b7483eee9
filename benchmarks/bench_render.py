"""Render benchmark: a nadir map of a ~1 M-triangle terrain, and the same rays traced bare.

The figures the project reports (``docs/benchmarks.md``):

* scene load time, render wall time, pixel·bands/s, rays traced (primary, shadow, sky,
  specular lobe, counted at the ray engine), rays/s, time spent inside the ray engine, peak
  resident memory of the render;
* the same kinds and numbers of rays traced *bare* through embreex (no radscene code in the
  loop; generating the rays is not timed), and the ratio render / bare;
* optionally the same scene rendered by Mitsuba 3 (``llvm_ad_rgb`` variant, ``direct``
  integrator) at equal noise: the time ratio and the per-band difference;
* where the render's time goes: one more render with the integrator's helpers timed
  (``--no-breakdown`` skips it), and with ``--profile`` a cProfile of one more.

Targets (on 2 cores): render <= 2 s, and render <= 1.5 x bare.

Run ``python benchmarks/bench_render.py`` (``--quick`` for a 256 x 256 smoke run; ``--help``
lists the options). Figures go to ``out/bench/bench_render.json``.
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as _dt
import io
import json
import os
import pstats
import sys
import time
from pathlib import Path

import numpy as np
from render_bench import OUT
from render_bench.bare import BareTrace
from render_bench.mitsuba import mitsuba_compare
from render_bench.report import machine, print_table, source_version
from render_bench.scene import (
    ATMOSPHERES,
    BANDS,
    SUN,
    TERRAIN_SIZE,
    TERRAIN_SPACING,
    scene_dict,
)
from render_bench.timing import AtmosphereTimer, PhaseTimer, RayCounter, peak_rss_mib, reset_peak


def _mean(ds, name):
    """Image mean of a truth layer, or None where this radscene version lacks it."""
    return float(ds[name].mean()) if name in ds else None


def run(args) -> dict:
    import radscene
    from radscene.render import sun_geometry

    terrain_size = args.terrain_size or (TERRAIN_SIZE * args.size / 1024 if args.quick
                                         else TERRAIN_SIZE)
    spec = scene_dict(args.size, args.sky_samples, terrain_size, lake=args.lake,
                      atmosphere=args.atmosphere)
    report = {"date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
              "load_average_at_start": os.getloadavg(), "radscene": source_version(),
              "machine": machine(), "command": " ".join([Path(sys.executable).name] + sys.argv),
              "settings": {"size": args.size, "sky_samples": args.sky_samples,
                           "terrain_size_m": terrain_size, "terrain_spacing_m": TERRAIN_SPACING,
                           "bands": len(BANDS), "lake": args.lake, "sun": SUN,
                           "atmosphere": args.atmosphere}}

    t0 = time.perf_counter()
    scene = radscene.load_scene(spec)
    load_s = time.perf_counter() - t0
    terrain = scene.objects[0].mesh
    n_tri = len(terrain.faces)
    print(f"scene: {len(terrain.vertices)} vertices, {n_tri} triangles; loaded in {load_s:.2f} s")

    # untimed warm-up on a small scene: first imports and JIT compilation (numba) are not timed
    t0 = time.perf_counter()
    radscene.render(radscene.load_scene(scene_dict(32, args.sky_samples, 200.0, args.lake,
                                                   atmosphere=args.atmosphere)))
    report["warmup_s"] = time.perf_counter() - t0
    if args.warmup:
        radscene.render(scene, "nadir")

    # the headline: `repeat` rounds of one timed render (counting its rays) and one bare trace
    # of the same rays, interleaved so that each ratio compares like conditions
    sun = sun_geometry(scene)
    bare_tracer = BareTrace(terrain, args.size, sun.direction, args.sky_samples,
                            threads=args.threads, seed=1)
    n_pix = args.size * args.size
    runs, bares = [], []
    ds = None
    for _ in range(args.repeat):
        ds = None
        reset_peak()
        rss_start = peak_rss_mib()
        with RayCounter() as counter:
            cpu0, t0 = time.process_time(), time.perf_counter()
            ds = radscene.render(scene, "nadir")
            wall = time.perf_counter() - t0
            cpu = time.process_time() - cpu0
        runs.append({"wall_s": wall, "cpu_s": cpu, "rays": dict(counter.rays),
                     "total_rays": counter.total, "engine_s": dict(counter.engine_s),
                     "query_s": dict(counter.query_s), "engine_calls": dict(counter.calls),
                     "peak_rss_mib": peak_rss_mib(), "rss_at_start_mib": rss_start})
        bares.append(bare_tracer.run())
    order = np.argsort([r["wall_s"] for r in runs])
    median = runs[order[len(runs) // 2]]
    render_s = median["wall_s"]
    render = {
        **median,
        "walls_s": [r["wall_s"] for r in runs],
        "cpu_s_all": [r["cpu_s"] for r in runs],
        "pixel_bands_per_s": n_pix * len(BANDS) / render_s,
        "rays_per_s": median["total_rays"] / render_s,
        "engine_total_s": sum(median["engine_s"].values()),
        "peak_rss_mib": max(r["peak_rss_mib"] for r in runs),
        "mean_radiance": [float(x) for x in ds["radiance"].mean(("y", "x")).values],
        "mean_sky_view": _mean(ds, "sky_view_fraction"),
        "mean_shadow_fraction": _mean(ds, "shadow_fraction"),
    }
    bare = sorted(bares, key=lambda r: r["total_s"])[len(bares) // 2]
    bare["totals_s"] = [b["total_s"] for b in bares]
    ratios = [r["wall_s"] / b["total_s"] for r, b in zip(runs, bares, strict=True)]
    if all("packets_total_s" in b for b in bares):
        report["render_over_bare_packets_each"] = [
            r["wall_s"] / b["packets_total_s"] for r, b in zip(runs, bares, strict=True)]
        report["render_over_bare_packets"] = float(np.median(
            report["render_over_bare_packets_each"]))
    report["load_s"] = load_s
    report["triangles"] = n_tri
    report["render"] = render

    # where the time goes: one more render with the integrator's helpers timed
    if args.breakdown:
        with RayCounter() as counter, PhaseTimer() as phases:
            t0 = time.perf_counter()
            radscene.render(scene, "nadir")
            wall = time.perf_counter() - t0
        report["breakdown"] = {"wall_s": wall, "engine_s": dict(counter.engine_s),
                               "seconds": phases.seconds, "calls": phases.calls}
    # the atmospheric look-ups: one more render with the engine's queries and the per-sample
    # node interpolation timed
    with AtmosphereTimer(type(scene.atmosphere)) as atm_timer:
        t0, cpu0 = time.perf_counter(), time.process_time()
        radscene.render(scene, "nadir")
        wall, cpu = time.perf_counter() - t0, time.process_time() - cpu0
    # the share is taken of the headline (untimed) render's median wall time: the timer's
    # repeated calls lengthen its own render
    lookups = (atm_timer.seconds["queries"] + atm_timer.seconds["mixing"]
               + atm_timer.seconds["sky_fold"])
    report["atmosphere"] = {"engine": scene.atmosphere.name, "timed_render_wall_s": wall,
                            "timed_render_cpu_s": cpu, "wall_s": render_s,
                            "seconds": dict(atm_timer.seconds), "calls": dict(atm_timer.calls),
                            "seconds_by_function": dict(atm_timer.by_function),
                            "lookup_s": lookups, "lookup_fraction": lookups / render_s,
                            "lookup_fraction_max": 0.15,
                            "lookup_met": lookups / render_s <= 0.15}
    if args.profile:
        profiler = cProfile.Profile()
        profiler.runcall(radscene.render, scene, "nadir")
        OUT.mkdir(parents=True, exist_ok=True)
        profiler.dump_stats(OUT / "render.prof")
        for key in ("cumulative", "tottime"):
            text = io.StringIO()
            pstats.Stats(profiler, stream=text).sort_stats(key).print_stats(30)
            (OUT / f"render_profile_{key}.txt").write_text(text.getvalue())
        print(f"profile: {OUT / 'render.prof'}, render_profile_{{cumulative,tottime}}.txt")

    report["bare"] = bare
    report["render_over_bare_each"] = ratios
    report["render_over_bare"] = float(np.median(ratios))
    applies = args.size == 1024 and args.sky_samples == 16 and n_tri >= 900_000
    report["targets"] = {"render_wall_s_max": 2.0, "render_over_bare_max": 1.5,
                         "cores": 2, "apply": applies,
                         "wall_met": render_s <= 2.0,
                         "ratio_met": report["render_over_bare"] <= 1.5}
    if args.mitsuba:
        extent = round(terrain_size / TERRAIN_SPACING) * TERRAIN_SPACING
        mit = mitsuba_compare(scene, ds, args, args.size, extent / args.size, terrain_size)
        if "wall_s" in mit:
            mit["radscene_over_mitsuba"] = render_s / mit["wall_s"]
        report["mitsuba"] = mit
    del ds
    return report


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=1024, help="image side [pixels]")
    parser.add_argument("--sky-samples", type=int, default=16, help="sky rays per pixel")
    parser.add_argument("--terrain-size", type=float, default=None,
                        help=f"terrain side [m]; default {TERRAIN_SIZE:g} (scaled with --quick)")
    parser.add_argument("--quick", action="store_true", help="256 x 256 smoke run")
    parser.add_argument("--lake", action="store_true",
                        help="add a specular lake (specular-lobe rays; no Mitsuba comparison)")
    parser.add_argument("--threads", type=int, default=None, help="bare-trace threads")
    parser.add_argument("--warmup", action="store_true",
                        help="also render the full scene once, untimed, before timing")
    parser.add_argument("--repeat", type=int, default=3,
                        help="timed renders and bare traces; the median is reported")
    parser.add_argument("--no-breakdown", dest="breakdown", action="store_false",
                        help="skip the extra render that times the integrator's helpers")
    parser.add_argument("--profile", action="store_true",
                        help="cProfile one more render into out/bench/render_profile_*.txt")
    parser.add_argument("--atmosphere", choices=sorted(ATMOSPHERES), default="uniform",
                        help="the scene's atmosphere: the illustrative uniform one, or the "
                             "shipped database (then no Mitsuba comparison)")
    parser.add_argument("--no-mitsuba", dest="mitsuba", action="store_false",
                        help="skip the Mitsuba 3 comparison")
    parser.add_argument("--output", type=Path, default=OUT / "bench_render.json")
    args = parser.parse_args(argv)
    if args.quick:
        args.size = 256
    if args.atmosphere != "uniform":  # the Mitsuba twin needs one path node (band_inputs)
        args.mitsuba = False
    for name in ("size", "sky_samples", "repeat"):
        if getattr(args, name) < 1:
            parser.error(f"--{name.replace('_', '-')} must be >= 1")
    report = run(args)
    print_table(report)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.write_text(json.dumps(report, indent=2, default=float))
    print(f"figures: {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
