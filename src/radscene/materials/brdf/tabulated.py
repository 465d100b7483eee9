"""A measured or precomputed isotropic BRDF read from a table file.

File format
-----------
A text table, columns separated by commas, semicolons, tabs or spaces; ``#`` starts a comment
(whole line or trailing). The first non-comment line is the header naming the columns:

=====================  ========  ==========================================================
column                 unit      meaning
=====================  ========  ==========================================================
``wavelength``         [um]      optional; without it the table holds at every wavelength
``incidence_zenith``   [deg]     θ_i in [0, 90]
``view_zenith``        [deg]     θ_o in [0, 90]
``relative_azimuth``   [deg]     Δφ = φ_o − φ_i in [0, 180]; 0 = backscatter (hot spot)
``brdf`` or ``brf``    [sr-1]    f, or [-] for the reflectance factor BRF = π f
=====================  ========  ==========================================================

The rows must fill a regular grid: every combination of the distinct values of the coordinate
columns exactly once, in any order. Values must be finite and ≥ 0. A file that breaks a rule
is refused with its path and line.

Evaluation
----------
Multilinear interpolation in (θ_i, θ_o, Δφ, λ), in degrees. The model is isotropic (the
surface has no preferred azimuth), so Δφ and −Δφ are the same point. A measured table is not
exactly reciprocal (noise, instrument asymmetry); it is evaluated as its reciprocal part,

.. math:: f(\\omega_i, \\omega_o) = \\tfrac12\\,[T(\\theta_i, \\theta_o, \\Delta\\phi)
          + T(\\theta_o, \\theta_i, \\Delta\\phi)],

and :attr:`Tabulated.asymmetry` reports the largest relative difference between the two on the
table's own grid. Beyond the table, ``extend`` states the rule, as for spectra: ``"error"``
(default) refuses, at load time, a table whose angles do not span θ ∈ [0, 90]° and
Δφ ∈ [0, 180]°, and at run time a wavelength outside the table; ``"edge"`` holds the nearest
tabulated value.

=========  =====  =======  =================================================
parameter  unit   default  meaning
=========  =====  =======  =================================================
file       path   —        table file (relative to the scene file)
extend     [-]    error    ``error`` or ``edge`` beyond the tabulated range
source     [-]    ""       citation of the data
=========  =====  =======  =================================================

Config snippet: ``{type: tabulated, file: brdf/grass_brf.csv, extend: edge,
source: "measured, goniometer X, 2021"}``.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
from scipy.interpolate import RegularGridInterpolator

from radscene.errors import ConfigError, unreadable
from radscene.materials.brdf.base import BRDF, Parameter

__all__ = ["Tabulated", "read_table", "write_table"]

_SPLIT = re.compile(r"[,;\s]+")
_COORDS = ("wavelength", "incidence_zenith", "view_zenith", "relative_azimuth")
_RANGES = {"incidence_zenith": (0.0, 90.0), "view_zenith": (0.0, 90.0),
           "relative_azimuth": (0.0, 180.0)}


def _is_float(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def read_table(path) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Read a tabulated BRDF file (module docstring).

    Parameters
    ----------
    path : path-like
        The file.

    Returns
    -------
    axes : dict of numpy.ndarray
        Sorted distinct values of each coordinate present (``wavelength`` [um] only if the file
        has it; angles [deg]).
    brdf : numpy.ndarray
        f [sr-1] on the grid, axes in the order (wavelength,) incidence_zenith, view_zenith,
        relative_azimuth.

    Raises
    ------
    ConfigError
        Naming the file and line: unreadable file, missing or unknown columns, bad numbers,
        out-of-range angles, negative values, an incomplete or repeated grid point.
    """
    path = Path(path)
    label = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeError) as exc:
        raise ConfigError(f"cannot read BRDF table: {unreadable(exc)}", key=label) from None
    header = None
    rows: list[list[float]] = []
    lines: list[int] = []
    for number, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f for f in _SPLIT.split(line) if f]
        if header is None:
            header = [f.lower() for f in fields]
            _check_header(header, f"{label}:{number}")
            continue
        if len(fields) != len(header):
            raise ConfigError(
                f"expected {len(header)} columns ({', '.join(header)}); got {len(fields)}",
                key=f"{label}:{number}",
            )
        try:
            values = [float(f) for f in fields]
        except ValueError:
            bad = next(k for k, f in enumerate(fields, start=1) if not _is_float(f))
            raise ConfigError(f"column {bad} is not a number", key=f"{label}:{number}") from None
        rows.append(values)
        lines.append(number)
    if header is None or not rows:
        raise ConfigError("no header and data rows in BRDF table", key=label)
    data = np.array(rows)
    value_col = "brdf" if "brdf" in header else "brf"
    values = data[:, header.index(value_col)]
    bad = ~np.isfinite(values) | (values < 0.0)
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ConfigError(f"{value_col} must be finite and >= 0; got {values[i]:g}",
                          key=f"{label}:{lines[i]}")
    if value_col == "brf":
        values = values / np.pi
    names = [c for c in _COORDS if c in header]
    axes: dict[str, np.ndarray] = {}
    index = []
    for name in names:
        col = data[:, header.index(name)]
        if name == "wavelength":
            out = ~np.isfinite(col) | (col <= 0.0)
            rule = "be finite and > 0 [µm]"
        else:
            lo, hi = _RANGES[name]
            out = ~np.isfinite(col) | (col < lo) | (col > hi)
            rule = f"lie in [{lo:g}, {hi:g}] [deg]"
        if np.any(out):
            i = int(np.argmax(out))
            raise ConfigError(f"{name} must {rule}; got {col[i]:g}", key=f"{label}:{lines[i]}")
        axis, inverse = np.unique(col, return_inverse=True)
        axes[name] = axis
        index.append(inverse)
    shape = tuple(axes[n].size for n in names)
    grid = np.full(shape, np.nan)
    flat = np.ravel_multi_index(tuple(index), shape)
    seen = np.zeros(int(np.prod(shape)), dtype=bool)
    for row, cell in enumerate(flat):
        if seen[cell]:
            raise ConfigError("grid point given twice", key=f"{label}:{lines[row]}")
        seen[cell] = True
    grid.ravel()[flat] = values
    if not seen.all():
        missing = np.unravel_index(int(np.argmin(seen)), shape)
        point = ", ".join(f"{n}={axes[n][k]:g}" for n, k in zip(names, missing, strict=True))
        raise ConfigError(f"the rows do not fill a regular grid: no row for {point}",
                          key=label)
    return axes, grid


def _check_header(header: list[str], where: str) -> None:
    known = set(_COORDS) | {"brdf", "brf"}
    unknown = [k for k, h in enumerate(header, start=1) if h not in known]
    if unknown:  # named by its place: the header may be any file's first line
        raise ConfigError(
            f"column {unknown[0]} is none of {', '.join(_COORDS)}, brdf, brf",
            key=where,
        )
    missing = [c for c in _COORDS[1:] if c not in header]
    if missing:
        raise ConfigError(f"missing column {missing[0]!r}", key=where)
    if ("brdf" in header) == ("brf" in header):
        raise ConfigError("give exactly one of the columns brdf [sr-1] or brf [-]", key=where)
    if len(set(header)) != len(header):
        raise ConfigError("a column is named twice", key=where)


def write_table(path, incidence_zenith, view_zenith, relative_azimuth, brdf,
                wavelength=None, comment: str = "") -> Path:
    """Write a BRDF table file that :func:`read_table` reads.

    Parameters
    ----------
    path : path-like
        Output file.
    incidence_zenith, view_zenith, relative_azimuth : array_like
        1-D grids [deg].
    brdf : array_like
        f [sr-1], shape ``(n_wavelength,)? + (n_i, n_o, n_phi)``.
    wavelength : array_like, optional
        1-D grid [um].
    comment : str, optional
        Written as ``#`` lines at the top (e.g. the source).

    Returns
    -------
    pathlib.Path
    """
    axes = [np.asarray(a, dtype=float) for a in (incidence_zenith, view_zenith,
                                                 relative_azimuth)]
    names = list(_COORDS[1:])
    if wavelength is not None:
        axes.insert(0, np.asarray(wavelength, dtype=float))
        names.insert(0, "wavelength")
    values = np.asarray(brdf, dtype=float).reshape(tuple(a.size for a in axes))
    mesh = np.meshgrid(*axes, indexing="ij")
    columns = np.stack([m.ravel() for m in mesh] + [values.ravel()], axis=-1)
    lines = [f"# {c}" for c in comment.splitlines()] + [",".join(names + ["brdf"])]
    lines += [",".join(repr(float(v)) for v in row) for row in columns]  # exact round trip
    path = Path(path)
    path.write_text("\n".join(lines) + "\n")
    return path


class Tabulated(BRDF):
    """BRDF interpolated in a table file (module docstring).

    Attributes
    ----------
    asymmetry : float
        Largest |T(θ_i, θ_o, Δφ) − T(θ_o, θ_i, Δφ)| / max T on the common grid [-].
    """

    name = "tabulated"
    PARAMETERS = {
        "file": Parameter("path", "table file", kind="path"),
        "extend": Parameter("-", "rule beyond the table: error or edge", "error",
                            kind="choice", choices=("error", "edge")),
        "source": Parameter("-", "citation of the data", "", kind="text"),
    }

    def _check(self):
        path = self.parameter("file")
        axes, grid = read_table(path)
        self.axes = axes
        self.table = grid
        if self.parameter("extend") == "error":
            for name, (lo, hi) in _RANGES.items():
                a = axes[name]
                if a[0] > lo or a[-1] < hi:
                    raise ConfigError(
                        f"{path}: {name} spans [{a[0]:g}, {a[-1]:g}] deg, not [{lo:g}, "
                        f"{hi:g}]; set extend: edge to hold the edge values beyond the table",
                        key=f"{self.key}.extend",
                    )
        names = [n for n in _COORDS if n in axes]
        self._names = names
        axes_list = [axes[n] for n in names]
        # a single-valued axis cannot be interpolated: duplicate it
        padded, values = [], grid
        for dim, a in enumerate(axes_list):
            if a.size == 1:
                a = np.array([a[0], a[0] + 1.0])
                values = np.concatenate([values, values], axis=dim)
            padded.append(a)
        self._interp = RegularGridInterpolator(padded, values, method="linear",
                                               bounds_error=False, fill_value=None)
        self._lo = np.array([a[0] for a in axes_list])
        self._hi = np.array([a[-1] for a in axes_list])
        self.asymmetry = self._measure_asymmetry()

    def _measure_asymmetry(self) -> float:
        a = self.axes
        common = np.intersect1d(a["incidence_zenith"], a["view_zenith"])
        if common.size == 0 or not np.any(self.table > 0):
            return 0.0
        if "wavelength" in a:
            wl, ti, to, ph = np.meshgrid(a["wavelength"], common, common,
                                         a["relative_azimuth"], indexing="ij")
            d = self._lookup((wl, ti, to, ph)) - self._lookup((wl, to, ti, ph))
        else:
            ti, to, ph = np.meshgrid(common, common, a["relative_azimuth"], indexing="ij")
            d = self._lookup((ti, to, ph)) - self._lookup((to, ti, ph))
        return float(np.abs(d).max() / self.table.max())

    def _lookup(self, coords) -> np.ndarray:
        pts = np.stack(np.broadcast_arrays(*coords), axis=-1)
        pts = np.clip(pts, self._lo, self._hi)
        return self._interp(pts.reshape(-1, pts.shape[-1])).reshape(pts.shape[:-1])

    def _kernel(self, mu_i, mu_o, cos_g, wavelength):
        ti = np.degrees(np.arccos(np.clip(mu_i, -1.0, 1.0)))
        to = np.degrees(np.arccos(np.clip(mu_o, -1.0, 1.0)))
        sin_prod = np.sqrt(np.maximum((1.0 - mu_i * mu_i) * (1.0 - mu_o * mu_o), 0.0))
        with np.errstate(divide="ignore", invalid="ignore"):
            cos_dphi = np.where(sin_prod > 1e-12, (cos_g - mu_i * mu_o) / sin_prod, 1.0)
        dphi = np.degrees(np.arccos(np.clip(cos_dphi, -1.0, 1.0)))
        if "wavelength" in self.axes:
            if wavelength is None:
                raise ConfigError("this BRDF table varies with wavelength; pass wavelength [µm]",
                                  key=f"{self.key}.file")
            wl = np.asarray(wavelength, dtype=float)
            lo, hi = self.axes["wavelength"][[0, -1]]
            if self.parameter("extend") == "error" and np.any((wl < lo) | (wl > hi)):
                bad = wl[(wl < lo) | (wl > hi)].flat[0]
                raise ConfigError(
                    f"wavelength {bad:g} µm is outside the range [{lo:g}, {hi:g}] µm of "
                    f"{self.parameter('file')} (extend: error; extend: edge holds the end "
                    "values)", key=f"{self.key}.file")
            forward = self._lookup((wl, ti, to, dphi))
            backward = self._lookup((wl, to, ti, dphi))
        else:
            forward = self._lookup((ti, to, dphi))
            backward = self._lookup((to, ti, dphi))
        return 0.5 * (forward + backward)
