"""Line-of-sight geometry for LOWTRAN: the observer's end of a path, and path nodes.

Pure functions over numpy arrays; altitudes [m], angles [deg].
"""

from __future__ import annotations

import math

import numpy as np

from radscene.atmosphere.base import PathNodes

__all__ = ["DEFAULT_EARTH_RADIUS", "HORIZONTAL_LAYER", "NEAR_HORIZONTAL_SHARE",
           "observer_geometry", "path_kind", "path_node_grid"]

#: Top of LOWTRAN's atmosphere [m].
_TOP = 100_000.0

#: Earth radius LOWTRAN uses when card 3 leaves RO blank, except models 1, 4, 5 [m].
DEFAULT_EARTH_RADIUS = 6371.23e3


def observer_geometry(observer_altitude, target_altitude, view_zenith,
                      earth_radius=DEFAULT_EARTH_RADIUS):
    """Straight line of sight on a spherical Earth, seen from the observer's end.

    Parameters
    ----------
    observer_altitude, target_altitude : array_like
        Altitudes [m].
    view_zenith : array_like
        Zenith angle at the target of the direction towards the observer [deg].
    earth_radius : float
        [m].

    Returns
    -------
    observer_zenith : numpy.ndarray
        Zenith angle at the observer of the direction towards the target [deg] (LOWTRAN's
        ANGLE with H1 the observer).
    central_angle : numpy.ndarray
        Angle at the Earth's centre between target and observer [deg].
    distance : numpy.ndarray
        Length of the path [m]; NaN where no straight line joins them at that zenith
        (observer above the target but looking down, or below it but looking up).

    Notes
    -----
    Along a straight line :math:`r \\sin\\theta` is constant; the path length solves
    :math:`r_o^2 = r_t^2 + s^2 + 2 r_t s \\cos\\theta_t`.

    Examples
    --------
    >>> z, beta, s = observer_geometry(1000.0, 0.0, 0.0)
    >>> float(z), float(beta), float(s)
    (180.0, 0.0, 1000.0)
    """
    h_o, h_t, vz = np.broadcast_arrays(np.asarray(observer_altitude, float),
                                       np.asarray(target_altitude, float),
                                       np.asarray(view_zenith, float))
    r_o = earth_radius + h_o
    r_t = earth_radius + h_t
    cos_t = np.cos(np.radians(vz))
    sin_t = np.sin(np.radians(vz))
    disc = r_o**2 - (r_t * sin_t) ** 2
    up = r_o >= r_t
    with np.errstate(invalid="ignore"):
        root = np.sqrt(disc)
        s = np.where(up, -r_t * cos_t + root, -r_t * cos_t - root)
    ok = (disc >= 0) & np.where(up, cos_t >= -1e-12, cos_t <= 1e-12) & (s >= 0)
    s = np.where(ok, s, np.nan)
    cos_dir = np.clip((r_t * cos_t + s) / r_o, -1.0, 1.0)  # zenith of the ray at the observer
    observer_zenith = 180.0 - np.degrees(np.arccos(cos_dir))
    central = np.degrees(np.arctan2(s * sin_t, r_t + s * cos_t))
    return observer_zenith, central, s


#: A line of sight within the atmosphere is the flat scene's straight line of length
#: r = Δh / |cos θ| between its ends' altitudes where a ray leaving the target at its zenith
#: on the spherical Earth would rise to the observer's altitude over a length shorter by
#: more than this share of Δh (r² / 2R > share × Δh): towards the horizon, where the flat
#: scene and the sphere part.
NEAR_HORIZONTAL_SHARE = 0.01
#: Lines of sight within the atmosphere spanning at most this altitude [m] run as a level
#: (horizontal) path of their length at their mean altitude, whatever their zenith; so do
#: those near the horizon whose chord on the sphere would dip below their lower end. Over
#: 100 m such a path's thermal radiance was within 0.6 % of LOWTRAN's slant path (8-12 and
#: 4.4-4.9 um, zenith 0-85 deg), where a slant path of 10 m lost 7-10 % to its target's
#: lift of 1 m off the ground and LOWTRAN's slant geometry was uneven by 10-20 % below 30 m.
HORIZONTAL_LAYER = 100.0


def path_kind(observer_altitude, target_altitude, view_zenith, earth_radius=DEFAULT_EARTH_RADIUS,
              zero_length=0.5) -> tuple[str, float]:
    """How one line of sight is run, and its length in the flat scene [m].

    Returns
    -------
    kind : str
        ``"none"``: shorter than ``zero_length`` [m] (no path), or level with no length
        (zenith 90 deg); ``"contradiction"``: an observer above its target seen at a zenith
        beyond 90 deg, or below it at one short of 90; ``"slant"``: the straight line from
        the target at its zenith on the sphere (an observer at or above
        the top of LOWTRAN's atmosphere, 100 km, or far enough from the horizon, :data:`NEAR_HORIZONTAL_SHARE`);
        ``"chord"``: the straight line between the two altitudes with the flat scene's
        length; ``"horizontal"``: a level path of that length at the mean altitude (a span
        up to :data:`HORIZONTAL_LAYER`, or a chord that would dip below its lower end).
    length : float
        Δh / |cos θ| [m] (inf where level with a height difference).

    Examples
    --------
    >>> kind, length = path_kind(2.0, 0.0, 89.9)
    >>> kind, round(length, 1)
    ('horizontal', 1145.9)
    >>> path_kind(700.0, 0.0, 40.0)[0], path_kind(30.0, 0.0, 40.0)[0]
    ('slant', 'horizontal')
    """
    dh = abs(float(observer_altitude) - float(target_altitude))
    cos_z = math.cos(math.radians(float(view_zenith)))
    level = abs(cos_z) < 1e-12
    if (level and dh < zero_length) or (not level and dh / abs(cos_z) < zero_length):
        return "none", 0.0
    up = float(observer_altitude) > float(target_altitude)
    if level or (cos_z < 0 if up else cos_z > 0):
        # within the ground-hit noise an observer may lie on either side of its target
        return ("none", 0.0) if dh < zero_length else ("contradiction", math.inf)
    length = dh / abs(cos_z)
    if max(observer_altitude, target_altitude) >= _TOP - 1.0:
        return "slant", length
    if dh <= HORIZONTAL_LAYER:
        return "horizontal", length
    drop = length**2 / (2.0 * earth_radius)
    if drop <= NEAR_HORIZONTAL_SHARE * dh:
        return "slant", length
    return ("horizontal" if drop > dh else "chord"), length


#: Air mass of the steepest node of a grid (zenith 89 deg).
_AIRMASS_CAP = 1.0 / math.cos(math.radians(89.0))


def _axis(values, n_nodes: int, spread: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Nodes of one axis and each value's two bracketing nodes with linear weights."""
    lo, hi = float(values.min()), float(values.max())
    n = values.size
    if n_nodes < 2 or hi - lo <= spread:
        return (np.array([0.5 * (lo + hi)]), np.zeros((n, 1), dtype=np.int64), np.ones((n, 1)))
    nodes = np.linspace(lo, hi, n_nodes)
    i = np.clip(np.searchsorted(nodes, values, side="right") - 1, 0, n_nodes - 2)
    frac = np.clip((values - nodes[i]) / (nodes[i + 1] - nodes[i]), 0.0, 1.0)
    return nodes, np.stack([i, i + 1], axis=1), np.stack([1.0 - frac, frac], axis=1)


def _group_grid(obs, tgt, vz, zenith_nodes: int, looking_up: bool):
    """Grid nodes of lines of sight that all look down (or all up) from the target.

    The axes are air mass, target altitude and observer altitude; where a corner of that
    grid would put the observer on the wrong side of the target, the observer-minus-target
    altitude replaces the observer altitude, so that every node is a path that exists.
    """
    airmass = np.minimum(1.0 / np.maximum(np.abs(np.cos(np.radians(vz))), 1e-12), _AIRMASS_CAP)
    if looking_up:
        corners_ok = obs.max() <= tgt.min() + 0.5
    else:
        corners_ok = obs.min() >= tgt.max() - 0.5
    third = obs if corners_ok else obs - tgt
    axes = [_axis(airmass, zenith_nodes, 1e-9), _axis(tgt, 2, 1.0), _axis(third, 2, 1.0)]
    sizes = [a[0].size for a in axes]
    grid = np.array(np.meshgrid(*[np.arange(s) for s in sizes], indexing="ij")).reshape(3, -1)
    zenith = np.degrees(np.arccos(1.0 / axes[0][0][grid[0]]))
    if looking_up:
        zenith = 180.0 - zenith
    target = axes[1][0][grid[1]]
    observer = axes[2][0][grid[2]] if corners_ok else target + axes[2][0][grid[2]]
    (_, i0, w0), (_, i1, w1), (_, i2, w2) = axes
    index = (i0[:, :, None, None] * sizes[1] * sizes[2] + i1[:, None, :, None] * sizes[2]
             + i2[:, None, None, :])
    weight = w0[:, :, None, None] * w1[:, None, :, None] * w2[:, None, None, :]
    n = obs.size
    return observer, target, zenith, index.reshape(n, -1), weight.reshape(n, -1)


def path_node_grid(observer_altitude, target_altitude, view_zenith, zenith_nodes: int = 6,
                   max_distinct: int = 8) -> PathNodes:
    """Path nodes of many lines of sight and each one's weights on them.

    Parameters
    ----------
    observer_altitude, target_altitude : array_like
        [m], one per line of sight (broadcast).
    view_zenith : array_like
        Zenith angle at the target of the direction towards the observer [deg].
    zenith_nodes : int
        Nodes along the air-mass axis of a grid.
    max_distinct : int
        Up to this many distinct geometries (altitudes rounded to 1 m, zenith to 0.01 deg)
        each become a node of their own, with weight 1.

    Returns
    -------
    PathNodes
        Beyond ``max_distinct``: lines of sight looking down and looking up each get a grid
        of ``zenith_nodes`` air masses (1/|cos θ|, at most that of 89 deg) × target altitude
        × observer altitude (two nodes each where they spread over more than 1 m, else one),
        with multilinear weights summing to 1. Where a corner of that grid would put the
        observer on the wrong side of the target, the observer-minus-target altitude takes
        the observer altitude's place, so that every node is a path that exists. Lines of
        sight near the horizon get nodes over their length instead
        (:func:`radscene.atmosphere.nodes.with_level_nodes`).

    Examples
    --------
    >>> nodes = path_node_grid([3000.0, 3000.0], [0.0, 0.0], [10.0, 10.0])
    >>> nodes.size, nodes.weight.tolist()
    (1, [[1.0], [1.0]])
    """
    obs, tgt, vz = (np.ravel(np.asarray(x, dtype=float)).copy() for x in
                    np.broadcast_arrays(observer_altitude, target_altitude, view_zenith))
    n = obs.size
    if n == 0:
        return PathNodes(np.array([1.0]), np.array([0.0]), np.array([0.0]),
                         np.zeros((0, 1), dtype=np.int64), np.ones((0, 1)))
    keys = np.stack([np.round(obs), np.round(tgt), np.round(vz, 2)], axis=1)
    unique, inverse = np.unique(keys, axis=0, return_inverse=True)
    from radscene.atmosphere.nodes import level_lines, with_level_nodes

    if len(unique) <= max_distinct and not np.any(level_lines(obs, tgt, vz)):
        return PathNodes(observer_altitude=unique[:, 0].copy(), target_altitude=unique[:, 1].copy(),
                         view_zenith=unique[:, 2].copy(),
                         index=inverse.reshape(n, 1).astype(np.int64), weight=np.ones((n, 1)))
    return with_level_nodes(obs, tgt, vz, lambda o, t, z: _grid(o, t, z, zenith_nodes))


def _grid(obs, tgt, vz, zenith_nodes) -> PathNodes:
    """:func:`path_node_grid`'s grid of lines of sight away from the horizon."""
    n = obs.size
    parts, offset = [], 0
    index = None
    for looking_up in (False, True):
        sel = (vz > 90.0) if looking_up else (vz <= 90.0)
        if not np.any(sel):
            continue
        o, t, z, idx, w = _group_grid(obs[sel], tgt[sel], vz[sel], zenith_nodes, looking_up)
        parts.append((sel, o, t, z, idx + offset, w))
        offset += o.size
    width = max(p[4].shape[1] for p in parts)
    index = np.zeros((n, width), dtype=np.int64)
    weight = np.zeros((n, width))
    for sel, _, _, _, idx, w in parts:
        index[sel, : idx.shape[1]] = idx
        weight[sel, : w.shape[1]] = w
    return PathNodes(observer_altitude=np.concatenate([p[1] for p in parts]),
                     target_altitude=np.concatenate([p[2] for p in parts]),
                     view_zenith=np.concatenate([p[3] for p in parts]), index=index, weight=weight)
