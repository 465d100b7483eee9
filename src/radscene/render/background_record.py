"""What a key frame's reflected background depends on beyond its pixels' own rays.

Between two key frames of a sequence (:mod:`radscene.render.key_frames`) a pixel's reflected
background (:mod:`radscene.render.background`) changes smoothly with time — the sun and the
temperatures at its paths' vertices — unless something moved through one of its paths or a
vertex's sun shadow changed. The first directions of the sky fan are tested every frame
against the moved objects' bounding spheres (:func:`~radscene.render.kept_fans.
fans_meet_spheres`); a key frame records the rest of each one-bounce path:

* the first directions drawn beyond the fan (the Phong lobes', the diffuse ones past the
  fan's count, those of BRDF models), met or not;
* at each vertex, its shadow ray towards the sun (where it faces the sun) and its occlusion
  ray towards the sky (where the path goes on upwards);
* per ray sample, a checksum of which of its vertices the sun lit.

A pixel whose recorded rays pass through none of the spheres of what moved, and whose
vertices the sun lit alike in the key frame behind and the one ahead, has the same paths at
every instant between: its background is interpolated with its other terms. The others are
shaded at the frame's instant. A shadow ray at an instant between lies in the wedge between
the two key frames' sun directions: the spheres are widened by the distance to the farthest
recorded origin times the tangent of the angle the sun turned (at most
:data:`~radscene.render.key_frames.MAX_SUN_STEP`). Lit alike at both ends is taken as lit
alike between: the sun turns one way, so only a still occluder narrower, seen from the
vertex, than that angle (a 0.9 m pole 1 km away at 0.05°; over the demo's 1 s between key
frames the sun turns 0.004°: 7 cm at 1 km) could shade a vertex between two instants at
which it is lit.

Memory: per recorded ray 56 bytes (origin and direction in float64, the ray sample), per ray
sample 8 bytes; on the demo (measured 2026-11-26) 0.21 M rays a key frame of its map (17 MB)
and 0.45 M of its oblique camera (31 MB): 96 MB for the two key frames of both.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from radscene.render.kept_fans import meets_spheres

__all__ = ["PathRecord", "meeting_samples"]

#: The constants of SplitMix64's finaliser (Steele, Lea & Flood 2014), which spreads each lit
#: vertex's key over 64 bits before it enters its sample's sum.
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_MIX = (np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB))


def _spread(key) -> np.ndarray:
    """SplitMix64 of ``key`` (uint64 array): two sets of lit vertices collide in their sum
    with a probability of about 2^-64, where a sum of the keys themselves would collide
    whenever the keys summed alike."""
    z = np.asarray(key, dtype=np.uint64) + _GOLDEN
    z = (z ^ (z >> np.uint64(30))) * _MIX[0]
    z = (z ^ (z >> np.uint64(27))) * _MIX[1]
    return z ^ (z >> np.uint64(31))


class PathRecord:
    """The rays and lit vertices of one render's background paths, by ray sample.

    Parameters
    ----------
    n_samples : int
        The render's ray samples.
    """

    def __init__(self, n_samples: int):
        self.origins, self.directions, self.samples = [], [], []
        self.checksum = np.zeros(int(n_samples), dtype=np.uint64)

    def bind(self, hidx) -> _Bound:
        """The record of one call of the pass, whose points are the ray samples ``hidx``."""
        return _Bound(self, np.asarray(hidx, dtype=np.int64))

    def finish(self) -> SimpleNamespace:
        """The record as arrays: ``origin`` (M, 3), ``direction`` (M, 3), ``sample`` (M,),
        ``checksum`` (n_samples,)."""
        if self.samples:
            origin, direction = np.concatenate(self.origins), np.concatenate(self.directions)
            sample = np.concatenate(self.samples)
        else:
            origin, direction, sample = np.zeros((0, 3)), np.zeros((0, 3)), np.zeros(0, np.int64)
        self.origins, self.directions, self.samples = [], [], []  # held once, as arrays
        return SimpleNamespace(origin=origin, direction=direction, sample=sample,
                               checksum=self.checksum)


class _Bound:
    """A :class:`PathRecord` seen through one call's points (index into ``hidx``)."""

    def __init__(self, record: PathRecord, hidx: np.ndarray):
        self.record, self.hidx = record, hidx

    def rays(self, point, origins, directions) -> None:
        """Rays (``origins``, ``directions`` (N, 3)) of the paths of the call's ``point``."""
        if len(point):
            self.record.origins.append(np.array(origins, dtype=np.float64))
            self.record.directions.append(np.array(directions, dtype=np.float64))
            self.record.samples.append(self.hidx[np.asarray(point)])

    def lit(self, point, path, lit) -> None:
        """The sun flags ``lit`` of vertices of paths ``path`` (the pass's path indices) of
        the call's ``point``: the lit ones enter their sample's checksum."""
        at = np.asarray(lit, dtype=bool)
        if not np.any(at):
            return
        key = _spread(np.asarray(path, dtype=np.uint64)[at])
        np.add.at(self.record.checksum, self.hidx[np.asarray(point)[at]], key)


def meeting_samples(record, spheres, turn=0.0) -> np.ndarray:
    """The ray samples (unique, int64) of ``record`` (:meth:`PathRecord.finish`) with a
    recorded ray through one of ``spheres`` (S, 4) (centre [m], radius [m]), each widened by
    the distance to the farthest recorded origin times tan ``turn`` [rad] (the angle the sun
    turns over the instants the record stands for)."""
    if record is None or not len(spheres) or not len(record.sample):
        return np.zeros(0, dtype=np.int64)
    spheres = np.array(spheres, dtype=float).reshape(-1, 4)
    if turn > 0.0:
        lo, hi = record.origin.min(axis=0), record.origin.max(axis=0)
        corner = np.maximum(np.abs(spheres[:, :3] - lo), np.abs(spheres[:, :3] - hi))
        spheres[:, 3] += np.linalg.norm(corner, axis=1) * np.tan(turn)
    met = meets_spheres(record.origin, record.direction, spheres)
    return np.unique(record.sample[met])
