"""Axes of the path nodes: view zenith by air mass, and the relative azimuth.

View zenith. Between path nodes the renderer interpolates linearly; a line of sight's
transmittance and path radiance are nearly linear in its air mass m = 1/cos θ_v (exactly so
for a thin layer), so the engines' view-zenith nodes are mixed linearly in m
(:func:`air_mass`): between nodes 5 deg apart at 55–60 deg the path radiance's error is
below 0.12 % where linear in θ_v it reaches 1.1 % (forward scattering, the shipped
database, sun at 60 deg).

Relative azimuth.

Light scattered into a line of sight depends on the scattering angle Θ between the sun's beam
and the line of sight, and for a horizontally uniform (plane-parallel) atmosphere on nothing
else of the azimuths than their difference:

.. math::

    \\cos\\Theta = -\\cos\\theta_s \\cos\\theta_v - \\sin\\theta_s \\sin\\theta_v \\cos\\phi,
    \\qquad \\phi = \\varphi_v - \\varphi_s,

with θ_s, θ_v the sun and view zeniths and φ_v the azimuth of the direction from the target
to the observer (φ = 0: the observer on the sun's side, the backscattering "hot" side). The
path radiance is therefore even in φ; radscene folds every relative azimuth into [0, 180] deg
(that is the wrap-around: 350 deg is 10 deg) and interpolates linearly between nodes that
cover the pixels' range, spaced by :data:`AZIMUTH_STEPS` according to how far from the
vertical the lines of sight reach: the azimuthal variation grows as sin θ_v, and towards the
horizon the scattering angle sweeps faster with φ. Measured against the shipped database
(sun at 60 deg, rural aerosol, 23 km; tests/system/test_per_ray_geometry.py) the rendered
path radiance is within 0.3 % of the engine's at the pixel's exact geometry up to 60 deg view
zenith with 10 deg nodes, and within 0.6 % up to 76 deg with 5 deg nodes. Over whole azimuth
profiles (sun at 30, 60 and 75 deg; 0.45–1.6 µm) linear interpolation is within 0.8 % with
30 deg nodes up to 10 deg view zenith (maritime aerosol: 1.2 %); beyond, the database's own
profile in φ bends where the
scattering angle crosses a node of its tabulated phase function (20 deg apart beyond 40 deg),
and 10 deg nodes can miss such a bend by up to 2 % (rural) or 4 % (maritime) — the table's
artefact, which 6S's smooth phase function does not have.

Lines of sight within :data:`VERTICAL_ZENITH` of the vertical have no azimuth that matters
(the dependence goes as sin θ_v); they take the nearest node of the others.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["AZIMUTH_STEPS", "VERTICAL_ZENITH", "LEVEL_ZENITH", "LEVEL_LENGTH_RATIO", "air_mass",
           "zenith_from_air_mass", "fold_relative_azimuth", "relative_azimuth_axis",
           "azimuth_step", "level_lines", "level_nodes", "merge_nodes", "with_level_nodes"]

#: Lines of sight within the atmosphere further than this from the vertical [deg] are near the
#: horizon: their path nodes are over path length, not air mass (:func:`with_level_nodes`).
LEVEL_ZENITH = 85.0
#: Ratio of consecutive path lengths of those nodes: linear between them, a level path's
#: transmittance exp(-k r) is at most 0.6 % high where k r = 1.
LEVEL_LENGTH_RATIO = 1.25
#: Top of the atmosphere [m]: an observer there is in space.
_TOP = 100_000.0
#: Least altitude span [m] of a level path node: its view zenith then carries its length (the
#: engines hold spans up to 0.5 m, ground-hit noise, at 89 deg).
_LEAST_SPAN = 1.0
#: Longest path length of a level node [m] (a line of sight at exactly 90 deg has none).
_LONGEST = 300_000.0

#: Spacing of the relative-azimuth nodes [deg] by the largest angle of the lines of sight
#: from the vertical [deg]: (up to that angle, spacing), in increasing order.
AZIMUTH_STEPS = ((10.0, 30.0), (60.0, 10.0), (90.0, 5.0))
#: Lines of sight closer than this to the vertical do not widen the azimuth axis [deg].
VERTICAL_ZENITH = 0.5


def air_mass(view_zenith) -> np.ndarray:
    """Plane-parallel air mass 1/cos θ_v of view zeniths [deg] in [0, 90) [-].

    Examples
    --------
    >>> air_mass([0.0, 60.0]).round(12).tolist()
    [1.0, 2.0]
    """
    return 1.0 / np.cos(np.radians(np.asarray(view_zenith, dtype=float)))


def level_lines(observer_altitude, target_altitude, view_zenith) -> np.ndarray:
    """Which lines of sight lie near the horizon (:data:`LEVEL_ZENITH`) with both ends within
    the atmosphere."""
    o, t, z = (np.asarray(x, dtype=float) for x in (observer_altitude, target_altitude,
                                                   view_zenith))
    return (np.minimum(z, 180.0 - z) > LEVEL_ZENITH) & (np.maximum(o, t) < _TOP)


def level_nodes(observer_altitude, target_altitude, view_zenith):
    """Path nodes of lines of sight near the horizon, and each one's weights on them.

    A level line of sight is its air's altitude and its length: in the flat scene a camera
    2 m up sees 1.1 km of air at 89.9 deg and 11 km at 89.99 deg, so air mass steps of any
    fixed size cannot follow it. The nodes are over the path length r = Δh/|cos θ|
    (geometric, :data:`LEVEL_LENGTH_RATIO` apart, over the lines' range, at most
    :data:`_LONGEST`), the altitude of the line's lower end and its altitude span Δh (each at
    its extremes where they spread over more than 1 m), looking down and looking up apart,
    with multilinear weights; a node's view zenith is arccos(Δh/r), its span at least
    :data:`_LEAST_SPAN` so that it carries the length.

    Returns
    -------
    PathNodes
    """
    from radscene.atmosphere.base import PathNodes
    from radscene.atmosphere.sixs_model import multilinear_nodes

    obs, tgt, vz = (np.ravel(np.asarray(x, dtype=float)) for x in np.broadcast_arrays(
        observer_altitude, target_altitude, view_zenith))
    parts = []
    for up in (False, True):
        sel = np.flatnonzero((obs < tgt) if up else (obs >= tgt))
        if not sel.size:
            continue
        low, span = np.minimum(obs[sel], tgt[sel]), np.abs(obs[sel] - tgt[sel])
        cos_z = np.abs(np.cos(np.radians(vz[sel])))
        length = np.clip(span / np.maximum(cos_z, 1e-12), 1.0, _LONGEST)
        lo, hi = float(length.min()), float(length.max())
        steps = int(np.ceil(np.log(hi / lo) / np.log(LEVEL_LENGTH_RATIO) - 1e-9))
        lengths = np.geomspace(lo, hi, steps + 1) if steps > 0 else np.array([lo])

        def extremes(v):
            return np.unique([v.min(), v.max()]) if np.ptp(v) > 1.0 else np.array([v.mean()])

        coords, index, weight = multilinear_nodes(
            [low, span, length], [extremes(low), extremes(span), lengths])
        node_low, node_span, node_r = coords
        node_span = np.maximum(node_span, _LEAST_SPAN)
        zen = np.degrees(np.arccos(np.minimum(node_span / node_r, 1.0)))
        # the lower end is the target looking down, the observer looking up
        parts.append((sel, PathNodes(
            observer_altitude=node_low if up else node_low + node_span,
            target_altitude=node_low + node_span if up else node_low,
            view_zenith=180.0 - zen if up else zen, index=index, weight=weight)))
    return merge_nodes(obs.size, parts)


def merge_nodes(n, parts):
    """One :class:`~radscene.atmosphere.base.PathNodes` of ``n`` lines of sight from
    ``parts``, each (the rows it holds, the nodes of those rows) without an azimuth axis."""
    from radscene.atmosphere.base import PathNodes

    width = max(p.index.shape[1] for _, p in parts)
    index = np.zeros((n, width), dtype=np.int64)
    weight = np.zeros((n, width))
    offset = 0
    for rows, p in parts:
        k = p.index.shape[1]
        index[rows, :k] = p.index + offset
        weight[rows, :k] = p.weight
        offset += p.size
    return PathNodes(
        observer_altitude=np.concatenate([p.observer_altitude for _, p in parts]),
        target_altitude=np.concatenate([p.target_altitude for _, p in parts]),
        view_zenith=np.concatenate([p.view_zenith for _, p in parts]),
        index=index, weight=weight)


def with_level_nodes(observer_altitude, target_altitude, view_zenith, steep):
    """Path nodes of lines of sight: ``steep(observer, target, zenith)`` (an engine's own
    grid) for those away from the horizon, :func:`level_nodes` for those near it."""
    obs, tgt, vz = (np.ravel(np.asarray(x, dtype=float)) for x in np.broadcast_arrays(
        observer_altitude, target_altitude, view_zenith))
    level = level_lines(obs, tgt, vz)
    if not np.any(level):
        return steep(obs, tgt, vz)
    parts = [(np.flatnonzero(level), level_nodes(obs[level], tgt[level], vz[level]))]
    if not np.all(level):
        rest = ~level
        parts.insert(0, (np.flatnonzero(rest), steep(obs[rest], tgt[rest], vz[rest])))
    return merge_nodes(obs.size, parts)


def zenith_from_air_mass(mass) -> np.ndarray:
    """The view zenith [deg] of a plane-parallel air mass >= 1 (inverse of :func:`air_mass`)."""
    return np.degrees(np.arccos(np.clip(1.0 / np.asarray(mass, dtype=float), -1.0, 1.0)))


def fold_relative_azimuth(view_azimuth, sun_azimuth) -> np.ndarray:
    """The line of sight's azimuth relative to the sun's, folded into [0, 180] deg.

    Parameters
    ----------
    view_azimuth : array_like
        Azimuth of the direction from the target to the observer [deg, clockwise from north].
    sun_azimuth : array_like
        Azimuth of the sun [deg], broadcast with ``view_azimuth``.

    Returns
    -------
    numpy.ndarray
        :math:`|\\varphi_v - \\varphi_s|` wrapped to [0, 180] [deg]; 0 puts the observer on
        the sun's side.

    Examples
    --------
    >>> fold_relative_azimuth([350.0, 10.0, 170.0, 200.0], 0.0).tolist()
    [10.0, 10.0, 170.0, 160.0]
    """
    v, s = np.broadcast_arrays(np.asarray(view_azimuth, dtype=float),
                               np.asarray(sun_azimuth, dtype=float))
    out = np.empty(v.shape)
    _fold(np.ascontiguousarray(v).reshape(-1), np.ascontiguousarray(s).reshape(-1),
          out.reshape(-1))
    return out if out.ndim else out[()]


@numba.njit(cache=True)
def _fold(view, sun, out):  # pragma: no cover - compiled
    """min(d, 360 - d), d = (view - sun) mod 360 (the sign of the divisor, as numpy's %)."""
    for i in range(view.size):
        d = (view[i] - sun[i]) % 360.0
        out[i] = min(d, 360.0 - d)


def azimuth_step(view_zenith) -> float:
    """The relative-azimuth node spacing [deg] for lines of sight of these view zeniths [deg]
    (:data:`AZIMUTH_STEPS`; looking up, the angle from the vertical is 180 - zenith).

    Examples
    --------
    >>> azimuth_step([0.0, 8.0]), azimuth_step([5.0, 45.0]), azimuth_step([30.0, 110.0])
    (30.0, 10.0, 5.0)
    """
    vz = np.asarray(view_zenith, dtype=float)
    off = float(np.nanmax(np.minimum(vz, 180.0 - vz))) if vz.size else 0.0
    for limit, step in AZIMUTH_STEPS:
        if off <= limit:
            return step
    return AZIMUTH_STEPS[-1][1]


def relative_azimuth_axis(relative_azimuth, view_zenith, step: float | None = None):
    """Relative-azimuth nodes that cover the lines of sight, and each one's linear weights.

    Parameters
    ----------
    relative_azimuth : array_like
        Relative azimuth of each line of sight [deg], any value (folded here), shape (N,).
    view_zenith : array_like
        View zenith of each [deg], shape (N,): lines of sight within
        :data:`VERTICAL_ZENITH` of the vertical (looking up or down) leave the range alone.
    step : float, optional
        Node spacing [deg], > 0; nodes sit at multiples of it (and at 180). Default
        :func:`azimuth_step` of ``view_zenith``.

    Returns
    -------
    nodes : numpy.ndarray
        The used nodes, increasing, in [0, 180] [deg], shape (n,).
    index : numpy.ndarray
        Shape (N, 2) int into ``nodes``: the two nodes each line of sight mixes (one column
        where there is a single node).
    weight : numpy.ndarray
        Shape (N, 2) (or (N, 1)), rows summing to 1 [-].

    Examples
    --------
    >>> nodes, index, weight = relative_azimuth_axis([22.0, 44.0, 338.0], [30.0, 30.0, 30.0])
    >>> nodes.tolist(), index.tolist(), weight.round(3).tolist()
    ([20.0, 30.0, 40.0, 50.0], [[0, 1], [2, 3], [0, 1]], [[0.8, 0.2], [0.6, 0.4], [0.8, 0.2]])
    """
    phi = fold_relative_azimuth(np.ravel(relative_azimuth), 0.0)
    vz = np.ravel(np.asarray(view_zenith, dtype=float))
    if vz.shape != phi.shape:
        raise ValueError(f"view_zenith: one per line of sight ({phi.size}); got {vz.size}")
    if step is None:
        step = azimuth_step(vz)
    if not step > 0:
        raise ValueError(f"step must be > 0 deg; got {step!r}")
    n = phi.size
    if n == 0:
        return np.zeros(1), np.zeros((0, 1), dtype=np.int64), np.ones((0, 1))
    any_slanted, lo, hi = _slanted_range(phi, vz, VERTICAL_ZENITH)
    if any_slanted:
        phi = np.clip(phi, lo, hi)  # the vertical ones take the nearest end of the range
    else:
        phi = np.full(n, phi.mean())
    grid = np.unique(np.concatenate([np.arange(0.0, 180.0, step), [180.0]]))
    if phi.min() == phi.max():  # one geometry: one node, exactly there
        return np.array([phi[0]]), np.zeros((n, 1), dtype=np.int64), np.ones((n, 1))
    i = np.clip(np.searchsorted(grid, phi, side="right") - 1, 0, grid.size - 2)
    frac = (phi - grid[i]) / (grid[i + 1] - grid[i])
    # a line of sight on a node uses that node only: no node of weight 0 everywhere
    lower = np.where(frac < 1.0, i, i + 1)
    upper = np.where(frac > 0.0, i + 1, lower)
    used = np.unique(np.concatenate([lower, upper]))
    lookup = np.full(grid.size, -1, dtype=np.int64)
    lookup[used] = np.arange(used.size)
    index = np.stack([lookup[lower], lookup[upper]], axis=1)
    weight = np.stack([1.0 - frac, frac], axis=1)
    return grid[used], index, weight


@numba.njit(cache=True)
def _slanted_range(phi, view_zenith, vertical):  # pragma: no cover - compiled
    """Whether any line of sight is more than ``vertical`` from the vertical, and the range
    of ``phi`` over those that are."""
    found = False
    lo = np.inf
    hi = -np.inf
    for i in range(phi.size):
        z = view_zenith[i]
        if z > vertical and z < 180.0 - vertical:
            found = True
            lo = min(lo, phi[i])
            hi = max(hi, phi[i])
    return found, lo, hi
