"""Render benchmark: a nadir map of a ~1 M-triangle terrain, and the same rays traced bare.

The figures the project reports (``docs/benchmarks.md``):

* scene load time, render wall time, pixel·bands/s, rays traced (primary, shadow, sky,
  specular lobe, counted at the ray engine), rays/s, time spent inside the ray engine, peak
  resident memory of the render;
* the same kinds and numbers of rays traced *bare* through embreex (no radscene code in the
  loop; generating the rays is not timed), and the ratio render / bare;
* optionally the same scene rendered by Mitsuba 3 (``llvm_ad_rgb`` variant, ``direct``
  integrator) at equal noise: the time ratio and the per-band difference.

Targets (on 2 cores): render <= 2 s, and render <= 1.5 x bare.

Run ``python benchmarks/bench_render.py`` (``--quick`` for a 256 x 256 smoke run, ``--profile``
to write a cProfile of the render). Figures go to ``out/bench/bench_render.json``.
"""

from __future__ import annotations

import argparse
import cProfile
import datetime as _dt
import io
import json
import os
import platform
import pstats
import resource
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "bench"

#: Terrain extent [m] and sample spacing [m] of the full benchmark: 708 x 708 samples,
#: 2 x 707 x 707 = 999 698 triangles.
TERRAIN_SIZE = 3535.0
TERRAIN_SPACING = 5.0
#: Embree work unit, the same as radscene's RayTracer default [rays].
CHUNK = 65536

#: Eight bands from blue to LWIR (the demo scene's).
BANDS = [
    {"name": "blue", "min": 0.45, "max": 0.52},
    {"name": "green", "min": 0.52, "max": 0.60},
    {"name": "red", "min": 0.63, "max": 0.69},
    {"name": "nir", "min": 0.76, "max": 0.90},
    {"name": "swir1", "min": 1.55, "max": 1.75},
    {"name": "swir2", "min": 2.08, "max": 2.35},
    {"name": "mwir", "min": 3.0, "max": 5.0},
    {"name": "lwir", "min": 8.0, "max": 12.0},
]
#: Land cover (built-in, diffuse) and surface temperature of each [K].
COVER = {"green_vegetation": 297.0, "dry_grass": 303.0, "bare_soil": 306.0, "sand": 309.0}
#: Sun placed by hand: zenith, azimuth [deg].
SUN = (40.0, 135.0)
#: Uniform atmosphere (the demo scene's illustrative clear-sky spectra).
_WL = [0.4, 0.5, 0.6, 0.7, 0.9, 1.6, 2.2, 3.0, 4.0, 4.5, 5.0, 8.0, 10.0, 12.0, 20.0]
ATMOSPHERE = {
    "type": "uniform",
    "transmittance": {"wavelength": _WL, "values": [0.70, 0.78, 0.83, 0.87, 0.90, 0.94, 0.95,
                                                    0.70, 0.85, 0.55, 0.75, 0.80, 0.85, 0.75,
                                                    0.30]},
    "path_radiance": {"wavelength": _WL, "values": [40.0, 30.0, 20.0, 13.0, 7.0, 1.5, 0.5, 0.2,
                                                    0.1, 0.4, 0.3, 1.5, 1.2, 2.0, 4.0]},
    "sky_radiance": {"wavelength": _WL, "values": [60.0, 45.0, 30.0, 20.0, 10.0, 2.0, 0.8, 0.5,
                                                   0.3, 0.8, 0.6, 3.0, 2.0, 3.5, 5.0]},
    "sky_zenith": [0, 60, 85],
    "sky_profile": [1.0, 1.3, 2.0],
}


def scene_dict(size: int, sky_samples: int, terrain_size: float, lake: bool = False,
               seed: int = 1) -> dict:
    """The benchmark scene: procedural terrain, 8 bands, a fixed sun, one nadir map camera.

    The camera's ``size`` x ``size`` pixels tile the terrain exactly (every primary ray hits).
    """
    terrain = {
        "type": "procedural",
        "size": [terrain_size, terrain_size],
        "spacing": TERRAIN_SPACING,
        "relief": 0.04 * terrain_size,
        "seed": 7,
        "material_map": {"type": "noise", "materials": list(COVER), "scale": 150.0, "seed": 3},
        "temperature": 300.0,
        "temperatures": dict(COVER),
    }
    if lake:  # a flat specular water surface: adds specular-lobe rays
        terrain["lakes"] = [{"x": 0.3 * terrain_size, "y": 0.6 * terrain_size,
                             "radius": 0.08 * terrain_size, "depth": 3.0}]
        terrain["water_material"] = "water"
        terrain["temperatures"]["water"] = 295.0
    extent = round(terrain_size / TERRAIN_SPACING) * TERRAIN_SPACING
    return {
        "name": "bench_render",
        "environment": {
            "location": {"latitude": -25.75, "longitude": 27.86, "altitude": 1200.0},
            "sun": {"zenith": SUN[0], "azimuth": SUN[1]},
            "atmosphere": ATMOSPHERE,
        },
        "terrain": terrain,
        "bands": BANDS,
        "observers": [{
            "name": "nadir", "type": "orthographic", "center": [extent / 2, extent / 2],
            "gsd": extent / size, "shape": [size, size], "altitude": 8000.0, "supersample": 1,
        }],
        "render": {"sky_samples": sky_samples, "specular_samples": 16, "shadows": True,
                   "seed": seed},
    }


# ---------------------------------------------------------------------------------------------
# memory


def _reset_peak() -> bool:
    """Reset the process's peak resident set (Linux >= 4.0); False where that is refused."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def _peak_rss_mib() -> float:
    """Peak resident set since the last reset [MiB] (VmHWM; ru_maxrss where absent)."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


# ---------------------------------------------------------------------------------------------
# counting the rays of a render at the ray engine


class RayCounter:
    """Wraps ``RayTracer.intersect/occluded`` and the illumination queries to count rays.

    Rays are booked under the query that sent them: ``primary`` (intersect), ``shadow``
    (``cast_shadow``), ``sky`` (``sky_fractions``), ``lobe`` (``lobe_sky_fractions``). For each,
    the time inside the ray engine call and the time inside the whole query (ray generation,
    engine, reduction) are summed.
    """

    KINDS = ("primary", "shadow", "sky", "lobe")

    def __init__(self):
        self.rays = dict.fromkeys(self.KINDS, 0)
        self.calls = dict.fromkeys(self.KINDS, 0)
        self.engine_s = dict.fromkeys(self.KINDS, 0.0)
        self.query_s = dict.fromkeys(self.KINDS, 0.0)
        self._kind = None
        self._saved = []

    def _engine(self, method, kind_default):
        counter = self

        def wrapped(tracer, origins, directions, *args, **kwargs):
            kind = counter._kind or kind_default
            t0 = time.perf_counter()
            out = method(tracer, origins, directions, *args, **kwargs)
            counter.engine_s[kind] += time.perf_counter() - t0
            counter.rays[kind] += len(out)
            counter.calls[kind] += 1
            return out

        return wrapped

    def _query(self, function, kind):
        counter = self

        def wrapped(*args, **kwargs):
            counter._kind = kind
            t0 = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                counter.query_s[kind] += time.perf_counter() - t0
                counter._kind = None

        return wrapped

    def __enter__(self):
        from radscene.geometry import raytracer
        from radscene.render import illumination

        patches = [
            (raytracer.RayTracer, "intersect", self._engine(raytracer.RayTracer.intersect, "primary")),
            (raytracer.RayTracer, "occluded", self._engine(raytracer.RayTracer.occluded, "shadow")),
            (illumination, "cast_shadow", self._query(illumination.cast_shadow, "shadow")),
            (illumination, "sky_fractions", self._query(illumination.sky_fractions, "sky")),
            (illumination, "lobe_sky_fractions",
             self._query(illumination.lobe_sky_fractions, "lobe")),
        ]
        if hasattr(raytracer.RayTracer, "occluded_local"):  # the fast path for secondary rays
            patches.append((raytracer.RayTracer, "occluded_local",
                            self._engine(raytracer.RayTracer.occluded_local, "shadow")))
        for owner, name, new in patches:
            self._saved.append((owner, name, getattr(owner, name)))
            setattr(owner, name, new)
        return self

    def __exit__(self, *exc):
        for owner, name, old in reversed(self._saved):
            setattr(owner, name, old)
        self._saved.clear()
        return False

    @property
    def total(self) -> int:
        return sum(self.rays.values())


# ---------------------------------------------------------------------------------------------
# the same rays, bare


def _cosine_directions(normals, n_samples, rng):
    """``n_samples`` cosine-distributed unit directions about each normal: (N, n_samples, 3)."""
    n = len(normals)
    side = int(round(np.sqrt(n_samples)))
    if side * side == n_samples:  # stratified, as radscene does, rotated per point
        i, j = np.divmod(np.arange(n_samples), side)
        b1, b2 = (i + 0.5) / side, (j + 0.5) / side
    else:
        k = np.arange(n_samples)
        b1, b2 = (k + 0.5) / n_samples, (k * 0.6180339887498949) % 1.0
    shift = rng.random((n, 2))
    u1 = (b1[None, :] + shift[:, :1]) % 1.0
    u2 = (b2[None, :] + shift[:, 1:]) % 1.0
    r, phi = np.sqrt(u1), 2.0 * np.pi * u2
    local = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u1))], -1)
    # orthonormal frame about each normal (Duff et al. 2017, doi:10.1145/3095054)
    nz = normals
    sign = np.where(nz[:, 2] >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + nz[:, 2])
    b = nz[:, 0] * nz[:, 1] * a
    t = np.stack([1.0 + sign * nz[:, 0] ** 2 * a, sign * b, -sign * nz[:, 0]], -1)
    s = np.stack([b, sign + nz[:, 1] ** 2 * a, -nz[:, 1]], -1)
    return (local[..., :1] * t[:, None, :] + local[..., 1:2] * s[:, None, :]
            + local[..., 2:] * nz[:, None, :])


def _pool_map(threads, function, items):
    if threads == 1:
        return [function(x) for x in items]
    with ThreadPoolExecutor(max_workers=threads) as pool:
        return list(pool.map(function, items))


def bare_trace(mesh, image_size, sun_direction, sky_samples, robust=True, threads=None,
               seed=0) -> dict:
    """Trace primary, shadow and sky rays of a nadir map straight through embreex.

    Primary rays start just above the terrain (as radscene's tracer clips them to the scene
    box) and go straight down through the pixel centres; shadow rays leave each hit, offset
    along the normal, towards the sun where the sun is above the face; ``sky_samples``
    cosine-distributed rays per hit, those above the horizon, test for sky. Only the Embree
    calls are timed.
    """
    from embreex import mesh_construction, rtcore_scene

    threads = threads or os.cpu_count() or 1
    lo, hi = mesh.bounds
    center = 0.5 * (lo + hi)
    scene = rtcore_scene.EmbreeScene(robust=robust)
    mesh_construction.TriangleMesh(scene, (mesh.vertices - center).astype(np.float32),
                                   mesh.faces.astype(np.int32))
    scene.run(np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32))  # commit
    normals = mesh.face_normals
    epsilon = 1e-4 + 2e-6 * float(np.linalg.norm(hi - lo))
    timing = {}

    # primary: pixel centres over the terrain extent, straight down
    g = (np.arange(image_size) + 0.5) / image_size
    xx, yy = np.meshgrid(lo[0] + g * (hi[0] - lo[0]), hi[1] - g * (hi[1] - lo[1]))
    n = xx.size
    origins = np.column_stack([xx.ravel(), yy.ravel(), np.full(n, hi[2] + 1.0)]) - center
    down = np.broadcast_to(np.array([0.0, 0.0, -1.0]), (n, 3))
    chunks = [slice(s, min(s + CHUNK, n)) for s in range(0, n, CHUNK)]
    o32, d32 = origins.astype(np.float32), np.ascontiguousarray(down, dtype=np.float32)

    def primary(sl):
        return scene.run(o32[sl], d32[sl], output=1)

    t0 = time.perf_counter()
    results = _pool_map(threads, primary, chunks)
    timing["primary"] = time.perf_counter() - t0
    prim = np.concatenate([r["primID"] for r in results])
    tfar = np.concatenate([r["tfar"] for r in results]).astype(np.float64)
    hit = prim >= 0
    pos = origins[hit] + tfar[hit, None] * down[hit]
    nrm = normals[prim[hit]]
    start = pos + epsilon * nrm
    counts = {"primary": n}

    # shadow rays towards the sun, where it is above the face
    sun = np.asarray(sun_direction, dtype=float)
    facing = nrm @ sun > 0.0
    so = start[facing].astype(np.float32)
    sd = np.ascontiguousarray(np.broadcast_to(sun, so.shape), dtype=np.float32)
    counts["shadow"] = len(so)
    chunks = [slice(s, min(s + CHUNK, len(so))) for s in range(0, len(so), CHUNK)]

    def shadow(sl):
        return scene.run(so[sl], sd[sl], query="OCCLUDED")

    t0 = time.perf_counter()
    _pool_map(threads, shadow, chunks)
    timing["shadow"] = time.perf_counter() - t0

    # sky rays: generated first, per block of hits, then traced
    rng = np.random.default_rng(seed)
    blocks = []
    per_block = max(1, CHUNK // sky_samples)
    for s in range(0, len(start), per_block):
        dirs = _cosine_directions(nrm[s:s + per_block], sky_samples, rng)
        up = dirs[..., 2] > 0.0
        o = np.repeat(start[s:s + per_block, None, :], sky_samples, axis=1)[up]
        blocks.append((o.astype(np.float32), dirs[up].astype(np.float32)))
    counts["sky"] = sum(len(b[0]) for b in blocks)

    def sky(block):
        return scene.run(block[0], block[1], query="OCCLUDED")

    t0 = time.perf_counter()
    occluded = _pool_map(threads, sky, blocks)
    timing["sky"] = time.perf_counter() - t0
    sky_view = 1.0 - sum(int(np.count_nonzero(r >= 0)) for r in occluded) / max(counts["sky"], 1)
    total_s = sum(timing.values())
    total_rays = sum(counts.values())
    return {"rays": counts, "time_s": timing, "total_rays": total_rays, "total_s": total_s,
            "rays_per_s": total_rays / total_s, "threads": threads, "robust": robust,
            "mean_sky_view_of_samples": sky_view}


# ---------------------------------------------------------------------------------------------
# machine


def machine() -> dict:
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):
        mem = float("nan")
    import embreex
    import numpy

    return {"cpus": os.cpu_count(), "cpu_model": cpu, "ram_gib": round(mem, 1),
            "python": platform.python_version(), "numpy": numpy.__version__,
            "embreex": getattr(embreex, "__version__", "?"), "platform": platform.platform()}


# ---------------------------------------------------------------------------------------------


def _mean(ds, name):
    """Image mean of a truth layer, or None where this radscene version lacks it."""
    return float(ds[name].mean()) if name in ds else None


def run(args) -> dict:
    import radscene
    from radscene.render.integrator import sun_geometry

    terrain_size = args.terrain_size or (TERRAIN_SIZE * args.size / 1024 if args.quick
                                         else TERRAIN_SIZE)
    spec = scene_dict(args.size, args.sky_samples, terrain_size, lake=args.lake)
    report = {"date": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
              "machine": machine(), "command": " ".join([Path(sys.executable).name] + sys.argv),
              "settings": {"size": args.size, "sky_samples": args.sky_samples,
                           "terrain_size_m": terrain_size, "terrain_spacing_m": TERRAIN_SPACING,
                           "bands": len(BANDS), "lake": args.lake, "sun": SUN}}

    t0 = time.perf_counter()
    scene = radscene.load_scene(spec)
    load_s = time.perf_counter() - t0
    terrain = scene.objects[0].mesh
    n_tri = len(terrain.faces)
    print(f"scene: {len(terrain.vertices)} vertices, {n_tri} triangles; loaded in {load_s:.2f} s")

    # untimed warm-up on a small scene: first imports and JIT compilation (numba) are not timed
    t0 = time.perf_counter()
    radscene.render(radscene.load_scene(scene_dict(32, args.sky_samples, 200.0, args.lake)))
    report["warmup_s"] = time.perf_counter() - t0
    if args.warmup:
        radscene.render(scene, "nadir")
    _reset_peak()
    rss_before = _peak_rss_mib()
    with RayCounter() as counter:
        t0 = time.perf_counter()
        if args.profile:
            profiler = cProfile.Profile()
            ds = profiler.runcall(radscene.render, scene, "nadir")
        else:
            ds = radscene.render(scene, "nadir")
        render_s = time.perf_counter() - t0
    peak = _peak_rss_mib()
    n_pix = args.size * args.size
    render = {
        "wall_s": render_s,
        "pixel_bands_per_s": n_pix * len(BANDS) / render_s,
        "rays": dict(counter.rays), "total_rays": counter.total,
        "rays_per_s": counter.total / render_s,
        "engine_s": dict(counter.engine_s), "engine_total_s": sum(counter.engine_s.values()),
        "query_s": dict(counter.query_s), "engine_calls": dict(counter.calls),
        "peak_rss_mib": peak, "rss_at_start_mib": rss_before,
        "mean_radiance": [float(x) for x in ds["radiance"].mean(("y", "x")).values],
        "mean_sky_view": _mean(ds, "sky_view_fraction"),
        "mean_shadow_fraction": _mean(ds, "shadow_fraction"),
    }
    report["load_s"] = load_s
    report["triangles"] = n_tri
    report["render"] = render
    if args.profile:
        OUT.mkdir(parents=True, exist_ok=True)
        profiler.dump_stats(OUT / "render.prof")
        for key in ("cumulative", "tottime"):
            text = io.StringIO()
            pstats.Stats(profiler, stream=text).sort_stats(key).print_stats(30)
            (OUT / f"render_profile_{key}.txt").write_text(text.getvalue())
        print(f"profile: {OUT / 'render.prof'}, render_profile_{{cumulative,tottime}}.txt")

    sun = sun_geometry(scene)
    bare = bare_trace(terrain, args.size, sun.direction, args.sky_samples,
                      threads=args.threads, seed=1)
    report["bare"] = bare
    report["render_over_bare"] = render_s / bare["total_s"]
    report["targets"] = {"render_wall_s_max": 2.0, "render_over_bare_max": 1.5,
                         "wall_met": render_s <= 2.0,
                         "ratio_met": report["render_over_bare"] <= 1.5}
    del ds
    if args.mitsuba:
        from bench_mitsuba import compare  # noqa: PLC0415  (optional, beside this file)

        report["mitsuba"] = compare(scene, spec, args)
    return report


def print_table(r: dict) -> None:
    ren, bare = r["render"], r["bare"]
    rows = [
        ("triangles", f"{r['triangles']:,}"),
        ("image", f"{r['settings']['size']} x {r['settings']['size']} x "
                  f"{r['settings']['bands']} bands"),
        ("scene load", f"{r['load_s']:.2f} s"),
        ("render wall", f"{ren['wall_s']:.2f} s"),
        ("pixel·bands/s", f"{ren['pixel_bands_per_s'] / 1e6:.2f} M"),
        ("rays (render)", "  ".join(f"{k} {v / 1e6:.2f} M" for k, v in ren["rays"].items())),
        ("rays total / rays/s", f"{ren['total_rays'] / 1e6:.2f} M / "
                                f"{ren['rays_per_s'] / 1e6:.2f} M/s"),
        ("time in ray engine", f"{ren['engine_total_s']:.2f} s ("
         + "  ".join(f"{k} {v:.2f}" for k, v in ren["engine_s"].items()) + ")"),
        ("time in queries", "  ".join(f"{k} {v:.2f} s" for k, v in ren["query_s"].items())),
        ("peak RSS (render)", f"{ren['peak_rss_mib']:.0f} MiB (at start {ren['rss_at_start_mib']:.0f})"),
        ("bare embreex", f"{bare['total_s']:.2f} s for {bare['total_rays'] / 1e6:.2f} M rays = "
                         f"{bare['rays_per_s'] / 1e6:.2f} M/s on {bare['threads']} threads"),
        ("bare by kind", "  ".join(f"{k} {bare['time_s'][k]:.2f} s/{bare['rays'][k] / 1e6:.2f} M"
                                   for k in bare["rays"])),
        ("render / bare", f"{r['render_over_bare']:.2f}"),
        ("target wall <= 2 s", "met" if r["targets"]["wall_met"] else "NOT met"),
        ("target ratio <= 1.5", "met" if r["targets"]["ratio_met"] else "NOT met"),
    ]
    mit = r.get("mitsuba")
    if mit:
        for k, v in mit.get("table", {}).items():
            rows.append((k, v))
    width = max(len(k) for k, _ in rows)
    for k, v in rows:
        print(f"{k:<{width}}  {v}")


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
    parser.add_argument("--profile", action="store_true", help="cProfile the render")
    parser.add_argument("--no-mitsuba", dest="mitsuba", action="store_false",
                        help="skip the Mitsuba 3 comparison")
    parser.add_argument("--output", type=Path, default=OUT / "bench_render.json")
    args = parser.parse_args(argv)
    if args.quick:
        args.size = 256
    for name in ("size", "sky_samples"):
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
