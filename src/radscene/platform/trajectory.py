"""Platform poses and trajectories over time: interpolated positions, slerped attitudes.

A :class:`Trajectory` holds samples of a platform's position (scene frame, east-north-up, m)
and attitude (a unit quaternion, body → world) at increasing times [s] after an optional
epoch (a timezone-aware datetime). Between samples, positions are interpolated linearly, or by
cubic Hermite splines when the samples carry velocities (orbits: errors of micrometres at one
sample per second), and attitudes by spherical linear interpolation (slerp) of the
quaternions. Times outside the samples are refused, never extrapolated.

The body frame is radscene's (:func:`radscene.geometry.rotation_matrix`): right = +x,
forward = +y, up = +z; attitudes at public interfaces are ``(yaw, pitch, roll)`` [deg].
Quaternions are scalar-first ``(w, x, y, z)``.

========================  =======  ========  ===============================================
parameter                 unit     default   meaning
========================  =======  ========  ===============================================
``times``                 s        required  strictly increasing sample times after epoch
``positions``             m        required  (n, 3) platform positions, scene frame
``attitudes``             deg      level     (n, 3) yaw, pitch, roll; or ``quaternions``
``velocities``            m s-1    None      (n, 3): Hermite interpolation of positions
``epoch``                 -        None      timezone-aware datetime of time 0
========================  =======  ========  ===============================================

Config snippet (a straight, level flight line)::

    platform: {position: [0, -5000, 3000], velocity: [0, 60, 0], duration: 200}

References
----------
K. Shoemake, "Animating rotation with quaternion curves", SIGGRAPH '85, 245-254 (1985),
https://doi.org/10.1145/325165.325242 (slerp). S. W. Shepperd, "Quaternion from rotation
matrix", J. Guidance and Control 1(3), 223-224 (1978), https://doi.org/10.2514/3.55767b.
"""

from __future__ import annotations

import datetime as _dt
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.mesh import rotation_matrix

__all__ = [
    "quaternion_from_matrix",
    "matrix_from_quaternion",
    "attitude_from_matrix",
    "slerp",
    "Pose",
    "Trajectory",
]


def matrix_from_quaternion(q) -> np.ndarray:
    """Rotation matrices of unit quaternions ``(..., 4)`` scalar-first → ``(..., 3, 3)``."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = np.moveaxis(q, -1, 0)
    m = np.stack([
        1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
        2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
        2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y),
    ], axis=-1)
    return m.reshape(q.shape[:-1] + (3, 3))


def quaternion_from_matrix(m) -> np.ndarray:
    """Unit quaternions ``(..., 4)`` (scalar-first, w >= 0) of rotation matrices ``(..., 3, 3)``.

    Shepperd's method: the largest of 4w², 4x², 4y², 4z² sets the branch, so the result is
    accurate for every rotation.
    """
    m = np.asarray(m, dtype=float)
    if m.shape[-2:] != (3, 3):
        raise ConfigError(f"must have shape (..., 3, 3); got {m.shape}", key="matrix")
    flat = m.reshape(-1, 3, 3)
    tr = np.trace(flat, axis1=1, axis2=2)
    cand = np.stack([tr, flat[:, 0, 0], flat[:, 1, 1], flat[:, 2, 2]], axis=1)
    k = np.argmax(cand, axis=1)
    q = np.empty((len(flat), 4))
    m_ = flat
    for branch in range(4):
        sel = k == branch
        if not sel.any():
            continue
        a = m_[sel]
        if branch == 0:
            s = 2.0 * np.sqrt(1.0 + tr[sel])
            q[sel] = np.stack([0.25 * s, (a[:, 2, 1] - a[:, 1, 2]) / s,
                               (a[:, 0, 2] - a[:, 2, 0]) / s, (a[:, 1, 0] - a[:, 0, 1]) / s], 1)
        elif branch == 1:
            s = 2.0 * np.sqrt(1.0 + a[:, 0, 0] - a[:, 1, 1] - a[:, 2, 2])
            q[sel] = np.stack([(a[:, 2, 1] - a[:, 1, 2]) / s, 0.25 * s,
                               (a[:, 0, 1] + a[:, 1, 0]) / s, (a[:, 0, 2] + a[:, 2, 0]) / s], 1)
        elif branch == 2:
            s = 2.0 * np.sqrt(1.0 + a[:, 1, 1] - a[:, 0, 0] - a[:, 2, 2])
            q[sel] = np.stack([(a[:, 0, 2] - a[:, 2, 0]) / s, (a[:, 0, 1] + a[:, 1, 0]) / s,
                               0.25 * s, (a[:, 1, 2] + a[:, 2, 1]) / s], 1)
        else:
            s = 2.0 * np.sqrt(1.0 + a[:, 2, 2] - a[:, 0, 0] - a[:, 1, 1])
            q[sel] = np.stack([(a[:, 1, 0] - a[:, 0, 1]) / s, (a[:, 0, 2] + a[:, 2, 0]) / s,
                               (a[:, 1, 2] + a[:, 2, 1]) / s, 0.25 * s], 1)
    q *= np.where(q[:, :1] < 0.0, -1.0, 1.0)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return q.reshape(m.shape[:-2] + (4,))


def attitude_from_matrix(m) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(yaw, pitch, roll)`` [deg] of body-to-world rotation matrices ``(..., 3, 3)``.

    The inverse of :func:`radscene.geometry.rotation_matrix`: yaw in [0, 360), pitch in
    [-90, 90], roll in (-180, 180].
    """
    m = np.asarray(m, dtype=float)
    forward, right, up = m[..., :, 1], m[..., :, 0], m[..., :, 2]
    pitch = np.degrees(np.arcsin(np.clip(forward[..., 2], -1.0, 1.0)))
    yaw = np.degrees(np.arctan2(forward[..., 0], forward[..., 1])) % 360.0
    roll = np.degrees(np.arctan2(-right[..., 2], up[..., 2]))
    return yaw, pitch, roll


def slerp(q0, q1, fraction) -> np.ndarray:
    """Spherical linear interpolation between unit quaternions along the shorter arc.

    Parameters
    ----------
    q0, q1 : array_like
        ``(..., 4)`` unit quaternions (scalar-first).
    fraction : array_like
        ``(...)`` position between them, 0 at q0 and 1 at q1 [-].

    Returns
    -------
    numpy.ndarray
        ``(..., 4)`` unit quaternions.

    Notes
    -----
    .. math:: q(f) = \\frac{\\sin((1-f)\\Omega)}{\\sin\\Omega} q_0
              + \\frac{\\sin(f\\Omega)}{\\sin\\Omega} q_1, \\quad \\cos\\Omega = |q_0 \\cdot q_1|

    with q1 negated when q0·q1 < 0; normalised linear interpolation below Ω = 1e-6.
    """
    q0 = np.asarray(q0, dtype=float)
    q1 = np.asarray(q1, dtype=float)
    f = np.asarray(fraction, dtype=float)[..., None]
    dot = np.sum(q0 * q1, axis=-1, keepdims=True)
    q1 = np.where(dot < 0.0, -q1, q1)
    dot = np.abs(dot)
    omega = np.arccos(np.clip(dot, -1.0, 1.0))
    small = omega < 1e-6
    s = np.where(small, 1.0, np.sin(omega))
    w0 = np.where(small, 1.0 - f, np.sin((1.0 - f) * omega) / s)
    w1 = np.where(small, f, np.sin(f * omega) / s)
    q = w0 * q0 + w1 * q1
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


@dataclass(frozen=True)
class Pose:
    """Positions and attitudes of a platform at one or more times.

    Attributes
    ----------
    position : numpy.ndarray
        ``(..., 3)`` [m], scene frame.
    rotation : numpy.ndarray
        ``(..., 3, 3)`` body-to-world rotation; columns are the body's right, forward and up
        axes [-].
    """

    position: np.ndarray
    rotation: np.ndarray

    @property
    def attitude(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(yaw, pitch, roll)`` [deg]."""
        return attitude_from_matrix(self.rotation)


def _array(value, shape_tail, key, n=None):
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError(f"must be numbers of shape (n, {', '.join(map(str, shape_tail))})",
                          key=key) from None
    if a.ndim == len(shape_tail):
        a = a[None]
    if a.shape[1:] != tuple(shape_tail) or (n is not None and len(a) != n):
        want = f"({n if n is not None else 'n'}, {', '.join(map(str, shape_tail))})"
        raise ConfigError(f"must have shape {want}; got {a.shape}", key=key)
    if not np.isfinite(a).all():
        raise ConfigError("must be finite", key=key)
    return a


class Trajectory:
    """A platform's positions and attitudes sampled in time, interpolated in between.

    Parameters
    ----------
    times : array_like
        ``(n,)`` strictly increasing sample times [s] after ``epoch``; n = 1 is a platform
        at rest (valid at every time).
    positions : array_like
        ``(n, 3)`` positions in the scene frame [m].
    attitudes : array_like, optional
        ``(n, 3)`` ``(yaw, pitch, roll)`` [deg]; default level and heading north.
    quaternions : array_like, optional
        ``(n, 4)`` body-to-world unit quaternions instead of ``attitudes``.
    velocities : array_like, optional
        ``(n, 3)`` velocities [m s-1]; when given, positions are cubic Hermite splines.
    epoch : datetime, optional
        Timezone-aware time of t = 0.

    Examples
    --------
    >>> tr = Trajectory([0.0, 10.0], [[0, 0, 1000], [0, 100, 1000]], [[0, 0, 0], [90, 0, 0]])
    >>> tr.position(5.0).round(9).tolist(), round(float(tr.pose(5.0).attitude[0]), 9)
    ([0.0, 50.0, 1000.0], 45.0)
    """

    def __init__(self, times, positions, attitudes=None, *, quaternions=None, velocities=None,
                 epoch: _dt.datetime | None = None):
        t = np.atleast_1d(np.asarray(times, dtype=float))
        if t.ndim != 1 or t.size < 1 or not np.isfinite(t).all() or np.any(np.diff(t) <= 0):
            raise ConfigError("must be a 1-D, finite, strictly increasing array of times [s]",
                              key="times")
        n = t.size
        self.times = t
        self.positions = _array(positions, (3,), "positions", n)
        if attitudes is not None and quaternions is not None:
            raise ConfigError("give attitudes or quaternions, not both", key="attitudes")
        if quaternions is not None:
            q = _array(quaternions, (4,), "quaternions", n)
            norm = np.linalg.norm(q, axis=1)
            if np.any(norm == 0):
                raise ConfigError("must not be zero", key="quaternions")
            q = q / norm[:, None]
        else:
            att = np.zeros((n, 3)) if attitudes is None else _array(attitudes, (3,),
                                                                     "attitudes", n)
            q = quaternion_from_matrix(rotation_matrix(att[:, 0], att[:, 1], att[:, 2]))
        # successive quaternions on the same hemisphere, so that slerp takes the short arc
        for i in range(1, n):
            if q[i] @ q[i - 1] < 0.0:
                q[i] = -q[i]
        self.quaternions = q
        self.velocities = None if velocities is None else _array(velocities, (3,),
                                                                 "velocities", n)
        if epoch is not None and (not isinstance(epoch, _dt.datetime) or epoch.tzinfo is None):
            raise ConfigError(f"must be a timezone-aware datetime; got {epoch!r}", key="epoch")
        self.epoch = epoch

    def __repr__(self) -> str:
        return (f"Trajectory({self.times.size} samples, t = {self.times[0]:g}..{self.times[-1]:g}"
                f" s, epoch={self.epoch})")

    @property
    def span(self) -> tuple[float, float]:
        """First and last sample times [s]."""
        return float(self.times[0]), float(self.times[-1])

    def seconds(self, time) -> float:
        """Seconds after the epoch of a timezone-aware datetime (or a number, passed on) [s]."""
        if isinstance(time, _dt.datetime):
            if self.epoch is None:
                raise ConfigError("this trajectory has no epoch; give times in seconds",
                                  key="time")
            if time.tzinfo is None:
                raise ConfigError("must be timezone-aware", key="time")
            return (time - self.epoch).total_seconds()
        return float(time)

    def _locate(self, time):
        t = np.asarray(time, dtype=float)
        if self.times.size == 1:
            return t, np.zeros(t.shape, dtype=int), np.zeros(t.shape)
        lo, hi = self.span
        tol = 1e-9 * max(1.0, hi - lo)
        bad = ~np.isfinite(t) | (t < lo - tol) | (t > hi + tol)
        if np.any(bad):
            raise ConfigError(f"times must lie within the trajectory's samples "
                              f"[{lo:g}, {hi:g}] s; got {t[bad].ravel()[0]!r}", key="time")
        i = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, self.times.size - 2)
        dt = self.times[i + 1] - self.times[i]
        return t, i, np.clip((t - self.times[i]) / dt, 0.0, 1.0)

    def position(self, time) -> np.ndarray:
        """Positions ``(..., 3)`` [m] at times ``(...)`` [s]."""
        t, i, f = self._locate(time)
        if self.times.size == 1:
            return np.broadcast_to(self.positions[0], t.shape + (3,)).copy()
        p0, p1 = self.positions[i], self.positions[i + 1]
        f = f[..., None]
        if self.velocities is None:
            return p0 + f * (p1 - p0)
        dt = (self.times[i + 1] - self.times[i])[..., None]
        v0, v1 = self.velocities[i] * dt, self.velocities[i + 1] * dt
        f2, f3 = f * f, f * f * f
        return ((2 * f3 - 3 * f2 + 1) * p0 + (f3 - 2 * f2 + f) * v0
                + (-2 * f3 + 3 * f2) * p1 + (f3 - f2) * v1)

    def velocity(self, time) -> np.ndarray:
        """Velocities ``(..., 3)`` [m s-1] at times ``(...)`` [s] (derivative of the spline)."""
        t, i, f = self._locate(time)
        if self.times.size == 1:
            return np.zeros(t.shape + (3,))
        p0, p1 = self.positions[i], self.positions[i + 1]
        dt = (self.times[i + 1] - self.times[i])[..., None]
        f = f[..., None]
        if self.velocities is None:
            return (p1 - p0) / dt
        v0, v1 = self.velocities[i] * dt, self.velocities[i + 1] * dt
        f2 = f * f
        return ((6 * f2 - 6 * f) * p0 + (3 * f2 - 4 * f + 1) * v0 + (-6 * f2 + 6 * f) * p1
                + (3 * f2 - 2 * f) * v1) / dt

    def acceleration(self, time) -> np.ndarray:
        """Accelerations ``(..., 3)`` [m s-2] at times ``(...)`` [s]: the spline's second
        derivative; zero along straight legs (the turn at a sample is not resolved)."""
        t, i, f = self._locate(time)
        if self.times.size == 1 or self.velocities is None:
            return np.zeros(t.shape + (3,))
        p0, p1 = self.positions[i], self.positions[i + 1]
        dt = (self.times[i + 1] - self.times[i])[..., None]
        v0, v1 = self.velocities[i] * dt, self.velocities[i + 1] * dt
        f = f[..., None]
        return ((12 * f - 6) * p0 + (6 * f - 4) * v0 + (6 - 12 * f) * p1
                + (6 * f - 2) * v1) / (dt * dt)

    def quaternion(self, time) -> np.ndarray:
        """Body-to-world quaternions ``(..., 4)`` at times ``(...)`` [s] (slerp)."""
        t, i, f = self._locate(time)
        if self.times.size == 1:
            return np.broadcast_to(self.quaternions[0], t.shape + (4,)).copy()
        return slerp(self.quaternions[i], self.quaternions[i + 1], f)

    def rotation(self, time) -> np.ndarray:
        """Body-to-world rotation matrices ``(..., 3, 3)`` at times ``(...)`` [s]."""
        return matrix_from_quaternion(self.quaternion(time))

    def pose(self, time) -> Pose:
        """Position and attitude at times ``(...)`` [s] (or a timezone-aware datetime)."""
        if isinstance(time, _dt.datetime):
            time = self.seconds(time)
        return Pose(self.position(time), self.rotation(time))

    # -- constructors -----------------------------------------------------------------------

    @classmethod
    def static(cls, position, attitude=(0.0, 0.0, 0.0), epoch=None) -> Trajectory:
        """A platform at rest: one sample, valid at every time."""
        return cls([0.0], [position], [attitude], epoch=epoch)

    @classmethod
    def linear(cls, position, velocity, duration: float, attitude=None, *, start: float = 0.0,
               step: float | None = None, frame=None, epoch=None) -> Trajectory:
        """A straight line at constant velocity.

        Parameters
        ----------
        position : array_like
            Position at ``start`` [m], scene frame.
        velocity : array_like
            Velocity [m s-1]. With ``frame``, an inertial velocity (see below).
        duration : float
            Length of the line [s], > 0.
        attitude : array_like, optional
            ``(yaw, pitch, roll)`` [deg]; default level flight heading along the velocity's
            horizontal part (north when it has none).
        start : float
            Time of the first sample [s] after ``epoch``.
        step : float, optional
            Sample spacing [s]; default one sample at each end (exact for a line), or 1 s
            with ``frame``.
        frame : LocalFrame, optional
            When given, ``position``, ``velocity`` and ``attitude`` are inertial (fixed to
            axes that coincide with the scene frame at ``start``), and the Earth turns under
            them: every sample is rotated by ``-ω (t - start)`` about the Earth's axis, so that
            the trajectory is the one seen from the ground (Earth rotation in a pushbroom).
        epoch : datetime, optional
            Timezone-aware time of t = 0.

        Returns
        -------
        Trajectory
        """
        from radscene.platform.geolocation import EARTH_ROTATION_RATE

        p0 = _array(position, (3,), "position", 1)[0]
        v = _array(velocity, (3,), "velocity", 1)[0]
        d = float(duration)
        if not (np.isfinite(d) and d > 0):
            raise ConfigError(f"must be > 0 s; got {duration!r}", key="duration")
        if attitude is None:
            heading = np.degrees(np.arctan2(v[0], v[1])) if np.hypot(v[0], v[1]) > 0 else 0.0
            attitude = (heading, 0.0, 0.0)
        att = _array(attitude, (3,), "attitude", 1)[0]
        if step is None:
            step = d if frame is None else min(d, 1.0)
        step = float(step)
        if not (np.isfinite(step) and step > 0):
            raise ConfigError(f"must be > 0 s; got {step!r}", key="step")
        n = max(2, int(np.ceil(d / step - 1e-9)) + 1)
        tau = np.linspace(0.0, d, n)
        pos = p0 + tau[:, None] * v
        vel = np.broadcast_to(v, pos.shape).copy()
        rot = np.broadcast_to(rotation_matrix(*att), (n, 3, 3)).copy()
        if frame is not None:
            # ω in the scene axes; positions relative to the Earth's centre
            axis = frame.vector_from_ecef([0.0, 0.0, 1.0])
            centre = frame.from_ecef([0.0, 0.0, 0.0])
            angle = -EARTH_ROTATION_RATE * tau
            turn = _axis_rotation(axis, angle)
            rel = pos - centre
            pos = np.einsum("nij,nj->ni", turn, rel) + centre
            omega = EARTH_ROTATION_RATE * axis
            vel = np.einsum("nij,nj->ni", turn, vel) - np.cross(omega, pos - centre)
            rot = turn @ rot
        return cls(start + tau, pos, quaternions=quaternion_from_matrix(rot), velocities=vel,
                   epoch=epoch)


def _axis_rotation(axis, angle) -> np.ndarray:
    """Rotation matrices ``(n, 3, 3)`` by angles ``(n,)`` [rad] about one unit axis (Rodrigues)."""
    k = np.asarray(axis, dtype=float)
    k = k / np.linalg.norm(k)
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    a = np.asarray(angle, dtype=float)[:, None, None]
    return np.eye(3) + np.sin(a) * kx + (1.0 - np.cos(a)) * (kx @ kx)
