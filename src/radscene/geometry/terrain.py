"""Terrain as a regular grid of elevations: sampling, normals, meshing, GeoTIFF, procedural.

Layout of a :class:`Heightfield` (geo-style, as in a north-up raster): row 0 is the *north* edge
and column 0 the *west* edge; sample ``(i, j)`` lies at

.. math:: x = x_0 + j\\,\\Delta x, \\qquad y = y_0 + (n_y - 1 - i)\\,\\Delta y,

so ``origin = (x0, y0)`` is the south-west sample. Coordinates are those of the local
east-north-up frame (or of a projected CRS, for GeoTIFFs) [m].
"""

from __future__ import annotations

import os

import numpy as np

from radscene.errors import ConfigError, unreadable
from radscene.geometry.mesh import Mesh

__all__ = ["Heightfield", "polyline_distance", "procedural_terrain"]

# Points this far outside the grid, as a fraction of a cell, count as on its edge (float noise
# in hit positions); farther ones are an error.
_EDGE_TOLERANCE = 1e-6


def _pair(value, key: str, positive: bool) -> tuple[float, float]:
    a = np.asarray(value, dtype=float)
    if a.shape == ():
        a = np.array([a, a])
    if a.shape != (2,) or not np.isfinite(a).all() or (positive and (a <= 0).any()):
        what = "two positive numbers (dx, dy) [m]" if positive else "two finite numbers [m]"
        raise ConfigError(f"must be {what}, got {value!r}", key=key)
    return float(a[0]), float(a[1])


def _regular_axis(coords, key: str) -> tuple[float, float, bool]:
    """Start, step (> 0) and whether reversed, of a regular 1-d coordinate vector."""
    c = np.asarray(coords, dtype=float)
    if c.ndim != 1 or len(c) < 2 or not np.isfinite(c).all():
        raise ConfigError(f"must be at least 2 finite coordinates, got shape {c.shape}", key=key)
    step = np.diff(c)
    mean = (c[-1] - c[0]) / (len(c) - 1)
    if mean == 0 or np.abs(step - mean).max() > 1e-6 * abs(mean):
        raise ConfigError("coordinates must be regularly spaced and strictly monotonic", key=key)
    return (float(c[0]), mean, False) if mean > 0 else (float(c[-1]), -mean, True)


def _check_metres(crs, path) -> None:
    """Refuse a raster whose x, y are not metres: geographic degrees, or a projected CRS in
    another unit (feet)."""
    if crs is None:
        return
    if crs.is_geographic:
        raise ConfigError(f"{path!r} is in geographic coordinates ({crs.to_string()}, degrees); "
                          "reproject it to a projected CRS in metres first, e.g. gdalwarp "
                          "-t_srs EPSG:<UTM zone> in.tif out.tif", key="path")
    try:
        unit, factor = crs.linear_units_factor
    except Exception:  # noqa: BLE001 - a CRS without linear units: an engineering frame
        return
    if abs(float(factor) - 1.0) > 1e-9:
        raise ConfigError(f"{path!r} has x, y in {unit} ({crs.to_string()}); reproject it to a "
                          "CRS in metres first", key="path")


class Heightfield:
    """Elevation on a regular grid, north-up (see the module docstring for the layout).

    Parameters
    ----------
    elevation : array_like
        Heights, shape ``(ny, nx)`` with ``ny, nx >= 2``, row 0 north, column 0 west [m].
        Every value must be finite.
    origin : array_like
        ``(x0, y0)``, position of the south-west sample (row ``ny - 1``, column 0) [m].
    spacing : float or array_like
        ``(dx, dy)`` sample spacing east and north, > 0 [m].
    crs : str, optional
        Coordinate reference system of x, y (e.g. ``"EPSG:32633"``), None for a local frame.

    Examples
    --------
    >>> hf = Heightfield([[1.0, 1.0], [0.0, 0.0]], origin=(0, 0), spacing=10.0)
    >>> hf.extent, float(hf.height_at(5.0, 5.0))
    ((0.0, 10.0, 0.0, 10.0), 0.5)
    """

    def __init__(self, elevation, origin=(0.0, 0.0), spacing=(1.0, 1.0), crs: str | None = None):
        z = np.array(elevation, dtype=np.float64)
        if z.ndim != 2 or z.shape[0] < 2 or z.shape[1] < 2:
            raise ConfigError(f"must be a 2-d array of at least 2 x 2 samples, got shape "
                              f"{z.shape}", key="elevation")
        bad = ~np.isfinite(z)
        if bad.any():
            n_nan = int(np.isnan(z).sum())
            n_inf = int(bad.sum()) - n_nan
            row, col = np.unravel_index(int(np.argmax(bad)), z.shape)
            raise ConfigError(f"{n_nan} NaN and {n_inf} infinite samples of {z.size} (e.g. nodata "
                              f"or holes); first at (row, col) = ({row}, {col}); fill them first",
                              key="elevation")
        self.elevation = z
        self.origin = _pair(origin, "origin", positive=False)
        self.spacing = _pair(spacing, "spacing", positive=True)
        self.crs = crs

    def __repr__(self) -> str:
        return (f"Heightfield(shape={self.shape}, origin={self.origin}, spacing={self.spacing}, "
                f"crs={self.crs!r})")

    # -- construction ---------------------------------------------------------------------

    @classmethod
    def from_array(cls, elevation, x, y, crs: str | None = None) -> Heightfield:
        """A heightfield from an array and its sample-centre coordinate vectors.

        Parameters
        ----------
        elevation : array_like
            Heights, shape ``(len(y), len(x))``, ``elevation[i, j]`` at ``(x[j], y[i])`` [m].
        x, y : array_like
            Regularly spaced, strictly monotonic coordinates of the sample centres, in either
            order; the grid is flipped as needed to north-up, west-left [m].
        crs : str, optional
            Coordinate reference system of x, y.

        Returns
        -------
        Heightfield
        """
        z = np.asarray(elevation, dtype=float)
        x0, dx, flip_x = _regular_axis(x, "x")
        y0, dy, y_descending = _regular_axis(y, "y")
        if z.shape != (len(np.asarray(y)), len(np.asarray(x))):
            raise ConfigError(f"shape {z.shape} does not match (len(y), len(x)) = "
                              f"({len(np.asarray(y))}, {len(np.asarray(x))})", key="elevation")
        # North-up, west-left: x ascending along columns, y descending down the rows.
        if flip_x:
            z = z[:, ::-1]
        if not y_descending:
            z = z[::-1, :]
        return cls(z, origin=(x0, y0), spacing=(dx, dy), crs=crs)

    @classmethod
    def from_geotiff(cls, path, band: int = 1) -> Heightfield:
        """Read a digital elevation model from a GeoTIFF (rioxarray).

        Nodata becomes NaN, which is refused (:class:`ConfigError` with the count and the first
        position): fill holes before. A raster in geographic coordinates (degrees) or in a
        projected CRS whose unit is not the metre is refused: reproject it first (e.g.
        ``gdalwarp -t_srs EPSG:32633 in.tif out.tif``); its pixel spacing would be read as
        metres. Coordinates are the raster's projected x, y of the pixel
        centres, and the CRS is kept in ``.crs``. Rotated or sheared rasters are refused.

        Parameters
        ----------
        path : str or os.PathLike
            The GeoTIFF file.
        band : int
            1-based band number.

        Returns
        -------
        Heightfield
        """
        import rioxarray

        path = os.fspath(path)
        if not os.path.isfile(path):
            raise ConfigError(f"GeoTIFF not found: {path!r}", key="path")
        try:
            da = rioxarray.open_rasterio(path, masked=True)
        except Exception as exc:  # rasterio raises its own types
            raise ConfigError(f"cannot read GeoTIFF {path!r}: {unreadable(exc)}", key="path") from None
        with da:
            if "band" in da.dims:
                bands = [int(b) for b in da["band"].values]
                if band not in bands:
                    raise ConfigError(f"{path!r} has bands {bands}, not {band}", key="band")
                da = da.sel(band=band)
            transform = da.rio.transform()
            if transform.b != 0 or transform.d != 0:
                raise ConfigError(f"{path!r} is rotated or sheared (geotransform {transform}); "
                                  "only north-up rasters are accepted", key="path")
            crs = da.rio.crs.to_string() if da.rio.crs is not None else None
            _check_metres(da.rio.crs, path)
            values = np.asarray(da.values, dtype=float)
            try:
                return cls.from_array(values, da["x"].values, da["y"].values, crs=crs)
            except ConfigError as exc:
                raise ConfigError(f"{path!r}: {exc.message}", key=exc.key) from None

    # -- geometry -------------------------------------------------------------------------

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nx)``, number of rows and columns."""
        return self.elevation.shape

    @property
    def x(self) -> np.ndarray:
        """Easting of the columns, increasing, shape ``(nx,)`` [m]."""
        return self.origin[0] + self.spacing[0] * np.arange(self.shape[1])

    @property
    def y(self) -> np.ndarray:
        """Northing of the rows, *decreasing* (row 0 is north), shape ``(ny,)`` [m]."""
        return self.origin[1] + self.spacing[1] * np.arange(self.shape[0] - 1, -1, -1)

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """``(xmin, xmax, ymin, ymax)`` of the sample positions [m]."""
        (x0, y0), (dx, dy), (ny, nx) = self.origin, self.spacing, self.shape
        return (x0, x0 + (nx - 1) * dx, y0, y0 + (ny - 1) * dy)

    def _fractional(self, x, y, margin: float):
        """Fractional column and south-based row indices, checked to lie within the grid."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        fx = (x - self.origin[0]) / self.spacing[0]
        fy = (y - self.origin[1]) / self.spacing[1]
        ny, nx = self.shape
        outside = ~((fx >= -margin) & (fx <= nx - 1 + margin)
                    & (fy >= -margin) & (fy <= ny - 1 + margin))
        if outside.any():
            k = int(np.argmax(outside.ravel()))
            raise ConfigError(f"{int(outside.sum())} points lie outside the terrain extent "
                              f"{self.extent}, the first is (x, y) = ({x.ravel()[k]}, "
                              f"{y.ravel()[k]}) [m]", key="x, y")
        return fx, fy

    def _cell(self, x, y):
        ny, nx = self.shape
        fx, fy = self._fractional(x, y, _EDGE_TOLERANCE)
        j = np.clip(np.floor(fx), 0, nx - 2).astype(np.int64)
        k = np.clip(np.floor(fy), 0, ny - 2).astype(np.int64)  # south-based cell row
        tx = np.clip(fx - j, 0.0, 1.0)
        ty = np.clip(fy - k, 0.0, 1.0)
        i_south = ny - 1 - k  # array row of the cell's south edge
        z = self.elevation
        z00 = z[i_south, j]  # south-west corner
        z10 = z[i_south, j + 1]  # south-east
        z01 = z[i_south - 1, j]  # north-west
        z11 = z[i_south - 1, j + 1]  # north-east
        return tx, ty, z00, z10, z01, z11

    def height_at(self, x, y) -> np.ndarray:
        """Bilinear interpolation of the elevation.

        Parameters
        ----------
        x, y : array_like
            Easting and northing, broadcast together, within :attr:`extent` [m].

        Returns
        -------
        numpy.ndarray
            Elevation, shape of the broadcast [m].

        Raises
        ------
        ConfigError
            A point lies outside the extent.
        """
        tx, ty, z00, z10, z01, z11 = self._cell(x, y)
        return ((1 - tx) * (1 - ty) * z00 + tx * (1 - ty) * z10
                + (1 - tx) * ty * z01 + tx * ty * z11)

    def normal_at(self, x, y) -> np.ndarray:
        """Unit upward normal of the bilinear surface of :meth:`height_at`.

        .. math:: \\mathbf{n} \\propto (-\\partial z/\\partial x,\\ -\\partial z/\\partial y,\\ 1)

        Parameters
        ----------
        x, y : array_like
            Easting and northing, broadcast together, within :attr:`extent` [m].

        Returns
        -------
        numpy.ndarray
            Normals, shape ``broadcast.shape + (3,)`` [-], z component > 0.
        """
        tx, ty, z00, z10, z01, z11 = self._cell(x, y)
        dzdx = ((1 - ty) * (z10 - z00) + ty * (z11 - z01)) / self.spacing[0]
        dzdy = ((1 - tx) * (z01 - z00) + tx * (z11 - z10)) / self.spacing[1]
        n = np.stack([-dzdx, -dzdy, np.ones_like(dzdx)], axis=-1)
        return n / np.linalg.norm(n, axis=-1, keepdims=True)

    def cell_index(self, x, y) -> tuple[np.ndarray, np.ndarray]:
        """Row and column of the sample nearest to each point (e.g. to look up material maps).

        Parameters
        ----------
        x, y : array_like
            Easting and northing, broadcast together [m]; within the extent grown by half a
            spacing on every side (the area the samples stand for).

        Returns
        -------
        row, col : numpy.ndarray
            int64 indices into :attr:`elevation`, shape of the broadcast.
        """
        fx, fy = self._fractional(x, y, 0.5 + _EDGE_TOLERANCE)
        ny, nx = self.shape
        col = np.clip(np.rint(fx), 0, nx - 1).astype(np.int64)
        row = ny - 1 - np.clip(np.rint(fy), 0, ny - 1).astype(np.int64)
        return row, col

    def to_mesh(self, name: str = "terrain") -> Mesh:
        """Triangulate: one vertex per sample, two upward-facing triangles per cell.

        Vertex ``i * nx + j`` is sample ``(i, j)``. Cell ``c = i * (nx - 1) + j`` (between rows
        ``i, i + 1`` and columns ``j, j + 1``) is split along its south-west to north-east
        diagonal into faces ``2c`` (south-east half) and ``2c + 1`` (north-west half), so
        ``face // 2`` is the cell index. Both are wound counter-clockwise seen from above
        (normals have z > 0).

        Returns
        -------
        Mesh
            ``ny * nx`` vertices, ``2 (ny - 1)(nx - 1)`` faces.
        """
        ny, nx = self.shape
        xx, yy = np.meshgrid(self.x, self.y)
        vertices = np.column_stack([xx.ravel(), yy.ravel(), self.elevation.ravel()])
        nw = (np.arange(ny - 1)[:, None] * nx + np.arange(nx - 1)[None, :]).ravel()
        ne, sw = nw + 1, nw + nx
        se = sw + 1
        faces = np.empty((len(nw), 2, 3), dtype=np.int64)
        faces[:, 0, 0], faces[:, 0, 1], faces[:, 0, 2] = sw, se, ne
        faces[:, 1, 0], faces[:, 1, 1], faces[:, 1, 2] = sw, ne, nw
        return Mesh(vertices, faces.reshape(-1, 3), name)


def polyline_distance(points, vertices) -> np.ndarray:
    r"""Distance in the plane from each point to a polyline (roads draped on a terrain).

    Parameters
    ----------
    points : array_like
        ``(N, 2)`` x, y [m].
    vertices : array_like
        ``(M, 2)`` the polyline's vertices in order, M >= 1 [m].

    Returns
    -------
    numpy.ndarray
        ``(N,)`` the distance to the nearest point of any segment [m].

    Notes
    -----
    For a segment from :math:`a` to :math:`b` the nearest point to :math:`p` is
    :math:`a + t (b - a)` with :math:`t = \mathrm{clip}((p - a)\cdot(b - a) / |b - a|^2, 0, 1)`.

    Examples
    --------
    >>> polyline_distance([[0.0, 3.0], [15.0, 0.0]], [[0.0, 0.0], [10.0, 0.0]]).tolist()
    [3.0, 5.0]
    """
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    v = np.asarray(vertices, dtype=float).reshape(-1, 2)
    if len(v) == 0:
        raise ValueError("a polyline needs at least one vertex")
    if len(v) == 1:
        return np.hypot(*(p - v[0]).T)
    best = np.full(len(p), np.inf)
    for a, b in zip(v[:-1], v[1:], strict=True):
        ab = b - a
        length2 = float(ab @ ab)
        t = np.zeros(len(p)) if length2 == 0.0 else np.clip((p - a) @ ab / length2, 0.0, 1.0)
        d = p - (a + t[:, None] * ab)
        np.minimum(best, np.hypot(d[:, 0], d[:, 1]), out=best)
    return best


def _smoothstep(t):
    t = np.clip(t, 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def procedural_terrain(size=(1000.0, 1000.0), spacing: float = 5.0, relief: float = 40.0,
                       seed: int = 0, lakes=(), *, feature_size: float | None = None,
                       spectral_slope: float = 4.5) -> tuple[Heightfield, np.ndarray]:
    """Smooth fractal hills with flat lakes, centred on the origin; deterministic for a seed.

    The hills are Gaussian white noise filtered in the Fourier domain to a power spectrum
    :math:`P(k) \\propto (k^2 + k_0^2)^{-\\beta/2}` (fractional-Brownian-like for
    :math:`k > k_0`, :math:`\\beta` = ``spectral_slope``, :math:`k_0 = 1/`
    ``feature_size``), i.e. all octaves summed at once, then scaled to span
    ``[0, relief]``. Each lake ``(x, y, radius, depth)`` gets a flat water surface at
    ``depth`` below the lowest ground within the disc and its shore band (of width
    ``max(radius / 2, 2 spacing)`` outside the disc); the ground in the band is blended
    smoothly down to that level, so the shore rises all round from the water's edge and no
    ground near the lake lies below the water.

    Parameters
    ----------
    size : array_like
        ``(sx, sy)`` extent east and north [m]; the grid has ``round(s / spacing) + 1`` samples
        along each axis and spans ``[-(n-1) spacing / 2, +(n-1) spacing / 2]``.
    spacing : float
        Sample spacing, both axes [m], > 0.
    relief : float
        Peak-to-trough height of the hills before lakes are carved [m], >= 0.
    seed : int
        Seed of ``numpy.random.default_rng``.
    lakes : sequence of (x, y, radius, depth)
        Lake centre [m] (within the grid), radius [m] (> 0, must cover at least one sample)
        and depth of the water surface below the lowest ground within the disc and its shore
        band [m] (>= 0).
        Discs must not overlap.
    feature_size : float, optional
        Wavelength above which the spectrum flattens: the size of the largest hills [m];
        default half the smaller side.
    spectral_slope : float
        Exponent :math:`\\beta` of the power spectrum [-]; larger is smoother. With the
        defaults, 1 km at 5 m spacing and 40 m relief has slopes of about 7 deg on average and
        25 deg at most.

    Returns
    -------
    heightfield : Heightfield
        Ground and water-surface elevation [m].
    water_mask : numpy.ndarray
        bool, shape ``heightfield.shape``: samples within a lake disc; their elevations are
        exactly equal lake by lake.

    Examples
    --------
    >>> hf, water = procedural_terrain((200, 200), 5.0, lakes=[(0.0, 0.0, 30.0, 2.0)])
    >>> float(np.ptp(hf.elevation[water]))
    0.0
    """
    sx, sy = _pair(size, "size", positive=True)
    try:
        dx = float(spacing)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a positive number [m], got {spacing!r}", key="spacing") from None
    if not np.isfinite(dx) or dx <= 0:
        raise ConfigError(f"must be a positive number [m], got {spacing!r}", key="spacing")
    if not np.isfinite(relief) or relief < 0:
        raise ConfigError(f"must be a finite number >= 0 [m], got {relief!r}", key="relief")
    nx, ny = int(round(sx / dx)) + 1, int(round(sy / dx)) + 1
    if nx < 2 or ny < 2:
        raise ConfigError(f"size {size!r} must be at least one spacing ({dx} m)", key="size")
    if feature_size is None:
        feature_size = 0.5 * min(sx, sy)
    if not np.isfinite(feature_size) or feature_size <= 0:
        raise ConfigError(f"must be a positive length [m], got {feature_size!r}",
                          key="feature_size")

    rng = np.random.default_rng(seed)
    noise = rng.standard_normal((ny, nx))
    k2 = np.fft.fftfreq(ny, d=dx)[:, None] ** 2 + np.fft.rfftfreq(nx, d=dx)[None, :] ** 2
    amplitude = (k2 + feature_size**-2) ** (-spectral_slope / 4.0)
    z = np.fft.irfft2(np.fft.rfft2(noise) * amplitude, s=(ny, nx))
    span = np.ptp(z)
    z = (z - z.min()) * (relief / span) if span > 0 and relief > 0 else np.zeros_like(z)

    x0, y0 = -0.5 * (nx - 1) * dx, -0.5 * (ny - 1) * dx
    xx, yy = np.meshgrid(x0 + dx * np.arange(nx), y0 + dx * np.arange(ny - 1, -1, -1))
    lakes = [tuple(lake) for lake in lakes]
    discs, levels = [], []
    ground = z.copy()
    for k, lake in enumerate(lakes):
        key = f"lakes[{k}]"
        if len(lake) != 4 or not np.isfinite(np.asarray(lake, dtype=float)).all():
            raise ConfigError(f"must be 4 finite numbers (x, y, radius, depth), got {lake!r}",
                              key=key)
        lx, ly, radius, depth = (float(v) for v in lake)
        if radius <= 0 or depth < 0:
            raise ConfigError(f"radius must be > 0 and depth >= 0 [m], got {lake!r}", key=key)
        if not (x0 <= lx <= -x0 and y0 <= ly <= -y0):
            raise ConfigError(f"centre ({lx}, {ly}) lies outside the terrain "
                              f"[{x0}, {-x0}] x [{y0}, {-y0}] [m]", key=key)
        for m, other in enumerate(lakes[:k]):
            if np.hypot(lx - other[0], ly - other[1]) < radius + other[2]:
                raise ConfigError(f"overlaps lakes[{m}]; lakes must be disjoint discs", key=key)
        distance = np.hypot(xx - lx, yy - ly)
        disc = distance <= radius
        if not disc.any():
            raise ConfigError(f"radius {radius} m covers no sample of the {dx} m grid", key=key)
        band = max(0.5 * radius, 2.0 * dx)
        level = ground[distance <= radius + band].min() - depth
        near = distance < radius + band  # beyond, the ground stays exactly as it was
        shore = level + (ground[near] - level) * _smoothstep((distance[near] - radius) / band)
        z[near] = np.minimum(z[near], shore)
        discs.append(disc)
        levels.append(level)
    water = np.zeros((ny, nx), dtype=bool)
    for disc, level in zip(discs, levels, strict=True):
        z[disc] = level
        water |= disc
    return Heightfield(z, origin=(x0, y0), spacing=(dx, dx)), water
