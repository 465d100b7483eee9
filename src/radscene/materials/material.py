"""Opaque or translucent surface materials: reflectance, transmittance and, by Kirchhoff, emissivity.

A :class:`Material` holds three spectra (dimensionless, piecewise linear in wavelength [um]):

* ``diffuse_reflectance`` ρ_d — directional-hemispherical reflectance of the Lambertian part;
* ``specular_reflectance`` ρ_s — albedo of the Phong lobe of OSSIM (Willers et al. 2011, eq. 4, the
  "wideband Fresnel reflection"; see :mod:`radscene.materials.brdf.phong`);
* ``transmittance`` τ — diffuse transmittance;

and the emissivity follows from energy conservation and Kirchhoff's law for a surface in
local thermodynamic equilibrium:

.. math:: \\varepsilon(\\lambda) = 1 - \\rho_d(\\lambda) - \\rho_s(\\lambda) - \\tau(\\lambda)

Every component must lie in [0, 1]; a material that breaks this is refused, never repaired.
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.spectrum import (
    Spectrum,
    linear_combination,
    make_spectrum,
    union_wavelengths,
)

__all__ = ["Material", "KIRCHHOFF_TOLERANCE"]

#: Largest |ρ + ε + τ − 1| accepted by :meth:`Material.create` when both reflectance and
#: emissivity are given [-].
KIRCHHOFF_TOLERANCE = 1e-6

#: Rounding allowance of :meth:`Material.check`: values in [-1e-12, 1 + 1e-12] pass (they are
#: not altered) [-].
BOUNDS_TOLERANCE = 1e-12

#: Wavelength at which materials made only of constants are checked [um].
_CONSTANT_CHECK_WAVELENGTH = 1.0


def _zero() -> Spectrum:
    return Spectrum.constant(0.0)


@dataclass(frozen=True)
class Material:
    """A surface material: diffuse and specular reflectance, transmittance, emissivity.

    Parameters
    ----------
    name : str
        Material name (used in error messages).
    diffuse_reflectance : Spectrum
        ρ_d, directional-hemispherical reflectance of the Lambertian part [-].
    specular_reflectance : Spectrum, optional
        ρ_s, albedo of the Phong specular lobe [-]; default 0.
    specular_exponent : float, optional
        Phong exponent n ≥ 0 [-]; default 0.
    transmittance : Spectrum, optional
        τ, diffuse transmittance [-]; default 0 (opaque).
    source : str, optional
        Citation of the data.
    description : str, optional
        What the material is.
    category : str, optional
        Free-form class, e.g. ``"vegetation"``, ``"soil"``, ``"man-made"``.

    Raises
    ------
    ConfigError
        Wrong types, a negative or non-finite exponent, or a component outside [0, 1] at some
        tabulated wavelength (see :meth:`check`, run on construction).

    Examples
    --------
    >>> m = Material.create("grey", reflectance=0.3)
    >>> float(m.emissivity(10.0))
    0.7
    """

    name: str
    diffuse_reflectance: Spectrum
    specular_reflectance: Spectrum = field(default_factory=_zero)
    specular_exponent: float = 0.0
    transmittance: Spectrum = field(default_factory=_zero)
    source: str = ""
    description: str = ""
    category: str = ""

    def __post_init__(self):
        for attr in ("diffuse_reflectance", "specular_reflectance", "transmittance"):
            if not isinstance(getattr(self, attr), Spectrum):
                raise ConfigError(
                    f"must be a Spectrum (see radscene.materials.make_spectrum); got "
                    f"{type(getattr(self, attr)).__name__}",
                    key=f"{self.name}.{attr}",
                )
        n = self.specular_exponent
        if (
            isinstance(n, bool)
            or not isinstance(n, numbers.Real)
            or not math.isfinite(float(n))
            or n < 0
        ):
            raise ConfigError(
                f"specular_exponent must be a finite number >= 0; got {n!r}",
                key=f"{self.name}.specular_exponent",
            )
        object.__setattr__(self, "specular_exponent", float(n))
        self.check()

    # ------------------------------------------------------------------ construction
    @classmethod
    def create(
        cls,
        name: str,
        *,
        reflectance=None,
        emissivity=None,
        transmittance=0.0,
        specular_reflectance=0.0,
        specular_exponent: float = 0.0,
        source: str = "",
        description: str = "",
        category: str = "",
        key: str | None = None,
        base_dir=None,
    ) -> Material:
        """Build a material from total reflectance and/or emissivity.

        Each spectral argument is anything :func:`~radscene.materials.make_spectrum` takes (a
        number, a table mapping, a file mapping or a :class:`Spectrum`).

        Parameters
        ----------
        name : str
            Material name.
        reflectance : spectrum-like, optional
            Total directional-hemispherical reflectance ρ = ρ_d + ρ_s [-].
        emissivity : spectrum-like, optional
            Hemispherical emissivity ε [-].
        transmittance : spectrum-like, optional
            τ [-]; default 0.
        specular_reflectance : spectrum-like, optional
            ρ_s, the Phong-lobe albedo [-]; default 0.
        specular_exponent : float, optional
            Phong exponent n ≥ 0 [-].
        source, description, category : str, optional
            Metadata.
        key : str, optional
            Config key path for error messages; defaults to ``name``.
        base_dir : path-like, optional
            Directory for relative spectrum file paths.

        Returns
        -------
        Material

        Notes
        -----
        * ``reflectance`` only: ρ_d = ρ − ρ_s.
        * ``emissivity`` only: ρ_d = 1 − ε − τ − ρ_s.
        * both: they must satisfy |ρ + ε + τ − 1| ≤ 1e-6 at every tabulated wavelength (else
          :class:`ConfigError`, not a silent fix); then ρ_d = ρ − ρ_s.
        * neither: :class:`ConfigError`.

        The result is checked with :meth:`check` on the union of the tabulated wavelengths.

        Examples
        --------
        >>> m = Material.create("paint", emissivity=0.9, specular_reflectance=0.04)
        >>> round(float(m.diffuse_reflectance(1.0)), 12)
        0.06
        """
        key = key or name
        tau = make_spectrum(transmittance, key=f"{key}.transmittance", base_dir=base_dir)
        rho_s = make_spectrum(
            specular_reflectance, key=f"{key}.specular_reflectance", base_dir=base_dir
        )
        given = {"transmittance": (transmittance, tau),
                 "specular_reflectance": (specular_reflectance, rho_s)}
        if reflectance is None and emissivity is None:
            raise ConfigError(
                "give reflectance (total hemispherical, rho_d + rho_s) or emissivity, or both",
                key=key,
            )
        if reflectance is not None:
            rho = make_spectrum(reflectance, key=f"{key}.reflectance", base_dir=base_dir)
            given["reflectance"] = (reflectance, rho)
            if emissivity is not None:
                eps = make_spectrum(emissivity, key=f"{key}.emissivity", base_dir=base_dir)
                given["emissivity"] = (emissivity, eps)
                _check_kirchhoff(key, rho, eps, tau)
            rho_d = linear_combination(
                [(1.0, rho), (-1.0, rho_s)],
                name=f"{key}.diffuse_reflectance",
                source=rho.source,
            )
        else:
            eps = make_spectrum(emissivity, key=f"{key}.emissivity", base_dir=base_dir)
            given["emissivity"] = (emissivity, eps)
        for label, (spec, spectrum) in given.items():
            _check_unit_range(name, f"{key}.{label}", label, spec, spectrum, base_dir)
        if reflectance is not None:
            _check_sum(name, key, given, base_dir)
        if reflectance is None:
            rho_d = linear_combination(
                [(-1.0, eps), (-1.0, tau), (-1.0, rho_s)],
                offset=1.0,
                name=f"{key}.diffuse_reflectance",
                source=eps.source,
            )
        return cls(
            name=name,
            diffuse_reflectance=rho_d,
            specular_reflectance=rho_s,
            specular_exponent=specular_exponent,
            transmittance=tau,
            source=source,
            description=description,
            category=category,
        )

    # ------------------------------------------------------------------ evaluation
    @property
    def spectra(self) -> tuple[Spectrum, Spectrum, Spectrum]:
        """(ρ_d, ρ_s, τ) as spectra."""
        return (self.diffuse_reflectance, self.specular_reflectance, self.transmittance)

    @property
    def emissivity_spectrum(self) -> Spectrum:
        """ε = 1 − ρ_d − ρ_s − τ as a :class:`Spectrum` (exact, piecewise linear)."""
        return linear_combination(
            [(-1.0, s) for s in self.spectra],
            offset=1.0,
            name=f"{self.name}.emissivity",
            source=self.source,
        )

    @property
    def reflectance_spectrum(self) -> Spectrum:
        """Total hemispherical reflectance ρ = ρ_d + ρ_s as a :class:`Spectrum`."""
        return linear_combination(
            [(1.0, self.diffuse_reflectance), (1.0, self.specular_reflectance)],
            name=f"{self.name}.reflectance",
            source=self.source,
        )

    @property
    def wavelength_range(self) -> tuple[float, float]:
        """Range where every component is defined [um] (``(0, inf)`` for constants)."""
        ranges = [s.defined_range for s in self.spectra]
        return (max(r[0] for r in ranges), min(r[1] for r in ranges))

    def reflectance(self, wavelength) -> np.ndarray:
        """Total hemispherical reflectance ρ_d + ρ_s [-] at ``wavelength`` [um]."""
        return np.asarray(
            self.diffuse_reflectance(wavelength) + self.specular_reflectance(wavelength)
        )

    def emissivity(self, wavelength) -> np.ndarray:
        """Hemispherical emissivity by Kirchhoff's law, ε = 1 − ρ_d − ρ_s − τ [-].

        Parameters
        ----------
        wavelength : array_like
            Wavelengths [um].

        Returns
        -------
        numpy.ndarray
            Same shape as ``wavelength`` [-].
        """
        return np.asarray(
            1.0
            - self.diffuse_reflectance(wavelength)
            - self.specular_reflectance(wavelength)
            - self.transmittance(wavelength)
        )

    def components(self, wavelength) -> dict[str, np.ndarray]:
        """All four components at ``wavelength`` [um].

        Returns
        -------
        dict of str to numpy.ndarray
            Keys ``"diffuse_reflectance"``, ``"specular_reflectance"``, ``"transmittance"``,
            ``"emissivity"``; float arrays of the shape of ``wavelength`` [-].
        """
        rho_d = self.diffuse_reflectance(wavelength)
        rho_s = self.specular_reflectance(wavelength)
        tau = self.transmittance(wavelength)
        return {
            "diffuse_reflectance": rho_d,
            "specular_reflectance": rho_s,
            "transmittance": tau,
            "emissivity": np.asarray(1.0 - rho_d - rho_s - tau),
        }

    def check(self, wavelength=None) -> None:
        """Raise if any of ρ_d, ρ_s, τ, ε is below 0 or above 1 (to ``BOUNDS_TOLERANCE``).

        Parameters
        ----------
        wavelength : array_like, optional
            Wavelengths to check [um]. Default: the union of the tabulated wavelengths of the
            three spectra inside :attr:`wavelength_range` — exact for piecewise-linear spectra,
            whose extrema lie at their knots.

        Raises
        ------
        ConfigError
            Naming the material, the component, its value and the first offending wavelength.
        """
        if wavelength is None:
            wl = union_wavelengths(self.spectra)
            lo, hi = self.wavelength_range
            if lo >= hi:
                names = ", ".join(f"{s.name or 'spectrum'} {list(s.range)}" for s in self.spectra)
                raise ConfigError(
                    f"material {self.name!r}: its spectra have no common wavelength range: "
                    f"{names} [µm]",
                    key=self.name,
                )
            wl = wl[(wl >= lo) & (wl <= hi)]
            if wl.size == 0:
                wl = np.array([_CONSTANT_CHECK_WAVELENGTH])
        else:
            wl = np.atleast_1d(np.asarray(wavelength, dtype=float)).ravel()
        comps = self.components(wl)
        order = np.argsort(wl, kind="stable")
        for label, values in comps.items():
            bad = ~((values >= -BOUNDS_TOLERANCE) & (values <= 1.0 + BOUNDS_TOLERANCE))
            if np.any(bad):
                i = order[bad[order]][0]
                hint = {
                    "emissivity": " (rho_d + rho_s + tau exceeds 1: reflectance plus "
                    "transmittance must not exceed 1)",
                    "diffuse_reflectance": " (rho_d = rho - rho_s: the specular reflectance must "
                    "not exceed the total reflectance; with emissivity given, rho_d = 1 - eps - "
                    "tau - rho_s)",
                }.get(label, "")
                raise ConfigError(
                    f"material {self.name!r}: {label} = {values[i]:.6g} at wavelength "
                    f"{wl[i]:g} µm is outside [0, 1]{hint}",
                    key=self.name,
                )


def _data_line_numbers(path) -> list[int]:
    """1-based line numbers of the data rows of a spectrum text file (comments, blank lines and
    the one header line skipped), in the order :meth:`Spectrum.from_file` reads them."""
    out, seen_data = [], False
    for lineno, raw in enumerate(Path(path).read_text(encoding="utf-8").splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        try:
            [float(f) for f in re.split(r"[\s,;]+", line) if f]
        except ValueError:
            if not seen_data:
                continue  # the header
        seen_data = True
        out.append(lineno)
    return out


def _file_line(spec, spectrum: Spectrum, index: int | None, wavelength, base_dir) -> str:
    """``"path:line: "`` of a file-given spectrum's row (by index, or by its wavelength), or ``""``."""
    if not (isinstance(spec, dict) and "file" in spec):
        return ""
    path = Path(spec["file"])
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    if index is None and spectrum.wavelength is not None and wavelength is not None:
        hits = np.flatnonzero(np.isclose(spectrum.wavelength, wavelength, rtol=0, atol=1e-12))
        index = int(hits[0]) if hits.size else None
    try:
        return f"{path}:{_data_line_numbers(path)[index]}: " if index is not None else f"{path}: "
    except (OSError, IndexError):
        return f"{path}: "


def _check_sum(name: str, key: str, given: dict, base_dir) -> None:
    """Refuse reflectance + transmittance > 1 at any knot, naming the file and line."""
    (rho_spec, rho), (tau_spec, tau) = given["reflectance"], given["transmittance"]
    total = linear_combination([(1.0, rho), (1.0, tau)])
    values = np.atleast_1d(total.values)
    bad = np.flatnonzero(values > 1.0 + 1e-12)
    if bad.size == 0:
        return
    i = int(bad[0])
    wl = None if total.wavelength is None else float(total.wavelength[i])
    where = (_file_line(rho_spec, rho, None, wl, base_dir)
             or _file_line(tau_spec, tau, None, wl, base_dir))
    at = "" if wl is None else f" at {wl:g} µm"
    raise ConfigError(
        f"{where}material {name!r}: reflectance + transmittance = {values[i]:g}{at} exceeds 1 "
        "(emissivity 1 - rho - tau would be negative)",
        key=key,
    )


def _check_unit_range(name: str, key: str, label: str, spec, spectrum: Spectrum, base_dir) -> None:
    """Refuse a given ρ, ρ_s, τ or ε outside [0, 1], naming the file and line it came from."""
    values = np.atleast_1d(spectrum.values)
    bad = np.flatnonzero((values < 0.0) | (values > 1.0) | ~np.isfinite(values))
    if bad.size == 0:
        return
    i = int(bad[0])
    at = "" if spectrum.wavelength is None else f" at {spectrum.wavelength[i]:g} µm"
    message = (f"material {name!r}: {label} = {values[i]:g}{at} is outside [0, 1] "
               "(a reflectance, transmittance or emissivity is a fraction)")
    raise ConfigError(_file_line(spec, spectrum, i, None, base_dir) + message, key=key)


def _check_kirchhoff(key: str, rho: Spectrum, eps: Spectrum, tau: Spectrum) -> None:
    """Refuse reflectance and emissivity that do not satisfy ρ + ε + τ = 1."""
    total = linear_combination([(1.0, rho), (1.0, eps), (1.0, tau)], name=f"{key}.rho+eps+tau")
    if total.is_constant:
        wl = np.array([_CONSTANT_CHECK_WAVELENGTH])
    else:
        wl = total.wavelength
    residual = total(wl) - 1.0
    bad = np.abs(residual) > KIRCHHOFF_TOLERANCE
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ConfigError(
            f"reflectance + emissivity + transmittance = {residual[i] + 1.0:.6g} at "
            f"{wl[i]:g} µm; Kirchhoff's law needs 1 (to {KIRCHHOFF_TOLERANCE:g}). Give only one "
            "of reflectance and emissivity, or consistent ones",
            key=key,
        )
