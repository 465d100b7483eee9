"""Scanning observers: pushbroom and whiskbroom (line scanner), with a time for every ray.

A scanner rides a :class:`~radscene.platform.trajectory.Trajectory` and builds its image in
time, so the platform's motion, its attitude changes, the Earth's rotation (in an orbit's
Earth-fixed trajectory) and any motion of the target all distort the image as they do in real
ones. ``rays()`` returns a :class:`~radscene.platform.cameras.RayBundle` whose ``time`` holds
each ray's acquisition time [s] on the trajectory's clock (``observer.epoch`` is its t = 0).

Image layout: rows run in acquisition order (row 0 first), so on the ground they advance
along the track; columns increase towards the *left* of the direction of flight, which keeps
the image unmirrored (a southbound pass gives a north-up image, a northbound one an image
turned by 180 deg). Continuous pixel coordinates are those of the frame cameras: the centre of
pixel ``(i, j)`` is ``(i + 1/2, j + 1/2)``.

Sensor frame: the sensor's boresight is the body's down axis (-up), tilted by ``off_nadir``
towards the right of the flight direction (a roll of the line of sight) and then by
``forward_tilt`` towards the front.

**Pushbroom** — a linear array across the track, one line every ``line_time``. Detector
column ``c`` looks along ``-up + u right + v forward`` in the sensor frame (a focal-plane array
behind a lens: tan-plane offsets ``u = (nx/2 - c) p``, ``v`` the along-track offset within the
detector, ``p = tan(ifov)``). Every sub-sample of line i is taken at the line's mid-time
``start + (i + 1/2) line_time``; the smear during integration belongs to the sensor's
linear-motion MTF.

**Whiskbroom** — a mirror sweeps the line of sight across the track; ``detectors`` lines are
recorded per sweep (MODIS: 10), one sweep every ``scan_period``. Column ``c`` of a sweep is
seen at ``start + s scan_period + c sample_time`` (bidirectional scanners run odd sweeps
backwards), so every sample, and every sub-sample, has its own time; the mirror angle against
time is linear by default (an angular step of ``ifov`` per sample) or a user table. Detector
offsets along the track are tan-plane offsets rotated with the mirror, which reproduces the
bow-tie growth of the footprint at the swath edges.

========================  =======  ========  ===============================================
parameter                 unit     default   meaning
========================  =======  ========  ===============================================
``trajectory``            -        required  the platform's path (``Trajectory``)
``shape``                 -        required  (lines, samples)
``ifov`` or ``gsd``       deg, m   required  detector angle; or nadir ground sample distance
``line_time``             s        matched   pushbroom line period (default: square pixels)
``scan_period``           s        matched   whiskbroom sweep period (default: contiguous)
``detectors``             -        1         whiskbroom lines per sweep
``sample_time``           s        period/n  whiskbroom dwell per sample
``bidirectional``         -        false     whiskbroom odd sweeps run backwards
``mirror_profile``        -, deg   linear    (phase, angle) table of a sweep
``start``                 s        0         time of the first line/sweep on the trajectory
``off_nadir``             deg      0         roll of the line of sight, positive right
``forward_tilt``          deg      0         pitch of the line of sight, positive ahead
========================  =======  ========  ===============================================

Config snippet::

    observers:
      - {type: pushbroom, name: oli, shape: [400, 600], gsd: 30 m,
         orbit: {overpass: {altitude: 705 km}}}
      - {type: whiskbroom, name: scanner, shape: [200, 300], ifov: 0.05, detectors: 10,
         platform: {position: [0, -3000, 2000], velocity: [0, 70, 0], duration: 60}}
"""

from __future__ import annotations

import datetime as _dt

import numpy as np

from radscene.errors import ConfigError
from radscene.platform.cameras import RayBundle, _number, _sample_grid, _shape
from radscene.platform.trajectory import Trajectory

__all__ = ["PushbroomScanner", "WhiskbroomScanner", "to_body_frame", "mount_rotation"]


def mount_rotation(off_nadir: float = 0.0, forward_tilt: float = 0.0) -> np.ndarray:
    """Sensor axes in the body frame for a line of sight tilted from nadir.

    Parameters
    ----------
    off_nadir : float
        Roll of the line of sight towards the right of the flight direction [deg].
    forward_tilt : float
        Then its pitch towards the front [deg].

    Returns
    -------
    numpy.ndarray
        (3, 3): columns are the sensor's right, forward and up axes in body coordinates; the
        boresight is minus the third column.

    Examples
    --------
    >>> (-mount_rotation(30.0)[:, 2]).round(6) + 0.0  # boresight: right and down
    array([ 0.5     ,  0.      , -0.866025])
    """
    a, b = np.radians(float(off_nadir)), np.radians(float(forward_tilt))
    # about the forward (y) axis by -a takes -z towards +x; about the right axis by b takes
    # -z towards +y
    ry = np.array([[np.cos(a), 0.0, -np.sin(a)], [0.0, 1.0, 0.0], [np.sin(a), 0.0, np.cos(a)]])
    rx = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(b), -np.sin(b)], [0.0, np.sin(b), np.cos(b)]])
    return ry @ rx


def to_body_frame(bundle: RayBundle, trajectory: Trajectory, time=None) -> RayBundle:
    """Express rays in the frame of a body moving along a trajectory, each at its own time.

    A renderer intersects a moving object by transforming every ray into the object's body
    frame at the ray's time (origin ``R(t)ᵀ (o - p(t))``, direction ``R(t)ᵀ d``); that is how a
    target moving during a scan comes out stretched, compressed or sheared.

    Parameters
    ----------
    bundle : RayBundle
        Rays with ``time`` (a scanner's), or any rays when ``time`` is given.
    trajectory : Trajectory
        The body's path on the same clock as the rays.
    time : float, optional
        One time [s] for every ray (a static frame camera).

    Returns
    -------
    RayBundle
        Same pixels, weights and times; origins [m] and directions [-] in the body frame.
    """
    t = bundle.time if time is None else np.full(len(bundle), float(time))
    if t is None:
        raise ConfigError("the rays carry no times; give one with time=", key="time")
    pose = trajectory.pose(t)
    rt = np.swapaxes(pose.rotation, -1, -2)
    origins = np.einsum("nij,nj->ni", rt, bundle.origins - pose.position)
    directions = np.einsum("nij,nj->ni", rt, bundle.directions)
    return RayBundle(origins, directions, bundle.pixel, bundle.weight, bundle.shape,
                     bundle.subsample, time=np.asarray(t, dtype=float))


class _Scanner:
    """Common parts: trajectory, shape, IFOV, mount and clock."""

    def __init__(self, trajectory, shape, ifov, gsd, start, off_nadir, forward_tilt):
        if not isinstance(trajectory, Trajectory):
            raise ConfigError(f"must be a Trajectory; got {type(trajectory).__name__}",
                              key="trajectory")
        self.trajectory = trajectory
        self.shape = _shape(shape)
        self.start = _number(trajectory.seconds(start), "start")
        self.off_nadir = _number(off_nadir, "off_nadir", -90.0, 90.0, True, True)
        self.forward_tilt = _number(forward_tilt, "forward_tilt", -90.0, 90.0, True, True)
        self.mount = mount_rotation(self.off_nadir, self.forward_tilt)
        if (ifov is None) == (gsd is None):
            raise ConfigError("give exactly one of ifov [deg] and gsd [m]", key="ifov, gsd")
        if ifov is not None:
            self.ifov = _number(ifov, "ifov", 0.0, 10.0, low_open=True)
        else:
            g = _number(gsd, "gsd", 0.0, low_open=True)
            pos, axes = self.sensor_axes(self.start)
            bore = -axes[:, 2]
            distance = -pos[2] / bore[2] if bore[2] < 0 else -1.0
            if not distance > 0:
                raise ConfigError("the line of sight must meet the ground (z = 0) at the start "
                                  "to turn a gsd into an ifov", key="gsd")
            self.ifov = float(np.degrees(np.arctan(g / distance)))

    @property
    def epoch(self) -> _dt.datetime | None:
        """Timezone-aware time of t = 0 of the ray times (the trajectory's epoch)."""
        return self.trajectory.epoch

    def _ground_speed(self) -> tuple[float, float]:
        """Speed [m s-1] of the boresight's footprint on z = 0 at the start, and the range
        [m] from the sensor to it."""
        lo, hi = self.trajectory.span
        dt = 0.01 if self.trajectory.times.size == 1 else min(0.01, 0.5 * (hi - lo))
        t0 = self.start if self.start + dt <= hi or self.trajectory.times.size == 1 else \
            self.start - dt
        pos, axes = self.sensor_axes(np.array([t0, t0 + dt]))
        bore = -axes[:, :, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            dist = -pos[:, 2] / bore[:, 2]
        if not np.all(dist > 0):
            raise ConfigError("the line of sight does not meet the ground (z = 0) at the start:"
                              " give ifov and the period explicitly", key="line_time")
        foot = pos + dist[:, None] * bore
        speed = float(np.linalg.norm(foot[1] - foot[0]) / dt)
        if speed <= 0:
            raise ConfigError("the platform does not move at the start: give the period",
                              key="line_time")
        return speed, float(dist[0])

    def sensor_axes(self, time) -> tuple[np.ndarray, np.ndarray]:
        """Sensor position ``(..., 3)`` [m] and axes ``(..., 3, 3)`` (columns right, forward,
        up) in the scene frame at times ``(...)`` [s]."""
        pose = self.trajectory.pose(time)
        return pose.position, pose.rotation @ self.mount

    def _start_for(self, time):
        return self.start if time is None else _number(self.trajectory.seconds(time), "time")


class PushbroomScanner(_Scanner):
    """A pushbroom (along-track) scanner: a line of detectors, one line per ``line_time``.

    Parameters
    ----------
    trajectory : Trajectory
        The platform's path; it must cover every line time.
    shape : tuple of int
        ``(lines, detectors)``.
    ifov : float, optional
        Detector pitch over focal length as an angle [deg] (tan-plane pitch ``tan(ifov)``).
    line_time : float, optional
        Line period [s], > 0; default the time the boresight's footprint on z = 0 takes to
        move one pixel at the start (square pixels at the boresight).
    gsd : float, optional
        Ground sample distance on z = 0 at the boresight, at the start [m], instead of ifov
        (perpendicular to the line of sight; off nadir the ground footprint is longer).
    start : float or datetime
        Time of the start of line 0 [s on the trajectory's clock].
    off_nadir, forward_tilt : float
        Pointing of the line of sight [deg] (see the module docstring).

    Examples
    --------
    >>> tr = Trajectory.linear([0, 0, 1000.0], [0, 10.0, 0], duration=10.0)
    >>> pb = PushbroomScanner(tr, (5, 4), gsd=1.0)
    >>> round(pb.line_time, 12), pb.line_times()[:2].round(12).tolist()
    (0.1, [0.05, 0.15])
    """

    def __init__(self, trajectory, shape, ifov=None, line_time=None, *, gsd=None, start=0.0,
                 off_nadir=0.0, forward_tilt=0.0):
        super().__init__(trajectory, shape, ifov, gsd, start, off_nadir, forward_tilt)
        self.pitch = float(np.tan(np.radians(self.ifov)))
        if line_time is None:
            speed, height = self._ground_speed()
            line_time = height * self.pitch / speed
        self.line_time = _number(line_time, "line_time", 0.0, low_open=True)

    def __repr__(self) -> str:
        return (f"PushbroomScanner(shape={self.shape}, ifov={self.ifov:g} deg, "
                f"line_time={self.line_time:g} s, start={self.start:g} s)")

    def line_times(self, start=None) -> np.ndarray:
        """Mid-times of the lines [s], shape ``(lines,)``."""
        return self._start_for(start) + (np.arange(self.shape[0]) + 0.5) * self.line_time

    def _local_directions(self, row_f, col_f):
        nx = self.shape[1]
        d = np.empty(np.shape(col_f) + (3,))
        d[..., 0] = (0.5 * nx - col_f) * self.pitch
        d[..., 1] = (row_f - np.floor(row_f) - 0.5) * self.pitch
        d[..., 2] = -1.0
        d /= np.sqrt(d[..., 0] ** 2 + d[..., 1] ** 2 + 1.0)[..., None]
        return d

    def rays(self, supersample: int = 1, time=None, window=None) -> RayBundle:
        """Rays of every (sub-)pixel, each at its line's mid-time.

        Parameters
        ----------
        supersample : int
            ``k x k`` rays per pixel.
        time : float or datetime, optional
            Start of line 0, instead of ``start``.
        window : tuple of int, optional
            ``(row0, row1, col0, col1)`` tile; pixel indices stay those of the whole image.

        Returns
        -------
        RayBundle
            With ``time`` [s on the trajectory's clock].
        """
        start = self._start_for(time)
        row_f, col_f, pixel, sub, weight = _sample_grid(self.shape, supersample, window)
        # the samples of a line are contiguous: (lines, samples per line)
        r0 = int(np.floor(row_f[0]))
        n_lines = int(np.floor(row_f[-1])) - r0 + 1
        per_line = len(row_f) // n_lines
        t_line = start + (np.arange(r0, r0 + n_lines) + 0.5) * self.line_time
        pos, axes = self.sensor_axes(t_line)
        local = self._local_directions(row_f, col_f).reshape(n_lines, per_line, 3)
        directions = np.matmul(local, np.swapaxes(axes, 1, 2)).reshape(-1, 3)
        return RayBundle(np.repeat(pos, per_line, axis=0), directions, pixel, weight,
                         self.shape, sub, time=np.repeat(t_line, per_line))

    def project(self, points, iterations: int = 50) -> tuple[np.ndarray, np.ndarray]:
        """Continuous pixel coordinates of scene points (the inverse of :meth:`rays`).

        The line is found by fixed-point iteration: from a line, the point's along-track
        offset in that line's sensor frame gives the next line, until the point falls inside
        the line's detector footprint.

        Parameters
        ----------
        points : array_like
            ``(..., 3)`` [m].

        Returns
        -------
        row, col : numpy.ndarray
            ``(...)`` [px]; NaN for points behind the sensor. Points seen before the first or
            after the last line get rows outside ``[0, lines)``.
        """
        p = np.asarray(points, dtype=float)
        flat = p.reshape(-1, 3)
        ny, nx = self.shape
        line = np.full(len(flat), ny // 2, dtype=np.int64)
        row = np.full(len(flat), np.nan)
        col = np.full(len(flat), np.nan)
        active = np.ones(len(flat), dtype=bool)
        for _ in range(iterations):
            if not active.any():
                break
            idx = np.nonzero(active)[0]
            t = self.start + (line[idx] + 0.5) * self.line_time
            pos, axes = self.sensor_axes(t)
            rel = np.einsum("nji,nj->ni", axes, flat[idx] - pos)  # sensor coordinates
            depth = -rel[:, 2]
            with np.errstate(divide="ignore", invalid="ignore"):
                u, v = rel[:, 0] / depth, rel[:, 1] / depth
            behind = ~(depth > 0)
            r = line[idx] + 0.5 + v / self.pitch
            c = 0.5 * nx - u / self.pitch
            new = np.clip(np.floor(r), 0, ny - 1).astype(np.int64)
            done = (new == line[idx]) | behind
            row[idx] = np.where(behind, np.nan, r)
            col[idx] = np.where(behind, np.nan, c)
            line[idx] = new
            active[idx[done]] = False
        return row.reshape(p.shape[:-1]), col.reshape(p.shape[:-1])


class WhiskbroomScanner(_Scanner):
    """A whiskbroom (cross-track) scanner: a mirror sweeps ``detectors`` lines at a time.

    Parameters
    ----------
    trajectory : Trajectory
        The platform's path; it must cover every sample time.
    shape : tuple of int
        ``(lines, samples)``; lines a multiple of ``detectors``.
    ifov : float, optional
        Angular size of a detector and of the linear mirror's step per sample [deg].
    scan_period : float, optional
        Time from one sweep to the next [s], > 0; default the time the boresight's footprint
        on z = 0 takes to move ``detectors`` pixels at the start (contiguous sweeps at the
        scan centre).
    detectors : int
        Detectors along the track, i.e. lines per sweep, >= 1.
    sample_time : float, optional
        Dwell per sample [s]; default ``scan_period / samples`` (no dead time); at most that.
    bidirectional : bool
        Odd sweeps run from the last column to the first.
    mirror_profile : array_like, optional
        ``(m, 2)`` table of (sweep phase in [0, 1], mirror angle [deg], positive to the
        right) of a forward sweep, phase = time since the sweep's start / (samples x
        sample_time), angles strictly decreasing; linear interpolation. Default linear,
        ``(1/2 - phase) samples ifov``.
    gsd : float, optional
        Ground sample distance at the boresight at the start [m] instead of ``ifov``.
    start : float or datetime
        Start of sweep 0 [s on the trajectory's clock].
    off_nadir, forward_tilt : float
        Pointing of the scan centre [deg].
    """

    def __init__(self, trajectory, shape, ifov=None, scan_period=None, *, detectors: int = 1,
                 sample_time=None, bidirectional: bool = False, mirror_profile=None, gsd=None,
                 start=0.0, off_nadir=0.0, forward_tilt=0.0):
        super().__init__(trajectory, shape, ifov, gsd, start, off_nadir, forward_tilt)
        if isinstance(detectors, bool) or not isinstance(detectors, int | np.integer) \
                or detectors < 1:
            raise ConfigError(f"must be an integer >= 1; got {detectors!r}", key="detectors")
        self.detectors = int(detectors)
        if self.shape[0] % self.detectors:
            raise ConfigError(f"the number of lines {self.shape[0]} must be a multiple of "
                              f"detectors = {self.detectors}", key="shape")
        self.ifov_rad = float(np.radians(self.ifov))
        self.pitch = float(np.tan(self.ifov_rad))
        if scan_period is None:
            speed, height = self._ground_speed()
            scan_period = self.detectors * height * self.pitch / speed
        self.scan_period = _number(scan_period, "scan_period", 0.0, low_open=True)
        nx = self.shape[1]
        if sample_time is None:
            sample_time = self.scan_period / nx
        self.sample_time = _number(sample_time, "sample_time", 0.0, low_open=True)
        if self.sample_time * nx > self.scan_period * (1 + 1e-12):
            raise ConfigError(f"samples x sample_time = {self.sample_time * nx:g} s exceeds "
                              f"scan_period = {self.scan_period:g} s", key="sample_time")
        self.bidirectional = bool(bidirectional)
        if mirror_profile is None:
            self.mirror_profile = None
        else:
            table = np.asarray(mirror_profile, dtype=float)
            if table.ndim != 2 or table.shape[1] != 2 or len(table) < 2 \
                    or not np.isfinite(table).all():
                raise ConfigError("must be an (m, 2) table of (phase, angle [deg]), m >= 2",
                                  key="mirror_profile")
            if table[0, 0] > 0 or table[-1, 0] < 1 or np.any(np.diff(table[:, 0]) <= 0):
                raise ConfigError("phases must increase strictly and cover [0, 1]",
                                  key="mirror_profile")
            if np.any(np.diff(table[:, 1]) >= 0):
                raise ConfigError("angles must decrease strictly with phase (a forward sweep "
                                  "runs from right to left)", key="mirror_profile")
            self.mirror_profile = table

    def __repr__(self) -> str:
        return (f"WhiskbroomScanner(shape={self.shape}, ifov={self.ifov:g} deg, "
                f"detectors={self.detectors}, scan_period={self.scan_period:g} s)")

    def mirror_angle(self, col) -> np.ndarray:
        """Mirror angle [rad], positive right, at continuous columns ``col`` [px]."""
        nx = self.shape[1]
        c = np.asarray(col, dtype=float)
        if self.mirror_profile is None:
            return (0.5 * nx - c) * self.ifov_rad
        return np.radians(np.interp(c / nx, self.mirror_profile[:, 0], self.mirror_profile[:, 1]))

    def _column_of_angle(self, theta) -> np.ndarray:
        nx = self.shape[1]
        if self.mirror_profile is None:
            return 0.5 * nx - theta / self.ifov_rad
        table = self.mirror_profile
        ang = np.radians(table[::-1, 1])
        phase = np.interp(theta, ang, table[::-1, 0], left=np.nan, right=np.nan)
        # outside the table: continue the end slopes, so that far points stay ordered
        lo = (theta - ang[0]) / (ang[1] - ang[0]) * (table[-2, 0] - table[-1, 0]) + table[-1, 0]
        hi = (theta - ang[-1]) / (ang[-1] - ang[-2]) * (table[1, 0] - table[0, 0]) + table[0, 0]
        phase = np.where(theta < ang[0], lo, np.where(theta > ang[-1], hi, phase))
        return phase * nx

    def sample_times(self, row, col, start=None) -> np.ndarray:
        """Acquisition times [s] of continuous pixel coordinates ``(row, col)``."""
        start = self._start_for(start)
        r, c = np.broadcast_arrays(np.asarray(row, dtype=float), np.asarray(col, dtype=float))
        scan = np.floor(r / self.detectors)
        nx = self.shape[1]
        backwards = self.bidirectional & (scan % 2 == 1)
        tau = np.where(backwards, nx - c, c) * self.sample_time
        return start + scan * self.scan_period + tau

    def _local_directions(self, rho, theta):
        tan_a = (rho - 0.5 * self.detectors) * self.pitch
        cos_a = 1.0 / np.sqrt(1.0 + tan_a * tan_a)
        sin_a = tan_a * cos_a
        return np.stack([cos_a * np.sin(theta), sin_a, -cos_a * np.cos(theta)], axis=-1)

    def rays(self, supersample: int = 1, time=None, window=None) -> RayBundle:
        """Rays of every (sub-)pixel, each at the time the mirror points it.

        Parameters
        ----------
        supersample : int
            ``k x k`` rays per pixel.
        time : float or datetime, optional
            Start of sweep 0, instead of ``start``.
        window : tuple of int, optional
            ``(row0, row1, col0, col1)`` tile.

        Returns
        -------
        RayBundle
            With ``time`` [s on the trajectory's clock].
        """
        row_f, col_f, pixel, sub, weight = _sample_grid(self.shape, supersample, window)
        t = self.sample_times(row_f, col_f, self._start_for(time))
        # one pose per distinct time (a sweep's rows share them), applied in chunks
        times, inverse = np.unique(t, return_inverse=True)
        pos, axes = self.sensor_axes(times)
        rho = row_f - np.floor(row_f / self.detectors) * self.detectors
        local = self._local_directions(rho, self.mirror_angle(col_f))
        directions = np.empty_like(local)
        chunk = 1 << 18
        for s in range(0, len(t), chunk):
            sl = slice(s, s + chunk)
            directions[sl] = np.einsum("nij,nj->ni", axes[inverse[sl]], local[sl])
        return RayBundle(pos[inverse], directions, pixel, weight, self.shape, sub, time=t)

    def project(self, points, iterations: int = 50) -> tuple[np.ndarray, np.ndarray]:
        """Continuous pixel coordinates of scene points (the inverse of :meth:`rays`).

        Fixed-point iteration on (sweep, column): the point's mirror angle and along-track
        offset in the sensor frame at the current guess's time give the next guess.

        Parameters
        ----------
        points : array_like
            ``(..., 3)`` [m].

        Returns
        -------
        row, col : numpy.ndarray
            ``(...)`` [px]; NaN for points behind the sensor. Where successive sweeps overlap
            (the bow-tie at the swath edges) a point is seen twice and the sweep the
            iteration reaches first is returned.
        """
        p = np.asarray(points, dtype=float)
        flat = p.reshape(-1, 3)
        ny, nx = self.shape
        nd = self.detectors
        n_scan = ny // nd
        scan = np.full(len(flat), n_scan // 2, dtype=np.int64)
        col = np.full(len(flat), 0.5 * nx)
        row = np.full(len(flat), np.nan)
        out_col = np.full(len(flat), np.nan)
        active = np.ones(len(flat), dtype=bool)
        for _ in range(iterations):
            if not active.any():
                break
            idx = np.nonzero(active)[0]
            c_eval = np.clip(col[idx], 0.0, nx)
            t = self.sample_times(scan[idx] * nd, c_eval)
            pos, axes = self.sensor_axes(t)
            rel = np.einsum("nji,nj->ni", axes, flat[idx] - pos)
            theta = np.arctan2(rel[:, 0], -rel[:, 2])
            cross = np.hypot(rel[:, 0], rel[:, 2])
            behind = ~(-rel[:, 2] > 0)
            rho = 0.5 * nd + rel[:, 1] / cross / self.pitch
            c = self._column_of_angle(theta)
            r = scan[idx] * nd + rho
            new_scan = np.clip(np.floor(r / nd), 0, n_scan - 1).astype(np.int64)
            done = ((new_scan == scan[idx]) & (np.abs(c - col[idx]) < 1e-9)) | behind
            row[idx] = np.where(behind, np.nan, r)
            out_col[idx] = np.where(behind, np.nan, c)
            scan[idx] = new_scan
            col[idx] = c
            active[idx[done]] = False
        return row.reshape(p.shape[:-1]), out_col.reshape(p.shape[:-1])
