"""Spectra read from spectral libraries: one :class:`LibrarySpectrum`, many :class:`SpectralLibrary`.

Every reader of :mod:`radscene.materials.libraries` returns these two types, whatever the file
format, with the wavelength in micrometres (increasing) and the values as fractions [-]. The
file and the line of every sample are kept, so a bad value (a negative reflectance, a reflectance
plus transmittance above 1) is reported where it sits in the file.
"""

from __future__ import annotations

import fnmatch
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from radscene.errors import ConfigError

__all__ = ["LibrarySpectrum", "SpectralLibrary", "QUANTITIES"]

#: Quantities a library spectrum may hold.
QUANTITIES = ("reflectance", "emissivity", "transmittance")


def _readonly(array, dtype=float) -> np.ndarray:
    if isinstance(array, np.ndarray) and array.dtype == dtype and not array.flags.writeable:
        return array  # already an immutable array of the right type: share it
    out = np.array(array, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class LibrarySpectrum:
    """One spectrum of a spectral library, in radscene's units.

    Parameters
    ----------
    name : str
        The spectrum's name in its library.
    wavelength : array_like
        Strictly increasing wavelengths [um].
    values : array_like
        Values at ``wavelength`` as fractions [-] (percent already divided by 100).
    quantity : {"reflectance", "emissivity", "transmittance"}
        What the values are.
    source : str, optional
        The file (or library) the spectrum was read from.
    lines : array_like of int, optional
        Line (1-based) of ``source`` that holds each sample, for text formats; None for binary.
    metadata : mapping, optional
        The library's own fields (class, sample number, measurement, ...), as strings.

    Raises
    ------
    ConfigError
        Shapes that differ, a wavelength that is not strictly increasing and positive, a value
        that is not finite or is negative (naming the file and line where known), or an unknown
        ``quantity``.

    Examples
    --------
    >>> s = LibrarySpectrum("grey", [0.4, 2.5], [0.2, 0.3])
    >>> float(s.to_spectrum()(1.45))
    0.25
    """

    name: str
    wavelength: np.ndarray
    values: np.ndarray
    quantity: str = "reflectance"
    source: str = ""
    lines: np.ndarray | None = None
    metadata: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self):
        key = self.where()
        if self.quantity not in QUANTITIES:
            raise ConfigError(
                f"quantity must be one of {', '.join(QUANTITIES)}; got {self.quantity!r}",
                key=key,
            )
        wl = np.asarray(self.wavelength, dtype=float)
        vals = np.asarray(self.values, dtype=float)
        if wl.ndim != 1 or wl.shape != vals.shape or wl.size < 2:
            raise ConfigError(
                f"spectrum {self.name!r} needs matching 1-D wavelength and values with at least 2 "
                f"samples; got shapes {wl.shape} and {vals.shape}",
                key=key,
            )
        if not np.all(np.isfinite(wl)) or np.any(wl <= 0) or np.any(np.diff(wl) <= 0):
            raise ConfigError(
                f"spectrum {self.name!r}: wavelengths must be finite, positive and strictly "
                "increasing [µm]",
                key=key,
            )
        lines = None
        if self.lines is not None:
            lines = np.asarray(self.lines, dtype=np.int64)
            if lines.shape != wl.shape:
                raise ConfigError("lines must have one entry per sample", key=key)
        bad = np.flatnonzero(~np.isfinite(vals) | (vals < 0.0))
        if bad.size:
            i = int(bad[0])
            raise ConfigError(
                f"spectrum {self.name!r}: {self.quantity} {vals[i]:g} at {wl[i]:g} µm is "
                f"{'not finite' if not np.isfinite(vals[i]) else 'negative'}; a library "
                f"{self.quantity} must be >= 0",
                key=self.where(i, lines),
            )
        object.__setattr__(self, "wavelength", _readonly(wl))
        object.__setattr__(self, "values", _readonly(vals))
        object.__setattr__(self, "lines", None if lines is None else _readonly(lines, np.int64))
        object.__setattr__(self, "metadata", dict(self.metadata))

    # ------------------------------------------------------------------ locations
    def where(self, index: int | None = None, lines=None) -> str:
        """``"file:line"`` of sample ``index`` (or just the file / the name) for messages."""
        lines = self.lines if lines is None else lines
        base = self.source or self.name or "spectrum"
        if index is not None and lines is not None:
            return f"{base}:{int(lines[index])}"
        return base

    @property
    def range(self) -> tuple[float, float]:
        """Tabulated wavelength range [um]."""
        return (float(self.wavelength[0]), float(self.wavelength[-1]))

    # ------------------------------------------------------------------ conversions
    def to_spectrum(self, extend: str = "error"):
        """This spectrum as a :class:`~radscene.materials.Spectrum` (piecewise linear).

        Parameters
        ----------
        extend : {"error", "edge"}, optional
            Rule outside the tabulated range (see :mod:`radscene.materials.spectrum`).

        Returns
        -------
        Spectrum
        """
        from radscene.materials.spectrum import Spectrum

        return Spectrum.from_table(
            self.wavelength,
            self.values,
            extend=extend,
            name=self.name,
            source=self.source,
        )

    def to_material(
        self,
        name: str | None = None,
        *,
        transmittance=0.0,
        specular_reflectance=0.0,
        specular_exponent: float = 0.0,
        extend: str = "error",
        description: str = "",
        category: str = "",
    ):
        """A :class:`~radscene.materials.Material` from this spectrum.

        A reflectance spectrum gives ρ (emissivity by Kirchhoff, ε = 1 − ρ − τ); an emissivity
        spectrum gives ε (ρ = 1 − ε − τ). A transmittance spectrum alone does not define a
        material.

        Parameters
        ----------
        name : str, optional
            Material name; default the spectrum's name.
        transmittance : spectrum-like, optional
            τ [-]; default 0 (opaque).
        specular_reflectance : spectrum-like, optional
            ρ_s, the Phong-lobe part of ρ [-].
        specular_exponent : float, optional
            Phong exponent [-].
        extend : {"error", "edge"}, optional
            Rule outside the measured range.
        description, category : str, optional
            Metadata.

        Returns
        -------
        Material

        Raises
        ------
        ConfigError
            A reflectance above 1, or reflectance plus transmittance above 1, naming the file
            and line of the offending sample; a transmittance-only spectrum.
        """
        from radscene.materials.material import Material
        from radscene.materials.spectrum import make_spectrum

        name = name or self.name
        if self.quantity == "transmittance":
            raise ConfigError(
                f"spectrum {self.name!r} is a transmittance; a material needs a reflectance or "
                "an emissivity spectrum",
                key=self.where(),
            )
        tau = make_spectrum(transmittance, key=f"{name}.transmittance")
        tau_here = np.asarray(tau(self.wavelength)) if _covers(tau, self.range) else None
        if tau_here is not None:
            total = self.values + tau_here
            label = f"{self.quantity} + transmittance"
            bad = np.flatnonzero(total > 1.0 + 1e-12)
            if bad.size:
                i = int(bad[0])
                raise ConfigError(
                    f"material {name!r}: {label} = {total[i]:.6g} at {self.wavelength[i]:g} µm "
                    "exceeds 1 (reflectance plus transmittance must not exceed 1)",
                    key=self.where(i),
                )
        spectrum = self.to_spectrum(extend=extend)
        source = self.metadata.get("citation") or self.source
        kwargs = dict(
            transmittance=tau,
            specular_reflectance=specular_reflectance,
            specular_exponent=specular_exponent,
            source=source,
            description=description or self.metadata.get("description", ""),
            category=category or self.metadata.get("class", ""),
        )
        if self.quantity == "reflectance":
            return Material.create(name, reflectance=spectrum, **kwargs)
        return Material.create(name, emissivity=spectrum, **kwargs)

    def __repr__(self) -> str:
        lo, hi = self.range
        return (
            f"LibrarySpectrum({self.name!r}, {self.quantity}, {self.wavelength.size} samples on "
            f"[{lo:g}, {hi:g}] µm, source={self.source!r})"
        )


def _covers(spectrum, interval) -> bool:
    lo, hi = spectrum.defined_range
    return lo <= interval[0] and hi >= interval[1]


class SpectralLibrary(Sequence):
    """An ordered collection of :class:`LibrarySpectrum`, searchable by name and class.

    Parameters
    ----------
    spectra : sequence of LibrarySpectrum
    name : str, optional
        The library's name (e.g. its file).

    Examples
    --------
    >>> lib = SpectralLibrary([LibrarySpectrum("Dry grass", [0.4, 2.5], [0.1, 0.3],
    ...                                        metadata={"class": "vegetation"})])
    >>> [s.name for s in lib.search(name="*grass*")]
    ['Dry grass']
    """

    def __init__(self, spectra, name: str = ""):
        self._spectra = tuple(spectra)
        for s in self._spectra:
            if not isinstance(s, LibrarySpectrum):
                raise ConfigError(
                    f"a SpectralLibrary holds LibrarySpectrum objects; got {type(s).__name__}",
                    key=name or "library",
                )
        self.name = str(name)

    def __len__(self) -> int:
        return len(self._spectra)

    def __getitem__(self, index):
        if isinstance(index, slice):
            return SpectralLibrary(self._spectra[index], name=self.name)
        return self._spectra[index]

    def __iter__(self) -> Iterator[LibrarySpectrum]:
        return iter(self._spectra)

    @property
    def names(self) -> list[str]:
        """Names of the spectra, in order (not necessarily unique)."""
        return [s.name for s in self._spectra]

    def get(self, name: str) -> LibrarySpectrum:
        """The one spectrum called ``name`` (case-insensitive).

        Raises
        ------
        ConfigError
            No spectrum, or several, of that name (the message lists candidates or indices).
        """
        lowered = str(name).strip().lower()
        hits = [i for i, s in enumerate(self._spectra) if s.name.lower() == lowered]
        if len(hits) == 1:
            return self._spectra[hits[0]]
        if not hits:
            close = [s.name for s in self._spectra if lowered in s.name.lower()][:10]
            hint = f"; names containing it: {', '.join(close)}" if close else ""
            raise ConfigError(
                f"no spectrum named {name!r} in library {self.name or '(unnamed)'} "
                f"({len(self)} spectra){hint}",
                key=self.name or "library",
            )
        raise ConfigError(
            f"{len(hits)} spectra are named {name!r} (indices {hits}); index the library instead",
            key=self.name or "library",
        )

    def search(self, name: str | None = None, **fields) -> SpectralLibrary:
        """Spectra whose name and metadata match, case-insensitively.

        Parameters
        ----------
        name : str, optional
            A glob pattern (``*``, ``?``) on the name, or a plain substring when it has no
            wildcard.
        **fields : str
            ``key=pattern`` on the spectra's metadata (same matching rule). The special key
            ``cls`` matches any metadata field whose key contains ``class`` or ``level`` or is
            ``type`` (the libraries name their class hierarchies differently).

        Returns
        -------
        SpectralLibrary
            The matching spectra, in library order (possibly empty).
        """
        out = [
            s
            for s in self._spectra
            if (name is None or _match(name, s.name))
            and all(_field_match(s.metadata, k, v) for k, v in fields.items())
        ]
        return SpectralLibrary(out, name=self.name)

    def __repr__(self) -> str:
        return f"SpectralLibrary({self.name!r}, {len(self)} spectra)"


def _match(pattern: str, text: str) -> bool:
    pattern, text = str(pattern).lower(), str(text).lower()
    if any(c in pattern for c in "*?["):
        return fnmatch.fnmatchcase(text, pattern)
    return pattern in text


def _field_match(metadata: Mapping[str, str], key: str, pattern: str) -> bool:
    if key == "cls":
        keys = [k for k in metadata if "class" in k.lower() or "level" in k.lower()]
        keys += [k for k in metadata if k.lower() == "type"]
        return any(_match(pattern, metadata[k]) for k in keys)
    for k, v in metadata.items():
        if k.lower() == key.lower():
            return _match(pattern, v)
    return False
