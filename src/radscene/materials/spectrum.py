"""Dimensionless spectral quantities: reflectance, emissivity, transmittance, multipliers.

A :class:`Spectrum` is either a constant or a table that is piecewise linear in wavelength
[um]. Tables are defined on their tabulated range only; what happens outside it is a stated
rule recorded in :attr:`Spectrum.extend`:

``"error"`` (default)
    a query outside ``[wavelength[0], wavelength[-1]]`` raises :class:`~radscene.errors.ConfigError`
    naming the spectrum and its range;
``"edge"``
    the end values are held outside the range.

There is no other extrapolation. Sums, differences and scalar multiples of spectra are exact
(piecewise-linear functions stay piecewise linear on the union of the knots), so derived
quantities such as an emissivity ``1 - rho - tau`` are spectra of the same kind.

Text files (:meth:`Spectrum.from_file`)
---------------------------------------
Two or more columns separated by commas, semicolons, tabs or spaces; ``#`` starts a comment
(whole line or trailing); at most one header line, before the first data row. The first column is
the wavelength. **Unit rule:** the wavelength is in micrometres unless the header's first column
name states nanometres (a token ``nm``, ``nanometer(s)`` or ``nanometre(s)``, e.g.
``wavelength_nm``, ``Wavelength (nm)``, ``lambda[nm]``); a name stating ``um``, ``µm``,
``micron(s)`` or ``micrometre(s)``, or a file without header, means micrometres. Values are used
as written (fractions, not percent).
"""

from __future__ import annotations

import numbers
import re
from collections.abc import Iterable, Mapping
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError

__all__ = ["Spectrum", "make_spectrum", "linear_combination", "union_wavelengths", "EXTEND_RULES"]

#: Accepted values of ``extend``.
EXTEND_RULES = ("error", "edge")

_NM_RE = re.compile(r"(?<![a-z])(nm|nanomet(er|re)s?)(?![a-z])")
_SPLIT_RE = re.compile(r"[,;\s]+")


def _readonly(array: np.ndarray) -> np.ndarray:
    array = np.array(array, dtype=float, copy=True)
    array.setflags(write=False)
    return array


class Spectrum:
    """An immutable dimensionless spectral quantity, constant or piecewise linear in wavelength.

    Build one with :meth:`constant`, :meth:`from_table`, :meth:`from_file` or
    :func:`make_spectrum` rather than with the constructor.

    Parameters
    ----------
    wavelength : array_like or None
        Strictly increasing, positive wavelengths of the table [um]; ``None`` for a constant.
    values : array_like
        Values at ``wavelength`` [-], or the constant (a scalar) when ``wavelength`` is None.
    name : str, optional
        Name used in error messages, e.g. ``"asphalt.reflectance"``.
    source : str, optional
        Citation or file the values come from.
    extend : {"error", "edge"}, optional
        Rule outside the tabulated range (see the module docstring). Ignored for constants,
        which are defined at every positive wavelength.

    Attributes
    ----------
    wavelength : numpy.ndarray or None
        Tabulated wavelengths [um], read-only; None for a constant.
    values : numpy.ndarray
        Tabulated values [-] (read-only), or a 0-d array holding the constant.
    name, source, extend : str

    Examples
    --------
    >>> s = Spectrum.from_table([0.4, 0.8], [0.1, 0.5], name="demo")
    >>> s([0.4, 0.6, 0.8]).round(12)
    array([0.1, 0.3, 0.5])
    >>> s.range
    (0.4, 0.8)
    >>> round(float((1.0 - s)(0.6)), 12)
    0.7
    """

    __slots__ = ("_wavelength", "_values", "_name", "_source", "_extend")

    def __init__(self, wavelength, values, *, name: str = "", source: str = "", extend="error"):
        key = name or "spectrum"
        if extend not in EXTEND_RULES:
            raise ConfigError(
                f"extend must be one of {', '.join(map(repr, EXTEND_RULES))}; got {extend!r}",
                key=f"{key}.extend",
            )
        if wavelength is None:
            value = _as_float_array(values, f"{key}.values")
            if value.ndim != 0:
                raise ConfigError(
                    f"a constant spectrum takes one number; got shape {value.shape}",
                    key=f"{key}.values",
                )
            if not np.isfinite(value):
                raise ConfigError(f"value must be finite; got {float(value)}", key=f"{key}.values")
            wl = None
            vals = _readonly(value)
        else:
            wl = _as_float_array(wavelength, f"{key}.wavelength")
            vals = _as_float_array(values, f"{key}.values")
            if wl.ndim != 1 or wl.size < 2:
                raise ConfigError(
                    f"wavelength must be a 1-D sequence of at least 2 values [µm]; got shape "
                    f"{wl.shape}",
                    key=f"{key}.wavelength",
                )
            if vals.shape != wl.shape:
                raise ConfigError(
                    f"values must have the shape of wavelength {wl.shape}; got {vals.shape}",
                    key=f"{key}.values",
                )
            if not np.all(np.isfinite(wl)) or np.any(wl <= 0.0):
                raise ConfigError(
                    "wavelength must be finite and positive [µm]", key=f"{key}.wavelength"
                )
            if np.any(np.diff(wl) <= 0.0):
                i = int(np.argmax(np.diff(wl) <= 0.0))
                raise ConfigError(
                    f"wavelength must be strictly increasing; {wl[i + 1]:g} µm follows "
                    f"{wl[i]:g} µm",
                    key=f"{key}.wavelength",
                )
            if not np.all(np.isfinite(vals)):
                i = int(np.argmax(~np.isfinite(vals)))
                raise ConfigError(
                    f"values must be finite; got {vals[i]} at {wl[i]:g} µm", key=f"{key}.values"
                )
            wl = _readonly(wl)
            vals = _readonly(vals)
        self._wavelength = wl
        self._values = vals
        self._name = str(name)
        self._source = str(source)
        self._extend = extend

    # ------------------------------------------------------------------ constructors
    @classmethod
    def constant(cls, value, *, name: str = "", source: str = "") -> Spectrum:
        """A spectrum with the same value at every wavelength.

        Parameters
        ----------
        value : float
            The value [-].
        name, source : str, optional
            Name for messages and citation.

        Returns
        -------
        Spectrum
            Its :attr:`range` is ``(0, inf)``.

        Examples
        --------
        >>> Spectrum.constant(0.3)([1.0, 10.0])
        array([0.3, 0.3])
        """
        return cls(None, value, name=name, source=source)

    @classmethod
    def from_table(
        cls, wavelength, values, extend: str = "error", *, name: str = "", source: str = ""
    ) -> Spectrum:
        """A spectrum tabulated at increasing wavelengths, linear in between.

        Parameters
        ----------
        wavelength : array_like
            Strictly increasing positive wavelengths, at least two [um].
        values : array_like
            Values at those wavelengths [-].
        extend : {"error", "edge"}, optional
            Rule outside the tabulated range.
        name, source : str, optional
            Name for messages and citation.

        Returns
        -------
        Spectrum
        """
        return cls(wavelength, values, name=name, source=source, extend=extend)

    @classmethod
    def from_file(
        cls,
        path,
        column=1,
        extend: str = "error",
        *,
        name: str | None = None,
        source: str | None = None,
    ) -> Spectrum:
        """Read a spectrum from a delimited text file.

        See the module docstring for the format and the wavelength-unit rule (micrometres
        unless the header's wavelength name says ``nm``).

        Parameters
        ----------
        path : str or path-like
            The file.
        column : int or str, optional
            Index of the value column (0 is the wavelength, so at least 1) or its header name.
        extend : {"error", "edge"}, optional
            Rule outside the tabulated range.
        name : str, optional
            Name for messages; defaults to ``"<file>:<column>"``.
        source : str, optional
            Citation; defaults to the file path.

        Returns
        -------
        Spectrum

        Raises
        ------
        ConfigError
            Missing file, unreadable rows, unknown column, or a table that is not valid.
        """
        path = Path(path)
        key = name or str(path)
        try:
            text = path.read_text(encoding="utf-8")
        except OSError as exc:
            raise ConfigError(f"cannot read spectrum file: {exc.strerror or exc}", key=key) from exc
        except UnicodeDecodeError:
            raise ConfigError(f"{path.name} is not a text file of spectrum rows", key=key) from None
        header, rows = _parse_table(text, str(path), key)
        if not rows:
            raise ConfigError(f"spectrum file {path} has no data rows", key=key)
        ncols = min(len(r) for r in rows)
        if isinstance(column, str):
            if header is None or column not in header:
                held = (f"its header names {len(header) - 1} value column(s)" if header
                        else "it has no header")
                raise ConfigError(
                    f"column {column!r} is not in the header of {path} ({held})",
                    key=key,
                )
            index = header.index(column)
        elif isinstance(column, numbers.Integral) and not isinstance(column, bool):
            index = int(column)
        else:
            raise ConfigError(
                f"column must be an int >= 1 or a header name; got {column!r}", key=key
            )
        if index < 1 or index >= ncols:
            raise ConfigError(
                f"column {column!r} is not a value column of {path}, which has columns "
                f"1..{ncols - 1} after the wavelength",
                key=key,
            )
        data = np.array([r[:ncols] for r in rows], dtype=float)
        wavelength = data[:, 0]
        if header is not None and _NM_RE.search(header[0].lower()):
            wavelength = wavelength * 1e-3
        col_name = header[index] if header else str(index)
        return cls(
            wavelength,
            data[:, index],
            name=name if name is not None else f"{path.name}:{col_name}",
            source=source if source is not None else str(path),
            extend=extend,
        )

    # ------------------------------------------------------------------ attributes
    @property
    def wavelength(self) -> np.ndarray | None:
        """Tabulated wavelengths [um] (read-only), or None for a constant."""
        return self._wavelength

    @property
    def values(self) -> np.ndarray:
        """Tabulated values [-] (read-only), or a 0-d array with the constant."""
        return self._values

    @property
    def name(self) -> str:
        """Name used in error messages."""
        return self._name

    @property
    def source(self) -> str:
        """Citation or file of the values."""
        return self._source

    @property
    def extend(self) -> str:
        """Rule outside the tabulated range: ``"error"`` or ``"edge"``."""
        return self._extend

    @property
    def is_constant(self) -> bool:
        """True for a constant spectrum."""
        return self._wavelength is None

    @property
    def range(self) -> tuple[float, float]:
        """Tabulated wavelength range ``(min, max)`` [um]; ``(0, inf)`` for a constant."""
        if self._wavelength is None:
            return (0.0, float("inf"))
        return (float(self._wavelength[0]), float(self._wavelength[-1]))

    @property
    def defined_range(self) -> tuple[float, float]:
        """Range where the spectrum can be evaluated [um]: :attr:`range`, or ``(0, inf)``
        when ``extend == "edge"``."""
        if self._wavelength is None or self._extend == "edge":
            return (0.0, float("inf"))
        return self.range

    # ------------------------------------------------------------------ evaluation
    def __call__(self, wavelength) -> np.ndarray:
        """Evaluate at ``wavelength`` [um].

        Parameters
        ----------
        wavelength : array_like
            Wavelengths [um], any shape. NaN gives NaN.

        Returns
        -------
        numpy.ndarray
            Float values [-], same shape as ``wavelength``.

        Raises
        ------
        ConfigError
            A wavelength outside the tabulated range when ``extend == "error"``, or a
            non-positive wavelength.
        """
        wl = np.asarray(wavelength, dtype=float)
        bad = wl <= 0.0
        if np.any(bad):
            raise ConfigError(
                f"wavelength must be positive [µm]; got {wl[bad].flat[0]:g}", key=self._label()
            )
        if self._wavelength is None:
            out = np.full(wl.shape, float(self._values))
            out[np.isnan(wl)] = np.nan
            return out
        lo, hi = self.range
        if self._extend == "error":
            outside = (wl < lo) | (wl > hi)
            if np.any(outside):
                raise ConfigError(
                    f"wavelength {wl[outside].flat[0]:g} µm is outside the tabulated range "
                    f"[{lo:g}, {hi:g}] µm of spectrum {self._label()!r}"
                    f"{' (' + self._source + ')' if self._source else ''}; extend='error' "
                    "allows no extrapolation (use extend='edge' to hold the end values)",
                    key=self._label(),
                )
        return np.asarray(np.interp(wl, self._wavelength, self._values))

    def _label(self) -> str:
        return self._name or "spectrum"

    # ------------------------------------------------------------------ arithmetic
    def __add__(self, other) -> Spectrum:
        return linear_combination([(1.0, self), (1.0, other)])

    __radd__ = __add__

    def __sub__(self, other) -> Spectrum:
        return linear_combination([(1.0, self), (-1.0, other)])

    def __rsub__(self, other) -> Spectrum:
        return linear_combination([(-1.0, self), (1.0, other)])

    def __neg__(self) -> Spectrum:
        return linear_combination([(-1.0, self)])

    def __mul__(self, other) -> Spectrum:
        if isinstance(other, Spectrum) and not other.is_constant and not self.is_constant:
            return NotImplemented  # the product of two tables is not piecewise linear
        if isinstance(other, Spectrum):
            const, spec = (other, self) if other.is_constant else (self, other)
            return linear_combination([(float(const.values), spec)])
        if isinstance(other, numbers.Real):
            return linear_combination([(float(other), self)])
        return NotImplemented

    __rmul__ = __mul__

    def with_name(self, name: str, source: str | None = None) -> Spectrum:
        """A copy with another name (and optionally source)."""
        return Spectrum(
            self._wavelength,
            self._values,
            name=name,
            source=self._source if source is None else source,
            extend=self._extend,
        )

    def __repr__(self) -> str:
        if self._wavelength is None:
            return f"Spectrum.constant({float(self._values)!r}, name={self._name!r})"
        lo, hi = self.range
        return (
            f"Spectrum(name={self._name!r}, {self._wavelength.size} points on [{lo:g}, {hi:g}] "
            f"µm, extend={self._extend!r})"
        )


def linear_combination(terms, offset: float = 0.0, *, name: str = "", source: str = ""):
    """Exact ``offset + sum(c_i * s_i)`` of spectra and numbers.

    Parameters
    ----------
    terms : iterable of (float, Spectrum or float)
        Coefficients [-] and spectra (numbers count as constants).
    offset : float, optional
        Added constant [-].
    name, source : str, optional
        Name and citation of the result.

    Returns
    -------
    Spectrum
        Constant when every term is; otherwise tabulated on the union of the knots inside the
        common defined range. Its ``extend`` is ``"error"`` when any term's is (its range is
        then the intersection of those terms' ranges), else ``"edge"``.

    Raises
    ------
    ConfigError
        Terms whose ranges do not overlap.
    """
    const = float(offset)
    tables: list[tuple[float, Spectrum]] = []
    for coef, spec in terms:
        coef = float(coef)
        if isinstance(spec, numbers.Real) and not isinstance(spec, bool):
            const += coef * float(spec)
        elif isinstance(spec, Spectrum):
            if spec.is_constant:
                const += coef * float(spec.values)
            else:
                tables.append((coef, spec))
        else:
            return NotImplemented
    if not tables:
        return Spectrum.constant(const, name=name, source=source)
    strict = [s for _, s in tables if s.extend == "error"]
    if strict:
        lo = max(s.range[0] for s in strict)
        hi = min(s.range[1] for s in strict)
        if lo >= hi:
            names = ", ".join(f"{s.name or 'spectrum'} {list(s.range)}" for s in strict)
            raise ConfigError(
                f"spectra have no common wavelength range to combine: {names} [µm]",
                key=name or None,
            )
        extend = "error"
    else:
        lo = min(s.range[0] for _, s in tables)
        hi = max(s.range[1] for _, s in tables)
        extend = "edge"
    knots = np.unique(np.concatenate([s.wavelength for _, s in tables] + [[lo, hi]]))
    knots = knots[(knots >= lo) & (knots <= hi)]
    values = np.full(knots.shape, const)
    for coef, spec in tables:
        values += coef * np.interp(knots, spec.wavelength, spec.values)
    return Spectrum(knots, values, name=name, source=source, extend=extend)


def union_wavelengths(spectra: Iterable[Spectrum]) -> np.ndarray:
    """Sorted union of the tabulated wavelengths of ``spectra`` [um] (empty if all constant).

    Inside the common range of piecewise-linear spectra, any linear combination of them has its
    extrema at these knots, so checking bounds there is exact.
    """
    arrays = [s.wavelength for s in spectra if s.wavelength is not None]
    if not arrays:
        return np.empty(0)
    return np.unique(np.concatenate(arrays))


_SPEC_KEYS_TABLE = {"wavelength", "values", "extend", "name", "source"}
_SPEC_KEYS_FILE = {"file", "column", "extend", "name", "source"}


def make_spectrum(spec, key: str = "spectrum", *, base_dir=None) -> Spectrum:
    """Build a :class:`Spectrum` from YAML-like input.

    Parameters
    ----------
    spec : Spectrum, number, or mapping
        A number: a constant. ``{"wavelength": [...], "values": [...], "extend": ...}``: a
        table [um]. ``{"file": path, "column": 1, "extend": ...}``: a text file (see
        :meth:`Spectrum.from_file`). ``name`` and ``source`` keys are accepted in both mappings.
        A :class:`Spectrum` is returned as it is.
    key : str, optional
        Config key path, used as the spectrum's name and in error messages.
    base_dir : str or path-like, optional
        Directory that relative ``file`` paths are relative to (e.g. the scene file's).

    Returns
    -------
    Spectrum

    Raises
    ------
    ConfigError
        Naming ``key`` and what is accepted.

    Examples
    --------
    >>> make_spectrum(0.25, key="grass.transmittance")(0.5)
    array(0.25)
    >>> make_spectrum({"wavelength": [1, 2], "values": [0, 1]})(1.5)
    array(0.5)
    """
    if isinstance(spec, Spectrum):
        return spec
    if isinstance(spec, numbers.Real) and not isinstance(spec, bool):
        return Spectrum.constant(float(spec), name=key)
    if isinstance(spec, Mapping):
        keys = set(spec)
        extend = spec.get("extend", "error")
        name = spec.get("name", key)
        if "file" in keys:
            unknown = keys - _SPEC_KEYS_FILE
            if unknown:
                raise ConfigError(
                    f"unknown keys {sorted(unknown)} for a file spectrum; accepted: "
                    f"{sorted(_SPEC_KEYS_FILE)}",
                    key=key,
                )
            path = Path(spec["file"])
            if base_dir is not None and not path.is_absolute():
                path = Path(base_dir) / path
            return Spectrum.from_file(
                path,
                column=spec.get("column", 1),
                extend=extend,
                name=name,
                source=spec.get("source", str(path)),
            )
        if {"wavelength", "values"} <= keys:
            unknown = keys - _SPEC_KEYS_TABLE
            if unknown:
                raise ConfigError(
                    f"unknown keys {sorted(unknown)} for a tabulated spectrum; accepted: "
                    f"{sorted(_SPEC_KEYS_TABLE)}",
                    key=key,
                )
            return Spectrum.from_table(
                spec["wavelength"],
                spec["values"],
                extend=extend,
                name=name,
                source=spec.get("source", ""),
            )
        raise ConfigError(
            f"a spectrum mapping needs 'wavelength' and 'values' [µm], or 'file'; got keys "
            f"{sorted(keys)}",
            key=key,
        )
    raise ConfigError(
        "a spectrum is a number, a mapping {wavelength: [...], values: [...]} or "
        f"{{file: path, column: 1}}; got {type(spec).__name__} {spec!r}",
        key=key,
    )


def _as_float_array(value, key: str) -> np.ndarray:
    if isinstance(value, bool) or (isinstance(value, np.ndarray) and value.dtype == bool):
        raise ConfigError(f"expected numbers, got booleans {value!r}", key=key)
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"expected numbers; got {value!r}", key=key) from exc


def _parse_table(text: str, label: str, key: str | None = None
                 ) -> tuple[list[str] | None, list[list[float]]]:
    """Header (or None) and numeric rows of the delimited text table ``label``; errors name
    ``key`` (default ``label``)."""
    header: list[str] | None = None
    rows: list[list[float]] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        fields = [f for f in _SPLIT_RE.split(line) if f]
        try:
            numbers_ = [float(f) for f in fields]
        except ValueError:
            if rows or header is not None:
                raise ConfigError(
                    f"line {lineno} of {label} is not numeric (only one header line is "
                    "allowed, before the data)",
                    key=key or label,
                ) from None
            header = [f.strip().strip('"').strip("'") for f in _split_header(line)]
            continue
        if len(numbers_) < 2:
            raise ConfigError(
                f"line {lineno} of {label} has {len(numbers_)} column(s); a spectrum file needs "
                "a wavelength and at least one value column",
                key=key or label,
            )
        rows.append(numbers_)
    return header, rows


def _split_header(line: str) -> list[str]:
    """Split a header on commas/semicolons/tabs if present (names may hold spaces), else spaces."""
    if re.search(r"[,;\t]", line):
        return [f for f in re.split(r"\s*[,;\t]\s*", line) if f]
    return line.split()
