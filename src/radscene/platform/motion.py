"""How scene objects move: paths through waypoints or tabulated tracks, attitudes that follow
the path or the terrain, spinning parts, and parts carried by a parent.

A :class:`Motion` gives an object's pose at a time ``t`` [s] after the start of a simulation:
its position (scene frame, east-north-up) [m] and its body-to-world rotation matrix (columns:
the model's right, forward and up axes, :func:`radscene.geometry.rotation_matrix`). A child's
pose is relative to its parent's body frame; :func:`compose` turns the poses of a family into
world poses.

Paths reuse :class:`radscene.platform.trajectory.Trajectory`. A ``spline`` path is the C2 cubic
spline through the points with not-a-knot end conditions (scipy's ``CubicSpline``, its
default): the third derivative is continuous across the second and the second-to-last points,
so a spline through samples of any cubic polynomial is that polynomial (4 points or more; 3
points give a parabola, 2 a straight line). It is stored as Hermite pieces with the spline's
own derivatives at the points, which on each interval is the same cubic.

Attitudes, then a constant ``rotation`` turning the model within that frame, then a spin:

=============  ==============================================================================
``attitude``   the body frame
=============  ==============================================================================
fixed          ``rotation`` alone (no offset on top)
path           forward along the velocity: heading (yaw) from its horizontal part, pitch from
               the climb, no roll; on the terrain: heading along the path, pitch and roll from
               the terrain's normal under the object (its up axis)
banked         as ``path``, and rolled into the turn as an aircraft in coordinated flight: the
               up axis along the lift the path asks for, a + g z (a the path's acceleration,
               g = 9.80665 m s-2), less its part along the velocity; a level turn of radius r
               at speed V banks by atan(V² / (g r)), right wing down in a right-hand turn.
               Airborne objects only; straight (``linear``) legs carry no acceleration, so a
               ``spline`` path is what banks
tabulated      the waypoints' or the track file's attitudes, slerped between samples
=============  ==============================================================================

``R = R_attitude R_rotation R_spin(t)``, ``R_spin`` a turn by ``rate t`` about the spin
axis (in the model's frame, right-handed: positive is counter-clockwise seen from the axis's
tip). An object at rest on a ``path`` keeps the heading of the last leg it moved along (the
next one before it first moves).

========================  ========  ========  ===============================================
parameter                 unit      default   meaning
========================  ========  ========  ===============================================
``position``              m         required  fixed position; z above the terrain when given
``rotation``              deg       0, 0, 0   (yaw, pitch, roll); the offset in path/tabulated
``trajectory``            -         None      a Trajectory, times from the simulation's start
``attitude``              -         fixed     fixed, path or tabulated
``terrain``               -         None      a Heightfield: z is a height above it
``spin_axis``             -         None      (3,) in the model's frame
``spin_rate``             deg s-1   0         turn rate about the spin axis
``parent``                -         None      the object this one's pose is relative to
========================  ========  ========  ===============================================

Config snippet::

    objects:
      - {name: heli, ..., on_ground: false, trajectory: {waypoints: [[0, 0, 0, 50], [10, 100, 0, 60],
         [20, 150, 80, 60], [30, 150, 200, 50]], interpolation: spline, attitude: path}}
      - {name: rotor, ..., parent: heli, position: [0, 0, 2.5], spin: {axis: [0, 0, 1], rate: 300 rpm}}
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.geometry.mesh import rotation_matrix
from radscene.platform.trajectory import Trajectory, _axis_rotation

__all__ = ["ATTITUDES", "INTERPOLATIONS", "Motion", "compose", "path_trajectory", "route_times",
           "terrain_rotation"]

INTERPOLATIONS = ("linear", "spline")
ATTITUDES = ("fixed", "path", "banked", "tabulated")
#: Standard gravity [m s-2] (the lift of a banked turn).
STANDARD_GRAVITY = 9.80665
#: Below this speed [m s-1] a path gives no heading: the object keeps that of a leg it moved on.
REST_SPEED = 1e-9


def path_trajectory(times, positions, attitudes=None, *, quaternions=None,
                    interpolation: str = "linear") -> Trajectory:
    """A trajectory through sampled positions, straight or a C2 cubic spline.

    Parameters
    ----------
    times : array_like
        ``(n,)`` strictly increasing [s].
    positions : array_like
        ``(n, 3)`` [m].
    attitudes : array_like, optional
        ``(n, 3)`` (yaw, pitch, roll) [deg], slerped; or ``quaternions`` ``(n, 4)`` (w, x, y, z).
    interpolation : {"linear", "spline"}
        Straight lines between the points, or the not-a-knot cubic spline through them.

    Returns
    -------
    Trajectory

    Examples
    --------
    >>> t = [0.0, 1.0, 2.0, 3.0]
    >>> tr = path_trajectory(t, [[s**3, 0.0, 0.0] for s in t], interpolation="spline")
    >>> round(float(tr.position(1.5)[0]), 12)  # 1.5 ** 3
    3.375
    """
    from scipy.interpolate import CubicSpline

    if interpolation not in INTERPOLATIONS:
        raise ConfigError(f"unknown interpolation {interpolation!r}; known: {', '.join(INTERPOLATIONS)}"
                          f"{did_you_mean(interpolation, INTERPOLATIONS)}",
                          key="interpolation")
    velocities = None
    if interpolation == "spline" and len(times) > 1:
        t = np.asarray(times, dtype=float)
        if t.ndim != 1 or np.any(np.diff(t) <= 0):
            raise ConfigError("must be a 1-D, strictly increasing array of times [s]", key="times")
        velocities = CubicSpline(t, np.asarray(positions, dtype=float), axis=0,
                                 bc_type="not-a-knot")(t, 1)
    return Trajectory(times, positions, attitudes, quaternions=quaternions, velocities=velocities)


def route_times(points, speed: float, start: float = 0.0) -> np.ndarray:
    """Times [s] at the points of a route driven at a constant speed over the map.

    Parameters
    ----------
    points : array_like
        ``(n, 2)`` or ``(n, 3)`` [m]; only x and y count (the distance over the map).
    speed : float
        [m s-1], > 0.
    start : float
        Time at the first point [s].

    Returns
    -------
    numpy.ndarray
        ``(n,)``: ``start + cumulative horizontal distance / speed``.
    """
    p = np.asarray(points, dtype=float)
    if not (np.isfinite(speed) and speed > 0):
        raise ConfigError(f"must be > 0 m/s; got {speed!r}", key="speed")
    legs = np.hypot(*np.diff(p[:, :2], axis=0).T)
    if np.any(legs == 0):
        k = int(np.argmax(legs == 0)) + 1
        raise ConfigError(f"route[{k}] lies where route[{k - 1}] does: a route at a speed cannot stop",
                          key="route")
    return start + np.concatenate([[0.0], np.cumsum(legs)]) / speed


def terrain_rotation(normal, heading) -> np.ndarray:
    """Body-to-world rotation of a body standing on a surface: up along its normal, forward
    along a heading projected onto the surface.

    Parameters
    ----------
    normal : array_like
        ``(3,)`` upward unit normal of the surface [-].
    heading : float
        Yaw of the forward axis, clockwise from north [deg].

    Returns
    -------
    numpy.ndarray
        ``(3, 3)``: columns right, forward, up.

    Notes
    -----
    With :math:`\\mathbf{h} = (\\sin\\psi, \\cos\\psi, 0)`:
    :math:`\\mathbf{f} \\propto \\mathbf{h} - (\\mathbf{h}\\cdot\\mathbf{n})\\mathbf{n}`,
    :math:`\\mathbf{r} = \\mathbf{f} \\times \\mathbf{n}`. On a plane of slope α driven up its
    fall line, the pitch is α; driven across it, the roll is ±α.
    """
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    psi = np.radians(heading)
    h = np.array([np.sin(psi), np.cos(psi), 0.0])
    f = h - (h @ n) * n
    f /= np.linalg.norm(f)
    return np.column_stack([np.cross(f, n), f, n])


@dataclass(frozen=True)
class Motion:
    """How one object moves (see the module's table of parameters).

    ``key`` names the object in errors, e.g. ``objects[2]``.
    """

    key: str
    position: np.ndarray
    rotation: tuple = (0.0, 0.0, 0.0)
    trajectory: Trajectory | None = None
    attitude: str = "fixed"
    terrain: object = None
    spin_axis: np.ndarray | None = None
    spin_rate: float = 0.0
    parent: str | None = None
    #: what the trajectory came from, for errors: "waypoints", "route" or "track"
    source: str = "waypoints"

    def __post_init__(self):
        if self.attitude not in ATTITUDES:
            raise ConfigError(f"unknown attitude {self.attitude!r}; known: {', '.join(ATTITUDES)}"
                              f"{did_you_mean(self.attitude, ATTITUDES)}",
                              key=f"{self.key}.trajectory.attitude")
        if self.attitude != "fixed" and self.trajectory is None:
            raise ConfigError(f"attitude {self.attitude!r} needs a trajectory", key=f"{self.key}.trajectory")
        if self.attitude == "banked" and self.terrain is not None:
            raise ConfigError("attitude 'banked' is for airborne objects; on the ground the "
                              "terrain sets pitch and roll (attitude 'path')",
                              key=f"{self.key}.trajectory.attitude")

    @property
    def moves(self) -> bool:
        """Whether the pose changes with time (by itself; a parent may move it too)."""
        return self.trajectory is not None or (self.spin_axis is not None and self.spin_rate != 0.0)

    def rest_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """``(position [m], rotation (3, 3))`` where the scene file places the object, without its
        trajectory or spin (relative to the parent for a child)."""
        p = np.array(self.position, dtype=float)
        if self.terrain is not None:
            p[2] += float(self.terrain.height_at(p[0], p[1]))
        return p, rotation_matrix(*self.rotation)

    def pose(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        """``(position (3,) [m], rotation (3, 3))`` at ``t`` [s] after the start (relative to the
        parent for a child).

        Raises
        ------
        ConfigError
            ``t`` outside the trajectory's samples, or the object off the terrain it stands on.
        """
        if self.trajectory is None:
            p, rot = self.rest_pose()
        else:
            p, rot = self._path_pose(float(t))
        if self.spin_axis is not None:
            rot = rot @ _axis_rotation(self.spin_axis, np.radians([self.spin_rate * t]))[0]
        return p, rot

    def _path_pose(self, t):
        tr = self.trajectory
        lo, hi = tr.span
        if not lo <= t <= hi:
            what = {"waypoints": "waypoints'", "route": "route's", "track": "track's"}[self.source]
            raise ConfigError(f"the clock at {t:g} s lies outside the {what} {lo:g} - {hi:g} s",
                              key=f"{self.key}.trajectory")
        p = tr.position(t)
        normal = None
        if self.terrain is not None:
            xmin, xmax, ymin, ymax = self.terrain.extent
            if not (xmin <= p[0] <= xmax and ymin <= p[1] <= ymax):
                raise ConfigError(f"at {t:g} s ({p[0]:g}, {p[1]:g}) m lies outside the terrain "
                                  f"{self.terrain.extent} m", key=f"{self.key}.trajectory")
            p[2] += float(self.terrain.height_at(p[0], p[1]))
            normal = self.terrain.normal_at(p[0], p[1])
        offset = rotation_matrix(*self.rotation)
        if self.attitude == "fixed":
            return p, offset
        if self.attitude == "tabulated":
            return p, tr.rotation(t) @ offset
        yaw, pitch = self._heading(t)
        roll = self._bank(t, yaw, pitch) if self.attitude == "banked" else 0.0
        frame = rotation_matrix(yaw, pitch, roll) if normal is None else terrain_rotation(normal, yaw)
        return p, frame @ offset

    def _bank(self, t, yaw, pitch):
        """Roll [deg] of a coordinated turn at ``t``: the body's up axis along the lift
        a + g z, less its part along the forward axis (0 when that lift vanishes)."""
        right, forward, up = rotation_matrix(yaw, pitch, 0.0).T
        lift = self.trajectory.acceleration(t) + np.array([0.0, 0.0, STANDARD_GRAVITY])
        lift = lift - (lift @ forward) * forward
        if np.linalg.norm(lift) <= 1e-12:
            return 0.0
        return float(np.degrees(np.arctan2(lift @ right, lift @ up)))

    def _heading(self, t):
        """Yaw and pitch [deg] of the velocity at ``t``; at rest those of the nearest leg moved."""
        tr = self.trajectory
        v = tr.velocity(t)
        if np.linalg.norm(v) <= REST_SPEED:
            legs = np.diff(tr.positions, axis=0)
            moving = np.linalg.norm(legs, axis=1) > 0
            if not moving.any():
                return 0.0, 0.0
            i = int(np.clip(np.searchsorted(tr.times, t, side="right") - 1, 0, len(legs) - 1))
            before = np.flatnonzero(moving[: i + 1])
            v = legs[before[-1]] if before.size else legs[np.flatnonzero(moving)[0]]
        horizontal = float(np.hypot(v[0], v[1]))
        yaw = float(np.degrees(np.arctan2(v[0], v[1]))) if horizontal > 0 else 0.0
        return yaw, float(np.degrees(np.arctan2(v[2], horizontal)))


def compose(local: dict, parents: dict) -> dict:
    """World poses of a family of objects from their local poses.

    Parameters
    ----------
    local : dict of str to (position (3,), rotation (3, 3))
        Each object's pose, relative to its parent's body frame when it has one.
    parents : dict of str to str or None
        Each object's parent (a key of ``local``), or None.

    Returns
    -------
    dict of str to (position (3,), rotation (3, 3))

    Notes
    -----
    .. math:: \\mathbf{p} = \\mathbf{p}_P + R_P\\,\\mathbf{p}_c, \\qquad R = R_P R_c
    """
    world = {}

    def resolve(name, chain=()):
        if name in world:
            return world[name]
        if name in chain:
            raise ConfigError(f"{' -> '.join((*chain, name))} is a loop", key="parent")
        p, rot = local[name]
        parent = parents.get(name)
        if parent is not None:
            pp, prot = resolve(parent, (*chain, name))
            p, rot = pp + prot @ p, prot @ rot
        world[name] = (p, rot)
        return world[name]

    for name in local:
        resolve(name)
    return world
