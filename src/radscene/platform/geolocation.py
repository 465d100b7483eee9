"""The WGS84 Earth, the scene's local frame, and the geolocation of every pixel.

radscene renders a scene in a local east-north-up frame (x east, y north, z up, metres) whose
origin is a point on the Earth (the scene's location). :class:`LocalFrame` ties that frame to
the WGS84 ellipsoid: geodetic (latitude, longitude, height above the ellipsoid) ↔ ECEF
(Earth-centred, Earth-fixed, metres) ↔ local ENU, with geodetic → ECEF done by pyproj
(EPSG:4979 → EPSG:4978), ECEF → geodetic by a compiled closed-form-plus-iteration kernel (one
pass over the points, as the render geolocates a million pixels) and the ENU rotation written
out (it is exact and rigid: the frame is the tangent plane at the origin, and points far from
the origin keep their true ECEF position, e.g. a point on the plane z = 0 100 km away is 785 m
above the ellipsoid).

Geolocation takes an observer's rays through the pixel centres, meets them with a surface (a
plane ``z = height`` of the scene frame, the WGS84 ellipsoid at a height, or the scene's ray
tracer) and reports, per pixel, the ground point's latitude, longitude and height, the view
and sun angles in the local geodetic frame *at the ground point*, and the acquisition time
(:func:`geolocation_truth`). :func:`project` goes the other way, ground point → continuous
pixel coordinates, for every observer (frame cameras in closed form, scanners by iteration),
so that pixel → ground → pixel closes to far better than 0.1 pixel.

References
----------
NIMA TR8350.2, *Department of Defense World Geodetic System 1984*, 3rd ed. (2000): a =
6378137 m, 1/f = 298.257223563, ω = 7.292115e-5 rad/s.
"""

from __future__ import annotations

import datetime as _dt
import math
from functools import lru_cache

import numba
import numpy as np

from radscene.errors import ConfigError

__all__ = [
    "WGS84_A",
    "WGS84_F",
    "WGS84_B",
    "WGS84_E2",
    "EARTH_ROTATION_RATE",
    "geodetic_to_ecef",
    "ecef_to_geodetic",
    "enu_basis",
    "LocalFrame",
    "intersect_ellipsoid",
    "intersect_plane",
    "pixel_center_rays",
    "ground_points",
    "project",
    "geolocation_truth",
]

#: WGS84 semi-major axis [m].
WGS84_A = 6378137.0
#: WGS84 flattening [-].
WGS84_F = 1.0 / 298.257223563
#: WGS84 semi-minor axis [m].
WGS84_B = WGS84_A * (1.0 - WGS84_F)
#: WGS84 first eccentricity squared [-].
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
#: The Earth's rotation rate (WGS84) [rad s-1].
EARTH_ROTATION_RATE = 7.292115e-5


@lru_cache(maxsize=2)
def _transformer(forward: bool):
    from pyproj import Transformer

    src, dst = ("EPSG:4979", "EPSG:4978") if forward else ("EPSG:4978", "EPSG:4979")
    return Transformer.from_crs(src, dst, always_xy=True)


def _check_latitude(latitude, key="latitude"):
    lat = np.asarray(latitude, dtype=float)
    if not np.all(np.abs(lat[np.isfinite(lat)]) <= 90.0):
        raise ConfigError(f"must be in [-90, 90] deg; got values up to "
                          f"{np.nanmax(np.abs(lat)):g}", key=key)
    return lat


def geodetic_to_ecef(latitude, longitude, height=0.0) -> np.ndarray:
    """ECEF coordinates of geodetic positions on WGS84 (pyproj, EPSG:4979 → EPSG:4978).

    Parameters
    ----------
    latitude : array_like
        Geodetic latitude [deg], in [-90, 90].
    longitude : array_like
        Longitude [deg], east positive.
    height : array_like
        Height above the ellipsoid [m].

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast(latitude, longitude, height).shape + (3,)`` [m].

    Examples
    --------
    >>> geodetic_to_ecef(0.0, 90.0, 0.0).round(6)
    array([      0., 6378137.,       0.])
    """
    lat = _check_latitude(latitude)
    lat, lon, h = np.broadcast_arrays(lat, np.asarray(longitude, dtype=float),
                                      np.asarray(height, dtype=float))
    x, y, z = _transformer(True).transform(lon.ravel(), lat.ravel(), h.ravel())
    return np.stack([x, y, z], axis=-1).reshape(lat.shape + (3,))


def ecef_to_geodetic(xyz) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Geodetic latitude [deg], longitude [deg] and height [m] of ECEF points.

    Compiled (numba): Bowring's closed-form estimate of the latitude, then two fixed-point
    iterations on it make it exact to double precision at any height (tested against pyproj's
    EPSG:4978 → EPSG:4979).

    Parameters
    ----------
    xyz : array_like
        ECEF coordinates, shape ``(..., 3)`` [m].

    Returns
    -------
    latitude, longitude, height : numpy.ndarray
        Shape ``xyz.shape[:-1]`` each; longitude in (-180, 180].
    """
    p = np.asarray(xyz, dtype=float)
    if p.shape[-1:] != (3,):
        raise ConfigError(f"must have shape (..., 3); got {p.shape}", key="xyz")
    return _geodetic(p, np.eye(3), np.zeros(3))


#: Fixed-point steps on the latitude after Bowring's estimate.
_LATITUDE_STEPS = 2


@numba.njit(inline="always", error_model="numpy")
def _geodetic_point(px, py, pz, rotation, origin):
    """Geodetic coordinates of the ECEF point (px, py, pz) @ rotation + origin [deg, deg, m]."""
    a, e2 = WGS84_A, WGS84_E2
    b = a * math.sqrt(1.0 - e2)
    ep2 = e2 / (1.0 - e2)
    x = px * rotation[0, 0] + py * rotation[1, 0] + pz * rotation[2, 0] + origin[0]
    y = px * rotation[0, 1] + py * rotation[1, 1] + pz * rotation[2, 1] + origin[1]
    z = px * rotation[0, 2] + py * rotation[1, 2] + pz * rotation[2, 2] + origin[2]
    rho = math.sqrt(x * x + y * y)
    # Bowring's estimate through the parametric latitude β, then fixed-point steps on
    # tan φ = (z + e² N sin φ) / p, each gaining a factor ≈ e² (exact to double precision);
    # angles are carried as (cos, sin) pairs: no trigonometric call until the last
    c, s = _unit(b * rho, a * z)
    c, s = _unit(rho - e2 * a * c * c * c, z + ep2 * b * s * s * s)
    u, v = rho, z
    for _ in range(_LATITUDE_STEPS):
        n = a / math.sqrt(1.0 - e2 * s * s)
        u, v = rho, z + e2 * n * s
        c, s = _unit(u, v)
    return (math.degrees(math.atan2(v, u)), math.degrees(math.atan2(y, x)),
            rho * c + z * s - a * math.sqrt(1.0 - e2 * s * s))


@numba.njit(parallel=True, cache=True, error_model="numpy")
def _geodetic_kernel(points, rotation, origin, lat, lon, height):
    """Geodetic coordinates of ``points @ rotation + origin`` (ECEF) [deg, deg, m]."""
    for i in numba.prange(points.shape[0]):
        lat[i], lon[i], height[i] = _geodetic_point(points[i, 0], points[i, 1], points[i, 2],
                                                    rotation, origin)


@numba.njit(parallel=True, cache=True, error_model="numpy")
def _pixel_kernel(points, travel, pixel, rotation, origin, out):
    """:meth:`LocalFrame.pixel_geolocation` into ``out`` (5, n_pixels), NaN-filled."""
    for i in numba.prange(points.shape[0]):
        p = pixel[i]
        out[0, p], out[1, p], out[2, p] = _geodetic_point(points[i, 0], points[i, 1],
                                                          points[i, 2], rotation, origin)
        # the direction from the surface back along the ray, as angles_from_direction
        dx, dy, dz = -travel[i, 0], -travel[i, 1], -travel[i, 2]
        norm = math.sqrt(dx * dx + dy * dy + dz * dz)
        out[3, p] = math.degrees(math.acos(min(1.0, max(-1.0, dz / norm))))
        azimuth = math.degrees(math.atan2(dx, dy))
        out[4, p] = azimuth + 360.0 if azimuth < 0.0 else azimuth


@numba.njit(inline="always", error_model="numpy")
def _unit(u, v):
    """(u, v) / |(u, v)|; (1, 0) for the zero vector (the Earth's centre)."""
    r = math.sqrt(u * u + v * v)  # |u|, |v| < 1e10 m here: no overflow
    if r == 0.0:
        return 1.0, 0.0
    return u / r, v / r


def _geodetic(points, rotation, origin) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(latitude, longitude, height) of the ECEF points ``points @ rotation + origin``."""
    shape = points.shape[:-1]
    flat = np.ascontiguousarray(points.reshape(-1, 3), dtype=np.float64)
    out = np.empty((3, len(flat)))
    if len(flat):
        _geodetic_kernel(flat, np.ascontiguousarray(rotation, dtype=np.float64),
                         np.ascontiguousarray(origin, dtype=np.float64), out[0], out[1], out[2])
    return out[0].reshape(shape), out[1].reshape(shape), out[2].reshape(shape)


def enu_basis(latitude, longitude) -> np.ndarray:
    """Rotation from ECEF to the local east-north-up frame at a geodetic position.

    Parameters
    ----------
    latitude, longitude : array_like
        Geodetic latitude and longitude [deg].

    Returns
    -------
    numpy.ndarray
        Shape ``(..., 3, 3)`` [-]: rows are the unit east, north and up vectors in ECEF, so
        ``enu = basis @ (ecef - origin)``.

    Notes
    -----
    .. math::
        \\hat e = (-\\sin\\lambda, \\cos\\lambda, 0),\\quad
        \\hat n = (-\\sin\\varphi\\cos\\lambda, -\\sin\\varphi\\sin\\lambda, \\cos\\varphi),\\quad
        \\hat u = (\\cos\\varphi\\cos\\lambda, \\cos\\varphi\\sin\\lambda, \\sin\\varphi)
    """
    lat = np.radians(_check_latitude(latitude))
    lon = np.radians(np.asarray(longitude, dtype=float))
    lat, lon = np.broadcast_arrays(lat, lon)
    sp, cp, sl, cl = np.sin(lat), np.cos(lat), np.sin(lon), np.cos(lon)
    zero = np.zeros_like(lat)
    rows = [np.stack([-sl, cl, zero], -1), np.stack([-sp * cl, -sp * sl, cp], -1),
            np.stack([cp * cl, cp * sl, sp], -1)]
    return np.stack(rows, axis=-2)


class LocalFrame:
    """The scene's east-north-up frame, anchored at a geodetic origin on WGS84.

    Parameters
    ----------
    latitude, longitude : float
        Geodetic position of the origin [deg].
    height : float
        Height of the origin above the ellipsoid [m] (the scene's ``location.altitude``).

    Examples
    --------
    >>> f = LocalFrame(45.0, 7.0, 0.0)
    >>> [round(float(v), 6) for v in f.to_geodetic([0.0, 0.0, 100.0])]
    [45.0, 7.0, 100.0]
    """

    def __init__(self, latitude: float, longitude: float, height: float = 0.0):
        lat = float(latitude)
        if not (np.isfinite(lat) and -90.0 <= lat <= 90.0):
            raise ConfigError(f"must be in [-90, 90] deg; got {latitude!r}", key="latitude")
        lon = float(longitude)
        if not np.isfinite(lon):
            raise ConfigError(f"must be finite; got {longitude!r}", key="longitude")
        h = float(height)
        if not np.isfinite(h):
            raise ConfigError(f"must be finite; got {height!r}", key="height")
        self.latitude, self.longitude, self.height = lat, ((lon + 180.0) % 360.0) - 180.0, h
        #: ECEF position of the origin [m].
        self.origin_ecef = geodetic_to_ecef(lat, lon, h)
        #: Rows: east, north, up unit vectors in ECEF [-].
        self.rotation = enu_basis(lat, lon)

    def __repr__(self) -> str:
        return (f"LocalFrame(latitude={self.latitude}, longitude={self.longitude}, "
                f"height={self.height})")

    def to_ecef(self, enu) -> np.ndarray:
        """ECEF coordinates [m] of local points ``(..., 3)`` [m]."""
        return np.asarray(enu, dtype=float) @ self.rotation + self.origin_ecef

    def from_ecef(self, ecef) -> np.ndarray:
        """Local ENU coordinates [m] of ECEF points ``(..., 3)`` [m]."""
        return (np.asarray(ecef, dtype=float) - self.origin_ecef) @ self.rotation.T

    def vector_to_ecef(self, v) -> np.ndarray:
        """Rotate local vectors ``(..., 3)`` into ECEF axes (no translation)."""
        return np.asarray(v, dtype=float) @ self.rotation

    def vector_from_ecef(self, v) -> np.ndarray:
        """Rotate ECEF vectors ``(..., 3)`` into local axes (no translation)."""
        return np.asarray(v, dtype=float) @ self.rotation.T

    def to_geodetic(self, enu) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Latitude [deg], longitude [deg] and ellipsoidal height [m] of local points [m]."""
        p = np.asarray(enu, dtype=float)
        if p.shape[-1:] != (3,):
            raise ConfigError(f"must have shape (..., 3); got {p.shape}", key="enu")
        return _geodetic(p, self.rotation, self.origin_ecef)

    def pixel_geolocation(self, points, travel, pixel, size: int) -> np.ndarray:
        """Per-pixel geolocation of the surface points rays met, in one compiled pass.

        Parameters
        ----------
        points : (N, 3) float64 — local points [m], one per pixel
        travel : (N, 3) float64 — the direction each ray travelled to its point
        pixel : (N,) int — the flat pixel of each point, all distinct, in ``[0, size)``
        size : int — the number of pixels

        Returns
        -------
        numpy.ndarray
            (5, size): latitude [deg], longitude [deg], height [m] (as :meth:`to_geodetic`),
            then the zenith and azimuth [deg] of ``-travel`` (as
            :func:`radscene.geometry.frames.angles_from_direction`); NaN at pixels without a
            point.
        """
        out = np.full((5, int(size)), np.nan)
        if len(pixel):
            _pixel_kernel(np.ascontiguousarray(points, dtype=np.float64),
                          np.ascontiguousarray(travel, dtype=np.float64),
                          np.ascontiguousarray(pixel, dtype=np.int64),
                          np.ascontiguousarray(self.rotation, dtype=np.float64),
                          np.ascontiguousarray(self.origin_ecef, dtype=np.float64), out)
        return out

    def from_geodetic(self, latitude, longitude, height=0.0) -> np.ndarray:
        """Local ENU coordinates [m] of geodetic positions ([deg], [deg], [m])."""
        return self.from_ecef(geodetic_to_ecef(latitude, longitude, height))

    def local_basis(self, enu) -> np.ndarray:
        """East, north, up of the geodetic frame *at* local points, in local axes.

        Parameters
        ----------
        enu : array_like
            Points ``(..., 3)`` [m].

        Returns
        -------
        numpy.ndarray
            ``(..., 3, 3)``: rows are the point's own east, north and up unit vectors, in the
            scene frame's axes [-].
        """
        lat, lon, _ = self.to_geodetic(enu)
        return enu_basis(lat, lon) @ self.rotation.T

    def crs(self):
        """A pyproj CRS whose easting/northing are the frame's x/y on the ellipsoid.

        The ellipsoidal orthographic projection centred at the origin (EPSG method 9840)
        maps a point on the ellipsoid to its topocentric east and north, which are this
        frame's x and y. For a point ``(x, y, z)`` of the scene the CRS coordinates of the
        ellipsoid point below it differ from ``(x, y)`` by about ``h d / R`` (d the distance
        from the origin, R the Earth's radius, h the point's height above the ellipsoid):
        0.01 m at 10 km on the plane z = 0.

        Returns
        -------
        pyproj.CRS
        """
        from pyproj import CRS

        return CRS.from_proj4(f"+proj=ortho +lat_0={self.latitude!r} +lon_0={self.longitude!r} "
                              "+datum=WGS84 +units=m +no_defs +type=crs")


# -- rays and surfaces -------------------------------------------------------------------------


def intersect_plane(origins, directions, height=0.0) -> np.ndarray:
    """Distance along rays to the plane ``z = height`` of the scene frame [m].

    Parameters
    ----------
    origins, directions : array_like
        ``(..., 3)`` ray origins [m] and unit directions [-].
    height : float or array_like
        Plane elevation [m].

    Returns
    -------
    numpy.ndarray
        ``(...)`` distances [m]; NaN where the ray runs parallel to or away from the plane.
    """
    o = np.asarray(origins, dtype=float)
    d = np.asarray(directions, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (np.asarray(height, dtype=float) - o[..., 2]) / d[..., 2]
    return np.where(np.isfinite(t) & (t >= 0.0), t, np.nan)


def intersect_ellipsoid(origins_ecef, directions_ecef, height=0.0, iterations: int = 3):
    """Distance along ECEF rays to the surface at a constant height above WGS84 [m].

    The ray first meets the ellipsoid with semi-axes ``a + h, a + h, b + h`` (exact for
    h = 0), then Newton steps on the geodetic height (pyproj) bring the point onto the
    surface of constant height h to well under a millimetre.

    Parameters
    ----------
    origins_ecef, directions_ecef : array_like
        ``(..., 3)`` origins [m] and unit directions [-] in ECEF.
    height : float or array_like
        Height above the ellipsoid [m].
    iterations : int
        Newton steps after the first intersection.

    Returns
    -------
    numpy.ndarray
        ``(...)`` distances [m]; NaN where the ray misses.
    """
    o = np.asarray(origins_ecef, dtype=float)
    d = np.asarray(directions_ecef, dtype=float)
    h = np.asarray(height, dtype=float)
    scale = np.stack(np.broadcast_arrays(WGS84_A + h, WGS84_A + h, WGS84_B + h), axis=-1)
    os_, ds = o / scale, d / scale
    a = np.einsum("...c,...c->...", ds, ds)
    b = np.einsum("...c,...c->...", os_, ds)
    c = np.einsum("...c,...c->...", os_, os_) - 1.0
    disc = b * b - a * c
    with np.errstate(invalid="ignore"):
        root = np.sqrt(disc)
        t = np.where(c > 0.0, (-b - root) / a, (-b + root) / a)  # outside: near root
    t = np.where((disc >= 0.0) & (t >= 0.0), t, np.nan)
    ok = np.isfinite(t)
    for _ in range(iterations):
        if not ok.any():
            break
        p = o[ok] + t[ok, None] * d[ok]
        lat, lon, hp = ecef_to_geodetic(p)
        up = enu_basis(lat, lon)[..., 2, :]
        rate = np.einsum("nc,nc->n", d[ok], up)
        with np.errstate(divide="ignore", invalid="ignore"):
            t[ok] = t[ok] - (hp - np.broadcast_to(h, t.shape)[ok]) / rate
    return t


def pixel_center_rays(observer):
    """Rays through the pixel centres of an observer.

    Parameters
    ----------
    observer : camera or scanner
        Anything whose ``rays(supersample=1)`` returns a
        :class:`~radscene.platform.cameras.RayBundle`.

    Returns
    -------
    origins, directions : numpy.ndarray
        ``(ny, nx, 3)`` in the scene frame [m], [-].
    time : numpy.ndarray or None
        ``(ny, nx)`` acquisition times [s] after the observer's epoch; None for a static
        camera.
    """
    bundle = observer.rays(supersample=1)
    ny, nx = bundle.shape
    order = np.argsort(bundle.pixel, kind="stable")
    origins = bundle.origins[order].reshape(ny, nx, 3)
    directions = bundle.directions[order].reshape(ny, nx, 3)
    time = getattr(bundle, "time", None)
    if time is not None:
        time = np.asarray(time)[order].reshape(ny, nx)
    return origins, directions, time


def ground_points(origins, directions, surface=0.0, frame: LocalFrame | None = None):
    """Where rays meet the ground.

    Parameters
    ----------
    origins, directions : array_like
        ``(..., 3)`` rays in the scene frame [m], [-].
    surface : float, "ellipsoid" or RayTracer
        A number: the plane ``z = surface`` of the scene frame [m]. ``"ellipsoid"``: the WGS84
        ellipsoid (height 0; needs ``frame``). ``("ellipsoid", h)``: the surface at height h
        above it [m]. An object with ``intersect(origins, directions)`` (the scene's
        :class:`~radscene.geometry.RayTracer`): the scene geometry itself.
    frame : LocalFrame, optional
        The scene's frame; needed for the ellipsoid.

    Returns
    -------
    numpy.ndarray
        ``(..., 3)`` ground points in the scene frame [m]; NaN where a ray misses.
    """
    o = np.asarray(origins, dtype=float)
    d = np.asarray(directions, dtype=float)
    if hasattr(surface, "intersect"):
        flat_o, flat_d = o.reshape(-1, 3), d.reshape(-1, 3)
        hits = surface.intersect(flat_o, flat_d)
        t = np.where(hits.hit, hits.distance, np.nan).reshape(o.shape[:-1])
    elif isinstance(surface, str) or (isinstance(surface, tuple) and surface
                                        and surface[0] == "ellipsoid"):
        if surface != "ellipsoid" and not isinstance(surface, tuple):
            raise ConfigError(f"unknown surface {surface!r}; use a height [m], 'ellipsoid', "
                              "('ellipsoid', height) or a ray tracer", key="surface")
        if frame is None:
            raise ConfigError("the ellipsoid needs the scene's LocalFrame", key="frame")
        h = 0.0 if isinstance(surface, str) else float(surface[1])
        t = intersect_ellipsoid(frame.to_ecef(o), frame.vector_to_ecef(d), h)
    else:
        try:
            h = float(surface)
        except (TypeError, ValueError):
            raise ConfigError(f"unknown surface {surface!r}; use a height [m], 'ellipsoid', "
                              "('ellipsoid', height) or a ray tracer", key="surface") from None
        t = intersect_plane(o, d, h)
    return o + t[..., None] * d


# -- ground → pixel ------------------------------------------------------------------------------


def project(observer, points) -> tuple[np.ndarray, np.ndarray]:
    """Continuous pixel coordinates at which an observer sees points of the scene.

    Parameters
    ----------
    observer : OrthographicCamera, PerspectiveCamera, or a scanner with ``project``
    points : array_like
        ``(..., 3)`` points in the scene frame [m].

    Returns
    -------
    row, col : numpy.ndarray
        ``(...)`` continuous pixel coordinates (0 at the top/left edge; the centre of pixel
        ``(i, j)`` is ``(i + 0.5, j + 0.5)``) [px]; NaN for points behind a camera. Values
        outside ``[0, ny) x [0, nx)`` lie outside the image.
    """
    from radscene.platform.cameras import OrthographicCamera, PerspectiveCamera

    p = np.asarray(points, dtype=float)
    if isinstance(observer, OrthographicCamera):
        rel = p - observer.plane_center
        col = rel @ observer.right / observer.gsd + 0.5 * observer.shape[1]
        row = 0.5 * observer.shape[0] - rel @ observer.up / observer.gsd
        return row, col
    if isinstance(observer, PerspectiveCamera):
        rel = p - observer.position
        depth = rel @ observer.forward
        with np.errstate(divide="ignore", invalid="ignore"):
            a = np.where(depth > 0.0, rel @ observer.right / depth, np.nan)
            b = np.where(depth > 0.0, rel @ observer.up / depth, np.nan)
        pitch = observer.pixel_pitch
        return 0.5 * observer.shape[0] - b / pitch, a / pitch + 0.5 * observer.shape[1]
    if hasattr(observer, "project"):
        return observer.project(p)
    raise ConfigError(f"cannot project onto a {type(observer).__name__}", key="observer")


# -- truth -----------------------------------------------------------------------------------


def _sun_ecef(frame: LocalFrame, epoch, seconds) -> np.ndarray:
    """Unit ECEF vectors towards the Sun at times ``epoch + seconds`` (shape of seconds)."""
    from radscene.geometry.frames import direction_from_angles
    from radscene.sun import sun_position

    s = np.asarray(seconds, dtype=float)
    finite = s[np.isfinite(s)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    nodes = np.linspace(lo, hi, 2 if hi - lo < 60.0 else min(64, int((hi - lo) / 60.0) + 2))
    times = [epoch + _dt.timedelta(seconds=float(n)) for n in nodes]
    pos = sun_position(times, frame.latitude, frame.longitude, frame.height)
    sun = frame.vector_to_ecef(direction_from_angles(pos.zenith, pos.azimuth))
    out = np.stack([np.interp(s, nodes, sun[:, c]) for c in range(3)], axis=-1)
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def geolocation_truth(observer, frame: LocalFrame, surface=0.0, epoch=None):
    """Per-pixel geolocation truth: ground position, view and sun angles, time.

    Parameters
    ----------
    observer : camera or scanner
        The observer; its rays through the pixel centres are met with ``surface``.
    frame : LocalFrame
        The scene's frame on the Earth.
    surface : float, "ellipsoid", ("ellipsoid", h) or RayTracer
        See :func:`ground_points`; default the plane z = 0 of the scene.
    epoch : datetime, optional
        Timezone-aware time of the observer's time 0 (a static camera's acquisition time);
        default ``observer.epoch`` when it has one. Without a time the sun angles are NaN.

    Returns
    -------
    xarray.Dataset
        On ``(y, x)``: ``latitude``, ``longitude`` [degrees_north/east], ``height`` [m]
        above WGS84, ``ground_x/ground_y/ground_z`` [m] in the scene frame,
        ``view_zenith``/``view_azimuth`` [degree] of the direction from the ground point to
        the sensor and ``sun_zenith``/``sun_azimuth`` [degree] (true, no refraction), both in
        the geodetic east-north-up frame of the ground point, ``slant_range`` [m] and
        ``acquisition_time`` [s after ``epoch``]. NaN where the ray misses the surface.

    Notes
    -----
    The sun direction is computed with the SPA at the frame origin (pvlib) and carried to
    every pixel as an ECEF vector; the parallax over a scene is below 0.003 deg.
    """
    import xarray as xr

    from radscene.geometry.frames import angles_from_direction

    origins, directions, time = pixel_center_rays(observer)
    ground = ground_points(origins, directions, surface, frame)
    ny, nx = ground.shape[:2]
    lat, lon, height = frame.to_geodetic(ground)
    basis = enu_basis(np.nan_to_num(lat), np.nan_to_num(lon))  # ECEF → ground ENU
    to_sensor = frame.vector_to_ecef(-directions)
    view_local = np.einsum("...ij,...j->...i", basis, to_sensor)
    view_zenith, view_azimuth = angles_from_direction(view_local)
    epoch = epoch if epoch is not None else getattr(observer, "epoch", None)
    seconds = time if time is not None else np.zeros((ny, nx))
    if epoch is not None:
        if epoch.tzinfo is None:
            raise ConfigError("must be timezone-aware", key="epoch")
        sun_local = np.einsum("...ij,...j->...i", basis, _sun_ecef(frame, epoch, seconds))
        sun_zenith, sun_azimuth = angles_from_direction(sun_local)
    else:
        sun_zenith = sun_azimuth = np.full((ny, nx), np.nan)
    miss = ~np.isfinite(ground[..., 0])
    rng = np.linalg.norm(ground - origins, axis=-1)
    layers = {}
    for name, values in (("view_zenith", view_zenith), ("view_azimuth", view_azimuth),
                         ("sun_zenith", sun_zenith), ("sun_azimuth", sun_azimuth)):
        layers[name] = np.where(miss, np.nan, values)
    dims = ("y", "x")
    ds = xr.Dataset({
        "latitude": (dims, lat, {"units": "degrees_north", "standard_name": "latitude",
                                 "long_name": "geodetic latitude (WGS84) of the ground point"}),
        "longitude": (dims, lon, {"units": "degrees_east", "standard_name": "longitude",
                                  "long_name": "longitude (WGS84) of the ground point"}),
        "height": (dims, height, {"units": "m", "standard_name": "height_above_reference_ellipsoid",
                                  "long_name": "height of the ground point above WGS84"}),
        "ground_x": (dims, ground[..., 0], {"units": "m", "long_name": "ground point easting in the scene frame"}),
        "ground_y": (dims, ground[..., 1], {"units": "m", "long_name": "ground point northing in the scene frame"}),
        "ground_z": (dims, ground[..., 2], {"units": "m", "long_name": "ground point elevation in the scene frame"}),
        "view_zenith": (dims, layers["view_zenith"], {
            "units": "degree", "standard_name": "sensor_zenith_angle",
            "long_name": "zenith of the direction from the ground point to the sensor"}),
        "view_azimuth": (dims, layers["view_azimuth"], {
            "units": "degree", "standard_name": "sensor_azimuth_angle",
            "long_name": "azimuth (clockwise from north) of the direction to the sensor"}),
        "sun_zenith": (dims, layers["sun_zenith"], {
            "units": "degree", "standard_name": "solar_zenith_angle",
            "long_name": "true solar zenith angle at the ground point"}),
        "sun_azimuth": (dims, layers["sun_azimuth"], {
            "units": "degree", "standard_name": "solar_azimuth_angle",
            "long_name": "solar azimuth, clockwise from north, at the ground point"}),
        "slant_range": (dims, np.where(miss, np.nan, rng), {
            "units": "m", "long_name": "distance from the sensor to the ground point"}),
        "acquisition_time": (dims, seconds.astype(float), {
            "units": "s", "long_name": "acquisition time of the pixel centre after the epoch"}),
    })
    ds.attrs = {
        "frame_latitude_deg": frame.latitude,
        "frame_longitude_deg": frame.longitude,
        "frame_height_m": frame.height,
        "epoch": epoch.astimezone(_dt.UTC).isoformat() if epoch is not None else "",
        "surface": surface if isinstance(surface, int | float | str) else repr(surface),
    }
    return ds
