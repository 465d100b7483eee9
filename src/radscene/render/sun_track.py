"""The sun of a render: one position for a frame, the position at each ray's time for scanners.

A frame camera takes its image at one instant: the scene's sun (hand-placed, or the ephemeris
at ``environment.time``). A pushbroom or whiskbroom scanner takes each line, or each sample, at
its own time (``RayBundle.time``, seconds after the observer's epoch), and over a long flight
line or orbital pass the sun moves — a quarter of a degree a minute — so the render follows it:

* **geometry, per ray** — the cosine of incidence, the shadow rays and the specular mirror
  direction use the sun's direction at the ray's own time, interpolated linearly (then
  renormalised) between ephemeris samples (NREL SPA, :func:`radscene.sun.sun_position`)
  :data:`EPHEMERIS_STEP` apart: within 10⁻⁵ deg of the ephemeris itself;
* **spectra, per sun node** — the sun's transmittance and irradiance, the sky radiance and the
  path radiance are evaluated at a few *sun nodes*, times spaced so that the sun moves at most
  :data:`SUN_NODE_STEP` between two, and each ray mixes the two nodes around its time with
  linear weights in time; a scan during which the sun moves less than 0.01 deg (a satellite's
  image of a few seconds) has one, at its middle time. The renderer folds this axis into the path nodes' (the band tables
  are built once per sun node and path node: :func:`combine_nodes`).

The sun's position is the one seen from the scene's origin (``environment.location``): across
a scene of a few kilometres it differs by less than 0.03 deg.
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["SunGeometry", "SunTrack", "sun_geometry", "sun_track", "combine_nodes",
           "SUN_NODE_STEP", "EPHEMERIS_STEP"]

#: Largest angle the sun moves between two sun nodes of the spectral tables [deg].
SUN_NODE_STEP = 0.5
#: Spacing of the ephemeris samples the per-ray sun direction is interpolated between [s].
EPHEMERIS_STEP = 10.0
#: At most this many ephemeris samples (a pass of 11 hours at the step above) [-].
_MAX_SAMPLES = 4096
#: Below this travel over the rays' times the sun stands still for every ray [deg].
_STILL = 1e-4
#: Below this travel one sun node, at the middle time, serves the spectra: its zenith is
#: within 0.005 deg of every ray's [deg].
_ONE_NODE = 0.01


@dataclass(frozen=True)
class SunGeometry:
    """Where the sun is for a render: angles [deg], Earth–Sun distance [AU], unit vector to it."""

    zenith: float
    azimuth: float
    distance: float

    @property
    def direction(self) -> np.ndarray:
        from radscene.geometry.frames import direction_from_angles

        return direction_from_angles(self.zenith, self.azimuth)


def sun_geometry(scene) -> SunGeometry:
    """The sun of a scene: the hand-placed one, or the ephemeris at its place and time."""
    if scene.sun is not None:
        return SunGeometry(scene.sun.zenith, scene.sun.azimuth, scene.sun.distance)
    from radscene.sun import sun_position

    pos = sun_position(
        scene.time, scene.location.latitude, scene.location.longitude, scene.location.altitude
    )
    return SunGeometry(float(pos.zenith), float(pos.azimuth), float(pos.distance))


@dataclass(frozen=True)
class SunTrack:
    """The sun over a render's acquisition times.

    Attributes
    ----------
    nodes : tuple of SunGeometry
        The sun at the sun nodes, in time order: the band tables are built once per node.
    node_time : numpy.ndarray
        Times of the nodes [s after the epoch], shape (n_nodes,) (NaN for a fixed sun).
    sample_time : numpy.ndarray
        Times of the ephemeris samples [s], shape (n_samples,) (empty for a fixed sun).
    sample_direction : numpy.ndarray
        Unit vectors towards the sun at the samples (east, north, up), shape (n_samples, 3).
    """

    nodes: tuple[SunGeometry, ...]
    node_time: np.ndarray
    sample_time: np.ndarray
    sample_direction: np.ndarray

    @classmethod
    def fixed(cls, sun: SunGeometry) -> SunTrack:
        """One sun for every ray."""
        return cls((sun,), np.array([np.nan]), np.zeros(0), np.zeros((0, 3)))

    @property
    def moving(self) -> bool:
        """Whether rays at different times see the sun at different places."""
        return self.sample_time.size > 0

    @property
    def reference(self) -> int:
        """The node nearest the middle of the acquisition (the sky table's azimuth grid and
        the sky seen by rays that leave the scene are its)."""
        return (len(self.nodes) - 1) // 2

    @property
    def up(self) -> bool:
        """Whether the sun is above the horizon at some node or sample."""
        if any(s.zenith < 90.0 for s in self.nodes):
            return True
        return bool(self.moving and np.any(self.sample_direction[:, 2] > 0.0))

    def direction(self, time=None) -> np.ndarray:
        """Unit vectors towards the sun at ``time`` [s], shape (n, 3); for a fixed sun (or
        ``time`` None) one row, (1, 3), that holds for every ray."""
        if not self.moving or time is None:
            return self.nodes[self.reference].direction.reshape(1, 3)
        t = np.asarray(time, dtype=float)
        out = np.stack([np.interp(t, self.sample_time, self.sample_direction[:, c])
                        for c in range(3)], axis=-1)
        return out / np.linalg.norm(out, axis=-1, keepdims=True)

    def angles(self, time=None) -> tuple[np.ndarray, np.ndarray]:
        """Sun zenith and azimuth at ``time`` [deg], shape (n,) (one value for a fixed sun)."""
        from radscene.geometry.frames import angles_from_direction

        if not self.moving or time is None:
            s = self.nodes[self.reference]
            return np.array([s.zenith]), np.array([s.azimuth])
        return angles_from_direction(self.direction(time))

    def node_weights(self, time=None) -> tuple[np.ndarray, np.ndarray]:
        """Each ray's sun nodes and their weights, linear in time: (index, weight), shape
        (n, 2), or (n, 1) with one node (``time`` None: one row)."""
        n_s = len(self.nodes)
        if time is None or n_s == 1:
            n = 1 if time is None else np.size(time)
            return np.zeros((n, 1), dtype=np.int64), np.ones((n, 1))
        t = np.clip(np.asarray(time, dtype=float), self.node_time[0], self.node_time[-1])
        i = np.clip(np.searchsorted(self.node_time, t, side="right") - 1, 0, n_s - 2)
        frac = (t - self.node_time[i]) / (self.node_time[i + 1] - self.node_time[i])
        return np.stack([i, i + 1], axis=1), np.stack([1.0 - frac, frac], axis=1)


def sun_track(scene, time=None, epoch=None) -> SunTrack:
    """The sun for rays acquired at ``time`` [s after ``epoch``].

    Parameters
    ----------
    scene : radscene.scene.Scene
        Its location, and its hand-placed sun or its time.
    time : array_like, optional
        Each ray's acquisition time [s] (``RayBundle.time``); None: a frame.
    epoch : datetime, optional
        Timezone-aware time of t = 0 (the observer's epoch); default the scene's time.

    Returns
    -------
    SunTrack
        Fixed (:func:`sun_geometry`) for a frame, a hand-placed sun or rays all at one time;
        else sampled over the rays' times.
    """
    epoch = epoch if epoch is not None else scene.time
    t = None if time is None else np.asarray(time, dtype=float)
    if scene.sun is not None or t is None or epoch is None or t.size == 0:
        return SunTrack.fixed(sun_geometry(scene))
    finite = t[np.isfinite(t)]
    if finite.size == 0:
        return SunTrack.fixed(sun_geometry(scene))
    lo, hi = float(finite.min()), float(finite.max())
    from radscene.geometry.frames import direction_from_angles
    from radscene.sun import sun_position

    loc = scene.location

    def ephemeris(seconds):
        stamps = [epoch + _dt.timedelta(seconds=float(s)) for s in seconds]
        pos = sun_position(stamps, loc.latitude, loc.longitude, loc.altitude)
        return pos, direction_from_angles(pos.zenith, pos.azimuth)

    n_e = min(_MAX_SAMPLES, max(2, int(np.ceil((hi - lo) / EPHEMERIS_STEP)) + 1))
    sample_time = np.linspace(lo, hi, n_e)
    _, sample_direction = ephemeris(sample_time)
    cosines = np.clip(np.einsum("ij,ij->i", sample_direction[1:], sample_direction[:-1]),
                      -1.0, 1.0)
    travel = float(np.degrees(np.arccos(cosines)).sum())
    n_s = 1 if travel < _ONE_NODE else 1 + max(1, int(np.ceil(travel / SUN_NODE_STEP)))
    node_time = np.array([0.5 * (lo + hi)]) if n_s == 1 else np.linspace(lo, hi, n_s)
    pos, _ = ephemeris(node_time)
    nodes = tuple(SunGeometry(float(z), float(a), float(d)) for z, a, d in
                  zip(pos.zenith, pos.azimuth, pos.distance, strict=True))
    if travel < _STILL:
        return SunTrack(nodes, node_time, np.zeros(0), np.zeros((0, 3)))
    return SunTrack(nodes, node_time, sample_time, sample_direction)


def combine_nodes(path_nodes, sun_index, sun_weight):
    """Path nodes × sun nodes: node ``s · n_j + j`` is path node ``j`` under sun node ``s``.

    Parameters
    ----------
    path_nodes : radscene.atmosphere.PathNodes
        The line-of-sight nodes, n_j of them, with each pixel's (N, k) mixing.
    sun_index, sun_weight : numpy.ndarray
        Each pixel's sun nodes and weights, shape (N, m) (:meth:`SunTrack.node_weights`).

    Returns
    -------
    PathNodes
        The same geometry and azimuth axis; ``index`` and ``weight`` (N, m · k) over the
        combined nodes (unchanged with one sun node).
    """
    if sun_index.shape[1] == 1 and not np.any(sun_index):
        return path_nodes
    n_j = path_nodes.size
    index = (sun_index[:, :, None] * n_j + path_nodes.index[:, None, :]).reshape(
        len(sun_index), -1)
    weight = (sun_weight[:, :, None] * path_nodes.weight[:, None, :]).reshape(
        len(sun_weight), -1)
    return replace(path_nodes, index=index, weight=weight)
