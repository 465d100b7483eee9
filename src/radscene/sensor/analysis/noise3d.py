"""3-D noise decomposition of an image sequence (D'Agostino & Webb 1991).

A sequence ``U(t, v, h)`` (frames, rows, columns) is split into its mean S and seven
orthogonal components by directional averaging, as an analysis of variance:

===========  ======================  =====================================================
component    varies with             meaning
===========  ======================  =====================================================
``t``        frame                   frame-to-frame (frame mean) flicker
``v``        row                     fixed row noise
``h``        column                  fixed column noise
``tv``       frame, row              temporal row noise (streaks that change per frame)
``th``       frame, column           temporal column noise
``vh``       row, column             fixed pattern (pixel non-uniformity)
``tvh``      frame, row, column      random noise
===========  ======================  =====================================================

With m_x the mean over the axes not in x, e.g. N_t = m_t - S and
N_tv = m_tv - m_t - m_v + S; each figure is the standard deviation of its component array
over that array's own elements (``ddof=1`` by default, as pyradi's ``ry3dnoise``), and the
total is the root sum of squares of the seven.

References
----------
J. A. D'Agostino and C. M. Webb, "Three-dimensional analysis framework and measurement
methodology for imaging system noise", Proc. SPIE 1488, 110-121 (1991),
https://doi.org/10.1117/12.45794
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = ["Noise3D", "COMPONENTS", "noise_3d", "noise_3d_reference"]

#: The seven components, in the order of :class:`Noise3D`.
COMPONENTS = ("t", "v", "h", "tv", "th", "vh", "tvh")


@dataclass(frozen=True)
class Noise3D:
    """Result of :func:`noise_3d`: the mean and the seven component standard deviations.

    All in the unit of the input (e.g. [DN]). ``maps`` holds the component arrays, shaped to
    broadcast against the (frames, rows, columns) cube.
    """

    mean: float
    t: float
    v: float
    h: float
    tv: float
    th: float
    vh: float
    tvh: float
    maps: dict

    @property
    def total(self) -> float:
        """Root sum of squares of the seven components."""
        return float(np.sqrt(sum(getattr(self, c) ** 2 for c in COMPONENTS)))

    def as_dict(self) -> dict:
        """``{"mean": S, "t": ..., ..., "total": ...}``."""
        return {"mean": self.mean, **{c: getattr(self, c) for c in COMPONENTS},
                "total": self.total}


def _cube(cube):
    u = np.asarray(cube, dtype=np.float64)
    if u.ndim != 3 or min(u.shape) < 2:
        raise ConfigError(f"needs a (frames, rows, columns) cube with at least 2 of each; got "
                          f"shape {u.shape}", key="cube")
    return u


def noise_3d(cube, ddof: int = 1) -> Noise3D:
    """Decompose an image sequence into its 3-D noise components.

    Parameters
    ----------
    cube : array_like
        (frames, rows, columns), any unit.
    ddof : int
        Delta degrees of freedom of each standard deviation (1 as pyradi).

    Returns
    -------
    Noise3D

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> cube = 100 + 2.0 * rng.standard_normal((8, 64, 64))
    >>> r = noise_3d(cube)
    >>> round(r.total, 2), round(r.tvh, 2)   # white noise: tvh keeps (1-1/T)(1-1/V)(1-1/H) of it
    (2.0, 1.84)
    """
    u = _cube(cube)
    s = u.mean()
    m_t = u.mean(axis=(1, 2), keepdims=True)
    m_v = u.mean(axis=(0, 2), keepdims=True)
    m_h = u.mean(axis=(0, 1), keepdims=True)
    m_tv = u.mean(axis=2, keepdims=True)
    m_th = u.mean(axis=1, keepdims=True)
    m_vh = u.mean(axis=0, keepdims=True)
    maps = {
        "t": m_t - s,
        "v": m_v - s,
        "h": m_h - s,
        "tv": m_tv - m_t - m_v + s,
        "th": m_th - m_t - m_h + s,
        "vh": m_vh - m_v - m_h + s,
    }
    maps["tvh"] = u - m_tv - m_th - m_vh + m_t + m_v + m_h - s
    sd = {c: float(np.std(maps[c], ddof=ddof)) for c in COMPONENTS}
    return Noise3D(mean=float(s), maps=maps, **sd)


def noise_3d_reference(cube, ddof: int = 1) -> Noise3D:
    """Slow reference of :func:`noise_3d` with D'Agostino's sequential operators.

    Applies "subtract the mean along an axis" (S) and "average along an axis" (D) operators
    in sequence, one explicit loop per axis, as the 1991 paper describes them.
    """
    u = _cube(cube)
    nt, nv, nh = u.shape

    def avg(a, axis):
        out = np.zeros_like(np.take(a, [0], axis=axis))
        for i in range(a.shape[axis]):
            out += np.take(a, [i], axis=axis)
        return out / a.shape[axis]

    def sub(a, axis):
        return a - avg(a, axis)

    maps = {
        "t": avg(avg(sub(u, 0), 1), 2),
        "v": avg(avg(sub(u, 1), 0), 2),
        "h": avg(avg(sub(u, 2), 0), 1),
        "tv": avg(sub(sub(u, 0), 1), 2),
        "th": avg(sub(sub(u, 0), 2), 1),
        "vh": avg(sub(sub(u, 1), 2), 0),
        "tvh": sub(sub(sub(u, 0), 1), 2),
    }
    sd = {}
    for c in COMPONENTS:
        a = maps[c].ravel()
        sd[c] = float(np.sqrt(np.sum((a - a.mean()) ** 2) / (a.size - ddof)))
    return Noise3D(mean=float(avg(avg(avg(u, 0), 1), 2).item()), maps=maps, **sd)
