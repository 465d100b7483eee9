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
#: Sun placed by hand: zenith, azimuth [deg] (a morning sun: hills cast shadows).
SUN = (60.0, 135.0)
#: Peak-to-trough relief of the hills as a fraction of the terrain side (354 m on 3.5 km:
#: about 4 % of the image in shadow, mean sky view 0.94).
RELIEF = 0.1
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
#: The shipped atmospheric database under the demo scene's conditions (``--atmosphere database``).
DATABASE_ATMOSPHERE = {"type": "database", "profile": "midlatitude_summer", "aerosol": "rural",
                       "visibility": "23 km"}
ATMOSPHERES = {"uniform": ATMOSPHERE, "database": DATABASE_ATMOSPHERE}


def scene_dict(size: int, sky_samples: int, terrain_size: float, lake: bool = False,
               seed: int = 1, atmosphere: str = "uniform") -> dict:
    """The benchmark scene: procedural terrain, 8 bands, a fixed sun, one nadir map camera.

    The camera's ``size`` x ``size`` pixels tile the terrain exactly (every primary ray hits).
    """
    terrain = {
        "type": "procedural",
        "size": [terrain_size, terrain_size],
        "spacing": TERRAIN_SPACING,
        "relief": RELIEF * terrain_size,
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
            "atmosphere": ATMOSPHERES[atmosphere],
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

    def _kernel(self, function, kind_default):
        """A packet kernel that traces its own rays (a fan's, generated and folded; every
        hit's shadow ray): it returns its ray count (first of a pair); its whole time is
        booked as engine time."""
        counter = self

        def wrapped(*args, **kwargs):
            kind = counter._kind or kind_default
            t0 = time.perf_counter()
            out = function(*args, **kwargs)
            counter.engine_s[kind] += time.perf_counter() - t0
            counter.rays[kind] += int(out[0] if isinstance(out, tuple) else out)
            counter.calls[kind] += 1
            return out

        return wrapped

    def __enter__(self):
        from radscene.geometry import raytracer
        from radscene.render import illumination, kernels

        patches = [
            (raytracer.RayTracer, "intersect",
             self._engine(raytracer.RayTracer.intersect, "primary")),
            (raytracer.RayTracer, "occluded", self._engine(raytracer.RayTracer.occluded, "shadow")),
            (illumination, "cast_shadow", self._query(illumination.cast_shadow, "shadow")),
            (illumination, "sky_fractions", self._query(illumination.sky_fractions, "sky")),
            (illumination, "sky_sums", self._query(illumination.sky_sums, "sky")),
            (illumination, "lobe_sky_fractions",
             self._query(illumination.lobe_sky_fractions, "lobe")),
        ]
        for name, kind in (("packet_sky_sums", "sky"), ("packet_fractions", "sky"),
                           ("packet_shadows", "shadow")):  # rays traced inside kernels
            if hasattr(kernels, name):
                patches.append((kernels, name, self._kernel(getattr(kernels, name), kind)))
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


class _TimedNumpy:
    """Stands in for ``numpy`` in one module's namespace, timing a few of its functions."""

    def __init__(self, timer, names):
        for name in names:
            setattr(self, name, timer.wrap(getattr(np, name), f"np.{name}"))

    def __getattr__(self, name):
        return getattr(np, name)


class PhaseTimer:
    """Inclusive wall time and calls of the integrator's helpers during one render.

    Wraps, where they exist (the integrator is being optimised and names move): the scene
    tables (ray-engine build), the camera's rays, the band setup, the coefficient gathers, the
    emission, textures, the signature-term functions, the illumination queries, the dataset
    assembly, and ``np.bincount`` / ``np.einsum`` as the integrator calls them. Times are
    inclusive (a query's time contains its ray-engine time); what no wrapper covers is the
    integrator's own inline numpy.
    """

    INTEGRATOR = ("_SceneTables", "_BandSetup", "_emission_pairs", "_surface", "_textures",
                  "_geolocation", "_dataset", "_subset_nodes", "_central_subsample",
                  "_pixel_sums")
    NUMPY = ("bincount", "einsum", "vstack", "stack", "concatenate")

    def __init__(self):
        self.seconds = {}
        self.calls = {}
        self._saved = []

    def wrap(self, function, label):
        timer = self

        def wrapped(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                timer.seconds[label] = timer.seconds.get(label, 0.0) + time.perf_counter() - t0
                timer.calls[label] = timer.calls.get(label, 0) + 1

        return wrapped

    def _patch(self, owner, name, label):
        old = getattr(owner, name, None)
        if old is None:
            return
        self._saved.append((owner, name, old))
        setattr(owner, name, self.wrap(old, label))

    def __enter__(self):
        from radscene.platform import cameras
        from radscene.render import illumination, integrator, node_mixing, terms

        for name in self.INTEGRATOR:
            self._patch(integrator, name, name)
        self._patch(node_mixing, "mix_terms", "node_mixing.mix_terms")
        for name in getattr(terms, "__all__", ()):
            if callable(getattr(terms, name, None)):
                self._patch(terms, name, f"terms.{name}")
        for name in ("cast_shadow", "sky_fractions", "sky_sums", "lobe_sky_fractions"):
            self._patch(illumination, name, f"illumination.{name}")
        for cls in (cameras.OrthographicCamera, cameras.PerspectiveCamera):
            self._patch(cls, "rays", "camera.rays")
        self._saved.append((integrator, "np", integrator.np))
        integrator.np = _TimedNumpy(self, self.NUMPY)
        return self

    def __exit__(self, *exc):
        for owner, name, old in reversed(self._saved):
            setattr(owner, name, old)
        self._saved.clear()
        return False


class AtmosphereTimer:
    """Wall time of one render's atmospheric look-ups.

    ``queries``: calls of the scene atmosphere's engine (``path``, ``sun``, ``sky``,
    ``path_nodes``, ``with_sun``; nested calls count once). ``mixing``: the renderer's per-sample
    interpolation between path and sky nodes: in ``node_mixing.mix_terms``, which also forms
    the terms, its time less that of the same call with one path node per hit (the rest is
    counted as ``terms``); the integrator's ``_gather_band``, ``_sky_sum``, ``_subset_nodes``,
    ``sky_node_weights`` whole. ``sky_fold``: ``kernels.fold_sky_sums`` (``packet_sky_sums``) on the secondary-ray
    thread, which folds each point's sky rays onto the atmosphere's sky nodes and sums the band
    sky tables over them: only the sums are a look-up. Each call is repeated with no bands (the
    fold alone); the difference is counted as ``sky_fold``, and the repeat's time as ``extra``,
    which the caller takes off the render's wall time. ``band_tables``: the band integration of the node
    spectra with the materials (``_BandSetup``, ``_emission_pairs``), inclusive of the queries
    it makes. Nesting is counted per thread.
    """

    QUERIES = ("path", "sun", "sky", "path_nodes", "with_sun")
    MIXING = ("_gather_band", "_sky_sum", "_subset_nodes", "sky_node_weights")
    TABLES = ("_BandSetup", "_emission_pairs")

    def __init__(self, engine_class):
        import threading

        self.engine_class = engine_class
        self.seconds = {"queries": 0.0, "mixing": 0.0, "sky_fold": 0.0, "band_tables": 0.0,
                        "extra": 0.0}
        self.by_function = {}
        self.calls = {}
        self._local = threading.local()
        self._lock = threading.Lock()
        self._saved = []

    def _wrap(self, function, group, label):
        """Time ``function`` under ``group``: queries and mixing once however deeply nested;
        the band tables inclusively (the queries they make are counted there too)."""
        timer = self
        nests = group != "band_tables"

        def wrapped(*args, **kwargs):
            depth = getattr(timer._local, "depth", 0)
            outer = depth == 0 or not nests
            timer._local.depth = depth + nests
            t0 = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                timer._local.depth = depth
                dt = time.perf_counter() - t0
                with timer._lock:
                    if outer:
                        timer.seconds[group] += dt
                        timer.by_function[label] = timer.by_function.get(label, 0.0) + dt
                    timer.calls[label] = timer.calls.get(label, 0) + 1

        return wrapped

    def _sky_fold(self, function):
        """``kernels.fold_sky_sums``, timed with and without its band sums; or
        ``kernels.packet_sky_sums``, which also traces the fans: there the band sums are timed
        apart, on the fractions of the same fans (``node_mixing._mix_sky``, the same sums)."""
        timer = self
        packet = function.__name__ == "packet_sky_sums"

        def wrapped(*args):
            from radscene.render import kernels, node_mixing

            t0 = time.perf_counter()
            result = function(*args)
            t1 = time.perf_counter()
            *head, table, sums, view = args
            if packet:
                (packets, position, normal, center, epsilon, shift, base, side, zen, az, rank,
                 material, index, weight) = head
                fractions = np.empty((len(position), zen.size * az.size))
                kernels.packet_fractions(packets, position, normal, normal, np.zeros(0), False,
                                         center, epsilon, shift, base, side, False, zen, az,
                                         fractions)
                idx, w = np.ascontiguousarray(index[rank]), np.ascontiguousarray(weight[rank])
                out = np.empty_like(sums)
                t2 = time.perf_counter()
                node_mixing._mix_sky(table, material, idx, w, fractions, out)
                t3 = time.perf_counter()
                fold, extra = t3 - t2, t3 - t1
            else:
                no_bands = np.empty(table.shape[:2] + (0,) + table.shape[3:])
                function(*head, no_bands, np.empty((len(sums), 0)), np.empty_like(view))
                t2 = time.perf_counter()
                fold, extra = max(0.0, (t1 - t0) - (t2 - t1)), t2 - t1
            with timer._lock:
                timer.seconds["sky_fold"] += fold
                timer.seconds["extra"] += extra
                timer.calls["fold_sky_sums"] = timer.calls.get("fold_sky_sums", 0) + 1
            return result

        return wrapped

    def _mix(self, function):
        """``node_mixing.mix_terms``, timed as given and again with one path node per hit
        (into scratch outputs): the difference is the interpolation between path nodes."""
        timer = self

        def wrapped(out, transmittance_out, pixel, pixel_weight, rank, material, pair, index,
                    weight, **kw):
            t0 = time.perf_counter()
            function(out, transmittance_out, pixel, pixel_weight, rank, material, pair, index,
                     weight, **kw)
            t1 = time.perf_counter()
            mixing, extra = 0.0, 0.0
            if np.shape(index)[1] > 1:
                one = np.ascontiguousarray(np.asarray(index)[:, :1])
                function(np.empty_like(out), np.empty_like(transmittance_out), pixel,
                         pixel_weight, rank, material, pair, one, np.ones(one.shape), **kw)
                extra = time.perf_counter() - t1
                mixing = max(0.0, (t1 - t0) - extra)
            with timer._lock:
                timer.seconds["mixing"] += mixing
                timer.seconds["terms"] = timer.seconds.get("terms", 0.0) + (t1 - t0) - mixing
                timer.seconds["extra"] += extra
                timer.calls["mix_terms"] = timer.calls.get("mix_terms", 0) + 1

        return wrapped

    def __enter__(self):
        from radscene.render import integrator, node_mixing

        targets = [(self.engine_class, n, "queries") for n in self.QUERIES]
        targets += [(integrator, n, "mixing") for n in self.MIXING]
        self._saved.append((node_mixing, "mix_terms", node_mixing.mix_terms))
        node_mixing.mix_terms = self._mix(node_mixing.mix_terms)

        for owner, name, group in targets:
            old = owner.__dict__.get(name) if isinstance(owner, type) else getattr(owner, name,
                                                                                   None)
            if old is None and isinstance(owner, type):  # inherited: patch on the class itself
                old = getattr(owner, name, None)
                self._saved.append((owner, name, None))
            elif old is not None:
                self._saved.append((owner, name, old))
            if old is not None:
                setattr(owner, name, self._wrap(old, group, name))
        from radscene.render import kernels

        for name in ("fold_sky_sums", "packet_sky_sums"):
            if hasattr(kernels, name):
                self._saved.append((kernels, name, getattr(kernels, name)))
                setattr(kernels, name, self._sky_fold(getattr(kernels, name)))
        for name in self.TABLES:  # inclusive: their queries are counted there too
            old = getattr(integrator, name, None)
            if old is not None:
                self._saved.append((integrator, name, old))
                setattr(integrator, name, self._wrap(old, "band_tables", name))
        return self

    def __exit__(self, *exc):
        for owner, name, old in reversed(self._saved):
            if old is None:
                delattr(owner, name)
            else:
                setattr(owner, name, old)
        self._saved.clear()
        return False


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


class BareTrace:
    """The render's rays, traced straight through embreex: the floor the render is held to.

    Primary rays start just above the terrain (radscene's tracer clips them to the scene box)
    and go straight down through the pixel centres; shadow rays leave each hit, offset along
    the normal, towards the sun where the sun is above the face; ``sky_samples``
    cosine-distributed rays per hit, those above the horizon, test for sky. Everything —
    Embree scene, BVH, all rays as float32 — is prepared once; :meth:`run` times only the
    Embree calls, on ``threads`` threads over chunks of :data:`CHUNK` rays.
    """

    def __init__(self, mesh, image_size, sun_direction, sky_samples, robust=True,
                 threads=None, seed=0):
        from embreex import mesh_construction, rtcore_scene

        self.threads = threads or os.cpu_count() or 1
        self.robust = robust
        lo, hi = mesh.bounds
        center = 0.5 * (lo + hi)
        t0 = time.perf_counter()
        self.scene = rtcore_scene.EmbreeScene(robust=robust)
        mesh_construction.TriangleMesh(self.scene, (mesh.vertices - center).astype(np.float32),
                                       mesh.faces.astype(np.int32))
        self.scene.run(np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32))
        self.build_s = time.perf_counter() - t0
        epsilon = 1e-4 + 2e-6 * float(np.linalg.norm(hi - lo))

        # primary: pixel centres over the terrain extent, straight down
        g = (np.arange(image_size) + 0.5) / image_size
        xx, yy = np.meshgrid(lo[0] + g * (hi[0] - lo[0]), hi[1] - g * (hi[1] - lo[1]))
        n = xx.size
        origins = np.column_stack([xx.ravel(), yy.ravel(), np.full(n, hi[2] + 1.0)]) - center
        down = np.broadcast_to(np.array([0.0, 0.0, -1.0]), (n, 3))
        self.primary = self._chunked(origins.astype(np.float32), down.astype(np.float32))
        results = [self.scene.run(o, d, output=1) for o, d in self.primary]
        prim = np.concatenate([r["primID"] for r in results])
        tfar = np.concatenate([r["tfar"] for r in results]).astype(np.float64)
        hit = prim >= 0
        nrm = mesh.face_normals[prim[hit]]
        start = origins[hit] + tfar[hit, None] * down[hit] + epsilon * nrm

        # shadow rays towards the sun, where it is above the face
        sun = np.asarray(sun_direction, dtype=float)
        so = start[nrm @ sun > 0.0]
        self.shadow = self._chunked(so.astype(np.float32),
                                    np.broadcast_to(sun, so.shape).astype(np.float32))
        # sky rays, per block of hits
        rng = np.random.default_rng(seed)
        self.sky = []
        per_block = max(1, CHUNK // sky_samples)
        for s in range(0, len(start), per_block):
            dirs = _cosine_directions(nrm[s:s + per_block], sky_samples, rng)
            up = dirs[..., 2] > 0.0
            o = np.repeat(start[s:s + per_block, None, :], sky_samples, axis=1)[up]
            self.sky.append((o.astype(np.float32), dirs[up].astype(np.float32)))
        self.rays = {"primary": n, "shadow": len(so), "sky": sum(len(b[0]) for b in self.sky)}
        # the same occlusion rays as Embree packets of eight, where radscene uses them
        from radscene.geometry import embree

        self.packets = None
        if embree.packets_available():
            self.packets = embree.PacketScene([(mesh.vertices - center).astype(np.float32)],
                                              [mesh.faces], robust)
            self.packet_rays = {
                "shadow": tuple(np.concatenate(x) for x in zip(*self.shadow, strict=True)),
                "sky": tuple(np.concatenate(x) for x in zip(*self.sky, strict=True))}
            self.packets.occluded(self.packet_rays["sky"][0][:64], self.packet_rays["sky"][1][:64])

    @staticmethod
    def _chunked(o, d):
        return [(o[s:s + CHUNK], np.ascontiguousarray(d[s:s + CHUNK]))
                for s in range(0, len(o), CHUNK)]

    def run(self) -> dict:
        """Trace all rays once; returns the timings [s] and counts."""
        scene = self.scene
        work = {"primary": (self.primary, lambda c: scene.run(c[0], c[1], output=1)),
                "shadow": (self.shadow, lambda c: scene.run(c[0], c[1], query="OCCLUDED")),
                "sky": (self.sky, lambda c: scene.run(c[0], c[1], query="OCCLUDED"))}
        timing = {}
        for kind, (chunks, call) in work.items():
            t0 = time.perf_counter()
            _pool_map(self.threads, call, chunks)
            timing[kind] = time.perf_counter() - t0
        total_s = sum(timing.values())
        total_rays = sum(self.rays.values())
        out = {"rays": dict(self.rays), "time_s": timing, "total_rays": total_rays,
               "total_s": total_s, "rays_per_s": total_rays / total_s, "threads": self.threads,
               "robust": self.robust, "bvh_build_s": self.build_s}
        if self.packets is not None:  # primary rays as above; occlusion as packets
            packet = {"primary": timing["primary"]}
            for kind, (o, d) in self.packet_rays.items():
                t0 = time.perf_counter()
                self.packets.occluded(o, d)
                packet[kind] = time.perf_counter() - t0
            out["packets_time_s"] = packet
            out["packets_total_s"] = sum(packet.values())
        return out


# ---------------------------------------------------------------------------------------------
# Mitsuba 3 comparison

#: Mitsuba variant: CPU (Dr.Jit LLVM backend), three channels per pass (three bands at a time).
MITSUBA_VARIANT = "llvm_ad_rgb"
#: Window used to measure per-pixel noise (centre of the image) [pixels].
NOISE_WINDOW = 256
#: Largest sample count the equal-noise search may ask of Mitsuba [samples per pixel].
MITSUBA_MAX_SPP = 1024

_PROBE = """
import mitsuba as mi, numpy as np
mi.set_variant({variant!r})
T = mi.ScalarTransform4f
scene = mi.load_dict({{"type": "scene",
    "integrator": {{"type": "direct", "emitter_samples": 1, "bsdf_samples": 0}},
    "sun": {{"type": "directional", "direction": [0, 0, -1],
             "irradiance": {{"type": "rgb", "value": 3.14159265}}}},
    "floor": {{"type": "rectangle", "to_world": T().scale([10, 10, 1]),
               "bsdf": {{"type": "diffuse", "reflectance": {{"type": "rgb", "value": 0.5}}}}}},
    "sensor": {{"type": "orthographic",
                "to_world": T().look_at(origin=[0, 0, 100], target=[0, 0, 0], up=[0, 1, 0])
                            @ T().scale([10, 10, 1]),
                "sampler": {{"type": "stratified", "sample_count": 1, "jitter": False}},
                "film": {{"type": "hdrfilm", "width": 8, "height": 8, "pixel_format": "rgb",
                          "rfilter": {{"type": "box"}}}}}}}})
image = np.array(mi.render(scene))
assert abs(float(image.mean()) - 0.5) < 1e-4, image.mean()
print(mi.__version__)
"""


def mitsuba_status(variant: str = MITSUBA_VARIANT) -> tuple[bool, str]:
    """Whether Mitsuba renders here: a tiny render in a child process (LLVM errors abort).

    Returns ``(ok, version or the reason it does not)``.
    """
    import subprocess

    try:
        done = subprocess.run([sys.executable, "-c", _PROBE.format(variant=variant)],
                              capture_output=True, text=True, timeout=600)
    except subprocess.TimeoutExpired:
        return False, "the Mitsuba probe render did not finish in 600 s"
    if done.returncode == 0:
        return True, done.stdout.strip().splitlines()[-1]
    lines = [ln for ln in (done.stderr + done.stdout).splitlines()
             if ln.strip() and not ln.strip().startswith("0x")]
    reason = " | ".join(lines[-3:]) or f"exit status {done.returncode}"
    if "No module named" in reason:
        reason = "mitsuba is not installed (pip install 'radscene[mitsuba]')"
    elif "LLVM" in reason:
        reason = ("Dr.Jit's LLVM backend failed (" + reason[:300] + "); it needs a recent "
                  "libLLVM, e.g. Debian's libllvm19, or DRJIT_LIBLLVM_PATH")
    return False, reason


def band_inputs(scene) -> dict:
    """The band-integrated factors radscene uses, per material and band, for a nadir view.

    For the uniform atmosphere every line of sight shares one path node, so each term is a
    per-material constant times a geometry scalar: ``sun[m, b]`` times cos θ_i · lit,
    ``sky[m, b, k]`` times the visible-sky fraction F_k, ``emission[m, b]``, ``path[b]``
    (all [W m-2 sr-1]), with ``zenith_nodes`` [deg] of the sky table.
    """
    from types import SimpleNamespace

    from radscene.atmosphere import PathNodes
    from radscene.render import integrator, sun_geometry
    from radscene.render.spectral import emission_coefficients

    if getattr(scene.atmosphere, "geometry_dependent", True):
        raise ValueError("the comparison needs an atmosphere whose path does not depend on "
                         "geometry (uniform)")
    obj = scene.objects[0]
    alt = scene.location.altitude
    z = float(np.mean(obj.mesh.vertices[:, 2]))
    nodes = PathNodes(np.array([alt + 8000.0]), np.array([alt + z]), np.array([0.0]),
                      np.zeros((1, 1), dtype=np.int64), np.ones((1, 1)))
    tables = SimpleNamespace(sun=sun_geometry(scene))
    bands = [scene.band(b["name"]) for b in BANDS]
    try:  # one sun node, its atmosphere (radscene after the per-ray sun)
        setup = integrator._BandSetup(scene, bands, nodes, [(tables.sun, scene.atmosphere)])
    except TypeError:
        setup = integrator._BandSetup(scene, tables, bands, nodes, scene.atmosphere)
    c = setup.coefficients
    n_m = len(scene.materials)
    temperature = np.full(n_m, np.nan)
    for m in np.unique(obj.face_material):
        t = np.unique(obj.face_temperature[obj.face_material == m])
        if t.size != 1:
            raise ValueError(f"material {scene.material_names[m]} has {t.size} temperatures")
        temperature[m] = t[0]
    used = np.flatnonzero(np.isfinite(temperature))
    emission = np.zeros((n_m, len(bands)))
    for b, (q_nodes, q_weights) in enumerate(setup.quadrature):
        emission[used, b] = emission_coefficients(setup.emissivity_tau[b], q_nodes, q_weights,
                                                  used, temperature[used])[:, 0]
    if np.any(c.sun_specular[used] != 0) or np.any(c.sky_specular[used] != 0):
        raise ValueError("specular materials (Phong) have no counterpart in Mitsuba 3")
    sky = c.sky_diffuse[:, :, 0, :]
    if hasattr(setup, "sky_nodes"):  # zenith × azimuth grid, zenith-major
        zenith_nodes, azimuth_nodes = (np.asarray(x, dtype=float) for x in setup.sky_nodes)
        sky = sky.reshape(sky.shape[:2] + (zenith_nodes.size, azimuth_nodes.size))
        if np.ptp(sky, axis=-1).max() > 1e-9 * max(1.0, np.abs(sky).max()):
            raise ValueError("the sky depends on azimuth; only zenith profiles are mapped")
        sky = sky[..., 0]
    else:  # a zenith profile only (radscene before the azimuth grid)
        zenith_nodes = np.asarray(setup.zenith_nodes, dtype=float)
    return {"sun": c.sun_diffuse[:, :, 0], "sky": sky,
            "emission": emission,
            "path": c.path[0, :, 0] if c.path.ndim == 3 else c.path[:, 0],  # azimuth node 0
            "zenith_nodes": zenith_nodes,
            "used": used, "sun_direction": tables.sun.direction}


def _write_ply(path: Path, vertices: np.ndarray, faces: np.ndarray) -> None:
    """Binary little-endian PLY of a triangle mesh (float32 vertices, int32 faces)."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(vertices)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    face_rec = np.empty(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face_rec["n"] = 3
    face_rec["i"] = faces
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        f.write(np.ascontiguousarray(vertices, dtype="<f4").tobytes())
        f.write(face_rec.tobytes())


def _sky_bitmap(zenith_nodes, profile, height=1024):
    """Latitude-longitude map (Mitsuba envmap, +Y up) of a zenith profile; zero below horizon."""
    theta = (np.arange(height) + 0.5) / height * 180.0
    row = np.interp(theta, zenith_nodes, profile) * (theta < 90.0)  # constant beyond the ends
    return np.repeat(np.repeat(row[:, None, None], 8, axis=1), 3, axis=2).astype(np.float32)


class MitsubaTwin:
    """The benchmark scene in Mitsuba 3, as two scenes of the same geometry.

    * ``sun``: per-material diffuse BSDFs lit by a directional emitter, with per-material area
      emitters (not sampled: seen only by camera rays) for the thermal emission; one sample at
      each pixel centre (stratified sampler without jitter), like radscene's supersample 1.
    * ``sky``: the same BSDFs lit by an environment map of the sky's zenith profile, sampled by
      the BSDF (cosine) only, as radscene samples its sky.

    Band-integrated factors are mapped exactly onto RGB channels, three bands per pass:
    reflectance ρ_m = 0.9 c_m / max c, emitter strength π max c / 0.9 (sun) or max c / 0.9
    (sky map scale), so that (ρ/π) E = c. The sky split is exact because the uniform
    atmosphere's sky is one spectrum times a zenith profile (the map holds the profile).
    """

    def __init__(self, mi, scene, inputs, size, gsd, workdir: Path):
        self.mi = mi
        self.inputs = inputs
        self.size = size
        obj = scene.objects[0]
        lo, hi = obj.mesh.bounds
        self.center = 0.5 * (lo + hi)
        self.used = inputs["used"]
        sky = inputs["sky"][self.used]
        node0 = sky[..., :1]
        profile = sky / np.where(node0 > 0, node0, 1.0)
        spread = np.ptp(profile, axis=0)
        if np.any(spread > 1e-9 * np.maximum(1.0, np.abs(profile).max())):
            raise ValueError("the sky is not one spectrum times a zenith profile")
        self.profile = profile[0, 0]  # (n_k,)
        if np.ptp(profile[0], axis=0).max() > 1e-9 * max(1.0, np.abs(profile).max()):
            raise ValueError("the sky's zenith profile differs between bands")
        plys = {}
        for m in self.used:
            faces = obj.mesh.faces[obj.face_material == m]
            path = workdir / f"terrain_{m}.ply"
            _write_ply(path, obj.mesh.vertices - self.center, faces)
            plys[m] = str(path)
        T = mi.ScalarTransform4f
        half = 0.5 * size * gsd
        cam = scene.observers[0].camera
        cx, cy = (np.asarray(cam.center[:2]) if hasattr(cam, "center")
                  else 0.5 * (lo[:2] + hi[:2])) - self.center[:2]
        top = float(hi[2] - self.center[2]) + 100.0
        to_world = T().look_at(origin=[cx, cy, top], target=[cx, cy, top - 1.0],
                               up=[0.0, 1.0, 0.0]) @ T().scale([half, half, 1.0])
        win0 = (size - NOISE_WINDOW) // 2 if size > NOISE_WINDOW else 0
        win = min(NOISE_WINDOW, size)
        self.window = (win0, win0 + win)

        def sensor(sampler, crop):
            film = {"type": "hdrfilm", "width": size, "height": size, "pixel_format": "rgb",
                    "rfilter": {"type": "box"}, "sample_border": False}
            if crop:
                film.update(crop_offset_x=win0, crop_offset_y=win0, crop_width=win,
                            crop_height=win)
            return {"type": "orthographic", "to_world": to_world, "near_clip": 1.0,
                    "far_clip": 2.0 * top + 1e4, "sampler": sampler, "film": film}

        def shapes(emit):
            out = {}
            for m, path in plys.items():
                # distinct start values: Mitsuba shares identical BSDFs and merges their meshes
                grey = 0.5 + 0.001 * int(m)
                shape = {"type": "ply", "filename": path, "face_normals": True,
                         "bsdf": {"type": "diffuse",
                                  "reflectance": {"type": "rgb", "value": [grey] * 3}}}
                if emit:
                    shape["emitter"] = {"type": "area", "sampling_weight": 0.0,
                                        "radiance": {"type": "rgb", "value": [0.0, 0.0, 0.0]}}
                out[f"terrain_{m}"] = shape
            return out

        sun_dir = np.asarray(inputs["sun_direction"], dtype=float)
        centre_sampler = {"type": "stratified", "sample_count": 1, "jitter": False}
        self.scenes = {
            "sun": mi.load_dict({
                "type": "scene",
                "integrator": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
                "sun": {"type": "directional", "direction": (-sun_dir).tolist(),
                        "irradiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]}},
                "full": sensor(centre_sampler, False),
                **shapes(True)}),
            "sky": mi.load_dict({
                "type": "scene",
                "integrator": {"type": "direct", "emitter_samples": 0, "bsdf_samples": 1},
                "sky": {"type": "envmap",
                        "bitmap": mi.Bitmap(_sky_bitmap(inputs["zenith_nodes"], self.profile)),
                        "to_world": T().rotate([1, 0, 0], 90.0)},
                "full": sensor({"type": "stratified", "sample_count": 16}, False),
                "window": sensor({"type": "stratified", "sample_count": 16}, True),
                **shapes(False)}),
        }
        self.params = {k: mi.traverse(v) for k, v in self.scenes.items()}
        self.compile_ms = 0.0  # Dr.Jit kernel history: code generation + LLVM compilation
        self.execute_ms = 0.0  # and kernel execution, summed over renders

    def set_bands(self, bands) -> None:
        """Load the factors of (up to) three bands into the RGB channels of both scenes."""
        b = list(bands) + [bands[-1]] * (3 - len(bands))
        inp = self.inputs
        sun = inp["sun"][:, b]
        sky0 = inp["sky"][:, b, 0]
        sun_max = np.maximum(sun[self.used].max(axis=0), 1e-30)
        sky_max = max(float(sky0[self.used].max()), 1e-30)  # one scale for the sky map
        ps, pk = self.params["sun"], self.params["sky"]
        for m in self.used:
            ps[f"terrain_{m}.bsdf.reflectance.value"] = (0.9 * sun[m] / sun_max).tolist()
            ps[f"terrain_{m}.emitter.radiance.value"] = inp["emission"][m, b].tolist()
            pk[f"terrain_{m}.bsdf.reflectance.value"] = (0.9 * sky0[m] / sky_max).tolist()
        ps["sun.irradiance.value"] = (np.pi * sun_max / 0.9).tolist()
        pk["sky.scale"] = sky_max / 0.9
        ps.update()
        pk.update()

    def render(self, which, sensor="full", spp=None, seed=0) -> tuple[np.ndarray, float]:
        """Render; returns (image (3, ny, nx) [W m-2 sr-1], wall time [s])."""
        scene = self.scenes[which]
        index = [s.id() for s in scene.sensors()].index(sensor)
        import drjit as dr

        dr.kernel_history()  # clear
        t0 = time.perf_counter()
        image = np.array(self.mi.render(scene, sensor=index, spp=spp or 0, seed=seed))
        wall = time.perf_counter() - t0
        for k in dr.kernel_history():
            self.compile_ms += k.get("codegen_time", 0.0) + k.get("backend_time", 0.0)
            self.execute_ms += k.get("execution_time", 0.0)
        return np.moveaxis(image, -1, 0), wall


def mitsuba_compare(scene, ds, args, size, gsd, terrain_size) -> dict:
    """Render the benchmark scene with Mitsuba 3 at radscene's noise; compare time and bands.

    ``ds`` is radscene's render of the same scene (its term layers are compared).
    """
    import tempfile

    import radscene

    ok, info = mitsuba_status()
    if not ok:
        print(f"mitsuba: skipped: {info}")
        return {"skipped": info}
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(MITSUBA_VARIANT)
    dr.set_flag(dr.JitFlag.KernelHistory, True)
    out = {"version": info, "variant": MITSUBA_VARIANT}
    try:
        inputs = band_inputs(scene)
    except ValueError as err:
        print(f"mitsuba: skipped: {err}")
        return {"skipped": str(err)}
    except (AttributeError, TypeError, KeyError, IndexError) as err:  # internals moved
        reason = f"radscene's band setup changed ({type(err).__name__}: {err})"
        print(f"mitsuba: skipped: {reason}")
        return {"skipped": reason}
    n_b = len(BANDS)
    groups = [list(range(i, min(i + 3, n_b))) for i in range(0, n_b, 3)]
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.perf_counter()
        twin = MitsubaTwin(mi, scene, inputs, size, gsd, Path(tmp))
        out["scene_build_s"] = time.perf_counter() - t0
        r0, r1 = twin.window

        # radscene's noise: its only stochastic term, the reflected sky, rendered twice (two
        # seeds) over the centre window with the same pixel grid
        spec = scene_dict(size, args.sky_samples, terrain_size, lake=args.lake)
        obs = spec["observers"][0]
        offset = gsd * (r0 + 0.5 * (r1 - r0) - 0.5 * size)  # window centre, east and south
        c0 = np.asarray(obs["center"]) + offset * np.array([1.0, -1.0])
        obs.update(center=c0.tolist(), shape=[r1 - r0, r1 - r0])
        sky_rs = []
        for seed in (11, 12):
            spec["render"]["seed"] = seed
            win = radscene.render(radscene.load_scene(spec), "nadir")
            sky_rs.append(win["sky_reflected"].values)
        check = ds["sky_reflected"].values[:, r0:r1, r0:r1]
        sigma_rs = np.std(sky_rs[0] - sky_rs[1], axis=(1, 2)) / np.sqrt(2.0)
        out["window_mean_check"] = float(np.mean(sky_rs[0]) / np.mean(check))

        # Mitsuba's noise at 16 samples per pixel over the same window, then the sample count
        # that matches radscene's noise in every band
        t0 = time.perf_counter()
        sky_mi = np.zeros((2, n_b, r1 - r0, r1 - r0))
        for g in groups:
            twin.set_bands(g)
            for k, seed in enumerate((1, 2)):
                img, _ = twin.render("sky", "window", spp=16, seed=seed)
                sky_mi[k, g] = img[: len(g)]
        out["noise_search_s"] = time.perf_counter() - t0
        sigma_mi16 = np.std(sky_mi[0] - sky_mi[1], axis=(1, 2)) / np.sqrt(2.0)
        need = 16.0 * np.max((sigma_mi16 / np.maximum(sigma_rs, 1e-300)) ** 2)
        spp = int(np.ceil(np.sqrt(min(max(need, 1.0), MITSUBA_MAX_SPP)))) ** 2
        out["noise"] = {"radscene_sigma": sigma_rs.tolist(), "mitsuba_sigma_16spp":
                        sigma_mi16.tolist(), "equal_noise_spp": float(need), "spp": spp}

        # full-size renders, timed; warm-up (JIT) first: both scenes at the sample counts used
        twin.set_bands(groups[0])
        t0 = time.perf_counter()
        twin.render("sun")
        twin.render("sky", "window", spp=spp)
        out["jit_warmup_s"] = time.perf_counter() - t0
        twin.compile_ms = twin.execute_ms = 0.0
        sun_img = np.zeros((n_b, size, size))
        sky_img = np.zeros((n_b, size, size))
        times = {"sun": 0.0, "sky": 0.0}
        for g in groups:
            twin.set_bands(g)
            img, dt = twin.render("sun")
            sun_img[g] = img[: len(g)]
            times["sun"] += dt
            img, dt = twin.render("sky", spp=spp, seed=3)
            sky_img[g] = img[: len(g)]
            times["sky"] += dt
    total_mi = sun_img + sky_img + inputs["path"][:, None, None]
    # Dr.Jit compiles a kernel when a parameter it holds as a literal changes; that compile
    # time (from its kernel history) is left out of the time compared with radscene's
    wall = sum(times.values()) - twin.compile_ms / 1e3
    out.update(render_s=times, wall_s=wall, wall_with_compile_s=sum(times.values()),
               passes=2 * len(groups),
               jit_compile_s=twin.compile_ms / 1e3, kernel_execution_s=twin.execute_ms / 1e3,
               rays_traced_estimate=int(size * size * (len(groups) * (2 + 2 * spp))))

    rs_sun = ds["sun_diffuse"].values + ds["thermal_emission"].values
    rs_sky = ds["sky_reflected"].values
    rs_tot = ds["radiance"].values
    per_band = []
    for b, band in enumerate(BANDS):
        d_sun = sun_img[b] - rs_sun[b]
        scale_sun = max(float(np.abs(rs_sun[b]).mean()), 1e-30)
        d_sky = sky_img[b] - rs_sky[b]
        d_tot = total_mi[b] - rs_tot[b]
        mean_tot = float(rs_tot[b].mean())
        noise = float(np.sqrt(sigma_rs[b] ** 2 + (sigma_mi16[b] ** 2) * 16.0 / spp))
        per_band.append({
            "band": band["name"],
            "radscene_mean": mean_tot, "mitsuba_mean": float(total_mi[b].mean()),
            "mean_rel_diff": float(d_tot.mean()) / mean_tot,
            "rms_rel_diff": float(np.sqrt(np.mean(d_tot ** 2))) / mean_tot,
            "sun_emission_mean_rel_diff": float(d_sun.mean()) / scale_sun,
            "sun_emission_pixels_off_1pct": float(np.mean(np.abs(d_sun) > 0.01 * scale_sun)),
            "sky_mean_rel_diff": float(d_sky.mean()) / max(float(rs_sky[b].mean()), 1e-30),
            "sky_rms_diff_over_noise": float(np.sqrt(np.mean(d_sky ** 2))) / max(noise, 1e-30),
        })
    out["bands"] = per_band
    out["radscene_over_mitsuba"] = None  # set by the caller, who knows radscene's time
    return out


# ---------------------------------------------------------------------------------------------
# machine


def source_version() -> dict:
    """The radscene commit measured, and whether its sources differ from it."""
    import subprocess

    def git(*cmd):
        try:
            return subprocess.run(["git", *cmd], cwd=ROOT, capture_output=True, text=True,
                                  timeout=30).stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return ""

    return {"commit": git("rev-parse", "--short", "HEAD"),
            "src_modified": bool(git("status", "--porcelain", "--", "src"))}


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
        _reset_peak()
        rss_start = _peak_rss_mib()
        with RayCounter() as counter:
            cpu0, t0 = time.process_time(), time.perf_counter()
            ds = radscene.render(scene, "nadir")
            wall = time.perf_counter() - t0
            cpu = time.process_time() - cpu0
        runs.append({"wall_s": wall, "cpu_s": cpu, "rays": dict(counter.rays),
                     "total_rays": counter.total, "engine_s": dict(counter.engine_s),
                     "query_s": dict(counter.query_s), "engine_calls": dict(counter.calls),
                     "peak_rss_mib": _peak_rss_mib(), "rss_at_start_mib": rss_start})
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


def _verdict(targets, key):
    if not targets["apply"]:
        return "n/a (the targets are for 1024 x 1024, 16 sky rays, ~1 M triangles)"
    return "met" if targets[key] else "NOT met"


def print_table(r: dict) -> None:
    """The figures as a two-column table on stdout."""
    ren, bare = r["render"], r["bare"]
    walls = ", ".join(f"{w:.2f}" for w in ren["walls_s"])
    rows = [
        ("triangles", f"{r['triangles']:,}"),
        ("image", f"{r['settings']['size']} x {r['settings']['size']} x "
                  f"{r['settings']['bands']} bands, {r['settings']['sky_samples']} sky rays/px"),
        ("scene load", f"{r['load_s']:.2f} s"),
        ("scene", f"{100 * (ren['mean_shadow_fraction'] or 0):.1f} % of pixels in shadow, mean "
                  f"sky view {ren['mean_sky_view'] or float('nan'):.3f}"),
        ("render wall (median)", f"{ren['wall_s']:.2f} s  (runs: {walls})"),
        ("pixel·bands/s", f"{ren['pixel_bands_per_s'] / 1e6:.2f} M"),
        ("rays (render)", "  ".join(f"{k} {v / 1e6:.2f} M" for k, v in ren["rays"].items())),
        ("rays total / rays/s", f"{ren['total_rays'] / 1e6:.2f} M / "
                                f"{ren['rays_per_s'] / 1e6:.2f} M/s"),
        ("time in ray engine", f"{ren['engine_total_s']:.2f} s ("
         + "  ".join(f"{k} {v:.2f}" for k, v in ren["engine_s"].items()) + ")"),
        ("time in queries", "  ".join(f"{k} {v:.2f} s" for k, v in ren["query_s"].items())),
        ("render CPU / wall", f"{ren['cpu_s'] / ren['wall_s']:.2f} cores busy on average"),
        ("peak RSS (render)", f"{ren['peak_rss_mib']:.0f} MiB, "
                              f"{ren['peak_rss_mib'] - ren['rss_at_start_mib']:.0f} MiB above the "
                              f"{ren['rss_at_start_mib']:.0f} MiB held before it"),
        ("bare embreex (median)", f"{bare['total_s']:.2f} s for {bare['total_rays'] / 1e6:.2f} M "
                                  f"rays = {bare['rays_per_s'] / 1e6:.2f} M/s on "
                                  f"{bare['threads']} threads"),
        ("bare by kind", "  ".join(f"{k} {bare['time_s'][k]:.2f} s/{bare['rays'][k] / 1e6:.2f} M"
                                   for k in bare["rays"])),
        ("render / bare (median)", f"{r['render_over_bare']:.2f}  (rounds: "
         + ", ".join(f"{x:.2f}" for x in r["render_over_bare_each"]) + ")"),
        ("bare BVH build", f"{bare['bvh_build_s']:.2f} s (not in the bare time)"),
    ]
    if "packets_total_s" in bare:
        rows += [
            ("bare, Embree packets", f"{bare['packets_total_s']:.2f} s ("
             + "  ".join(f"{k} {v:.2f}" for k, v in bare["packets_time_s"].items())
             + " s; shadow and sky rays as packets of eight, as radscene traces them)"),
            ("render / bare packets", f"{r['render_over_bare_packets']:.2f}  (rounds: "
             + ", ".join(f"{x:.2f}" for x in r["render_over_bare_packets_each"]) + ")"),
        ]
    rows += [
        ("target wall <= 2 s", _verdict(r["targets"], "wall_met")),
        ("target ratio <= 1.5", _verdict(r["targets"], "ratio_met")),
    ]
    atm = r.get("atmosphere")
    if atm:
        sec = atm["seconds"]
        rows.append(("atmosphere look-ups", f"{atm['engine']}: {atm['lookup_s']:.2f} s of a "
                     f"{atm['wall_s']:.2f} s render = {100 * atm['lookup_fraction']:.1f} % "
                     f"(queries {sec['queries']:.2f} s, path-node mixing {sec['mixing']:.2f} s "
                     f"of {sec['mixing'] + sec.get('terms', 0.0):.2f} s in mix_terms, "
                     f"sky-table sums in the sky fold {sec.get('sky_fold', 0.0):.2f} s; "
                     f"band tables {sec['band_tables']:.2f} s incl. their queries); target "
                     "<= 15 %: " + (("met" if atm["lookup_met"] else "NOT met")
                                    if r["targets"]["apply"] else _verdict(r["targets"], ""))))
    brk = r.get("breakdown")
    if brk:
        top = sorted(brk["seconds"].items(), key=lambda kv: -kv[1])[:8]
        rows.append(("breakdown (1 render)", f"{brk['wall_s']:.2f} s wall; inclusive: "
                     + ", ".join(f"{k} {v:.2f}" for k, v in top)))
    mit = r.get("mitsuba")
    if mit and "skipped" in mit:
        rows.append(("mitsuba", f"skipped: {mit['skipped']}"))
    elif mit:
        rows.append(("mitsuba", f"{mit['version']} {mit['variant']}, {mit['passes']} passes, "
                                f"{mit['noise']['spp']} spp for equal noise (needed "
                                f"{mit['noise']['equal_noise_spp']:.1f})"))
        rows.append(("mitsuba render", f"{mit['wall_s']:.2f} s without JIT compilation ("
                                       f"with: sun {mit['render_s']['sun']:.2f}, "
                                       f"sky {mit['render_s']['sky']:.2f}); scene build "
                                       f"{mit['scene_build_s']:.2f} s, JIT warm-up "
                                       f"{mit['jit_warmup_s']:.2f} s; in the timed renders "
                                       f"JIT compile {mit['jit_compile_s']:.2f} s, kernels "
                                       f"{mit['kernel_execution_s']:.2f} s"))
        rows.append(("radscene / mitsuba", f"{mit['radscene_over_mitsuba']:.2f}"))
        for b in mit["bands"]:
            rows.append((f"  {b['band']}", f"mean {b['radscene_mean']:.4g} vs "
                         f"{b['mitsuba_mean']:.4g} W m-2 sr-1 "
                         f"({100 * b['mean_rel_diff']:+.3f} %), rms "
                         f"{100 * b['rms_rel_diff']:.2f} %; sun+emission "
                         f"{100 * b['sun_emission_mean_rel_diff']:+.3f} % "
                         f"({100 * b['sun_emission_pixels_off_1pct']:.2f} % px off >1 %); sky "
                         f"{100 * b['sky_mean_rel_diff']:+.2f} %, rms/noise "
                         f"{b['sky_rms_diff_over_noise']:.2f}"))
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
