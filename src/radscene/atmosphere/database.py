"""The ``database`` atmosphere engine: precomputed tables, interpolated at render time.

A database file (NetCDF, written by :func:`radscene.atmosphere.build.build_database` or
``radscene atmosphere build``) holds what an engine said over a grid of geometries, for several
atmospheric conditions, with its provenance. :class:`DatabaseAtmosphere` answers every
:class:`~radscene.atmosphere.base.Atmosphere` query from it by interpolation, vectorised over
lines of sight, with no Fortran and no 6S run.

Tables, stored where the physics needs resolution (the file's ``layout`` attribute is
``radscene-atmosphere-database/1``):

* **scattering** (per aerosol condition), at 6S's 20 scattering wavelengths
  (``scattering_wavelength``, interpolated log-log as 6S does) over surface altitude, observer
  height above the surface (``observer_height``; the last node is the top of the atmosphere),
  sun zenith, view zenith and relative azimuth (0, 90, 180 deg, a three-term cosine series):
  path reflectance of molecules + aerosol and of molecules alone; total scattering
  transmittances down and up; spherical albedo; optical depths; phase functions and aerosol
  single-scattering albedo for the sky model.
* **gas** (per gas profile), at fine ``wavelength`` resolution (adaptive: 2.5 nm inside
  absorption bands, coarse in windows) over surface altitude and airmass: the full column's
  gaseous transmittance, with and without water vapour, and that of the column below an
  aircraft observer.
* **thermal** (optional; from an emitting engine such as ``lowtran``), over
  ``thermal_wavelength``: transmittance, path thermal radiance (surface altitude × observer
  height × view zenith), sky thermal radiance and the sky's transmittance to space (surface
  altitude × sky zenith); the same at the ``water_scale`` nodes of LOWTRAN's water-vapour
  column for every condition, and aerosol-free at the ``ozone_scale`` nodes of its ozone
  column (:meth:`DatabaseAtmosphere._scale_thermal`). Where they overlap the scattering and
  gas tables (3-4 um) the gases are the thermal tables' (:meth:`DatabaseAtmosphere.
  _thermal_gases`).

Any profile of the file goes with any aerosol condition. The conditions of one aerosol model
at several AOT550 values (``aot550`` per condition; the condition ``none`` is every model's
AOT550 = 0) form a continuous axis: between two of them the smooth factors below, the
spherical albedo and the thermal tables are interpolated linearly in AOT550, the aerosol
optical depth exactly (it scales with AOT550 within a model), with the model's optical
properties; an aircraft's path reflectance under a low sun is each condition's own, computed
as below at the exact geometry, interpolated quadratically in AOT550 through the two nodes
about it and the next (:meth:`DatabaseAtmosphere._path_reflectances`). A visibility is turned into AOT550 by 6S's own relation (linear in
1 / visibility, through the conditions' recorded visibilities). The water-vapour and ozone
columns of the profile scale as absorber amounts along the path (:meth:`DatabaseAtmosphere.
_gas`): a column f times the profile's absorbs along airmass m as the profile's along f m.
In the thermal tables they are LOWTRAN's columns scaled (``thermal_profile_column``, the
factor from LOWTRAN's own column of the profile): water vapour through the tables at its
nodes, ozone as a layer in front of a downward path and behind the lower atmosphere for the
sky (:meth:`DatabaseAtmosphere._scale_thermal`).
Between nodes the database
interpolates only smooth factors: the path reflectance divided by its single-scattering value
ρ_ss (:func:`~radscene.atmosphere.sixs_model.single_scattering_reflectance`, with 6S's phase
functions and the mixture of the layer below the observer), which carries the sharp angular
and altitude structure analytically — where the aerosol is thick, the excess ρ - ρ_ss instead,
divided by the share of the column's single scattering below the observer
(:func:`~radscene.atmosphere.sixs_model.layer_share`, 1 at the top). ρ_ss takes the aerosol
phase function averaged over a 3 deg cap near backscatter (:func:`_backscatter_smoothed`): 6S's
radiance does not follow the maritime glory at exactly 180 deg, so with the tabulated value
the factor jumped at the nodes of exact backscatter (sun and view at the zenith; equal
zeniths at relative azimuth 0) and the spline carried the jump to the sun at 10 deg (maritime
AOT550 0.5, nadir, -4.3 %; now within 1.4 %). The choice of normaliser leaves the values on
the nodes as they are. In the glory region (scattering angles 135-150 deg,
:data:`_GLORY_BLEND`) the factor is the excess wherever the aerosol's optical depth reaches
:data:`_GLORY_DEPTH`: there ρ/ρ_ss follows ρ_ss's dip near 140-150 deg, which 6S's radiance
does not (maritime AOT550 0.5, sun 30 deg, nadir: +3.0 % at worst from the top, +3.8 % from 3
km before; +0.4 and +0.6 % after). The diffuse
shares (T - e^{-τ/μ}) / (1 - e^{-τ/μ}) of the total transmittances; linearly in surface
altitude, in the aerosol fraction below the observer x = 1 - exp(-Δh / 2 km) (6S's aerosol
profile; x = 1 at the top), in sun and view zenith (at the top of the atmosphere through a
cubic spline; an aircraft level's factor as the top's times its quotient, or plus its
difference, to the top's, linear in view zenith and in the sun's airmass 1/cos θ_s, the
quotient in its logarithm — as the build carries the aircraft levels from their coarse
zeniths; linearly in angle instead, a 3 km aircraft's path reflectance at sun 67 deg, rural
AOT550 0.6, 0.45 um, came out +23.3 % against 6S, then +9.9 %; under a sun lower than 50-60 deg
an aircraft level's path reflectance is the top's at the exact geometry times the level's
quotient to it, log-linear in the sun's and the view's airmass between the nodes:
:meth:`DatabaseAtmosphere._levels_by_quotient`, -2.2 to -1.0 % for that case), by a three-term
cosine series in relative azimuth (Simpson's rule for the azimuthal mean), log-linearly in airmass for the gases. Beyond
the table's zenith nodes the end node's factor is used (stated rule); targets may lie up to
500 m below the lowest surface-altitude node (that node's values then). The spectra are
combined with the formulas of :mod:`radscene.atmosphere.sixs_model`; wavelengths the file
does not cover are refused. Accuracy against direct 6S runs: tests/validation/
test_database_accuracy.py.

Parameters (scene file ``environment.atmosphere``, ``type: database``):

======================  =====  ================  =================================================
name                    unit   default           meaning
======================  =====  ================  =================================================
``file``                -      ``default``       a database file, or the name of one shipped with
                                                 radscene (``radscene.atmosphere.database.
                                                 shipped_databases()``)
``profile``             -      ``us_standard``   gas profile (one of the file's)
``aerosol``             -      ``rural``         aerosol model (one of the file's; ``rural``
                                                 and ``continental`` are 6S's continental)
``aot550``              -      (none)            aerosol optical thickness at 550 nm, within
                                                 the file's nodes of the model (0-1 shipped)
``visibility``          m      23 km             instead of ``aot550``: 6S's AOT550 of it
``water``               g cm-2 (profile's)       water-vapour column, 0-3 times the profile's
``ozone``               cm-atm (profile's)       ozone column, 0-3 times the profile's
                                                 (columns: ``PROFILE_COLUMNS``; in the
                                                 thermal tables, from 3 um, within their
                                                 nodes: 0.01-3 times LOWTRAN's, shipped)
``surface_albedo``      -      0                 albedo of the surroundings (sky irradiance)
``sun_zenith``,         deg    (none), 0         sun for path radiance (renderer: :meth:`set_sun`)
``sun_azimuth``
``view_azimuth``        deg    (none)            line of sight's azimuth; none: azimuthal mean
``earth_sun_distance``  AU     1                 scales E_0
``solar_spectrum``      -      ``radscene``      E_0: radscene's TOA spectrum ``radscene`` or
                                                 ``tsis1`` (:mod:`radscene.sun.spectrum`)
======================  =====  ================  =================================================

Example::

    atmosphere: {type: database, profile: midlatitude_summer, aerosol: rural, aot550: 0.3}
"""

from __future__ import annotations

import copy
import os
from functools import lru_cache
from importlib import resources
from pathlib import Path

import numpy as np

from radscene.atmosphere import sixs_model as model
from radscene.atmosphere.base import (
    CouplingSpectra,
    PathNodes,
    PathSpectra,
    SkyGeometry,
    SkyParts,
    SunDependentAtmosphere,
    SunSpectra,
)
from radscene.atmosphere.nodes import air_mass
from radscene.errors import ConfigError, did_you_mean, unreadable

__all__ = ["DatabaseAtmosphere", "LAYOUT", "shipped_databases", "database_path",
           "AEROSOL_SCALE_HEIGHT", "open_database", "water_tables"]

#: Identifies the file layout this module reads.
LAYOUT = "radscene-atmosphere-database/1"
#: Aerosol scale height of 6S's vertical profile [m]: the observer-height coordinate.
AEROSOL_SCALE_HEIGHT = 2000.0
#: Altitude spans [m] of a line of sight over which the thermal tables' level lines of sight
#: (at its mean altitude, over its length) take over from those over observer height and view
#: zenith: wholly below the first, not above the second, in the logarithm of the span between.
_LEVEL_SPAN = (100.0, 300.0)
#: View zeniths [deg] over which, in the reflective tables' range (below 3 µm), the level
#: lines of sight take over from the tables over view zenith whatever their span (up to
#: :data:`_LEVEL_MAX_SPAN`): the reflective tables' gas transmittance ends at air mass 40
#: (88.6 deg). The thermal range reads lines beyond its last view zenith by
#: :meth:`DatabaseAtmosphere._beyond_thermal` instead: the level air at the mean altitude
#: was up to 10 % off LOWTRAN there for spans of 150 m to 3 km (a 290 K ground's apparent
#: radiance, 3.5-4.9 um), the extrapolation within 3.9 %.
_LEVEL_ZENITH = (85.0, 87.0)
#: Lines of sight spanning more altitude than this [m] are never read as level air below 3 µm.
_LEVEL_MAX_SPAN = 3000.0
#: The zenith [deg] at which the air mass of :meth:`DatabaseAtmosphere._beyond_thermal` stops.
_BEYOND_ZENITH = 89.9
#: Altitude spans [m] over which a thermal line of sight beyond the tables' last view zenith
#: goes from their 85 deg value and the level air of its extra length (wholly up to the
#: first) to the extrapolation in air mass (wholly from the second), in the logarithm of the
#: span. Against LOWTRAN at 86-89.5 deg the first was within 0.011 in τ up to spans of 1 km
#: (the extrapolation up to 0.055 off at 150 m) and up to 0.048 off at 3 km (the
#: extrapolation within 0.021).
_BEYOND_SPAN = (1000.0, 3000.0)
#: Scale height [m] of the spherical shell whose air mass reads lines of sight from space
#: beyond the last view zenith (:meth:`DatabaseAtmosphere._beyond_thermal`): the air's.
#: Against LOWTRAN's sun at 89 deg (3.5-4.1 um, midlatitude summer) it gave τ 0.0145 for
#: 0.0133, water vapour's 2 km 0.0059; at 86-89.5 deg over 3.5-12 um and three conditions it
#: came closest of 2, 4, 6 and 8 km.
_ABSORBER_SCALE_HEIGHT = 8000.0
#: How far below the lowest surface-altitude node a target may lie [m].
_BELOW_TABLE = 500.0
#: Aerosol optical depths between which the interpolated factor of the path reflectance goes
#: from ρ/ρ_ss to ρ − ρ_ss (:meth:`DatabaseAtmosphere.components`).
_BLEND = (0.25, 0.75)
#: Scattering angles [deg] over which the interpolated factor turns to the excess ρ - ρ_ss
#: whatever the aerosol's optical depth (the glory region of the phase function).
_GLORY_BLEND = (135.0, 150.0)
#: ... where the aerosol's optical depth is enough for multiple scattering to matter (below,
#: ρ ≈ ρ_ss and their ratio is the better factor).
_GLORY_DEPTH = (0.1, 0.3)
#: Sun-zenith nodes [deg] that refine the grazing end of the grid: they enter the sun's cubic
#: spline only for suns beyond the node below them, so that the spline elsewhere is the one
#: through the other nodes. With the node at 80 deg in every sun's spline, aircraft under a
#: sun at 67 deg came out 1-2 points further from 6S (maritime AOT550 0.5, 3 km: 5.4 % against
#: 3.5 %). The view's spline keeps it: without it, an aircraft's 30 deg view under a sun at
#: 80 deg came out 6.7 % off 6S instead of 0.2 %.
_SPLINE_REFINEMENTS = (80.0,)
#: Which levels read their path-reflectance factors through a cubic spline in sun and view
#: zenith ("top": the top of the atmosphere; "all"; "none": linear everywhere).
_SPLINE_LEVELS = "top"
#: Sun zeniths [deg] over which an aircraft level's path reflectance goes from the factor
#: interpolated between the nodes to the quotient of the level's to the top's
#: (:meth:`DatabaseAtmosphere._levels_by_quotient`), linearly in the sun's airmass.
_LEVEL_QUOTIENT = (50.0, 60.0)
#: Sun zeniths [deg] over which an aircraft's path reflectance between two AOT550 nodes goes
#: from the smooth factors mixed linearly in AOT550 to each condition's own path reflectance,
#: quadratic in AOT550 (:meth:`DatabaseAtmosphere._path_reflectances`), linearly in the angle.
_AOT_CONDITIONS = (50.0, 60.0)
#: Sun zeniths [deg] over which an observer between the aircraft height nodes goes from the
#: factor read between them to the nodes' multiply scattered part per optical depth below
#: the observer (:meth:`DatabaseAtmosphere._scattering_levels`), linearly in the angle.
_LEVEL_HEIGHTS = (75.0, 85.0)


#: Radius [deg] of the cap over which the aerosol phase function of the single-scattering
#: normaliser is averaged near the backscatter direction (:func:`_backscatter_smoothed`).
_GLORY_RADIUS = 3.0


def _backscatter_smoothed(angles, phase, radius):
    """The phase function (k, n) at ``angles`` (k,) [deg] averaged over a cap of ``radius``
    [deg] about each direction, at the angles within ``radius`` + 5 deg of 180 deg (the rest
    as they are): the normaliser's phase function near backscatter, nearer what 6S's
    radiance follows. From 6S's path reflectance at the top of the atmosphere (maritime
    AOT550 0.6, 0.55 um, nadir view, the sun every 5 deg) the excess ρ - ρ_ss is smooth in the
    sun's zenith from 5 to 45 deg but drops by a fifth at 0 (0.0243 against about 0.030): the
    tabulated 180 deg value, 0.514, behaves as about 0.44 there (the cap average of 3 deg
    radius is 0.467, of 5 deg 0.438). Over 36 geometries off the nodes seen from the top the
    radii 2-4 deg did best (mean 1.18-1.24 %, worst 2.9-3.1 %; 5 deg: 1.33 and 4.1 %; none:
    1.46 and 4.5 %, the largest error over four wavelengths per geometry)."""
    angles = np.asarray(angles, dtype=float)
    out = np.array(phase, dtype=float)
    if radius <= 0:
        return out
    near = np.nonzero(angles >= 180.0 - radius - 5.0)[0]
    psi = np.radians(np.linspace(0.0, radius, 41))[1:]
    alpha = np.linspace(0.0, 2 * np.pi, 72, endpoint=False)
    w = np.sin(psi)[:, None] * np.ones(alpha.size)[None, :]
    for i in near:
        t = np.radians(angles[i])
        c = (np.cos(t) * np.cos(psi)[:, None]
             + np.sin(t) * np.sin(psi)[:, None] * np.cos(alpha)[None, :])
        th = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
        vals = model.phase_interp(th, angles, phase)  # (ψ, α, n)
        out[i] = np.tensordot(w, vals, axes=([0, 1], [0, 1])) / w.sum()
    return out


def _relative(tab, kind):
    """Each level's factor (λs, h, x, θs, θv, φ) relative to the top of the atmosphere's: the
    quotient of the ratios ρ/ρ_ss (positive), the difference of the excesses (either sign)."""
    top = tab[:, :, -1:]
    if kind == "excess":
        return tab - top
    with np.errstate(divide="ignore", invalid="ignore"):
        q = tab / top
    return np.where(np.isfinite(q) & (q > 0), q, 1.0)


def _angle_weights(values, nodes, spline: bool, refined: bool = False) -> np.ndarray:
    """Weights (N, k) of the k angle nodes [deg] for values (N,) [deg] (ends held): linear, or
    a natural cubic spline in the angle. The spline follows the curvature of ρ/ρ_ss between
    the nodes 0-20-40-60 deg: linearly, the top of the atmosphere's path reflectance came out
    2.9 % off 6S on average (10 % at worst) over a set of off-node geometries of the rural and
    maritime aerosols (docs/atmosphere.md, "Database accuracy"), through the spline 1.2 %."""
    v = np.clip(np.atleast_1d(np.asarray(values, dtype=float)), nodes[0], nodes[-1])
    nodes = np.asarray(nodes, dtype=float)
    if not spline or nodes.size < 3:
        i, f = model.axis_weights(v, nodes)
        w = np.zeros((v.size, nodes.size))
        rows = np.arange(v.size)
        w[rows, i] += 1 - f
        w[rows, np.minimum(i + 1, nodes.size - 1)] += f
        return w
    w = _spline_basis(tuple(nodes.tolist()))(v)
    for extra in _SPLINE_REFINEMENTS if refined else ():
        k = np.flatnonzero(np.isclose(nodes, extra))
        if k.size and 0 < k[0] < nodes.size - 1:
            below = v <= nodes[k[0] - 1]
            if below.any():  # the spline without the node, as if the grid had not been refined
                coarse = _spline_basis(tuple(np.delete(nodes, k[0]).tolist()))(v[below])
                w[below] = np.insert(coarse, k[0], 0.0, axis=1)
    return w


@lru_cache(maxsize=16)
def _spline_basis(nodes: tuple):
    """The natural cubic spline through the unit vectors on ``nodes``: its value at x is the
    weights of the nodes' values."""
    from scipy.interpolate import CubicSpline

    return CubicSpline(np.asarray(nodes), np.eye(len(nodes)), bc_type="natural")
#: The largest scale factor of a profile's water-vapour or ozone column.
_MAX_SCALE = 3.0


def shipped_databases() -> dict[str, Path]:
    """Databases shipped with radscene, by name (``default`` among them)."""
    folder = resources.files("radscene") / "data" / "atmosphere"
    out = {}
    try:
        for entry in folder.iterdir():
            if entry.name.endswith(".nc"):
                out[entry.name[:-3]] = Path(str(entry))
    except (FileNotFoundError, NotADirectoryError):
        pass
    return out


def database_path(file) -> Path:
    """Resolve a database name or path; raise ConfigError naming what exists."""
    if file is None:
        file = "default"
    shipped = shipped_databases()
    if str(file) in shipped:
        return shipped[str(file)]
    path = Path(os.path.expanduser(str(file)))
    if path.is_file():
        return path
    raise ConfigError(f"no database {str(file)!r}: neither a file nor one of the shipped "
                      f"databases ({', '.join(sorted(shipped)) or 'none'})",
                      key="atmosphere.file")


@lru_cache(maxsize=8)
def _load(path: str, mtime: float):
    import xarray as xr

    try:
        with xr.open_dataset(path, engine="h5netcdf") as ds:
            data = ds.drop_vars([k for k in ds.data_vars if k.startswith(_DEFERRED)]).load()
    except (OSError, ValueError) as err:
        raise ConfigError(f"cannot read the database {path}: {unreadable(err)}",
                          key="atmosphere.file") from None
    if data.attrs.get("layout") != LAYOUT:
        raise ConfigError(f"{path} is not a radscene atmosphere database (layout "
                          f"{data.attrs.get('layout')!r}, expected {LAYOUT!r})",
                          key="atmosphere.file")
    return data


def open_database(file=None):
    """The database Dataset (cached in memory), by name or path; the tables at the water-vapour
    nodes (``thermal_water_*``, most of the file) stay on disk: :func:`water_tables`."""
    path = database_path(file)
    return _load(str(path), path.stat().st_mtime)


#: Variables :func:`open_database` leaves on disk, read a condition at a time.
_DEFERRED = ("thermal_water_",)


def water_tables(file, profile: int, aerosol: int, mtime: float | None = None) -> dict | None:
    """One condition's thermal tables at the file's ``water_scale`` nodes, by table name
    without its ``thermal_water_`` prefix (None: the file has none). ``mtime``: the file's
    modification time when its other tables were read; a file changed since is refused."""
    path = database_path(file)
    now = path.stat().st_mtime
    if mtime is not None and now != mtime:
        raise ConfigError(f"{path} changed on disk since it was opened; open it again",
                          key="atmosphere.file")
    return _water_tables(str(path), now, int(profile), int(aerosol))


@lru_cache(maxsize=32)
def _water_tables(path: str, mtime: float, profile: int, aerosol: int):
    import xarray as xr

    with xr.open_dataset(path, engine="h5netcdf") as ds:
        names = [k for k in ds.data_vars if k.startswith("thermal_water_")]
        if not names:
            return None
        return {k.removeprefix("thermal_water_"): np.asarray(
            ds[k].isel(profile=profile, aerosol=aerosol).values, dtype=float) for k in names}


def _quadratic_nodes(nodes, k, want) -> list:
    """[(condition index, weight)]: the Lagrange weights at AOT550 ``want`` of the nodes
    ``nodes[k]`` and ``nodes[k + 1]`` ([(AOT550, index)], ascending) about it and the next
    above them (below them at the top); the two about it, linearly, where there is no
    third."""
    if len(nodes) < 3:
        (t0, i0), (t1, i1) = nodes[k], nodes[k + 1]
        w = (want - t0) / (t1 - t0)
        return [(i0, 1.0 - w), (i1, w)]
    third = k + 2 if k + 2 < len(nodes) else k - 1
    chosen = sorted([nodes[k], nodes[k + 1], nodes[third]])
    out = []
    for j, (tj, ij) in enumerate(chosen):
        weight = 1.0
        for m, (tm, _im) in enumerate(chosen):
            if m != j:
                weight *= (want - tm) / (tj - tm)
        out.append((ij, float(weight)))
    return out


def _simpson(n: int) -> np.ndarray:
    """Weights of Simpson's rule on n (odd) equal steps, normalised to a mean."""
    w = np.ones(n)
    w[1:-1:2] = 4.0
    w[2:-1:2] = 2.0
    return w / w.sum()


def _pchip_scale(nodes, stack, f, logarithm):
    """Tables ``stack`` at the column scale factors ``nodes`` (first axis), at ``f``: a
    monotone cubic in sqrt(f), of the logarithm where ``logarithm`` (transmittances)."""
    from scipy.interpolate import PchipInterpolator

    y = np.log(np.maximum(stack, 1e-30)) if logarithm else stack
    value = PchipInterpolator(np.sqrt(nodes), y, axis=0)(np.sqrt(f))
    return np.exp(value) if logarithm else value


def _level_weight(upper, lower, zen, horizon: bool = True):
    """Each line of sight's weight on the level air at its mean altitude (1 below an altitude
    span of :data:`_LEVEL_SPAN` [0], 0 above [1], logarithmically in the span between; with
    ``horizon``, also 1 beyond :data:`_LEVEL_ZENITH` [1] from the vertical, linearly in zenith
    from [0], for spans up to :data:`_LEVEL_MAX_SPAN`), that mean altitude and its length in
    the flat scene [m] (0 where the weight is 0 by the span, or from space)."""
    dh = np.maximum(upper - lower, 0.0)
    max_span = _LEVEL_MAX_SPAN if horizon else _LEVEL_SPAN[1]
    near = (upper < model.TOP_OF_ATMOSPHERE) & (dh > 0.0) & (dh <= max_span)
    with np.errstate(divide="ignore", invalid="ignore"):
        span = np.where(near, np.log(_LEVEL_SPAN[1] / dh), 0.0)
    weight = np.clip(span / np.log(_LEVEL_SPAN[1] / _LEVEL_SPAN[0]), 0.0, 1.0)
    if horizon:
        ramp = np.clip((zen - _LEVEL_ZENITH[0]) / (_LEVEL_ZENITH[1] - _LEVEL_ZENITH[0]), 0.0,
                       1.0)
        weight = np.maximum(weight, ramp)
    weight = np.where(near, weight, 0.0)
    cos_z = np.cos(np.radians(np.minimum(zen, 90.0)))
    length = np.where(near, dh / np.maximum(cos_z, 1e-12), 0.0)
    return weight, lower + 0.5 * dh, length


def _shell_air_mass(zenith, scale_height=None, radius=6.371e6):
    """Air mass of a homogeneous spherical shell as thick as ``scale_height`` [m] (default
    :data:`_ABSORBER_SCALE_HEIGHT`) over a sphere of ``radius`` [m], seen from its bottom at
    ``zenith`` [deg]: the chord through it over its thickness, sqrt((r cos θ)² + 2r + 1) -
    r cos θ with r = R/H: 39 at 89.9 deg, where a flat Earth's 1/cos θ is 573.

    Examples
    --------
    >>> round(float(_shell_air_mass(0.0)), 12), round(float(_shell_air_mass(88.0)), 2)
    (1.0, 20.85)
    """
    r = radius / (_ABSORBER_SCALE_HEIGHT if scale_height is None else scale_height)
    c = np.cos(np.radians(np.asarray(zenith, dtype=float)))
    return np.sqrt((r * c) ** 2 + 2.0 * r + 1.0) - r * c


def _source_form(t0, l0, t1, l1, f):
    """Transmittance and path radiance between two nodes at fraction ``f``: τ log-linearly,
    L as the mean source B = L/(1 - τ), linear, times 1 - τ (a node with 1 - τ < 1e-3 takes
    the other's source; both: L linearly)."""
    tau = np.exp((1.0 - f) * np.log(np.maximum(t0, 1e-30)) + f * np.log(np.maximum(t1, 1e-30)))
    with np.errstate(divide="ignore", invalid="ignore"):
        ok0, ok1 = 1.0 - t0 > 1e-3, 1.0 - t1 > 1e-3
        b1 = np.where(ok1, l1 / (1.0 - t1), 0.0)
        b0 = np.where(ok0, l0 / (1.0 - t0), b1)
        b1 = np.where(ok1, b1, b0)
        rad = np.where(ok0 | ok1, ((1.0 - f) * b0 + f * b1) * (1.0 - tau),
                       (1.0 - f) * l0 + f * l1)
    return tau, rad


class DatabaseAtmosphere(SunDependentAtmosphere):
    """An atmosphere interpolated from a database file; see the module docstring."""

    name = "database"
    geometry_dependent = True

    def __init__(self, file=None, profile="us_standard", aerosol="rural", visibility=None,
                 surface_albedo=0.0, sun_zenith=None, sun_azimuth=0.0, view_azimuth=None,
                 earth_sun_distance=1.0, aot550=None, water=None, ozone=None,
                 solar_spectrum="radscene"):
        from radscene.atmosphere.options import ENGINE_SPECTRA

        spectrum = str(solar_spectrum).strip().lower()
        if spectrum not in ENGINE_SPECTRA["database"]:
            raise ConfigError(f"unknown value {solar_spectrum!r}; known: "
                              f"{', '.join(ENGINE_SPECTRA['database'])}",
                              key="atmosphere.solar_spectrum")
        self.solar_spectrum = spectrum
        self.file = database_path(file)
        self._mtime = self.file.stat().st_mtime
        ds = open_database(self.file)
        self.source = ds
        profiles = [str(p) for p in ds["profile"].values]
        prof = str(profile).lower()
        if prof not in profiles:
            raise ConfigError(f"profile {profile!r} is not in {self.file.name}; it holds: "
                              f"{', '.join(profiles)}{did_you_mean(prof, profiles)}", key="atmosphere.profile")
        self.profile = prof
        self._ip = profiles.index(prof)
        self._nodes = self._aerosol_nodes(aerosol, visibility, aot550)
        self._scales = self._absorber_scales(water, ozone)
        self._thermal_scales, self._thermal_refusal = self._thermal_absorbers(water, ozone)
        self._set_geometry(surface_albedo, earth_sun_distance, sun_zenith, sun_azimuth,
                           view_azimuth)
        self._prepare()

    # -- the condition -------------------------------------------------------------------------
    def _aerosol_nodes(self, aerosol, visibility, aot550):
        """[(condition index, weight)] of the aerosol asked for: the file's conditions of that
        model bracketing its AOT550 (the condition ``none``, where the file has it, is every
        model's AOT550 = 0 node); one condition with weight 1 at a node."""
        from radscene.atmosphere.sixs_runner import AEROSOLS
        from radscene.radiometry.units import parse_quantity

        ds = self.source
        models = [str(m) for m in ds["aerosol_model"].values]
        aer = str(aerosol).lower()
        self._curve = []  # between two nodes: the conditions of the path reflectance

        def same(a, b):
            return a == b or (a in AEROSOLS and AEROSOLS.get(a) == AEROSOLS.get(b))

        candidates = [i for i, m in enumerate(models) if same(m, aer)]
        if not candidates:
            raise ConfigError(f"aerosol {aerosol!r} is not in {self.file.name}; it holds: "
                              f"{', '.join(sorted(set(models)))}{did_you_mean(aer, sorted(set(models)))}",
                              key="atmosphere.aerosol")
        if aot550 is not None and visibility is not None:
            raise ConfigError("give visibility or aot550, not both", key="atmosphere.aot550")
        self.aerosol = models[candidates[0]]
        vis = np.asarray(ds["visibility"].values, dtype=float)
        if self.aerosol == "none":
            if aot550 not in (None, 0, 0.0):
                raise ConfigError("the aerosol 'none' has AOT550 0", key="atmosphere.aot550")
            self.aot550, self.visibility = 0.0, float("inf")
            return [(candidates[0], 1.0)]
        want_vis = None
        if aot550 is None:
            want_vis = 23000.0 if visibility is None else parse_quantity(
                visibility, "length", key="atmosphere.visibility")
            if not (np.isfinite(want_vis) and want_vis > 0):
                raise ConfigError(f"must be > 0; got {visibility!r}", key="atmosphere.visibility")
        if "aot550" not in ds:  # a file of visibility conditions only
            if aot550 is not None:
                raise ConfigError(f"{self.file.name} has no AOT550 axis: give a visibility "
                                  "(build a database with AOT550 nodes with `radscene "
                                  "atmosphere build`)", key="atmosphere.aot550")
            match = [i for i in candidates if abs(vis[i] / want_vis - 1.0) <= 0.02]
            if not match:
                have = ", ".join(f"{vis[i] / 1000:g} km" for i in candidates)
                raise ConfigError(f"{self.file.name} holds the {aer} aerosol at visibility "
                                  f"{have}; not {want_vis / 1000:g} km (build a database for it "
                                  "with `radscene atmosphere build`)",
                                  key="atmosphere.visibility")
            self.aot550, self.visibility = float("nan"), float(vis[match[0]])
            return [(match[0], 1.0)]
        aots = np.asarray(ds["aot550"].values, dtype=float)
        order = sorted(candidates, key=lambda i: aots[i])
        if aot550 is None:  # files with an AOT550 axis tabulate 6S's AOT550 of visibility
            # 6S's own relation, tabulated; linear in 1 / visibility (6S scales the extinction
            # of its profile with it) between and beyond the tabulated visibilities
            inv = 1.0 / np.asarray(ds["visibility_node"].values, dtype=float)[::-1]
            tau = np.asarray(ds["aot550_of_visibility"].values[order[-1]], dtype=float)[::-1]
            x = 1.0 / want_vis
            k = int(np.clip(np.searchsorted(inv, x) - 1, 0, inv.size - 2))
            want = float(tau[k] + (tau[k + 1] - tau[k]) / (inv[k + 1] - inv[k]) * (x - inv[k]))
            key = "atmosphere.visibility"
        else:
            want = float(aot550)
            key = "atmosphere.aot550"
            if not np.isfinite(want) or want < 0:
                raise ConfigError(f"must be >= 0; got {aot550!r}", key=key)
        nodes = [(float(aots[i]), i) for i in order]
        if "none" in models:
            nodes.insert(0, (0.0, models.index("none")))
        lo, hi = nodes[0][0], nodes[-1][0]
        if not (lo - 1e-9 <= want <= hi + 1e-9):
            given = (f"visibility {want_vis / 1000:g} km (AOT550 {want:.3g})"
                     if want_vis is not None else f"AOT550 {want:g}")
            raise ConfigError(f"{given} is outside the {self.aerosol} aerosol's range in "
                              f"{self.file.name}: AOT550 {lo:g}-{hi:g}", key=key)
        self.aot550 = want
        self.visibility = float("nan") if want_vis is None else float(want_vis)
        if want_vis is None:  # the visibility 6S gives it
            inv = 1.0 / np.asarray(ds["visibility_node"].values, dtype=float)
            tau = np.asarray(ds["aot550_of_visibility"].values[order[-1]], dtype=float)
            if tau[-1] <= want <= tau[0]:
                self.visibility = float(1.0 / np.interp(want, tau[::-1], inv[::-1]))
        for k, ((t0, i0), (t1, i1)) in enumerate(zip(nodes[:-1], nodes[1:], strict=True)):
            if t0 - 1e-9 <= want <= t1 + 1e-9:
                w = float(np.clip((want - t0) / (t1 - t0), 0.0, 1.0))
                if w <= 1e-9:
                    return [(i0, 1.0)]
                if w >= 1.0 - 1e-9:
                    return [(i1, 1.0)]
                self._curve = _quadratic_nodes(nodes, k, want)
                return [(i0, 1.0 - w), (i1, w)]
        return [(nodes[-1][1], 1.0)]

    def _absorber_scales(self, water, ozone):
        """(water vapour, ozone) scale factors of the profile's columns."""
        from radscene.atmosphere.sixs_runner import PROFILE_COLUMNS

        out = []
        for name, value, own, unit in (("water", water, 0, "g cm-2"),
                                       ("ozone", ozone, 1, "cm-atm")):
            if value is None:
                out.append(1.0)
                continue
            key = f"atmosphere.{name}"
            ref = PROFILE_COLUMNS.get(self.profile, (0.0, 0.0))[own]
            if not ref > 0:
                raise ConfigError(f"the profile {self.profile!r} holds no {name} to scale",
                                  key=key)
            if "gas_column_ozone" not in self.source:
                raise ConfigError(f"{self.file.name} cannot scale the columns (no ozone "
                                  "tables: rebuild it with `radscene atmosphere build`)",
                                  key=key)
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise ConfigError(f"a column in {unit}; got {value!r}", key=key) from None
            f = v / ref
            if not (np.isfinite(f) and 0.0 <= f <= _MAX_SCALE):
                raise ConfigError(f"{v:g} {unit} is outside 0-{_MAX_SCALE * ref:.3g} {unit} "
                                  f"({_MAX_SCALE:g} times the {self.profile} profile's "
                                  f"{ref:g})", key=key)
            out.append(f)
        return tuple(out)

    def _thermal_absorbers(self, water, ozone):
        """Scale factors of LOWTRAN's water-vapour and ozone columns of the profile for the
        thermal tables, and why they cannot be met (None: they can).

        The thermal tables were built with LOWTRAN's own columns of each profile
        (``thermal_profile_column``), at the nodes ``water_scale`` and ``ozone_scale``."""
        ds = self.source
        if (water is None and ozone is None) or "thermal_wavelength" not in ds.coords:
            return (1.0, 1.0), None
        if "thermal_ozone_transmittance" not in ds:  # written with the water tables
            return (1.0, 1.0), (
                f"{self.file.name} scales the water-vapour and ozone columns up to "
                f"{float(ds.attrs.get('reflective_max_wavelength', 4.0)):g} µm only (its thermal "
                f"tables hold the {self.profile} profile's own columns; rebuild it with "
                "`radscene atmosphere build`)", "atmosphere.water" if water is not None
                else "atmosphere.ozone")
        own = np.asarray(ds["thermal_profile_column"].values[self._ip], dtype=float)
        out = []
        for k, (name, value, unit) in enumerate((("water", water, "g cm-2"),
                                                 ("ozone", ozone, "cm-atm"))):
            if value is None:
                out.append(1.0)
                continue
            f = float(value) / own[k]
            nodes = np.append(np.asarray(ds[f"{name}_scale"].values, dtype=float), 1.0)
            lo, hi = nodes.min(), nodes.max()
            if not lo * (1 - 1e-6) <= f <= hi * (1 + 1e-6):  # the columns are stored as float32
                return (1.0, 1.0), (
                    f"{float(value):g} {unit} is outside the thermal tables' "
                    f"{lo * own[k]:.3g}-{hi * own[k]:.3g} {unit} ({lo:g}-{hi:g} times LOWTRAN's "
                    f"{own[k]:.3g} {unit} of the {self.profile} profile), which hold "
                    f"{float(ds['thermal_wavelength'].values[0]):.3g} µm and beyond",
                    f"atmosphere.{name}")
            out.append(float(np.clip(f, lo, hi)))
        return tuple(out), None

    def _scale_thermal(self, out, ia):
        """Condition ``ia``'s thermal tables ``out`` at the columns asked for.

        Water vapour: the tables at the ``water_scale`` nodes of the same condition (LOWTRAN's
        aerosol swells with the humidity, so each condition has its own), a monotone cubic
        (PCHIP) in the square root of the scale factor — of ln τ for the transmittances.
        Ozone: the aerosol-free tables at the ``ozone_scale`` nodes, in the driest air of the
        water nodes (its emission seen through a clear lower atmosphere), give the ozone's
        transmittance ratio r = τ(f)/τ(1) and its radiance; the ozone layer lies in front of
        a downward path (L ← r L + L_O3(f) - r L_O3(1)) and behind the lower atmosphere for
        the sky (L ← L + [L_O3(f) - L_O3(1)] τ_sky / τ_sky,O3(1)); τ ← r τ.
        """
        fw, fo = self._thermal_scales
        ds, ip = self.source, self._ip
        names = ("transmittance", "path_radiance", "sky_radiance", "sky_transmittance")
        if "thermal_level_transmittance" in ds:
            names += ("level_transmittance", "level_path_radiance")
        if self._thermal_refusal is not None:
            if "thermal_ozone_transmittance" in ds:  # out of the nodes: never used silently
                for name in names:
                    out["thermal_" + name] = np.full_like(out["thermal_" + name], np.nan)
            return
        if fw != 1.0:
            nodes = np.append(np.asarray(ds["water_scale"].values, dtype=float), 1.0)
            order = np.argsort(nodes)
            at_nodes = water_tables(self.file, ip, ia, self._mtime)
            for name in names:
                stack = np.concatenate([at_nodes[name], out["thermal_" + name][None]])
                out["thermal_" + name] = _pchip_scale(nodes[order], stack[order], fw,
                                                      name.endswith("transmittance"))
        if fo != 1.0:
            nodes = np.asarray(ds["ozone_scale"].values, dtype=float)

            def ozone(name, f):
                stack = np.asarray(ds["thermal_ozone_" + name].isel(profile=ip).values, float)
                return _pchip_scale(nodes, stack, f, name.endswith("transmittance"))

            with np.errstate(divide="ignore", invalid="ignore"):
                t1, tf = ozone("transmittance", 1.0), ozone("transmittance", fo)
                r = np.where(t1 > 1e-12, tf / t1, 1.0)
                out["thermal_path_radiance"] = (r * out["thermal_path_radiance"]
                                                + ozone("path_radiance", fo)
                                                - r * ozone("path_radiance", 1.0))
                out["thermal_transmittance"] = r * out["thermal_transmittance"]
                if "level_transmittance" in names:  # the ozone along the level air
                    t1, tf = ozone("level_transmittance", 1.0), ozone("level_transmittance", fo)
                    r = np.where(t1 > 1e-12, tf / t1, 1.0)
                    out["thermal_level_path_radiance"] = (
                        r * out["thermal_level_path_radiance"]
                        + ozone("level_path_radiance", fo) - r * ozone("level_path_radiance", 1.0))
                    out["thermal_level_transmittance"] = r * out["thermal_level_transmittance"]
                s1, sf = ozone("sky_transmittance", 1.0), ozone("sky_transmittance", fo)
                seen = np.where(s1 > 1e-3, out["thermal_sky_transmittance"] / s1, 1.0)
                out["thermal_sky_radiance"] = (out["thermal_sky_radiance"] + seen * (
                    ozone("sky_radiance", fo) - ozone("sky_radiance", 1.0)))
                out["thermal_sky_transmittance"] = np.where(
                    s1 > 1e-12, sf / s1, 1.0) * out["thermal_sky_transmittance"]

    # -- tables ------------------------------------------------------------------------------
    def _prepare(self):
        ds, ip = self.source, self._ip
        a = {k: np.asarray(ds[k].values, dtype=float) for k in (
            "scattering_wavelength", "surface_altitude", "observer_height", "sun_zenith",
            "view_zenith", "relative_azimuth", "wavelength", "airmass", "scattering_angle",
            "height", "phase_wavelength")}
        self.axes = a
        self._lam_s = a["scattering_wavelength"]
        self._x_nodes = np.where(a["observer_height"] >= model.TOP_OF_ATMOSPHERE, 1.0,
                                 -np.expm1(-a["observer_height"] / AEROSOL_SCALE_HEIGHT))
        lo, hi = float(self._lam_s[0]), float(ds.attrs.get("reflective_max_wavelength", 4.0))
        self.reflective_range = (float(ds.attrs.get("reflective_min_wavelength", lo)), hi)
        self.thermal = "thermal_wavelength" in ds.coords
        if self.thermal:
            self.axes["thermal_wavelength"] = np.asarray(ds["thermal_wavelength"].values, float)
            self.axes["sky_zenith"] = np.asarray(ds["sky_zenith"].values, float)
            heights = np.asarray(ds["thermal_observer_height"].values if
                                 "thermal_observer_height" in ds.coords else
                                 a["observer_height"], float)
            self._thermal_heights = heights
            self._thermal_x = np.where(heights >= model.TOP_OF_ATMOSPHERE, 1.0,
                                       -np.expm1(-heights / AEROSOL_SCALE_HEIGHT))
            self.level = "thermal_level_transmittance" in ds
            if self.level:
                self.axes["path_length"] = np.asarray(ds["path_length"].values, float)
            self.wavelength_range = (self.reflective_range[0],
                                     max(hi, float(self.axes["thermal_wavelength"][-1])))
        else:
            self.wavelength_range = self.reflective_range
        names = ["rho_mixture", "rho_rayleigh", "total_down", "total_up", "spherical_albedo",
                 "tau_rayleigh", "tau_aerosol", "omega_aerosol", "phase_rayleigh",
                 "phase_aerosol", "gas_column", "gas_column_no_water", "gas_partial",
                 "gas_partial_no_water", "rayleigh_fraction"]
        names += [k for k in ("gas_column_ozone", "gas_partial_ozone") if k in ds]
        if self.thermal:
            names += [k for k in ("thermal_transmittance", "thermal_path_radiance",
                                  "thermal_sky_radiance", "thermal_sky_transmittance",
                                  "thermal_level_transmittance",
                                  "thermal_level_path_radiance") if k in ds]

        def tables(ia):
            out = {}
            for name in names:
                da = ds[name]
                idx = {d: i for d, i in {"aerosol": ia, "profile": ip}.items() if d in da.dims}
                out[name] = np.asarray(da.isel(idx).values, dtype=float)
            if self.thermal and "thermal_sky_transmittance" in ds:
                self._scale_thermal(out, ia)
            return out

        snaps, self._conditions = [], []
        for ia in dict.fromkeys([ia for ia, _w in self._nodes]
                                + [ia for ia, _w in self._curve]):
            self.t = tables(ia)
            # phase functions on the scattering wavelengths, (angle, λs)
            self._pr_s = model.loglog_interp(self._lam_s, a["phase_wavelength"],
                                             self.t["phase_rayleigh"])
            self._pa_s = model.loglog_interp(self._lam_s, a["phase_wavelength"],
                                             self.t["phase_aerosol"])
            self._pa_s = _backscatter_smoothed(a["scattering_angle"], self._pa_s,
                                                _GLORY_RADIUS)
            self._ratio_tables()
            snaps.append((ia, self.t, (self.ratio, self.excess), self.share_down,
                          self.share_up))
            if self._curve:  # the condition on its own, for its path reflectance
                node = copy.copy(self)
                node.__dict__.pop("_sun_tables", None)
                node._curve, node._conditions = [], []
                self._conditions.append((node, dict(self._curve)[ia]))
        if len(self._nodes) == 2:
            # between two AOT550 nodes: the smooth factors, the transmittances and the
            # spherical albedo linearly in AOT550, the optical depth exactly (one model: it
            # scales with AOT550), the aerosol's optical properties those of the model (the
            # upper node; the lower may be 'none'); an aircraft's path reflectance under a low
            # sun from each condition's own (_path_reflectances)
            held = {ia: (t, r, d, u) for ia, t, r, d, u in snaps}
            (t0, r0, d0, u0), (t1, r1, d1, u1) = (held[ia] for ia, _w in self._nodes)
            w = self._nodes[1][1]

            def mix(x0, x1):
                return (1.0 - w) * x0 + w * x1

            self.t = dict(t1)
            for k in ("rho_mixture", "rho_rayleigh", "total_down", "total_up",
                      "spherical_albedo", "tau_aerosol", "thermal_transmittance",
                      "thermal_path_radiance", "thermal_sky_radiance",
                      "thermal_sky_transmittance", "thermal_level_transmittance",
                      "thermal_level_path_radiance"):
                if k in t1:
                    self.t[k] = mix(t0[k], t1[k])
            self.ratio = {k: mix(r0[0][k], r1[0][k]) for k in r1[0]}
            self.excess = {k: mix(r0[1][k], r1[1][k]) for k in r1[1]}
            self.share_down, self.share_up = mix(d0, d1), mix(u0, u1)

    def _fractions(self, h_t, dh):
        """Shares of the molecular and aerosol columns below observers Δh above h_t [m]."""
        a = self.axes
        h_t, dh = np.broadcast_arrays(np.atleast_1d(np.asarray(h_t, dtype=float)),
                                      np.atleast_1d(np.asarray(dh, dtype=float)))
        space = dh >= model.TOP_OF_ATMOSPHERE
        frac = self.t["rayleigh_fraction"]  # (h, height)
        ih, fh = model.axis_weights(h_t, a["surface_altitude"])
        nh = a["surface_altitude"].size
        ig, fg = model.axis_weights(np.minimum(dh, a["height"][-1]), a["height"])
        ng = a["height"].size
        fr = 0.0
        for hi_, hw in ((ih, 1 - fh), (np.minimum(ih + 1, nh - 1), fh)):
            fr = fr + hw * (frac[hi_, ig] * (1 - fg) + frac[hi_, np.minimum(ig + 1, ng - 1)] * fg)
        fr = np.where(space, 1.0, fr)
        x = np.where(space, 1.0, -np.expm1(-np.maximum(dh, 0.0) / AEROSOL_SCALE_HEIGHT))
        return fr, x

    def _ss(self, sun_zenith, view_zenith, relative_azimuth, tau_r, tau_a, fr, x, rayleigh_only):
        """Single-scattering reflectance, (λs, N), for view zeniths (N,) and τ's (λs, N)."""
        theta = model.scattering_angle_view(sun_zenith, view_zenith, relative_azimuth)
        pr = model.phase_interp(theta, self.axes["scattering_angle"], self._pr_s).T
        pa = model.phase_interp(theta, self.axes["scattering_angle"], self._pa_s).T
        om = self.t["omega_aerosol"][:, None]
        ta = 0.0 * tau_a if rayleigh_only else tau_a
        return model.single_scattering_reflectance(sun_zenith, view_zenith[None, :], pr, pa,
                                                   tau_r, ta, om, fr[None, :], x[None, :])

    def _ratio_tables(self):
        """ρ / ρ_ss at every node, the smooth factor the database interpolates; and the
        diffuse shares (T - e^{-τ/μ}) / (1 - e^{-τ/μ}) of the total transmittances."""
        a = self.axes
        self.ratio, self.excess = {}, {}
        hs, obs = a["surface_altitude"], a["observer_height"]
        col = self.t["tau_rayleigh"] + self.t["tau_aerosol"]  # (λs, h)
        mu_s = np.cos(np.radians(np.minimum(a["sun_zenith"], 89.0)))
        mu_v = np.cos(np.radians(np.minimum(a["view_zenith"], 89.0)))
        with np.errstate(divide="ignore", invalid="ignore"):
            direct = np.exp(-col[:, :, None] / mu_s)
            share = (self.t["total_down"] - direct) / (1.0 - direct)
            self.share_down = np.where(np.isfinite(share), share, 0.0)
            up = np.zeros_like(self.t["total_up"])
            for ih, h in enumerate(hs):
                fr, x = self._fractions(np.full(obs.size, h), obs)
                lay = (self.t["tau_rayleigh"][:, ih, None] * fr[None, :]
                       + self.t["tau_aerosol"][:, ih, None] * x[None, :])  # (λs, x)
                direct = np.exp(-lay[:, :, None] / mu_v)
                share = (self.t["total_up"][:, ih] - direct) / (1.0 - direct)
                up[:, ih] = np.where(np.isfinite(share), share, 0.0)
            up[:, :, 0] = up[:, :, 1]  # no layer: hold the lowest observer's share
            self.share_up = up
        for key, ray in (("rho_mixture", False), ("rho_rayleigh", True)):
            rho = self.t[key]  # (λs, h, x, θs, θv, φ)
            out = np.zeros_like(rho)
            excess = np.zeros_like(rho)
            for ih, h in enumerate(hs):
                for ix in range(obs.size):
                    if ix == 0:
                        continue
                    fr, x = self._fractions(h, obs[ix])
                    ss = model.single_scattering_grid(
                        a["sun_zenith"], a["view_zenith"], a["relative_azimuth"],
                        a["scattering_angle"], self._pr_s, self._pa_s, self.t["tau_rayleigh"][:, ih],
                        self.t["tau_aerosol"][:, ih], self.t["omega_aerosol"], float(fr[0]),
                        float(x[0]), ray)
                    with np.errstate(divide="ignore", invalid="ignore"):
                        r = np.where(ss > 0, rho[:, ih, ix] / np.where(ss > 0, ss, 1.0), 1.0)
                    out[:, ih, ix] = r
                    share = model.layer_share(
                        a["sun_zenith"][:, None, None], a["view_zenith"][None, :, None],
                        self.t["tau_rayleigh"][:, ih, None, None, None],
                        self.t["tau_aerosol"][:, ih, None, None, None], float(fr[0]),
                        float(x[0]))
                    excess[:, ih, ix] = (rho[:, ih, ix] - ss) / share
                out[:, ih, 0] = out[:, ih, 1]
                excess[:, ih, 0] = excess[:, ih, 1]
            self.ratio[key] = out
            self.excess[key] = excess

    def describe(self) -> dict:
        """The condition and the file's provenance."""
        ds = self.source
        return {"file": str(self.file), "profile": self.profile, "aerosol": self.aerosol,
                "visibility_m": self.visibility, "aot550": self.aot550,
                "aerosol_condition": " + ".join(f"{w:.4g} x {ds['aerosol'].values[i]}"
                                                for i, w in self._nodes),
                "water_scale": self._scales[0], "ozone_scale": self._scales[1],
                **{k: ds.attrs[k] for k in ("engine", "created", "radscene_version")
                   if k in ds.attrs}}

    # -- settings ----------------------------------------------------------------------------
    def check_wavelength(self, wavelength, key: str = "wavelength") -> np.ndarray:
        wl = super().check_wavelength(wavelength, key)
        if self._thermal_refusal is not None and wl.size:
            has_nodes = "thermal_ozone_transmittance" in self.source
            if ((has_nodes and np.nanmax(wl) >= self.axes["thermal_wavelength"][0])
                    or np.nanmax(wl) > self.reflective_range[1]):
                message, column = self._thermal_refusal
                advice = ("give a column within that range or choose the profile whose "
                          "columns are nearest" if has_nodes else
                          "choose the profile whose columns are nearest instead")
                raise ConfigError(f"{message}; asked for up to {np.nanmax(wl):g} µm "
                                  f"({key}): {advice}", key=column)
        if self.thermal and wl.size:
            gap = (wl > self.reflective_range[1]) & (wl < self.axes["thermal_wavelength"][0])
            if np.any(gap):
                raise ConfigError(f"{self.file.name} has no tables at {wl[gap].min():g} µm",
                                  key=key)
        elif wl.size and np.nanmax(wl) > self.reflective_range[1]:
            raise ConfigError(
                f"{self.file.name} covers {self.reflective_range[0]:g}–"
                f"{self.reflective_range[1]:g} µm (6S, reflective); asked for up to "
                f"{np.nanmax(wl):g} µm. Thermal tables are added by `radscene atmosphere "
                "build` with an emitting engine (lowtran)", key=key)
        return wl

    # -- interpolation helpers --------------------------------------------------------------
    def _e0(self, wavelength):
        from radscene.sun import toa_solar_irradiance

        return toa_solar_irradiance(wavelength, self.earth_sun_distance, self.solar_spectrum)

    def _spectral(self, table, wavelength):
        """log-log from the scattering wavelengths onto ``wavelength`` (last axis)."""
        return model.loglog_interp(wavelength, self._lam_s, table)

    def _fine(self, table, wavelength, axis=0):
        """Linear in wavelength from the gas grid; ``table`` has wavelength on ``axis``."""
        grid = self.axes["wavelength"]
        i, f = model.axis_weights(wavelength, grid)
        t = np.moveaxis(table, axis, -1)
        hi = np.minimum(i + 1, grid.size - 1)
        return t[..., i] * (1.0 - f) + t[..., hi] * f

    def _gas(self, table_name, wavelength, h_t, airmass, extra_index=None):
        """Gas transmittance at (h_t, airmass) per geometry × wavelength: (N, n), with the
        profile's water-vapour and ozone columns scaled by ``self._scales``.

        A column scaled by f absorbs along an airmass m as the profile's own column along
        f m (the absorber amount on the path is what counts; the line shapes of the layers
        stay those of the profile): T = T_rest(m) T_O3(f_O3 m) T_H2O(f_H2O m), with
        T_H2O = T_all / T_no_water and T_rest = T_no_water / T_O3 taken at one airmass.
        """
        fw, fo = self._scales
        if fw == 1.0 and fo == 1.0:
            return self._gas_table(table_name, wavelength, h_t, airmass, extra_index)
        base = table_name.replace("_no_water", "")

        def at(name, m):
            return self._gas_table(name, wavelength, h_t, m, extra_index)

        with np.errstate(divide="ignore", invalid="ignore"):
            nw, o3 = at(base + "_no_water", airmass), at(base + "_ozone", airmass)
            out = np.where(o3 > 0, nw / o3, 0.0) * at(base + "_ozone", fo * airmass)
            if base == table_name:
                m = fw * airmass
                all_, nw_m = at(base, m), at(base + "_no_water", m)
                out = out * np.where(nw_m > 0, all_ / nw_m, 0.0)
        return out

    def _gas_table(self, table_name, wavelength, h_t, airmass, extra_index=None):
        """One gas table at (h_t, airmass): (N, n). Beyond the airmass nodes the optical depth
        -ln T follows the power law of the two end nodes (exponent within 0.5-1, the strong-
        and weak-line limits); airmass 0 transmits all."""
        airmass = np.asarray(airmass, dtype=float)
        nodes = self.axes["airmass"]
        if np.all((airmass >= nodes[0]) & (airmass <= nodes[-1])):
            return self._gas_nodes(table_name, wavelength, h_t, airmass, extra_index)
        out = self._gas_nodes(table_name, wavelength, h_t,
                              np.clip(airmass, nodes[0], nodes[-1]), extra_index)
        for sel, (ma, mb) in ((airmass < nodes[0], (nodes[0], nodes[1])),
                              (airmass > nodes[-1], (nodes[-1], nodes[-2]))):
            if not np.any(sel):
                continue
            n = int(sel.sum())
            ta = self._gas_nodes(table_name, wavelength, h_t[sel], np.full(n, ma), extra_index)
            tb = self._gas_nodes(table_name, wavelength, h_t[sel], np.full(n, mb), extra_index)
            with np.errstate(divide="ignore", invalid="ignore"):
                da, db = -np.log(np.maximum(ta, 1e-300)), -np.log(np.maximum(tb, 1e-300))
                k = np.where((da > 0) & (db > 0), np.log(db / da) / np.log(mb / ma), 1.0)
            k = np.clip(np.nan_to_num(k, nan=1.0), 0.5, 1.0)
            ratio = (airmass[sel] / ma)[:, None]
            out[sel] = np.exp(-da * ratio ** k)
        return out

    def _gas_spectra(self, table_name, wavelength, extra_index=None):
        """A gas table on ``wavelength``, (h_t, m, n). The tables of the last wavelength grid
        asked for are kept: a band's queries (path, sun, sky, coupling) share its grid."""
        key = np.asarray(wavelength, dtype=float).tobytes()
        grid, tables = self.__dict__.get("_gas_grid") or (None, None)
        if grid != key:
            grid, tables = key, {}
            self._gas_grid = (grid, tables)
        name = (table_name, extra_index)
        if name not in tables:
            tab = self.t[table_name]  # (wl, h_t, [obs], m)
            if extra_index is not None:
                tab = tab[:, :, extra_index, :]
            tables[name] = self._fine(tab, wavelength, axis=0)
        return tables[name]

    def _gas_nodes(self, table_name, wavelength, h_t, airmass, extra_index=None):
        """Gas transmittance at (h_t, airmass) per geometry × wavelength: (N, n)."""
        tab = self._gas_spectra(table_name, wavelength, extra_index)  # (h_t, m, n)
        ih, fh = model.axis_weights(h_t, self.axes["surface_altitude"])
        logm = np.log(self.axes["airmass"])
        im, fm = model.axis_weights(np.log(np.maximum(airmass, 1.0)), logm)
        nh, nm = tab.shape[0], tab.shape[1]
        ih1, im1 = np.minimum(ih + 1, nh - 1), np.minimum(im + 1, nm - 1)
        out = 0.0
        for hi_, hw in ((ih, 1 - fh), (ih1, fh)):
            for mi_, mw in ((im, 1 - fm), (im1, fm)):
                out = out + (hw * mw)[:, None] * tab[hi_, mi_]
        return out

    def _geometry(self, observer_altitude, target_altitude, view_zenith):
        low = self.axes["surface_altitude"][0] - _BELOW_TABLE
        upper, lower, zen = model.check_path_geometry(observer_altitude, target_altitude,
                                                      view_zenith, min_target=low)
        hmax = self.axes["surface_altitude"][-1]
        if lower.size and lower.max() > hmax:
            raise ConfigError(f"{self.file.name} covers surface altitudes up to {hmax:g} m; "
                              f"a path ends at {lower.max():g} m", key="target_altitude")
        return upper, lower, zen

    def _at_sun(self, kind, name, sz):
        """The ``kind`` ("ratio" or "excess") table of ``name`` at a sun zenith ``sz`` [deg] as
        (top, rel): the top of the atmosphere's factor (λs, h, θv, φ), through a cubic spline
        in sun zenith (:data:`_SPLINE_LEVELS`), and each level's relative to it (λs, h, x, θv,
        φ; :func:`_relative`), linear in the sun's airmass 1/cos θ_s (a quotient: in its
        logarithm), as the build derives the aircraft levels from their coarse nodes. Kept
        for the last four suns asked for (a configured engine's queries share its sun; an
        aircraft level under a low sun also reads the two nodes about it)."""
        sun = (float(sz), _SPLINE_LEVELS)
        held = self.__dict__.setdefault("_sun_tables", {})
        if sun not in held:
            if len(held) >= 4:  # the sun asked for and the nodes about it
                held.pop(next(iter(held)))
            held[sun] = {}
        tables = held[sun]
        if (kind, name) not in tables:
            tab = getattr(self, kind)[name]  # (λs, h, x, θs, θv, φ)
            nodes = self.axes["sun_zenith"]
            top = np.tensordot(tab[:, :, -1],
                               _angle_weights(sz, nodes, _SPLINE_LEVELS != "none", refined=True)[0],
                               axes=([2], [0]))
            rel = _relative(tab, kind)
            airmass = 1.0 / np.cos(np.radians(np.minimum(nodes, 89.0)))
            i, f = model.axis_weights(np.array([1.0 / np.cos(np.radians(min(sz, 89.0)))]),
                                      airmass)
            i, f = int(i[0]), float(f[0])
            lo, hi = rel[:, :, :, i], rel[:, :, :, min(i + 1, nodes.size - 1)]
            if kind == "ratio":
                level = np.exp(np.log(lo) * (1.0 - f) + np.log(hi) * f)
            else:
                level = lo * (1.0 - f) + hi * f
            tables[kind, name] = (top, level)
        return tables[kind, name]

    def _scattering(self, sz_eff, u, h_t, vz, phis, simpson, wl) -> dict:
        """The scattering path reflectances ``rho_mixture`` and ``rho_rayleigh``, each (N, n) at
        ``wl`` (or (N, λs) at the scattering wavelengths when ``wl`` is None), of observers at
        ``u`` over targets at ``h_t`` [m] seen at view zeniths ``vz`` [deg], the sun at
        ``sz_eff`` [deg]; averaged over the relative azimuths ``phis`` [deg] with the weights
        ``simpson``: the single-scattering normaliser at the exact geometry times (or plus) the
        factor interpolated between the nodes."""
        a = self.axes
        dh = u - h_t
        space = u >= model.TOP_OF_ATMOSPHERE
        x = np.where(space, 1.0, -np.expm1(-np.maximum(dh, 0.0) / AEROSOL_SCALE_HEIGHT))
        ih, fh = model.axis_weights(h_t, a["surface_altitude"])
        ix, fx = model.axis_weights(x, self._x_nodes)
        nh, nx = a["surface_altitude"].size, self._x_nodes.size
        tau_r_q, tau_a_q = self._column_depths(h_t)  # (λs, N)
        fr_q, x_q = self._fractions(h_t, np.where(space, model.TOP_OF_ATMOSPHERE, dh))
        rho = {}
        # the factor interpolated: ρ/ρ_ss where single scattering carries the angular
        # structure (thin aerosol), ρ − ρ_ss where multiple scattering dominates (AOT550 ≳ 0.5;
        # there ρ/ρ_ss swings with the phase function between the nodes): the two blended by
        # the aerosol optical depth at each wavelength, linearly from 0.25 to 0.75. The excess
        # is held over the layer's share of single scattering (1 at the top of the
        # atmosphere), which carries its growth with observer height: interpolated raw and
        # linearly in x, it came out 7 % (0.5 km) to 13 % (6 km) above 6S at 0.44 um for the
        # continental aerosol at AOT550 0.6 with every angle on a node; 3.7 % and 4.4 % now
        blend = np.clip((tau_a_q - _BLEND[0]) / (_BLEND[1] - _BLEND[0]), 0.0, 1.0)  # (λs, N)

        w_line = _angle_weights(vz, a["view_zenith"], _SPLINE_LEVELS == "all")  # (N, nv)
        w_top = _angle_weights(vz, a["view_zenith"], _SPLINE_LEVELS != "none")

        def at_geometry(kind, name):
            # the top's factor (spline in angle) times (ratio) or plus (excess) each level's
            # relative to it (linear in view zenith, in x, in surface altitude)
            top, rel = self._at_sun(kind, name, sz_eff)  # (λs, h, θv, φ), (λs, h, x, θv, φ)
            acc = 0.0
            for hi_, hw in ((ih, 1 - fh), (np.minimum(ih + 1, nh - 1), fh)):
                at_top = np.einsum("lnvp,nv->lnp", top[:, hi_], w_top)
                level = 0.0
                for xi_, xw in ((ix, 1 - fx), (np.minimum(ix + 1, nx - 1), fx)):
                    level = level + np.einsum("lnvp,nv->lnp", rel[:, hi_, xi_],
                                              w_line * xw[:, None])
                acc = acc + hw[None, :, None] * (at_top * level if kind == "ratio"
                                                 else at_top + level)
            return acc

        # near backscatter the aerosol's phase function has its glory, which single scattering
        # at the exact angle carries and 6S's multiple scattering does not follow: there the
        # excess is the smooth factor whatever the optical depth (:data:`_GLORY_BLEND`)
        glory_depth = np.clip((tau_a_q - _GLORY_DEPTH[0]) / (_GLORY_DEPTH[1] - _GLORY_DEPTH[0]),
                              0.0, 1.0)  # (λs, N)
        glory = {phi: np.clip((model.scattering_angle_view(sz_eff, np.minimum(vz, 89.0), phi)
                               - _GLORY_BLEND[0]) / (_GLORY_BLEND[1] - _GLORY_BLEND[0]), 0.0, 1.0)
                 for phi in phis}
        for name, ray in (("rho_mixture", False), ("rho_rayleigh", True)):
            mixes = {phi: blend if ray else np.maximum(blend, glory[phi][None, :] * glory_depth)
                     for phi in phis}
            by_ratio = at_geometry("ratio", name)
            by_excess = (at_geometry("excess", name) if any(np.any(m > 0.0) for m in mixes.values())
                         else None)
            share_q = model.layer_share(sz_eff, np.minimum(vz, 89.0)[None, :], tau_r_q, tau_a_q,
                                        fr_q[None, :], x_q[None, :])
            total = 0.0
            for phi, w in zip(phis, simpson, strict=True):
                ss = self._ss(sz_eff, np.minimum(vz, 89.0), phi, tau_r_q, tau_a_q, fr_q, x_q, ray)
                value = model.azimuth_fourier(phi, *np.moveaxis(by_ratio, -1, 0)) * ss
                if by_excess is not None:
                    extra = (model.azimuth_fourier(phi, *np.moveaxis(by_excess, -1, 0))
                             * share_q + ss)
                    value = value * (1.0 - mixes[phi]) + extra * mixes[phi]
                total = total + w * value
            rho[name] = total.T if wl is None else self._spectral(total.T, wl)  # (N, n)
        return rho

    def _column_depths(self, h_t):
        """The molecular and aerosol optical depths of the columns above targets at ``h_t``
        [m], each (λs, N), linear between the surface-altitude nodes."""
        ih, fh = model.axis_weights(h_t, self.axes["surface_altitude"])
        ih1 = np.minimum(ih + 1, self.axes["surface_altitude"].size - 1)
        return tuple(t[:, ih] * (1 - fh) + t[:, ih1] * fh
                     for t in (self.t["tau_rayleigh"], self.t["tau_aerosol"]))

    def _single(self, sz_eff, u, h_t, vz, phis, simpson, ray):
        """The single-scattering path reflectance, averaged over ``phis`` as in
        :meth:`_scattering`, and the optical depth below the observer τ_l (the molecules' alone
        when ``ray``), each (N, λs), of observers at ``u`` over targets at ``h_t`` [m]."""
        tau_r, tau_a = self._column_depths(h_t)
        fr, x = self._fractions(h_t, u - h_t)
        ss = 0.0
        for phi, w in zip(phis, simpson, strict=True):
            ss = ss + w * self._ss(sz_eff, np.minimum(vz, 89.0), phi, tau_r, tau_a, fr, x, ray)
        below = tau_r * fr[None, :] + (0.0 if ray else tau_a * x[None, :])
        return ss.T, below.T

    def _scattering_levels(self, sz_eff, u, h_t, vz, phis, simpson, wl) -> dict:
        """:meth:`_scattering` with the observers below the highest aircraft node read from the
        two aircraft nodes about them (the two lowest below the lowest): single scattering at
        the exact height, and the multiply scattered rest ρ_ms = ρ − ρ_ss held as ρ_ms / τ_l
        linear in τ_l, the optical depth below the observer (ρ_ms = a τ_l + b τ_l², through
        zero at the ground and the two nodes).

        Interpolated as a factor linearly in the aerosol's share of the column (as between the
        other nodes), ρ_ms came out up to +230 % off 6S 3 km up and -78 % 250 m up under a sun
        at 85 deg (continental AOT550 0.6, 0.44 um, nadir): the factor is held over the
        layer's share of single scattering, which under a grazing sun falls by two orders of
        magnitude from 4 km down to 1 km, while ρ_ms grows about linearly with height. Against
        6S at 0.25-3 km, suns 10-85 deg, nadir and 40 deg, 0.44/0.55/0.86 um, continental
        AOT550 0.1 and 0.6 and maritime 0.3 and 1.0, with 6S's own values at the nodes 1 and
        4 km: between the nodes within 6.3 % (mean 0.7 %; 229 % and 0.9 % before), below
        1 km within 15 % (mean 2.6 %; 78 % and 6 % before). Under a higher sun the factor
        does as well and carries the database's validated figures, and near the 1 km node it
        did better (continental AOT550 0.6, sun 67 deg, 823 m up: +0.2 to +1.4 % against +1.1
        to +2.7 % at 0.45 um): the two are blended by the sun's zenith over
        :data:`_LEVEL_HEIGHTS`, the factor's alone below."""
        heights = self.axes["observer_height"]
        nodes = heights[(heights > 0.0) & (heights < model.TOP_OF_ATMOSPHERE)]
        dh = u - h_t
        inside = (u < model.TOP_OF_ATMOSPHERE) & (dh > 0.5)
        if nodes.size >= 2:
            inside &= ((dh < nodes[-1] - 0.5)
                       & (np.abs(dh[:, None] - nodes[None, :]).min(axis=1) > 0.5))
        weight = float(np.clip((sz_eff - _LEVEL_HEIGHTS[0])
                               / (_LEVEL_HEIGHTS[1] - _LEVEL_HEIGHTS[0]), 0.0, 1.0))
        if nodes.size < 2 or weight == 0.0 or not np.any(inside):
            return self._scattering(sz_eff, u, h_t, vz, phis, simpson, wl)
        out = {name: np.zeros((u.size, wl.size)) for name in ("rho_mixture", "rho_rayleigh")}
        by_factor = ~inside if weight == 1.0 else np.ones(u.size, dtype=bool)
        if np.any(by_factor):
            for name, value in self._scattering(sz_eff, u[by_factor], h_t[by_factor],
                                                vz[by_factor], phis, simpson, wl).items():
                out[name][by_factor] = value
        pair = np.clip(np.searchsorted(nodes, dh) - 1, 0, nodes.size - 2)
        for k in np.unique(pair[inside]):
            rows = np.nonzero(inside & (pair == k))[0]
            h, v = h_t[rows], vz[rows]
            ends = [(self._scattering(sz_eff, h + node, h, v, phis, simpson, None), h + node)
                    for node in nodes[k:k + 2]]
            for name in out:
                ray = name == "rho_rayleigh"
                ss, tau = self._single(sz_eff, u[rows], h, v, phis, simpson, ray)
                per_depth = []
                for values, level in ends:
                    ss_k, tau_k = self._single(sz_eff, level, h, v, phis, simpson, ray)
                    per_depth.append(((values[name] - ss_k) / tau_k, tau_k))
                (m0, t0), (m1, t1) = per_depth
                f = (tau - t0) / (t1 - t0)
                value = self._spectral(ss + tau * (m0 * (1.0 - f) + m1 * f), wl)  # (N, n)
                out[name][rows] = (1.0 - weight) * out[name][rows] + weight * value
        return out

    def _levels_by_quotient(self, rho, sz_eff, u, h_t, vz, phis, simpson, wl) -> dict:
        """``rho`` with the observers inside the atmosphere under a low sun read as the top of
        the atmosphere's path reflectance at the exact geometry times the level's quotient to
        it, log-linear in the sun's and the view's airmass between the nodes.

        Under a low sun the factor :meth:`_scattering` interpolates for an aircraft level (its
        excess over single scattering held over the layer's share, which falls with the
        sunlight left above the observer) grows steeply between the nodes while the path
        reflectance itself does not: 1 km up, continental AOT550 0.6, 0.45 um, nadir, 6S gives
        ρ = 0.02716, 0.02691 and 0.02354 at sun 60, 67 and 75 deg, while that factor goes
        0.119, 0.163, 0.311. Read linearly between 60 and 75 deg it came out +9 to +15 % off
        6S at sun 67 deg (and +270 to +670 % at 80 deg); the quotient ρ_level/ρ_top, in its
        logarithm, +0.5 to -0.8 % at 67 deg. Under a high sun the quotient misses the
        phase function's structure that the factor carries (maritime AOT550 0.3, 1 km, sun
        10 deg: +5.7 % against +1.2 %), so the quotient takes over between the sun zeniths of
        :data:`_LEVEL_QUOTIENT`."""
        m_s = 1.0 / np.cos(np.radians(sz_eff))
        lo, hi = (1.0 / np.cos(np.radians(z)) for z in _LEVEL_QUOTIENT)
        weight = float(np.clip((m_s - lo) / (hi - lo), 0.0, 1.0))
        inside = (u < model.TOP_OF_ATMOSPHERE) & (u - h_t > 0.5)
        if weight == 0.0 or not np.any(inside):
            return rho
        rows = np.nonzero(inside)[0]
        h, v = h_t[rows], vz[rows]
        top = np.full(rows.size, model.TOP_OF_ATMOSPHERE)
        level = u[rows]

        def airmass(z):
            return 1.0 / np.cos(np.radians(np.minimum(z, 89.0)))

        def bracket(values, nodes):
            m, mn = airmass(values), airmass(nodes)
            i, f = model.axis_weights(m, mn)
            return nodes[i], nodes[np.minimum(i + 1, nodes.size - 1)], f

        s0, s1, fs = bracket(np.array([sz_eff]), self.axes["sun_zenith"])
        v0, v1, fv = bracket(v, self.axes["view_zenith"])
        log_q = {name: 0.0 for name in rho}
        for sun, ws in ((float(s0[0]), 1.0 - float(fs[0])), (float(s1[0]), float(fs[0]))):
            for view, wv in ((v0, 1.0 - fv), (v1, fv)):
                if ws == 0.0 or not np.any(wv > 0.0):
                    continue
                below = self._scattering_levels(sun, level, h, view, phis, simpson, wl)
                above = self._scattering(sun, top, h, view, phis, simpson, wl)
                for name in rho:
                    with np.errstate(divide="ignore", invalid="ignore"):
                        log_q[name] = log_q[name] + ws * wv[:, None] * np.log(
                            below[name] / above[name])
        at_top = self._scattering(sz_eff, top, h, v, phis, simpson, wl)
        out = {}
        for name, value in rho.items():
            quotient = at_top[name] * np.exp(log_q[name])
            good = np.isfinite(quotient)
            mixed = value[rows] * (1.0 - weight) + np.where(good, quotient, value[rows]) * weight
            out[name] = value.copy()
            out[name][rows] = mixed
        return out

    def _path_reflectances(self, sz_eff, u, h_t, vz, phis, simpson, wl) -> dict:
        """``rho_mixture`` and ``rho_rayleigh``, each (N, n) at ``wl``. Between two AOT550
        nodes, for observers inside the atmosphere under a low sun (blended in over the sun
        zeniths of :data:`_AOT_CONDITIONS`), each condition's own path reflectance through
        the quadratic in AOT550 of :func:`_quadratic_nodes`; elsewhere the factors mixed
        linearly in AOT550 (one evaluation instead of three).

        The factors mixed linearly fail for an aircraft under a low sun, where the excess over
        single scattering is held over the layer's share of it and that share falls steeply
        with the optical depth: 1 km up, rural AOT550 0.5, nadir, 0.45 um, +3.5 % off 6S
        with the sun at 67 deg and +74 % at 85 deg, where the nodes 0.3 and 0.6 themselves
        are within 0.3 and 3.2 %. Each node's own path reflectance, mixed linearly, left -1.2
        and +3.0 %: 6S's own values at the nodes 0.3 and 0.6, mixed so, are -1.4 and +0.3 %
        off its value at 0.5 (-2.8 % at worst over suns 10-85 deg, 1-700 km, nadir and 40 deg,
        0.45-0.87 um, rural and maritime); through the nodes 0.3, 0.6 and 1.0 quadratically
        -0.8 % at worst under suns to 67 deg and -1.8 % at 85 deg. Under a higher sun, and from
        the top of the atmosphere, the mixed factors do as well (sun 10 and 30 deg, 1 and 3 km:
        within 3.3 %, the conditions' own within 1.8 %; the top at 67 deg: +1.4 % against
        +2.2 %) at a third of the cost."""
        def mixed(sel):  # the factors mixed linearly in AOT550
            rho = self._scattering_levels(sz_eff, u[sel], h_t[sel], vz[sel], phis, simpson, wl)
            return self._levels_by_quotient(rho, sz_eff, u[sel], h_t[sel], vz[sel], phis,
                                            simpson, wl)

        weight = float(np.clip((sz_eff - _AOT_CONDITIONS[0])
                               / (_AOT_CONDITIONS[1] - _AOT_CONDITIONS[0]), 0.0, 1.0))
        inside = (u < model.TOP_OF_ATMOSPHERE) & (u - h_t > 0.5)
        if not self._conditions or weight == 0.0 or not np.any(inside):
            return mixed(slice(None))
        rows = np.nonzero(inside)[0]
        own = {}
        for node, w in self._conditions:
            for name, value in node._path_reflectances(sz_eff, u[rows], h_t[rows], vz[rows],
                                                       phis, simpson, wl).items():
                own[name] = own.get(name, 0.0) + w * value
        # the mixed factors where they are still wanted: outside, and inside within the blend
        rest = ~inside if weight == 1.0 else np.ones(u.size, dtype=bool)
        by_factors = mixed(rest) if np.any(rest) else {}
        out = {}
        for name, value in own.items():
            out[name] = np.empty((u.size, wl.size))
            if name in by_factors:
                out[name][rest] = by_factors[name]
            out[name][rows] = value if weight == 1.0 else (
                (1.0 - weight) * out[name][rows] + weight * value)
        return out

    # -- the whole set of quantities ----------------------------------------------------------
    def components(self, observer_altitude, target_altitude, view_zenith, wavelength,
                   sun_zenith=None, relative_azimuth=None) -> dict:
        """Reflective-range quantities of lines of sight, each (N, n) (see ``SixSAtmosphere``).

        Returns a dict of arrays over (geometry, wavelength): ``path_reflectance``,
        ``transmittance``, ``direct_transmittance_up``, ``diffuse_transmittance_up``,
        ``gas_transmittance_up``, ``sun_transmittance``, ``direct_transmittance_down``,
        ``diffuse_transmittance_down``, ``gas_transmittance_down``, ``spherical_albedo``,
        ``optical_depth_rayleigh``, ``optical_depth_aerosol``, ``optical_depth_view``,
        ``toa_irradiance``, ``direct_irradiance``, ``diffuse_irradiance``, ``path_radiance``.
        """
        wl = np.atleast_1d(np.asarray(wavelength, dtype=float))
        sz = self.sun_zenith if sun_zenith is None else float(sun_zenith)
        if sz is None:
            raise ConfigError("the database engine needs the sun position for path radiance: "
                              "give sun_zenith or call set_sun()", key="atmosphere.sun_zenith")
        upper, lower, zen = self._geometry(observer_altitude, target_altitude, view_zenith)
        u, h_t, vz = upper.ravel(), lower.ravel(), zen.ravel()
        n = u.size
        dh = u - h_t
        space = u >= model.TOP_OF_ATMOSPHERE
        x = np.where(space, 1.0, -np.expm1(-np.maximum(dh, 0.0) / AEROSOL_SCALE_HEIGHT))
        sz_eff = min(sz, 89.0)
        mu_s = np.cos(np.radians(sz_eff))
        mu_v = np.cos(np.radians(np.minimum(vz, 89.0)))
        a = self.axes
        # --- scattering tables at λ_s ---------------------------------------------------------
        i_s, f_s = model.axis_weights(sz_eff, a["sun_zenith"])
        ih, fh = model.axis_weights(h_t, a["surface_altitude"])
        ix, fx = model.axis_weights(x, self._x_nodes)
        iv, fv = model.axis_weights(vz, a["view_zenith"])
        nh, nx, nv = a["surface_altitude"].size, self._x_nodes.size, a["view_zenith"].size
        if relative_azimuth is not None:
            phis = np.array([float(relative_azimuth)])
        elif self.view_azimuth is not None:
            phis = np.array([self.view_azimuth - self.sun_azimuth])
        else:  # the azimuthal mean: Simpson's rule over 0..180 deg
            phis = np.linspace(0.0, 180.0, 13)
        simpson = np.ones(phis.size) if phis.size == 1 else _simpson(phis.size)
        rho = self._path_reflectances(sz_eff, u, h_t, vz, phis, simpson, wl)
        # total transmittances (through their diffuse shares) and spherical albedo
        tdown = self.share_down  # (λs, h, θs)
        td = tdown[:, :, i_s] * (1 - f_s) + tdown[:, :, min(i_s + 1, tdown.shape[2] - 1)] * f_s
        td = td[:, ih] * (1 - fh) + td[:, np.minimum(ih + 1, nh - 1)] * fh  # (λs, N)
        tup = self.share_up  # (λs, h, x, θv)
        tu = 0.0
        for hi_, hw in ((ih, 1 - fh), (np.minimum(ih + 1, nh - 1), fh)):
            for xi_, xw in ((ix, 1 - fx), (np.minimum(ix + 1, nx - 1), fx)):
                for vi_, vw in ((iv, 1 - fv), (np.minimum(iv + 1, nv - 1), fv)):
                    tu = tu + (hw * xw * vw)[None, :] * tup[:, hi_, xi_, vi_]
        sa = self.t["spherical_albedo"]  # (λs, h)
        s_alb = sa[:, ih] * (1 - fh) + sa[:, np.minimum(ih + 1, nh - 1)] * fh
        tau_r, tau_a = self._column_depths(h_t)
        # fraction of each column below the observer
        frac = self.t["rayleigh_fraction"]  # (h, height)
        height = a["height"]
        ig, fg = model.axis_weights(np.minimum(dh, height[-1]), height)
        ng = height.size
        fr = 0.0
        for hi_, hw in ((ih, 1 - fh), (np.minimum(ih + 1, nh - 1), fh)):
            fr = fr + hw * (frac[hi_, ig] * (1 - fg) + frac[hi_, np.minimum(ig + 1, ng - 1)] * fg)
        fr = np.where(space, 1.0, fr)
        # back from diffuse shares to totals, at the scattering wavelengths
        col = tau_r + tau_a
        lay = tau_r * fr[None, :] + tau_a * x[None, :]
        d_down = np.exp(-col / mu_s)
        d_up = np.exp(-lay / mu_v[None, :])
        td = d_down + td * (1.0 - d_down)
        tu = d_up + tu * (1.0 - d_up)
        spec = {k: self._spectral(v.T, wl) for k, v in (
            ("t_down", td), ("t_up", tu), ("s_alb", s_alb), ("tau_r", tau_r), ("tau_a", tau_a))}
        tau_view = spec["tau_r"] * fr[:, None] + spec["tau_a"] * x[:, None]
        # --- gases ------------------------------------------------------------------------------
        m_s, m_v = 1.0 / mu_s, 1.0 / mu_v
        ms_arr = np.full(n, m_s)
        g_down = self._gas("gas_column", wl, h_t, ms_arr)
        gnw_down = self._gas("gas_column_no_water", wl, h_t, ms_arr)
        nodes_up, nodes_tot, nodes_nw = [], [], []
        for k, xk in enumerate(self._x_nodes):
            if xk == 0.0:
                nodes_up.append(np.ones((n, wl.size)))
                nodes_tot.append(g_down)
                nodes_nw.append(gnw_down)
            elif xk == 1.0:
                nodes_up.append(self._gas("gas_column", wl, h_t, m_v))
                nodes_tot.append(self._gas("gas_column", wl, h_t, m_s + m_v))
                nodes_nw.append(self._gas("gas_column_no_water", wl, h_t, m_s + m_v))
            else:
                part = self._gas("gas_partial", wl, h_t, m_v, extra_index=k)
                part_nw = self._gas("gas_partial_no_water", wl, h_t, m_v, extra_index=k)
                nodes_up.append(part)
                nodes_tot.append(g_down * part)
                nodes_nw.append(gnw_down * part_nw)

        def along_x(nodes):
            lo = np.stack(nodes)  # (k, N, n)
            rows = np.arange(n)
            return (lo[ix, rows] * (1 - fx)[:, None]
                    + lo[np.minimum(ix + 1, nx - 1), rows] * fx[:, None])

        g_up, g_tot, g_nw = along_x(nodes_up), along_x(nodes_tot), along_x(nodes_nw)
        zero = (dh <= 0.5) & ~space
        e0 = np.broadcast_to(self._e0(wl), (n, wl.size))
        t_dir_up = np.exp(-tau_view / mu_v[:, None])
        t_dir_up[zero] = 1.0
        g_up[zero] = 1.0
        t_dir_down = np.exp(-(spec["tau_r"] + spec["tau_a"]) / mu_s)
        if self.thermal:  # the sun's path at its own zenith (the scattering's stops at 89)
            self._thermal_gases(u, h_t, vz, min(sz, _BEYOND_ZENITH), wl, t_dir_up, t_dir_down,
                                g_up, g_down, g_tot, g_nw)
        rho_path = model.path_reflectance(rho["rho_mixture"], rho["rho_rayleigh"], g_tot, g_nw)
        rho_path[zero] = 0.0
        up_sun = sz < 90.0
        out = {
            "path_reflectance": rho_path,
            "transmittance": t_dir_up * g_up,
            "direct_transmittance_up": t_dir_up,
            "diffuse_transmittance_up": np.where(zero[:, None], 0.0,
                                                 np.maximum(spec["t_up"] - t_dir_up, 0.0)),
            "gas_transmittance_up": g_up,
            "sun_transmittance": t_dir_down * g_down if up_sun else np.zeros((n, wl.size)),
            "direct_transmittance_down": t_dir_down,
            "diffuse_transmittance_down": np.maximum(spec["t_down"] - t_dir_down, 0.0),
            "gas_transmittance_down": g_down,
            "gas_transmittance_total": g_tot,
            "spherical_albedo": spec["s_alb"],
            "optical_depth_rayleigh": spec["tau_r"],
            "optical_depth_aerosol": spec["tau_a"],
            "optical_depth_view": np.where(zero[:, None], 0.0, tau_view),
            "toa_irradiance": np.array(e0),
        }
        mu_sun = np.cos(np.radians(sz)) if up_sun else 0.0
        out["direct_irradiance"] = e0 * mu_sun * out["sun_transmittance"]
        out["diffuse_irradiance"] = (e0 * mu_sun * out["diffuse_transmittance_down"] * g_down
                                     if up_sun else np.zeros((n, wl.size)))
        out["path_radiance"] = (model.radiance_from_reflectance(rho_path, e0, sz) if up_sun
                                else np.zeros((n, wl.size)))
        return out

    # -- thermal tables -------------------------------------------------------------------------
    def _thermal_path(self, upper, lower, zen, wl):
        """(τ, L_thermal) from the thermal tables, (N, n), ones and zeros outside their range;
        and the wavelengths inside it.

        Over observer height the tables are read in the aerosol fraction below the observer
        x: the transmittance log-linearly, the path radiance as the mean source B = L/(1 - τ)
        (linear; at the surface node the next node's) times 1 - τ, which follows the path
        radiance's fast rise near the ground (linearly where 1 - τ < 1e-3). Beyond the tables'
        last view zenith a line of sight is extrapolated in air mass
        (:meth:`_beyond_thermal`); within the atmosphere, spanning up to the spans of
        :data:`_BEYOND_SPAN`, it goes over to the tables' value there and the level air of
        its extra length. Near the ground (an altitude span below :data:`_LEVEL_SPAN`) the
        level lines of sight at the path's mean altitude and length take over
        (:meth:`_level_thermal`)."""
        a = self.axes
        n = upper.size
        tw = a["thermal_wavelength"]
        inside = (wl >= tw[0]) & (wl <= tw[-1])
        tau = np.ones((n, wl.size))
        rad = np.zeros((n, wl.size))
        if not self.thermal or not np.any(inside):
            return tau, rad, inside
        dh = np.maximum(upper - lower, 0.0)
        space = upper >= model.TOP_OF_ATMOSPHERE
        z_max = float(a["view_zenith"][-1])
        t_s, l_s = self._slant_thermal(dh, lower, np.minimum(zen, z_max), space)  # (N, λt)
        beyond = zen > z_max
        if np.any(beyond):  # beyond the last zenith: extrapolated in air mass
            t_s[beyond], l_s[beyond] = self._beyond_thermal(dh[beyond], lower[beyond],
                                                            zen[beyond], space[beyond])
        if self.level:
            weight, mid, length = _level_weight(upper, lower, zen, horizon=False)
            # near the ground, the 85 deg value and the level air of the extra length
            with np.errstate(divide="ignore"):
                share = np.clip(np.log(_BEYOND_SPAN[1] / np.maximum(dh, 1e-9))
                                / np.log(_BEYOND_SPAN[1] / _BEYOND_SPAN[0]), 0.0, 1.0)
            far = beyond & ~space & (share > 0)
            if np.any(far):
                t_85, l_85 = self._slant_thermal(dh[far], lower[far], np.full(far.sum(), z_max),
                                                 space[far])
                mid_f = lower[far] + 0.5 * dh[far]
                # the level air's own length (uncapped, as that of the level blend below)
                length_f = dh[far] / np.maximum(np.cos(np.radians(np.minimum(zen[far], 90.0))),
                                                1e-12)
                t_far, _ = self._level_thermal(mid_f, length_f)
                t_edge, _ = self._level_thermal(mid_f, dh[far] / np.cos(np.radians(z_max)))
                with np.errstate(divide="ignore", invalid="ignore"):
                    t_new = t_85 * np.where(t_edge > 1e-30, t_far / t_edge, 0.0)
                    l_new = np.where(1.0 - t_85 > 1e-3, l_85 / (1.0 - t_85) * (1.0 - t_new),
                                     l_85)
                f = share[far][:, None]
                t_s[far] = f * t_new + (1.0 - f) * t_s[far]
                l_s[far] = f * l_new + (1.0 - f) * l_s[far]
            blend = weight > 0
            if np.any(blend):
                t_l, l_l = self._level_thermal(mid[blend], length[blend])
                w = weight[blend][:, None]
                t_s[blend] = (1.0 - w) * t_s[blend] + w * t_l
                l_s[blend] = (1.0 - w) * l_s[blend] + w * l_l
        tau[:, inside] = self._on_wavelengths(t_s, wl[inside])
        rad[:, inside] = self._on_wavelengths(l_s, wl[inside])
        if self.level:  # a line of sight shorter than half a metre
            zero = ~space & (dh <= 0.5 * np.cos(np.radians(np.minimum(zen, 90.0))))
        else:
            zero = (dh <= 0.5) & ~space
        tau[zero] = 1.0
        rad[zero] = 0.0
        return tau, rad, inside

    def _beyond_thermal(self, dh, lower, zen, space):
        """(τ, L) on the thermal wavelengths, (N, λt), of lines of sight beyond the tables'
        last view zenith, from their last two (θ₁ < θ₂): the optical depth -ln τ as a power
        of the air mass m (the power between the two, within 0.5-1: a band model's curve of
        growth), the path's mean source B = L/(1 - τ) linear in 1/m (an opaque path's
        radiance comes from the air within an optical depth of its end, whose altitude span
        shrinks as 1/m; a thin one's is the air's mean, the same at every zenith),
        L = B (1 - τ). The air mass is the flat scene's 1/cos θ within the atmosphere, and
        for lines from space that of a spherical shell of the air's scale height
        (:func:`_shell_air_mass`, :data:`_ABSORBER_SCALE_HEIGHT`): the sun and views from
        space near the horizon cross the curved atmosphere. Observers between the thermal
        tables' highest height under the top and the top go from one to the other linearly
        in their height above the target."""
        nodes = self.axes["view_zenith"]
        z1, z2 = float(nodes[-2]), float(nodes[-1])
        t1, l1 = self._slant_thermal(dh, lower, np.full(dh.size, z1), space)
        t2, l2 = self._slant_thermal(dh, lower, np.full(dh.size, z2), space)

        def depth(t):
            return np.maximum(-np.log(np.clip(t, 1e-30, 1.0)), 1e-12)

        # the shell's air mass from space, the flat scene's up to the thermal tables' highest
        # observer height under the top, linearly in the observer's height above the target
        # between (continuous at the top)
        heights = self._thermal_heights
        high = float(heights[-2]) if heights.size > 1 else 0.0
        curved = np.where(space, 1.0, np.clip((dh - high) / (model.TOP_OF_ATMOSPHERE - high),
                                              0.0, 1.0))

        def mass(z):
            z = np.broadcast_to(np.minimum(z, _BEYOND_ZENITH), dh.shape)
            return ((1.0 - curved) * air_mass(z) + curved * _shell_air_mass(z))[:, None]

        d1, d2 = depth(t1), depth(t2)
        m1, m2, m = mass(z1), mass(z2), mass(zen)
        power = np.clip(np.log(d2 / d1) / np.log(m2 / m1), 0.5, 1.0)
        d = d2 * (m / m2) ** power
        tau = np.exp(-d)
        with np.errstate(divide="ignore", invalid="ignore"):
            ok1, ok2 = 1.0 - t1 > 1e-3, 1.0 - t2 > 1e-3
            b2 = np.where(ok2, l2 / (1.0 - t2), 0.0)
            b1 = np.where(ok1, l1 / (1.0 - t1), b2)
            b2 = np.where(ok2, b2, b1)
            source = np.maximum(b2 + (b2 - b1) * (1.0 / m - 1.0 / m2) / (1.0 / m2 - 1.0 / m1),
                                0.0)
            rad = np.where(ok1 | ok2, source * (1.0 - tau), l2 * d / d2)
        return tau, rad

    def _level_reflective(self, tau, scattered, refl, wl, upper, lower, zen, view_azimuth,
                          sun_up):
        """Lines of sight near the ground and the horizon in the reflective tables' range
        (below the thermal tables'), blended into ``tau`` and ``scattered`` in place by
        :func:`_level_weight`: the level air at the line's mean altitude over its length.

        Extinction: the molecules' and aerosol's per metre, from the tables' optical depth of
        the 10 m above that altitude. Gases: the first observer level's partial column
        (1 km) at the air mass that holds the line's amount, r / (H x₁) with H the aerosol
        scale height (water vapour's, near the ground) and x₁ its fraction below that level.
        Scattered sunlight (Koschmieder 1924, a level path in uniform air): the sky's
        scattered radiance at 89 deg from the zenith, looking along the line, times
        1 - τ — the sky near the horizon is the light such air scatters over an endless path.
        """
        weight, mid, length = _level_weight(upper, lower, zen)
        sel = np.flatnonzero(weight > 0)
        if not sel.size or not np.any(refl):
            return
        w_ = wl[refl]  # scattered sunlight: the whole reflective range

        def own_range(w):
            return w < (self.axes["thermal_wavelength"][0] if self.thermal else np.inf)

        # the air at the top surface-altitude node stands for the air above it
        h, r = np.minimum(mid[sel], self.axes["surface_altitude"][-1]), length[sel]
        thin = 10.0
        c = self.components(h + thin, h, 0.0, w_, sun_zenith=self.sun_zenith if sun_up else 0.0,
                            relative_azimuth=0.0)
        depth = c["optical_depth_view"] / thin * r[:, None]
        x1 = float(self._x_nodes[1])
        heights = self.axes["observer_height"]
        mass = r / (AEROSOL_SCALE_HEIGHT * x1)
        if heights[1] < model.TOP_OF_ATMOSPHERE:
            gas = self._gas("gas_partial", w_, h, mass, extra_index=1)
        else:
            gas = self._gas("gas_column", w_, h, mass)
        t_level = np.exp(-depth) * gas
        if self.thermal and self.level:  # from 3 µm the level air's gases are the thermal tables'
            t_level[:, ~own_range(w_)] = self._on_wavelengths(
                self._level_thermal(mid[sel], length[sel])[0], w_[~own_range(w_)])
        wt = weight[sel][:, None]
        # transmittance below the thermal tables' range (there the thermal tables give it)
        own = own_range(w_)
        cols = np.flatnonzero(refl)[own]
        tau[np.ix_(sel, cols)] = (1.0 - wt) * tau[np.ix_(sel, cols)] + wt * t_level[:, own]
        if not sun_up:
            return
        look = view_azimuth if view_azimuth is not None else self.view_azimuth
        azimuths = (np.array([float(look) + 180.0]) if look is not None
                    else self.sun_azimuth + np.arange(0.0, 360.0, 30.0))
        air = np.zeros((sel.size, w_.size))
        for alt in np.unique(np.round(h, -1)):
            rows = np.round(h, -1) == alt
            sky = self.sky_parts(np.full(azimuths.size, 89.0), azimuths % 360.0, w_,
                                 SkyGeometry(float(alt), self.sun_zenith, self.sun_azimuth))
            air[rows] = sky.solar.mean(axis=0) * (1.0 - t_level[rows])
        cols = np.flatnonzero(refl)
        scattered[np.ix_(sel, cols)] = ((1.0 - wt) * scattered[np.ix_(sel, cols)] + wt * air)

    def _on_wavelengths(self, values, wl):
        """``values`` (N, λt) on the thermal tables' wavelengths at wavelengths ``wl`` [um]
        within their range, (N, n): linear between them."""
        tw = self.axes["thermal_wavelength"]
        iw, fw = model.axis_weights(wl, tw)
        return values[:, iw] * (1 - fw) + values[:, np.minimum(iw + 1, tw.size - 1)] * fw

    def _slant_thermal(self, dh, lower, zen, space):
        """(τ, L) on the thermal wavelengths, (N, λt), from the tables over (surface altitude,
        observer height, view zenith): linear in surface altitude and in air mass (linear in
        zenith, a 500 m path at 70 deg came out 4.5 % above LOWTRAN over 8-12 um), over
        observer height as :meth:`_thermal_path` says."""
        a = self.axes
        x = np.where(space, 1.0, -np.expm1(-dh / AEROSOL_SCALE_HEIGHT))
        nodes = self._thermal_x
        ih, fh = model.axis_weights(lower, a["surface_altitude"])
        ix, fx = model.axis_weights(x, nodes)
        iv, fv = model.axis_weights(air_mass(zen), air_mass(a["view_zenith"]))
        nh, nx, nv = a["surface_altitude"].size, nodes.size, a["view_zenith"].size

        def at(xi):
            out = []
            for name in ("thermal_transmittance", "thermal_path_radiance"):
                tab = self.t[name]  # (λt, h, x, θv)
                acc = 0.0
                for hi_, hw in ((ih, 1 - fh), (np.minimum(ih + 1, nh - 1), fh)):
                    for vi_, vw in ((iv, 1 - fv), (np.minimum(iv + 1, nv - 1), fv)):
                        acc = acc + (hw * vw)[None, :] * tab[:, hi_, xi, vi_]
                out.append(acc.T)
            return out

        t0, l0 = at(ix)
        t1, l1 = at(np.minimum(ix + 1, nx - 1))
        return _source_form(t0, l0, t1, l1, fx[:, None])

    def _level_thermal(self, altitude, length):
        """(τ, L) on the thermal wavelengths, (N, λt), of level lines of sight ``length`` [m]
        long at ``altitude`` [m]: between the surface-altitude nodes (held beyond them) the
        optical depth log-linearly, the radiance linearly; over length, the optical depth -ln τ log-log (a power of the length, as
        LOWTRAN's band model makes it: 1 - τ grew as r^0.6 over 1-30 m of air at 8-12 um),
        continued below the first node with the first step's power (within 0.5-1), and beyond
        the last in proportion; L = B (1 - τ) with the air's source B = L/(1 - τ) linear
        between the nodes."""
        a = self.axes
        lengths = a["path_length"]
        ih, fh = model.axis_weights(altitude, a["surface_altitude"])
        nh = a["surface_altitude"].size
        loglen = np.log(lengths)
        r = np.maximum(length, 1e-3)
        ir, fr = model.axis_weights(np.clip(np.log(r), loglen[0], loglen[-1]), loglen)
        nr = lengths.size

        def at(ri):
            # the optical depth log-linearly in altitude (the air thins exponentially), the
            # path radiance linearly
            tau = self.t["thermal_level_transmittance"]  # (λt, h, r)
            rad = self.t["thermal_level_path_radiance"]
            lo_, hi_ = ih, np.minimum(ih + 1, nh - 1)
            d = np.exp((1 - fh)[None, :] * np.log(depth(tau[:, lo_, ri]))
                       + fh[None, :] * np.log(depth(tau[:, hi_, ri])))
            return np.exp(-d).T, ((1 - fh)[None, :] * rad[:, lo_, ri]
                                  + fh[None, :] * rad[:, hi_, ri]).T

        def depth(t):
            return np.maximum(-np.log(np.clip(t, 1e-30, 1.0)), 1e-12)

        t0, l0 = at(ir)
        t1, l1 = at(np.minimum(ir + 1, nr - 1))
        d0, d1 = depth(t0), depth(t1)
        f = fr[:, None]
        d = np.exp((1.0 - f) * np.log(d0) + f * np.log(d1))
        with np.errstate(divide="ignore", invalid="ignore"):
            source = ((1.0 - f) * l0 / np.maximum(1.0 - t0, 1e-12)
                      + f * l1 / np.maximum(1.0 - t1, 1e-12))
        short = length < lengths[0]
        if np.any(short) and lengths.size > 1:  # below the first node: the first step's power
            t_1 = at(np.ones(r.size, dtype=np.int64))[0][short]
            power = np.clip(np.log(depth(t_1) / d0[short]) / np.log(lengths[1] / lengths[0]),
                            0.5, 1.0)
            d[short] = d0[short] * (r[short] / lengths[0])[:, None] ** power
        long = length > lengths[-1]
        if np.any(long):  # beyond the last node: in proportion
            d[long] = d1[long] * (length[long] / lengths[-1])[:, None]
        tau = np.exp(-d)
        return tau, source * (1.0 - tau)

    def _thermal_gases(self, upper, lower, zen, sun_zenith, wl, t_dir_up, t_dir_down, g_up,
                       g_down, g_tot, g_nw):
        """From the thermal tables' start (3 µm) on, the gases' transmittances of
        :meth:`components`, in place: the thermal tables' transmittance of the line of sight
        and of the sun's path from the top over the scattering tables' direct ones, so that
        the direct, the scattered and the coupling's light cross the gases that go with the
        thermal tables' path radiance (6S's gas model has neither water vapour's continuum
        nor its HDO band). The two-way gas transmittance keeps the scattering tables' ratio
        to the product of the one-way ones (the lines a path down saturates absorb less on
        the way up: 1.36-1.47 at 3.0-3.5 um from space), at most the smaller one-way one;
        the gases without water keep their share of the total."""
        over = wl >= self.axes["thermal_wavelength"][0]
        if not np.any(over):
            return
        w = wl[over]
        t_view, _, _ = self._thermal_path(upper, lower, zen, w)
        t_sun, _, _ = self._thermal_path(np.full(lower.size, model.TOP_OF_ATMOSPHERE),
                                            lower, np.full(lower.size, sun_zenith), w)
        with np.errstate(divide="ignore", invalid="ignore"):
            # the direct beams are the thermal tables' exactly: above 1 where the scattering
            # tables' extinction (plane-parallel, the sun held at 89 deg) is the larger
            up = np.maximum(t_view / t_dir_up[:, over], 0.0)
            down = np.maximum(t_sun / t_dir_down[:, over], 0.0)
            product = g_up[:, over] * g_down[:, over]
            correlation = np.where(product > 0, g_tot[:, over] / product, 1.0)
            dry = np.where(g_tot[:, over] > 0, g_nw[:, over] / g_tot[:, over], 1.0)
        g_up[:, over], g_down[:, over] = up, down
        g_tot[:, over] = np.minimum(up * down * np.maximum(correlation, 1.0),
                                    np.minimum(np.minimum(up, down), 1.0))
        g_nw[:, over] = np.clip(g_tot[:, over] * dry, 0.0, 1.0)

    def _forward_fraction(self, wavelength) -> np.ndarray:
        """Share of the aerosol's scattered light that goes into the forward hemisphere."""
        theta = np.radians(self.axes["scattering_angle"])
        pa = model.loglog_interp(wavelength, self.axes["phase_wavelength"],
                                 self.t["phase_aerosol"])  # (angle, n)
        dens = pa * np.sin(theta)[:, None]
        whole = np.trapezoid(dens, theta, axis=0)
        fwd = theta <= np.pi / 2
        return np.trapezoid(dens[fwd], theta[fwd], axis=0) / whole

    # -- the Atmosphere interface -------------------------------------------------------------
    couples = True

    def coupling(self, observer_altitude, target_altitude, view_zenith, wavelength
                 ) -> CouplingSpectra:
        """Diffuse transmittance up, spherical albedo and irradiances over black ground from
        the scattering tables (reflective range; zero beyond it, where nothing scatters).

        The molecular share of t_d is that of the light scattered forward in single
        scattering by the column above the target: τ_R / 2 against ω_A τ_A f_A, with f_A
        the aerosol phase function's forward-hemisphere fraction.
        """
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(observer_altitude), np.asarray(target_altitude),
                             np.asarray(view_zenith)).shape
        n = int(np.prod(shape))
        out = {k: np.zeros((n, wl.size)) for k in ("t_d", "share", "s", "dir", "dif")}
        refl = wl <= self.reflective_range[1]
        if np.any(refl):
            if self.sun_zenith is None:
                raise ConfigError("the database engine needs the sun position: give sun_zenith "
                                  "or call set_sun()", key="atmosphere.sun_zenith")
            w = wl[refl]
            c = self.components(observer_altitude, target_altitude, view_zenith, w,
                                sun_zenith=min(self.sun_zenith, _BEYOND_ZENITH))
            out["t_d"][:, refl] = c["diffuse_transmittance_up"] * c["gas_transmittance_up"]
            out["s"][:, refl] = c["spherical_albedo"]
            lay_r = c["optical_depth_rayleigh"] * 0.5
            lay_a = (c["optical_depth_aerosol"] * self._spectral(self.t["omega_aerosol"], w)
                     * self._forward_fraction(w))
            total = lay_r + lay_a
            with np.errstate(divide="ignore", invalid="ignore"):
                out["share"][:, refl] = np.where(total > 0, lay_r / total, 1.0)
            if self.sun_zenith < 90.0:
                out["dir"][:, refl] = c["direct_irradiance"]
                out["dif"][:, refl] = c["diffuse_irradiance"]
        full = shape + wl.shape
        return CouplingSpectra(*(out[k].reshape(full) for k in ("t_d", "share", "s", "dir",
                                                                 "dif")))

    def path(self, observer_altitude, target_altitude, view_zenith, wavelength,
             view_azimuth=None) -> PathSpectra:
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(observer_altitude), np.asarray(target_altitude),
                             np.asarray(view_zenith)).shape
        upper, lower, zen = self._geometry(observer_altitude, target_altitude, view_zenith)
        n = upper.size
        refl = wl <= self.reflective_range[1]
        tau = np.ones((n, wl.size))
        scattered = np.zeros((n, wl.size))
        if np.any(refl):
            if self.sun_zenith is None:
                raise ConfigError("the database engine needs the sun position for path "
                                  "radiance: give sun_zenith or call set_sun()",
                                  key="atmosphere.sun_zenith")
            rel = None if view_azimuth is None else float(view_azimuth) - self.sun_azimuth
            sun_up = self.sun_zenith < 90.0
            c = self.components(observer_altitude, target_altitude, view_zenith, wl[refl],
                                sun_zenith=self.sun_zenith if sun_up else 0.0,
                                relative_azimuth=rel)
            tau[:, refl] = c["transmittance"]
            if sun_up:
                scattered[:, refl] = c["path_radiance"]
            self._level_reflective(tau, scattered, refl, wl, upper.ravel(), lower.ravel(),
                                   zen.ravel(), view_azimuth, sun_up)
        thermal = np.zeros((n, wl.size))
        if self.thermal:
            t_tau, t_rad, inside = self._thermal_path(upper.ravel(), lower.ravel(),
                                                             zen.ravel(), wl)
            # from the thermal tables' start on, their transmittance: the one their path
            # radiance goes with (6S's gases leave out water's continuum and HDO at 3-4 µm)
            tau[:, inside] = t_tau[:, inside]
            thermal[:, inside] = t_rad[:, inside]
        full = shape + wl.shape
        return PathSpectra(transmittance=tau.reshape(full), thermal_radiance=thermal.reshape(full),
                           scattered_radiance=scattered.reshape(full))

    def sun(self, target_altitude, sun_zenith, wavelength, toa_irradiance) -> SunSpectra:
        wl = self.check_wavelength(wavelength)
        t, z = np.broadcast_arrays(np.asarray(target_altitude, float),
                                   np.asarray(sun_zenith, float))
        out = np.zeros(t.shape + wl.shape)
        refl = wl <= self.reflective_range[1]
        for idx in np.ndindex(t.shape):
            if z[idx] >= 90.0:
                continue
            row = np.zeros(wl.size)
            if np.any(refl):
                c = self.components(model.TOP_OF_ATMOSPHERE, t[idx], 0.0, wl[refl],
                                    sun_zenith=float(z[idx]), relative_azimuth=0.0)
                row[refl] = c["sun_transmittance"][0]
            if self.thermal:
                tau_t, _, inside = self._thermal_path(np.array([model.TOP_OF_ATMOSPHERE]),
                                                      np.array([t[idx]]), np.array([z[idx]]), wl)
                row[inside] = tau_t[0, inside]
            out[idx] = row
        return SunSpectra(transmittance=out, irradiance=out * np.asarray(toa_irradiance, float))

    def sky(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None) -> np.ndarray:
        parts = self.sky_parts(zenith, azimuth, wavelength, geometry)
        return parts.solar + parts.thermal

    def sky_parts(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None
                  ) -> SkyParts:
        """The sky's scattered sunlight (the reflective tables, the sun up) and emission (the
        thermal sky table) apart; :meth:`sky` is their sum."""
        wl = self.check_wavelength(wavelength)
        geometry = geometry or SkyGeometry(sun_zenith=self.sun_zenith or 0.0,
                                           sun_azimuth=self.sun_azimuth)
        z, az = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
        out = np.zeros(z.shape + wl.shape)
        thermal = np.zeros(z.shape + wl.shape)
        refl = wl <= self.reflective_range[1]
        if np.any(refl) and geometry.sun_zenith < 90.0:
            w = wl[refl]
            c = self.components(model.TOP_OF_ATMOSPHERE, geometry.target_altitude, 0.0, w,
                                sun_zenith=geometry.sun_zenith, relative_azimuth=0.0)
            row = {k: v[0] for k, v in c.items()}
            t_down = row["direct_transmittance_down"] + row["diffuse_transmittance_down"]
            lam_p = self.axes["phase_wavelength"]
            pr = model.loglog_interp(w, lam_p, self.t["phase_rayleigh"])
            pa = model.loglog_interp(w, lam_p, self.t["phase_aerosol"])
            om = self._spectral(self.t["omega_aerosol"], w)
            out[..., refl] = model.sky_radiance(
                z, az - geometry.sun_azimuth, geometry.sun_zenith, row["toa_irradiance"],
                row["gas_transmittance_down"], row["optical_depth_rayleigh"],
                row["optical_depth_aerosol"], om, self.axes["scattering_angle"], pr, pa,
                t_down, row["spherical_albedo"], self.surface_albedo)
        if self.thermal:
            tw = self.axes["thermal_wavelength"]
            inside = (wl >= tw[0]) & (wl <= tw[-1])
            if np.any(inside):
                tab = self.t["thermal_sky_radiance"]  # (λt, h, sky zenith)
                ih, fh = model.axis_weights(geometry.target_altitude, self.axes["surface_altitude"])
                nh = tab.shape[1]
                col = tab[:, int(ih)] * (1 - fh) + tab[:, min(int(ih) + 1, nh - 1)] * fh
                iz, fz = model.axis_weights(z, self.axes["sky_zenith"])
                nz = col.shape[1]
                iw, fw = model.axis_weights(wl[inside], tw)
                nw = tw.size
                at = (col[:, iz] * (1 - fz) + col[:, np.minimum(iz + 1, nz - 1)] * fz)  # (λt, S)
                at = np.moveaxis(at, 0, -1)
                thermal[..., inside] = (at[..., iw] * (1 - fw)
                                        + at[..., np.minimum(iw + 1, nw - 1)] * fw)
        return SkyParts(solar=out, thermal=thermal)

    # -- nodes ---------------------------------------------------------------------------------
    def path_nodes(self, observer_altitude, target_altitude, view_zenith,
                   relative_azimuth=None) -> PathNodes:
        """A grid over the pixels' geometry that refines the table: view zenith every 5 deg
        (2.5 beyond 70, the table's nodes included; linear weights in air mass, 1/cos θ_v,
        :mod:`radscene.atmosphere.nodes`), surface altitude every 250 m, observer
        altitude at its extremes; multilinear weights, up to 8 nodes per pixel (an axis the
        pixels share one value of, such as one camera's altitude, adds none); lines of
        sight near the horizon over their length instead
        (:func:`radscene.atmosphere.nodes.with_level_nodes`); with the
        pixels' ``relative_azimuth`` [deg] and the sun up, an axis of relative azimuth every
        10 deg over their range for the path radiance (:mod:`radscene.atmosphere.nodes`)."""
        obs = np.asarray(observer_altitude, float).ravel()
        tgt = np.asarray(target_altitude, float).ravel()
        vz = np.asarray(view_zenith, float).ravel()
        if vz.size == 0:
            return super().path_nodes(observer_altitude, target_altitude, view_zenith,
                                      relative_azimuth)
        self._geometry(obs, tgt, vz)
        from radscene.atmosphere.nodes import with_level_nodes

        nodes = with_level_nodes(obs, tgt, vz, self._steep_nodes)
        return self.azimuth_axis(nodes, vz, relative_azimuth)

    def _steep_nodes(self, obs, tgt, vz) -> PathNodes:
        """:meth:`path_nodes`' grid of lines of sight away from the horizon."""
        upper, lower, zen = self._geometry(obs, tgt, vz)
        del upper, lower
        zen = np.minimum(zen, 89.0)
        grid = np.unique(np.concatenate([np.arange(0.0, 70.0, 5.0), np.arange(70.0, 89.0, 2.5),
                                         [89.0], self.axes["view_zenith"]]))
        lo_v, hi_v = zen.min(), zen.max()
        keep = grid[(grid >= grid[grid <= lo_v].max()) & (grid <= grid[grid >= hi_v].min())]
        t_lo, t_hi = tgt.min(), tgt.max()
        n_t = max(1, int(np.ceil((t_hi - t_lo) / 250.0)))
        t_axis = np.unique(np.linspace(t_lo, t_hi, n_t + 1))
        o_axis = np.unique([obs.min(), obs.max()])
        # the view zenith of the downward form (observer below target: 180 - zenith)
        vz_down = np.where(obs >= tgt, vz, 180.0 - vz)
        from radscene.atmosphere.nodes import zenith_from_air_mass

        coords, index, weight = model.multilinear_nodes(
            [obs, tgt, air_mass(np.minimum(vz_down, 89.0))], [o_axis, t_axis, air_mass(keep)])
        down = zenith_from_air_mass(coords[2])
        node_vz = np.where(coords[0] >= coords[1], down, 180.0 - down)
        return PathNodes(observer_altitude=coords[0], target_altitude=coords[1],
                         view_zenith=node_vz, index=index, weight=weight)

    def sky_zenith_nodes(self) -> np.ndarray:
        return np.array([0.0, 15.0, 30.0, 45.0, 60.0, 70.0, 78.0, 84.0, 88.0])

    def sky_azimuth_nodes(self, sun_azimuth=None) -> np.ndarray:
        """Absolute azimuths [deg, clockwise from north]: the sun's and every 30 deg from it,
        with 15 deg steps within 30 deg of the sun (the aureole)."""
        sa = self.sun_azimuth if sun_azimuth is None else float(sun_azimuth)
        rel = np.array([0.0, 15.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0, 210.0, 240.0, 270.0,
                        300.0, 330.0, 345.0])
        return np.sort((sa + rel) % 360.0)
