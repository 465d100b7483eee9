"""Instruments of one render: peak memory, its rays counted at the ray engine, the
integrator's helpers timed, and the atmospheric look-ups timed."""

from __future__ import annotations

import resource
import time

import numpy as np

# ---------------------------------------------------------------------------------------------
# memory


def reset_peak() -> bool:
    """Reset the process's peak resident set (Linux >= 4.0); False where that is refused."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def peak_rss_mib() -> float:
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


#: The modules of radscene.render that hold what the integrator did inline or in its own
#: helpers (the integrator orchestrates; its passes live beside it).
RENDER_MODULES = ("integrator", "band_setup", "brdf_tables", "coupling_pass", "media_sky",
                  "node_mixing", "outputs", "shading", "surface", "terms", "tiles", "truth")
#: Of those, the ones with the inline numpy of the render's tile loop.
INLINE_MODULES = ("integrator", "shading", "tiles")


def render_bindings(name, modules=RENDER_MODULES) -> list:
    """The modules of ``modules`` that bind ``name`` to the same object as the first that
    binds it (the helper's home and those that import it by name); none where this
    radscene version has no such helper."""
    import importlib

    found, target = [], None
    for short in modules:
        try:
            module = importlib.import_module(f"radscene.render.{short}")
        except ImportError:
            continue
        value = vars(module).get(name)
        if value is None or (target is not None and value is not target):
            continue
        target = value
        found.append(module)
    return found


def patch_render(saved, names, wrap) -> None:
    """Replace each of ``names`` by ``wrap(function, name)`` wherever the render's modules
    bind it (:func:`render_bindings`), noting (module, name, original) in ``saved``."""
    for name in names:
        modules = render_bindings(name)
        if modules:
            wrapped = wrap(getattr(modules[0], name), name)
            for module in modules:
                saved.append((module, name, getattr(module, name)))
                setattr(module, name, wrapped)


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
                  "_pixel_sums", "SceneTables", "BandSetup", "emission_pairs", "surface_state",
                  "textures", "geolocation", "dataset", "central_subsample", "pixel_sums")
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
        import importlib

        from radscene.platform import cameras
        from radscene.render import illumination, node_mixing, terms

        patch_render(self._saved, self.INTEGRATOR, self.wrap)
        self._patch(node_mixing, "mix_terms", "node_mixing.mix_terms")
        for name in getattr(terms, "__all__", ()):
            if callable(getattr(terms, name, None)):
                self._patch(terms, name, f"terms.{name}")
        for name in ("cast_shadow", "sky_fractions", "sky_sums", "lobe_sky_fractions"):
            self._patch(illumination, name, f"illumination.{name}")
        for cls in (cameras.OrthographicCamera, cameras.PerspectiveCamera):
            self._patch(cls, "rays", "camera.rays")
        timed = _TimedNumpy(self, self.NUMPY)
        for short in INLINE_MODULES:
            try:
                module = importlib.import_module(f"radscene.render.{short}")
            except ImportError:
                continue
            self._saved.append((module, "np", module.np))
            module.np = timed
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
    counted as ``terms``); ``gather_band``, ``sky_sum`` and ``sky_node_weights`` as the
    integrator's passes call them (``_gather_band``, ``_sky_sum``, ``_subset_nodes`` of older
    versions' integrator) whole. ``sky_fold``: ``kernels.fold_sky_sums`` (``packet_sky_sums``) on the secondary-ray
    thread, which folds each point's sky rays onto the atmosphere's sky nodes and sums the band
    sky tables over them: only the sums are a look-up. Each call is repeated with no bands (the
    fold alone); the difference is counted as ``sky_fold``, and the repeat's time as ``extra``,
    which the caller takes off the render's wall time. ``band_tables``: the band integration of the node
    spectra with the materials (``BandSetup``, ``emission_pairs``), inclusive of the queries
    it makes. Nesting is counted per thread.
    """

    QUERIES = ("path", "sun", "sky", "path_nodes", "with_sun")
    MIXING = ("_gather_band", "_sky_sum", "_subset_nodes", "sky_node_weights", "gather_band",
              "sky_sum")
    TABLES = ("_BandSetup", "_emission_pairs", "BandSetup", "emission_pairs")

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

        def wrapped(*args, **kwargs):
            from radscene.render import kernels, node_mixing

            t0 = time.perf_counter()
            result = function(*args, **kwargs)
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
        from radscene.render import node_mixing

        targets = [(self.engine_class, n, "queries") for n in self.QUERIES]
        patch_render(self._saved, self.MIXING, lambda f, n: self._wrap(f, "mixing", n))
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
        # inclusive: their queries are counted there too
        patch_render(self._saved, self.TABLES, lambda f, n: self._wrap(f, "band_tables", n))
        return self

    def __exit__(self, *exc):
        for owner, name, old in reversed(self._saved):
            if old is None:
                delattr(owner, name)
            else:
                setattr(owner, name, old)
        self._saved.clear()
        return False
