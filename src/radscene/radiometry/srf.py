"""Spectral response functions (SRF) of sensor bands and their quadrature.

A spectral response S(λ) is dimensionless (the analytic ones peak at 1). Every response
carries a quadrature rule (nodes [um], weights [um]) with weights that already include
S(λ), so that

.. math:: \\sum_i w_i f(\\lambda_i) \\approx \\int S(\\lambda) f(\\lambda)\\, d\\lambda

to better than 1e-9 relative for smooth f such as the Planck function. Rules are composite
Gauss-Legendre: panels no wider than 2 % in log wavelength (so that a Planck function at
any temperature is resolved), no wider than σ for a Gaussian, and never straddling a
breakpoint of a tabulated response (so that a piecewise-linear S times a smooth f is
integrated exactly up to the smoothness of f).

Registry (``RESPONSES``, used by :func:`make_response`, type names case-insensitive):

=============  ==========================================  =================================
type           parameters [unit]                           meaning
=============  ==========================================  =================================
rectangular    wavelength_min [um], wavelength_max [um]    S = 1 inside, 0 outside
gaussian       center [um], fwhm [um]                      peak 1, truncated at ±7σ
tabulated      wavelength [um], response [1]; or file [-]  piecewise linear between samples
=============  ==========================================  =================================

All take an optional ``name``. Config snippet::

    band: {type: gaussian, center: 10.0, fwhm: 1.0}
    band: {type: tabulated, file: srf/modis_b31.csv, wavelength_unit: nm}
"""

from __future__ import annotations

import abc
import inspect
import math
import re
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = [
    "SpectralResponse",
    "RectangularResponse",
    "GaussianResponse",
    "TabulatedResponse",
    "RESPONSES",
    "make_response",
]

_GL_ORDER = 8
_GL_X, _GL_W = np.polynomial.legendre.leggauss(_GL_ORDER)
_MAX_LOG_WIDTH = 0.02  # widest panel, in ln(λ)
#: Half-width of the truncated Gaussian response, in standard deviations. The lost area,
#: erfc(7 / √2) = 2.6e-12 of the total, is below the quadrature's accuracy.
GAUSSIAN_TRUNCATION = 7.0
_FWHM_TO_SIGMA = 1.0 / (2.0 * math.sqrt(2.0 * math.log(2.0)))


def _composite_gauss_legendre(breaks, max_width=np.inf):
    """Nodes and weights of composite Gauss-Legendre on the segments between `breaks`.

    Each segment [a, b] is cut into equal panels no wider than `max_width` [um] and no
    wider than `_MAX_LOG_WIDTH` in ln(λ).
    """
    a = breaks[:-1]
    b = breaks[1:]
    count = np.maximum(np.ceil(np.log(b / a) / _MAX_LOG_WIDTH), np.ceil((b - a) / max_width))
    count = np.maximum(count, 1).astype(int)
    seg = np.repeat(np.arange(a.size), count)
    j = np.arange(seg.size) - np.repeat(np.cumsum(count) - count, count)
    width = (b - a)[seg] / count[seg]
    left = a[seg] + j * width
    half = 0.5 * width
    nodes = (left + half)[:, None] + half[:, None] * _GL_X
    weights = half[:, None] * _GL_W
    return nodes.ravel(), weights.ravel()


def _real(value, key):
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a real number; got {value!r}", key=key) from None
    if not math.isfinite(v):
        raise ConfigError(f"must be finite; got {value!r}", key=key)
    return v


def _readonly(array):
    array = np.ascontiguousarray(array, dtype=float)
    array.flags.writeable = False
    return array


class SpectralResponse(abc.ABC):
    """A spectral response function S(λ) of a sensor band, with its quadrature rule.

    Subclasses set ``name`` and implement :attr:`support`, :meth:`__call__` and
    :meth:`_rule` (nodes and weights, S included).
    """

    name: str

    @property
    @abc.abstractmethod
    def support(self) -> tuple[float, float]:
        """(wavelength_min, wavelength_max) [um] outside which S = 0."""

    @property
    def center(self) -> float:
        """Centroid of the response, ∫λS dλ / ∫S dλ [um]."""
        nodes, weights = self.quadrature()
        return float(nodes @ weights / weights.sum())

    @abc.abstractmethod
    def __call__(self, wavelength):
        """Response S at `wavelength` [um] (dimensionless; 0 outside the support)."""

    @abc.abstractmethod
    def _rule(self) -> tuple[np.ndarray, np.ndarray]:
        """Compute (nodes [um], weights [um]) with S folded into the weights."""

    def quadrature(self) -> tuple[np.ndarray, np.ndarray]:
        """Quadrature rule of the response.

        Returns
        -------
        nodes : numpy.ndarray
            Wavelengths [um], increasing, inside :attr:`support` (read-only).
        weights : numpy.ndarray
            Weights [um] including S(nodes) (read-only), such that
            ``weights @ f(nodes)`` ≈ ∫ S(λ) f(λ) dλ.
        """
        rule = self.__dict__.get("_quadrature")
        if rule is None:
            nodes, weights = self._rule()
            rule = (_readonly(nodes), _readonly(weights))
            self.__dict__["_quadrature"] = rule
        return rule

    def integrate_function(self, function: Callable[[np.ndarray], np.ndarray]):
        """Integrate a spectral function weighted by the response, ∫ S(λ) f(λ) dλ.

        Parameters
        ----------
        function : callable
            Maps a 1-D wavelength array [um] of length n to values of shape (..., n),
            wavelength on the last axis (e.g. ``lambda wl: spectral_radiance(wl, T[:, None])``).

        Returns
        -------
        numpy.ndarray or float
            The integral, shape (...) [unit of f × um].

        Examples
        --------
        >>> band = RectangularResponse(8.0, 12.0)
        >>> round(float(band.integrate_function(lambda wl: wl)), 9)
        40.0
        """
        nodes, weights = self.quadrature()
        values = np.asarray(function(nodes), dtype=float)
        if values.ndim == 0 or values.shape[-1] != nodes.size:
            raise ConfigError(
                f"the function must return values with wavelength on the last axis "
                f"(length {nodes.size}); got shape {values.shape}",
                key="function",
            )
        return values @ weights

    def integrate(self, wavelength, values):
        """Integrate a tabulated spectrum weighted by the response, ∫ S(λ) v(λ) dλ.

        The spectrum is interpolated linearly onto the quadrature nodes.

        Parameters
        ----------
        wavelength : array_like
            Strictly increasing wavelengths [um], shape (n,), covering :attr:`support`.
        values : array_like
            Spectrum, shape (..., n), wavelength on the last axis.

        Returns
        -------
        numpy.ndarray or float
            The integral, shape (...) [unit of values × um].

        Raises
        ------
        ConfigError
            If the table does not cover the support or is not strictly increasing.
        """
        wl = np.asarray(wavelength, dtype=float)
        vals = np.asarray(values, dtype=float)
        if wl.ndim != 1 or wl.size < 2 or not np.all(np.diff(wl) > 0):
            raise ConfigError(
                "must be a 1-D, strictly increasing array of at least 2 wavelengths [µm]",
                key="wavelength",
            )
        if vals.ndim == 0 or vals.shape[-1] != wl.size:
            raise ConfigError(
                f"last axis must match wavelength (length {wl.size}); got shape {vals.shape}",
                key="values",
            )
        lo, hi = self.support
        if wl[0] > lo or wl[-1] < hi:
            raise ConfigError(
                f"table {wl[0]:g}-{wl[-1]:g} µm does not cover the support {lo:g}-{hi:g} µm "
                f"of response {self.name!r}",
                key="wavelength",
            )
        nodes, weights = self.quadrature()
        i = np.clip(np.searchsorted(wl, nodes, side="right") - 1, 0, wl.size - 2)
        frac = (nodes - wl[i]) / (wl[i + 1] - wl[i])
        interp = vals[..., i] * (1.0 - frac) + vals[..., i + 1] * frac
        return interp @ weights

    def equivalent_width(self) -> float:
        """Equivalent width ∫ S(λ) dλ [um]."""
        return float(self.quadrature()[1].sum())

    def __repr__(self) -> str:
        lo, hi = self.support
        return f"{type(self).__name__}(name={self.name!r}, support=({lo:g}, {hi:g}) µm)"


class RectangularResponse(SpectralResponse):
    """Rectangular (top-hat) response: S = 1 on [wavelength_min, wavelength_max], else 0.

    Parameters
    ----------
    wavelength_min, wavelength_max : float
        Band edges [um], 0 < `wavelength_min` < `wavelength_max`.
    name : str, optional
        Band name; default ``"rectangular 8-12 um"`` style.

    Examples
    --------
    >>> RectangularResponse(8.0, 12.0).equivalent_width()
    4.0
    """

    def __init__(self, wavelength_min, wavelength_max, name: str | None = None):
        lo = _real(wavelength_min, "wavelength_min")
        hi = _real(wavelength_max, "wavelength_max")
        if lo <= 0:
            raise ConfigError(f"must be > 0 µm; got {lo!r}", key="wavelength_min")
        if hi <= lo:
            raise ConfigError(
                f"must be > wavelength_min = {lo!r} µm; got {hi!r}", key="wavelength_max"
            )
        self.wavelength_min = lo
        self.wavelength_max = hi
        self.name = name if name is not None else f"rectangular {lo:g}-{hi:g} um"

    @property
    def support(self):
        return (self.wavelength_min, self.wavelength_max)

    @property
    def center(self):
        return 0.5 * (self.wavelength_min + self.wavelength_max)

    def __call__(self, wavelength):
        wl = np.asarray(wavelength, dtype=float)
        inside = (wl >= self.wavelength_min) & (wl <= self.wavelength_max)
        return np.where(np.isnan(wl), np.nan, inside.astype(float))

    def _rule(self):
        return _composite_gauss_legendre(np.array([self.wavelength_min, self.wavelength_max]))


class GaussianResponse(SpectralResponse):
    """Gaussian response of peak 1, truncated at ±7σ (S = 0 beyond).

    Parameters
    ----------
    center : float
        Centre wavelength [um].
    fwhm : float
        Full width at half maximum [um], > 0; σ = fwhm / (2 √(2 ln 2)).
    name : str, optional
        Band name.

    Notes
    -----
    .. math:: S(\\lambda) = \\exp\\left(-\\frac{(\\lambda - \\lambda_c)^2}{2\\sigma^2}\\right),
              \\quad |\\lambda - \\lambda_c| \\le 7\\sigma

    The truncation drops erfc(7/√2) = 2.6e-12 of the area, so the equivalent width is
    fwhm √(π / (4 ln 2)) to 1e-11. The support must stay at positive wavelength.

    Examples
    --------
    >>> round(GaussianResponse(10.0, 1.0).equivalent_width(), 9)
    1.064467019
    """

    def __init__(self, center, fwhm, name: str | None = None):
        c = _real(center, "center")
        w = _real(fwhm, "fwhm")
        if w <= 0:
            raise ConfigError(f"must be > 0 µm; got {w!r}", key="fwhm")
        sigma = w * _FWHM_TO_SIGMA
        if c - GAUSSIAN_TRUNCATION * sigma <= 0:
            raise ConfigError(
                f"center - {GAUSSIAN_TRUNCATION:g} sigma must be > 0 µm "
                f"(center {c!r} µm, fwhm {w!r} µm)",
                key="center",
            )
        self.center_wavelength = c
        self.fwhm = w
        self.sigma = sigma
        self.name = name if name is not None else f"gaussian {c:g} um, fwhm {w:g} um"

    @property
    def support(self):
        half = GAUSSIAN_TRUNCATION * self.sigma
        return (self.center_wavelength - half, self.center_wavelength + half)

    @property
    def center(self):
        return self.center_wavelength

    def __call__(self, wavelength):
        wl = np.asarray(wavelength, dtype=float)
        z = (wl - self.center_wavelength) / self.sigma
        inside = np.abs(z) <= GAUSSIAN_TRUNCATION
        return np.where(np.isnan(z), np.nan, np.where(inside, np.exp(-0.5 * z * z), 0.0))

    def _rule(self):
        lo, hi = self.support
        nodes, weights = _composite_gauss_legendre(np.array([lo, hi]), self.sigma)
        return nodes, weights * self(nodes)


class TabulatedResponse(SpectralResponse):
    """Tabulated response, linear between samples and 0 outside the table.

    Parameters
    ----------
    wavelength : array_like
        Strictly increasing wavelengths [um], > 0, at least 2.
    response : array_like
        Response S at `wavelength` (dimensionless), >= 0, with ∫S dλ > 0. Not normalised.
    name : str, optional
        Band name; default ``"tabulated"``.

    Notes
    -----
    Leading and trailing zeros are trimmed from the support (one zero sample is kept at
    each end, so that S stays exact). The quadrature is composite Gauss-Legendre on each
    table segment, exact for the piecewise-linear S times a polynomial of degree <= 14.

    Examples
    --------
    >>> tri = TabulatedResponse([9.0, 10.0, 11.0], [0.0, 1.0, 0.0])
    >>> round(tri.equivalent_width(), 12)
    1.0
    """

    def __init__(self, wavelength, response, name: str | None = None):
        wl = np.asarray(wavelength, dtype=float)
        s = np.asarray(response, dtype=float)
        if wl.ndim != 1 or wl.size < 2 or s.shape != wl.shape:
            raise ConfigError(
                f"wavelength and response must be 1-D of equal length >= 2; "
                f"got shapes {wl.shape} and {s.shape}",
                key="wavelength",
            )
        if not (np.all(np.isfinite(wl)) and np.all(np.isfinite(s))):
            raise ConfigError("wavelength and response must be finite", key="response")
        if wl[0] <= 0 or not np.all(np.diff(wl) > 0):
            raise ConfigError(
                "wavelength must be > 0 µm and strictly increasing", key="wavelength"
            )
        if np.any(s < 0):
            raise ConfigError(
                f"response must be >= 0; got {s.min()!r} at {wl[np.argmin(s)]:g} µm",
                key="response",
            )
        area = float(np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(wl)))
        if not area > 0:
            raise ConfigError("integral of the response must be > 0", key="response")
        nonzero = np.flatnonzero(s > 0)
        first = max(nonzero[0] - 1, 0)
        last = min(nonzero[-1] + 1, wl.size - 1)
        self.wavelength = _readonly(wl[first : last + 1])
        self.response = _readonly(s[first : last + 1])
        self.name = name if name is not None else "tabulated"

    @classmethod
    def from_file(cls, path, wavelength_unit: str = "um", name: str | None = None):
        """Read a two-column (wavelength, response) text or CSV file.

        Columns are separated by commas, semicolons, tabs or spaces; extra columns are
        ignored. Lines before the first numeric row are headers; lines starting with ``#``
        and blank lines are skipped anywhere.

        Parameters
        ----------
        path : str or path-like
            The file.
        wavelength_unit : str
            Unit of the first column, any wavelength unit of
            :func:`radscene.radiometry.units.parse_quantity` (``"um"``, ``"nm"``, ...).
        name : str, optional
            Band name; default the file's stem.

        Raises
        ------
        ConfigError
            If the file cannot be read, has a non-numeric row after the data began, or
            fails the checks of :class:`TabulatedResponse`; the message names the file.
        """
        from radscene.radiometry.units import parse_quantity

        path = Path(path)
        scale = parse_quantity(f"1 {wavelength_unit}", "wavelength", key="wavelength_unit")
        try:
            text = path.read_text(encoding="utf-8-sig")
        except OSError as exc:
            raise ConfigError(f"cannot read spectral response file: {exc}", key=str(path)) from None
        except UnicodeDecodeError:
            raise ConfigError(f"{path.name} is not a text file of (wavelength, response) rows",
                              key=str(path)) from None
        rows = []
        for lineno, line in enumerate(text.splitlines(), start=1):
            stripped = line.strip()
            if not stripped or stripped.startswith("#"):
                continue
            fields = [f for f in re.split(r"[,;\s]+", stripped) if f]
            try:
                rows.append((float(fields[0]), float(fields[1])))
            except (ValueError, IndexError):
                if rows:
                    raise ConfigError(
                        f"line {lineno}: expected two numbers (wavelength, response)",
                        key=str(path),
                    ) from None
        if len(rows) < 2:
            raise ConfigError(
                "a spectral response file needs at least 2 rows of (wavelength, response)",
                key=str(path),
            )
        data = np.array(rows)
        try:
            return cls(data[:, 0] * scale, data[:, 1],
                       name=name if name is not None else path.stem)
        except ConfigError as err:  # the file's values: the message names the file
            raise ConfigError(f"{path}: {err.message}", key=err.key) from None

    @property
    def support(self):
        return (float(self.wavelength[0]), float(self.wavelength[-1]))

    def __call__(self, wavelength):
        wl = np.asarray(wavelength, dtype=float)
        return np.interp(wl, self.wavelength, self.response, left=0.0, right=0.0)

    def _rule(self):
        nodes, weights = _composite_gauss_legendre(self.wavelength)
        return nodes, weights * self(nodes)


#: Registry of spectral-response types for :func:`make_response` (case-insensitive keys).
RESPONSES: dict[str, type[SpectralResponse]] = {
    "rectangular": RectangularResponse,
    "gaussian": GaussianResponse,
    "tabulated": TabulatedResponse,
}


def make_response(spec: Mapping) -> SpectralResponse:
    """Build a spectral response from a type-tagged dict.

    Parameters
    ----------
    spec : mapping
        ``{"type": <name in RESPONSES>, **parameters}``, the type case-insensitive. A
        tabulated response may give ``file`` (and ``wavelength_unit``) instead of arrays.

    Returns
    -------
    SpectralResponse

    Raises
    ------
    ConfigError
        Unknown type (the message lists the known ones) or unknown/missing parameters.

    Examples
    --------
    >>> make_response({"type": "Gaussian", "center": 10.0, "fwhm": 1.0}).center
    10.0
    """
    if not isinstance(spec, Mapping) or "type" not in spec:
        raise ConfigError(
            f"a spectral response must be a mapping with a 'type' key, one of "
            f"{', '.join(RESPONSES)}; got {spec!r}",
            key="type",
        )
    kind = str(spec["type"]).lower()
    if kind not in RESPONSES:
        raise ConfigError(
            f"unknown spectral response type {spec['type']!r}; known: {', '.join(RESPONSES)}"
            f"{did_you_mean(spec['type'], RESPONSES)}",
            key="type",
        )
    cls = RESPONSES[kind]
    params = {k: v for k, v in spec.items() if k != "type"}
    factory = cls
    if cls is TabulatedResponse and "file" in params:
        params["path"] = params.pop("file")
        factory = cls.from_file
    signature = inspect.signature(factory)
    accepted = [p for p in signature.parameters if not p.startswith("_")]
    if any(k.startswith("_") for k in params):
        raise ConfigError(f"unknown parameter; accepted: {', '.join(accepted)}", key=kind)
    try:
        signature.bind(**params)
    except TypeError as exc:
        raise ConfigError(
            f"{exc}; accepted parameters of {kind!r}: {', '.join(accepted)}", key=kind
        ) from None
    return factory(**params)
