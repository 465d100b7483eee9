"""Frame cameras that generate rays: an orthographic map camera and a pinhole camera.

Both lay a regular ``(ny, nx)`` pixel grid, row 0 at the top of the image and column 0 at its
left, and return a :class:`RayBundle` for it, pixel after pixel (row-major), each pixel's
``supersample**2`` sub-samples consecutive. A pixel's sub-samples sit at the centres of a regular
``k x k`` grid of sub-cells (``k = 1``: the pixel centre) and weigh ``1 / k**2`` each.

Continuous pixel coordinates run from 0 at the top (left) edge of row (column) 0 to ``ny``
(``nx``) at the bottom (right) edge; the centre of pixel ``(i, j)`` is ``(i + 1/2, j + 1/2)``.

========================  ======  =========  ===================================================
parameter                 unit    default    meaning
========================  ======  =========  ===================================================
``OrthographicCamera``
``center``                m       required   ground point (x, y) on z = 0 at the image centre
``shape``                 -       required   (ny, nx) pixels
``gsd``                   m       1.0        pixel pitch on the image plane (= on flat ground,
                                             at nadir)
``altitude``              m       10000.0    height of the image plane centre above z = 0
``zenith``, ``azimuth``   deg     0, 0       direction from the ground to the camera
``PerspectiveCamera``
``position``              m       required   pinhole (x, y, z)
``shape``                 -       required   (ny, nx) pixels, square
``fov``                   deg     60.0       horizontal full field of view, in (0, 180)
``look_at``               m       None       point on the optical axis; or ...
``attitude``              deg     None       ... (yaw, pitch, roll) of the optical axis
========================  ======  =========  ===================================================

Config snippet::

    observers:
      - {type: orthographic, center: [0, 0], shape: [512, 512], gsd: 2.0}
      - {type: perspective, position: [0, -800, 300], shape: [480, 640], fov: 40,
         look_at: [0, 0, 0]}
"""

from __future__ import annotations

from dataclasses import dataclass

import numba
import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.frames import angles_from_direction, direction_from_angles
from radscene.geometry.mesh import rotation_matrix

__all__ = ["RayBundle", "OrthographicCamera", "PerspectiveCamera"]


@dataclass
class RayBundle:
    """Rays of one image: N = (pixels) x (sub-samples per pixel).

    Attributes
    ----------
    origins : numpy.ndarray
        (N, 3) float64 ray origins [m].
    directions : numpy.ndarray
        (N, 3) float64 unit directions of travel [-].
    pixel : numpy.ndarray
        (N,) int64 flat pixel index, row-major over ``shape`` (``row * nx + col``).
    weight : numpy.ndarray
        (N,) float64 weight of the ray in its pixel; a pixel's weights sum to 1 [-].
    shape : tuple of int
        ``(ny, nx)`` of the whole image.
    subsample : numpy.ndarray
        (N,) int64 index of the sub-sample within its pixel, ``a * k + b`` for sub-row ``a``
        and sub-column ``b`` of the ``k x k`` grid.
    time : numpy.ndarray or None
        (N,) float64 acquisition time of each ray [s] on the observer's clock (t = 0 at
        ``observer.epoch``), for scanners; None for a frame taken at one instant.
    """

    origins: np.ndarray
    directions: np.ndarray
    pixel: np.ndarray
    weight: np.ndarray
    shape: tuple[int, int]
    subsample: np.ndarray
    time: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.pixel)

    def to_image(self, values) -> np.ndarray:
        """Weighted sum of per-ray values into their pixels.

        Parameters
        ----------
        values : array_like
            Shape ``(N,)`` or ``(N, K)``, in any unit.

        Returns
        -------
        numpy.ndarray
            Shape ``shape`` or ``shape + (K,)``, same unit; pixels without rays are 0.
        """
        values = np.asarray(values, dtype=float)
        if values.shape[:1] != (len(self),) or values.ndim > 2:
            raise ConfigError(f"must have shape ({len(self)},) or ({len(self)}, K), got "
                              f"{values.shape}", key="values")
        size = self.shape[0] * self.shape[1]
        if values.ndim == 1:
            out = np.bincount(self.pixel, weights=self.weight * values, minlength=size)
            return out.reshape(self.shape)
        out = np.stack([np.bincount(self.pixel, weights=self.weight * values[:, c],
                                    minlength=size) for c in range(values.shape[1])], axis=-1)
        return out.reshape(self.shape + (values.shape[1],))


# -- validation ------------------------------------------------------------------------------


def _shape(shape) -> tuple[int, int]:
    try:
        ny, nx = shape
        ok = all(isinstance(n, int | np.integer) and not isinstance(n, bool) and n > 0
                 for n in (ny, nx))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ConfigError(f"must be two positive integers (ny, nx), got {shape!r}", key="shape")
    return int(ny), int(nx)


def _vector(value, n: int, key: str) -> np.ndarray:
    try:
        a = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        a = np.array([np.nan])
    if a.shape != (n,) or not np.isfinite(a).all():
        raise ConfigError(f"must be {n} finite numbers, got {value!r}", key=key)
    return a


def _number(value, key: str, low=-np.inf, high=np.inf, low_open=False, high_open=False):
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = np.nan
    lo_ok = v > low if low_open else v >= low
    hi_ok = v < high if high_open else v <= high
    if not (np.isfinite(v) and lo_ok and hi_ok):
        interval = f"{'(' if low_open else '['}{low}, {high}{')' if high_open else ']'}"
        raise ConfigError(f"must be a finite number in {interval}, got {value!r}", key=key)
    return v


def _supersample(k) -> int:
    if isinstance(k, bool) or not isinstance(k, int | np.integer) or k < 1:
        raise ConfigError(f"must be an integer >= 1, got {k!r}", key="supersample")
    return int(k)


def _window(window, shape) -> tuple[int, int, int, int]:
    ny, nx = shape
    if window is None:
        return 0, ny, 0, nx
    try:
        r0, r1, c0, c1 = (int(w) for w in window)
    except (TypeError, ValueError):
        raise ConfigError(f"must be (row0, row1, col0, col1), got {window!r}",
                          key="window") from None
    if not (0 <= r0 < r1 <= ny and 0 <= c0 < c1 <= nx):
        raise ConfigError(f"must satisfy 0 <= row0 < row1 <= {ny} and 0 <= col0 < col1 <= "
                          f"{nx}, got {window!r}", key="window")
    return r0, r1, c0, c1


def _sample_grid(shape, supersample, window):
    """Continuous (row, col) of every sub-sample, with pixel, sub-sample index and weight."""
    k = _supersample(supersample)
    r0, r1, c0, c1 = _window(window, shape)
    offset = (np.arange(k) + 0.5) / k
    rows = np.arange(r0, r1)[:, None, None, None]
    cols = np.arange(c0, c1)[None, :, None, None]
    full = (r1 - r0, c1 - c0, k, k)
    row_f = np.broadcast_to(rows + offset[None, None, :, None], full).ravel()
    col_f = np.broadcast_to(cols + offset[None, None, None, :], full).ravel()
    pixel = np.broadcast_to(rows * shape[1] + cols, full).ravel().astype(np.int64)
    sub = np.broadcast_to(np.arange(k * k).reshape(1, 1, k, k), full).ravel().astype(np.int64)
    weight = np.full(pixel.shape, 1.0 / (k * k))
    return row_f, col_f, pixel, sub, weight


@numba.njit(parallel=True, cache=True)
def _plane_kernel(row_f, col_f, half_rows, half_cols, pitch, center, right, up, out):
    """Points of an image plane at continuous pixel coordinates (row, col): the centre, plus
    (col − nx/2) · pitch along ``right`` and (ny/2 − row) · pitch along ``up``, into ``out``."""
    for i in numba.prange(row_f.shape[0]):
        a = (col_f[i] - half_cols) * pitch
        b = (half_rows - row_f[i]) * pitch
        for c in range(3):
            out[i, c] = center[c] + a * right[c] + b * up[c]


# -- cameras ---------------------------------------------------------------------------------


class OrthographicCamera:
    """A map camera: parallel rays, a flat image plane perpendicular to them.

    At nadir (the default) the image is a north-up map: row 0 is the north edge, column 0 the
    west edge, pixel ``(i, j)`` covers ground ``x = x_c + (j - nx/2 .. j + 1 - nx/2) gsd``,
    ``y = y_c + (ny/2 - i - 1 .. ny/2 - i) gsd``. Off nadir the plane tilts: image "up" is north
    projected onto the plane (so the image stays north-up and varies smoothly with the view),
    image "right" completes the frame, and ``gsd`` is the pitch on the plane (the ground
    footprint stretches by ``1 / cos(zenith)`` along the tilt).

    Parameters
    ----------
    center : array_like
        ``(x, y)``: the image centre's ray meets the plane z = 0 there [m].
    shape : tuple of int
        ``(ny, nx)`` pixels.
    gsd : float
        Pixel pitch on the image plane [m], > 0.
    altitude : float
        Height above z = 0 of the image plane's centre, where rays start [m]; must exceed
        the terrain (geometry above the plane is not seen).
    zenith : float
        Zenith angle of the direction from the ground to the camera [deg], in [0, 90).
    azimuth : float
        Azimuth of that direction, clockwise from north [deg].

    Examples
    --------
    >>> cam = OrthographicCamera(center=(0.0, 0.0), shape=(2, 4), gsd=10.0)
    >>> cam.extent
    (-20.0, 20.0, -10.0, 10.0)
    """

    def __init__(self, center, shape, gsd: float = 1.0, altitude: float = 10000.0,
                 zenith: float = 0.0, azimuth: float = 0.0):
        self.center = tuple(float(c) for c in _vector(center, 2, "center"))
        self.shape = _shape(shape)
        self.gsd = _number(gsd, "gsd", low=0.0, low_open=True)
        self.altitude = _number(altitude, "altitude")
        self.zenith = _number(zenith, "zenith", 0.0, 90.0, high_open=True)
        self.azimuth = _number(azimuth, "azimuth")
        #: Unit direction of travel of every ray (camera to ground) [-].
        self.direction = -direction_from_angles(self.zenith, self.azimuth)
        north = np.array([0.0, 1.0, 0.0])
        up = north - (north @ self.direction) * self.direction
        #: Unit image-up and image-right axes in the world frame [-].
        self.up = up / np.linalg.norm(up)
        self.right = np.cross(self.direction, self.up)
        ground = np.array([self.center[0], self.center[1], 0.0])
        #: Centre of the image plane [m].
        self.plane_center = ground - self.direction * self.altitude / (-self.direction[2])

    def __repr__(self) -> str:
        return (f"OrthographicCamera(center={self.center}, shape={self.shape}, gsd={self.gsd}, "
                f"altitude={self.altitude}, zenith={self.zenith}, azimuth={self.azimuth})")

    def _plane_points(self, row_f, col_f) -> np.ndarray:
        row_f, col_f = np.broadcast_arrays(np.asarray(row_f, dtype=float),
                                           np.asarray(col_f, dtype=float))
        out = np.empty(row_f.shape + (3,))
        ny, nx = self.shape
        _plane_kernel(row_f.ravel(), col_f.ravel(), 0.5 * ny, 0.5 * nx, self.gsd,
                      self.plane_center, self.right, self.up, out.reshape(-1, 3))
        return out

    def _to_ground(self, points, height: float) -> np.ndarray:
        t = (points[..., 2] - height) / (-self.direction[2])
        return points + t[..., None] * self.direction

    def rays(self, supersample: int = 1, time=None, window=None) -> RayBundle:
        """Parallel rays from the image plane.

        Parameters
        ----------
        supersample : int
            ``k``: ``k x k`` rays per pixel, >= 1.
        time : datetime, optional
            Ignored (a static camera); accepted so that all observers share one call.
        window : tuple of int, optional
            ``(row0, row1, col0, col1)``: only pixels ``row0 <= row < row1``,
            ``col0 <= col < col1`` (a tile); pixel indices stay those of the whole image.

        Returns
        -------
        RayBundle
        """
        row_f, col_f, pixel, sub, weight = _sample_grid(self.shape, supersample, window)
        origins = self._plane_points(row_f, col_f)
        directions = np.broadcast_to(self.direction, origins.shape).copy()
        return RayBundle(origins, directions, pixel, weight, self.shape, sub)

    def project(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Continuous pixel coordinates of world points: the inverse of :meth:`rays`.

        Parameters
        ----------
        points : array_like
            ``(..., 3)`` world points [m].

        Returns
        -------
        row, col : numpy.ndarray
            Continuous coordinates of the ray through each point (0 at the top / left edge)
            [px].
        in_front : numpy.ndarray
            bool, whether each point lies beyond the image plane, where rays can meet it.

        Examples
        --------
        >>> cam = OrthographicCamera(center=(0.0, 0.0), shape=(2, 4), gsd=10.0)
        >>> [float(a[0]) for a in cam.project([[15.0, 5.0, 0.0]])[:2]]
        [0.5, 3.5]
        """
        rel = np.asarray(points, dtype=float) - self.plane_center
        ny, nx = self.shape
        col = rel @ self.right / self.gsd + 0.5 * nx
        row = 0.5 * ny - rel @ self.up / self.gsd
        return row, col, rel @ self.direction >= 0.0

    def pixel_coordinates(self, height: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Where the rays through the pixel centres meet the plane ``z = height``.

        Parameters
        ----------
        height : float
            Elevation of the reference plane [m].

        Returns
        -------
        x, y : numpy.ndarray
            Easting and northing, shape ``(ny, nx)`` each [m].
        """
        ny, nx = self.shape
        row_f, col_f = np.meshgrid(np.arange(ny) + 0.5, np.arange(nx) + 0.5, indexing="ij")
        g = self._to_ground(self._plane_points(row_f, col_f), float(height))
        return g[..., 0], g[..., 1]

    def map_axes(self, height: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """At nadir, the easting of each column and the northing of each row [m].

        The values :meth:`pixel_coordinates` gives along the first row and the first column
        (at nadir every row has the same eastings, every column the same northings).

        Examples
        --------
        >>> OrthographicCamera(center=(0.0, 0.0), shape=(2, 4), gsd=10.0).map_axes()
        (array([-15.,  -5.,   5.,  15.]), array([ 5., -5.]))
        """
        if self.zenith != 0.0:
            raise ValueError(f"map axes need a nadir camera; this one looks {self.zenith} deg "
                             "off nadir")
        ny, nx = self.shape
        x = self._to_ground(self._plane_points(np.full(nx, 0.5), np.arange(nx) + 0.5),
                            float(height))[:, 0]
        y = self._to_ground(self._plane_points(np.arange(ny) + 0.5, np.full(ny, 0.5)),
                            float(height))[:, 1]
        return x, y

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of the image's footprint on z = 0 [m].

        At nadir the footprint is exactly this rectangle; off nadir it is its bounding box.
        """
        ny, nx = self.shape
        corners = self._to_ground(self._plane_points(np.array([0, 0, ny, ny]),
                                                     np.array([0, nx, 0, nx])), 0.0)
        return (float(corners[:, 0].min()), float(corners[:, 0].max()),
                float(corners[:, 1].min()), float(corners[:, 1].max()))


class PerspectiveCamera:
    """A pinhole frame camera with square pixels.

    The optical axis is the camera's forward axis; image right and image up are the camera's
    right and up axes, from :func:`radscene.geometry.rotation_matrix` of the attitude
    (yaw = azimuth of the optical axis, pitch = its elevation above the horizontal, negative
    looking down, roll about it, positive turning the image's right side down). ``look_at``
    sets yaw and pitch from the direction to the point, with roll 0 (the horizon level); looking
    straight down, yaw is 0: image up is north and image right east.

    Pixel ``(i, j)`` at continuous coordinates ``(r, c)`` looks along
    ``forward + (c - nx/2) p right + (ny/2 - r) p up`` with ``p = 2 tan(fov/2) / nx``.

    Parameters
    ----------
    position : array_like
        Pinhole ``(x, y, z)`` [m].
    shape : tuple of int
        ``(ny, nx)`` pixels.
    fov : float
        Horizontal full field of view, edge to edge of the image, in (0, 180) [deg].
    look_at : array_like, optional
        A point ``(x, y, z)`` on the optical axis [m], not the position itself.
    attitude : array_like, optional
        ``(yaw, pitch, roll)`` [deg]. Exactly one of ``look_at`` and ``attitude``.

    Examples
    --------
    >>> cam = PerspectiveCamera((0, 0, 100), (3, 3), fov=90.0, look_at=(0, 0, 0))
    >>> cam.forward.round(12), cam.up.round(12)
    (array([ 0.,  0., -1.]), array([0., 1., 0.]))
    """

    def __init__(self, position, shape, fov: float = 60.0, look_at=None, attitude=None):
        self.position = _vector(position, 3, "position")
        self.shape = _shape(shape)
        self.fov = _number(fov, "fov", 0.0, 180.0, low_open=True, high_open=True)
        if (look_at is None) == (attitude is None):
            raise ConfigError("give exactly one of look_at (a point) and attitude "
                              "(yaw, pitch, roll)", key="look_at, attitude")
        if look_at is not None:
            target = _vector(look_at, 3, "look_at")
            axis = target - self.position
            length = np.linalg.norm(axis)
            if length == 0:
                raise ConfigError("must differ from position", key="look_at")
            zenith, azimuth = angles_from_direction(axis)
            if np.hypot(axis[0], axis[1]) <= 1e-12 * length:
                azimuth = 0.0  # straight up or down: north-up
            self.attitude = (float(azimuth), 90.0 - float(zenith), 0.0)
        else:
            self.attitude = tuple(float(a) for a in _vector(attitude, 3, "attitude"))
        rot = rotation_matrix(*self.attitude)
        #: Camera axes in the world frame, unit vectors [-].
        self.right, self.forward, self.up = rot[:, 0], rot[:, 1], rot[:, 2]

    def __repr__(self) -> str:
        return (f"PerspectiveCamera(position={tuple(self.position)}, shape={self.shape}, "
                f"fov={self.fov}, attitude={self.attitude})")

    @property
    def pixel_pitch(self) -> float:
        """Pixel size on a plane at unit distance along the axis, ``2 tan(fov/2) / nx`` [-]."""
        return 2.0 * np.tan(np.radians(0.5 * self.fov)) / self.shape[1]

    @property
    def fov_vertical(self) -> float:
        """Vertical full field of view [deg]."""
        return float(2.0 * np.degrees(np.arctan(0.5 * self.shape[0] * self.pixel_pitch)))

    def directions_at(self, row, col) -> np.ndarray:
        """Unit directions through continuous pixel coordinates.

        Parameters
        ----------
        row, col : array_like
            Continuous coordinates, 0 at the top / left edge (see the module docstring) [px].

        Returns
        -------
        numpy.ndarray
            Shape ``broadcast(row, col).shape + (3,)`` [-].
        """
        row, col = np.broadcast_arrays(np.asarray(row, dtype=float), np.asarray(col, dtype=float))
        ny, nx = self.shape
        p = self.pixel_pitch
        a = (col - 0.5 * nx) * p
        b = (0.5 * ny - row) * p
        d = self.forward + a[..., None] * self.right + b[..., None] * self.up
        return d / np.linalg.norm(d, axis=-1, keepdims=True)

    def project(self, points) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Continuous pixel coordinates of world points: the inverse of :meth:`directions_at`.

        Parameters
        ----------
        points : array_like
            ``(..., 3)`` world points [m].

        Returns
        -------
        row, col : numpy.ndarray
            Continuous coordinates of the ray through each point (0 at the top / left edge)
            [px]; NaN for points not in front of the pinhole.
        in_front : numpy.ndarray
            bool, whether each point lies in front of the pinhole (positive along the axis).

        Examples
        --------
        >>> cam = PerspectiveCamera((0, 0, 100), (3, 3), fov=90.0, look_at=(0, 0, 0))
        >>> [round(float(a[0]), 12) for a in cam.project([[0.0, 0.0, 0.0]])[:2]]
        [1.5, 1.5]
        """
        rel = np.asarray(points, dtype=float) - self.position
        depth = rel @ self.forward
        in_front = depth > 0.0
        ny, nx = self.shape
        p = self.pixel_pitch
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(in_front, 1.0 / (depth * p), np.nan)
            col = rel @ self.right * scale + 0.5 * nx
            row = 0.5 * ny - rel @ self.up * scale
        return row, col, in_front

    def rays(self, supersample: int = 1, time=None, window=None) -> RayBundle:
        """Rays from the pinhole through every (sub-)pixel.

        Parameters
        ----------
        supersample : int
            ``k``: ``k x k`` rays per pixel, >= 1.
        time : datetime, optional
            Ignored (a static camera); accepted so that all observers share one call.
        window : tuple of int, optional
            ``(row0, row1, col0, col1)`` tile of pixels; pixel indices stay those of the
            whole image.

        Returns
        -------
        RayBundle
        """
        row_f, col_f, pixel, sub, weight = _sample_grid(self.shape, supersample, window)
        directions = self.directions_at(row_f, col_f)
        origins = np.broadcast_to(self.position, directions.shape).copy()
        return RayBundle(origins, directions, pixel, weight, self.shape, sub)
