"""Optics of a sensor: aperture, focal length, f-number, obscuration, transmittance, the
aberration OTF, and the radiometry of the flux they deliver to a detector (Willers et al.
2011, eq. 7).

Radiometric geometry (aplanatic optics, image-space numerical aperture 1 / (2N)): a detector
of active area A sees the exit pupil under the projected solid angle Ω = π / (4 N²), so the
flux from a scene of radiance L is

.. math:: \\Phi_{scene} = L\\, \\tau_{dome}\\, \\tau_{optics}\\, A\\, \\frac{\\pi (1 - \\epsilon^2)}{4 N^2}

with ε the linear central obscuration ratio. The same cone carries the self-emission of the
optics (emissivity 1 - τ), of the obscuration (a blackbody at the optics temperature), of the
dome and of the heated air in front of it; the rest of the detector's field (up to the cold
shield, or the hemisphere without one) sees the optics mounting.

========================  ======  ==========  ==============================================
key                       unit    default     meaning
========================  ======  ==========  ==============================================
focal_length              m       (2 of 3)    effective focal length
f_number                  -       (2 of 3)    working f-number N = f / D, > 0.5
aperture_diameter         m       (2 of 3)    entrance pupil diameter D
obscuration               -       0           linear central obscuration ratio, [0, 1)
transmittance             -       1           spectrum or number, in [0, 1]
emissivity                -       1 - τ       spectrum or number, in [0, 1]
temperature               K       293.15      optics temperature
wavefront_error           um      0           rms wavefront error (a length)
defocus                   um      0           defocus W020 at the pupil edge (a length)
relative_illumination     -       none        ``none`` or ``cos4`` (cos⁴ of the field angle)
mounting.temperature      K       optics T    housing / mounting seen outside the beam
mounting.emissivity       -       1
dome.transmittance        -       (no dome)   dome (window) in front of the optics
dome.emissivity           -       1 - τ
dome.temperature          K       293.15
heated_air.emissivity     -       (none)      compressed heated air in front of the dome
heated_air.temperature    K       293.15
========================  ======  ==========  ==============================================

Config snippet::

    optics: {focal_length: 100 mm, f_number: 2.5, transmittance: 0.8, temperature: 300 K,
             wavefront_error: 0.25 um, dome: {transmittance: 0.9, temperature: 320 K}}

References
----------
C. J. Willers, M. S. Willers and F. Lapierre, "Signature modelling and radiometric rendering
equations in infrared scene simulation systems", Proc. SPIE 8187, 81870R (2011),
https://doi.org/10.1117/12.903352
C. J. Willers, *Electro-Optical System Analysis and Design: A Radiometry Perspective*, SPIE
Press PM236 (2013), https://doi.org/10.1117/3.1001964
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.materials.spectrum import Spectrum
from radscene.sensor import _parse as P
from radscene.sensor.otf import defocus_otf, diffraction_otf, wavefront_error_otf

__all__ = [
    "projected_solid_angle",
    "detector_etendue",
    "relative_illumination",
    "Optics",
    "Dome",
    "HeatedAir",
    "RELATIVE_ILLUMINATION",
]

#: Accepted values of ``relative_illumination``.
RELATIVE_ILLUMINATION = ("none", "cos4")


def projected_solid_angle(f_number):
    r"""Projected solid angle of the cone from a detector to an aplanatic exit pupil.

    Parameters
    ----------
    f_number : array_like
        Working f-number N [-], > 0.5.

    Returns
    -------
    numpy.ndarray
        :math:`\Omega = \pi \sin^2\theta = \pi / (4 N^2)` [sr].

    Examples
    --------
    >>> round(float(projected_solid_angle(1.0)), 6)
    0.785398
    """
    n = np.asarray(f_number, dtype=float)
    if np.any(~(n > 0.5)):
        raise ConfigError(f"must be > 0.5 (numerical aperture 1/(2N) <= 1); got {f_number!r}",
                          key="f_number")
    return np.pi / (4.0 * n * n)


def detector_etendue(area, f_number, obscuration=0.0):
    r"""Etendue of one detector through an (annular) aperture.

    Parameters
    ----------
    area : array_like
        Active detector area [m2].
    f_number : array_like
        Working f-number [-], > 0.5.
    obscuration : array_like, optional
        Linear central obscuration ratio ε [-].

    Returns
    -------
    numpy.ndarray
        :math:`G = A \pi (1 - \epsilon^2) / (4 N^2)` [m2 sr]; flux = G τ L.
    """
    eta = np.asarray(obscuration, dtype=float)
    return np.asarray(area, dtype=float) * projected_solid_angle(f_number) * (1.0 - eta * eta)


def relative_illumination(field_angle, law: str = "cos4"):
    """Relative irradiance in the focal plane against the field angle.

    Parameters
    ----------
    field_angle : array_like
        Angle between the chief ray and the optical axis [deg].
    law : {"none", "cos4"}
        ``cos4``: the cosine-fourth law; ``none``: 1 everywhere.

    Returns
    -------
    numpy.ndarray
        Factor [-] multiplying the on-axis irradiance.

    Examples
    --------
    >>> round(float(relative_illumination(60.0)), 6)
    0.0625
    """
    angle = np.asarray(field_angle, dtype=float)
    if law == "none":
        return np.ones_like(angle)
    if law == "cos4":
        return np.cos(np.radians(angle)) ** 4
    raise ConfigError(f"unknown law {law!r}; known: {', '.join(RELATIVE_ILLUMINATION)}"
                      f"{did_you_mean(law, RELATIVE_ILLUMINATION)}",
                      key="relative_illumination")


@dataclass(frozen=True)
class Dome:
    """A window or dome in front of the optics: transmittance, emissivity, temperature [K]."""

    transmittance: Spectrum
    emissivity: Spectrum
    temperature: float

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "optics.dome") -> Dome:
        P.check_keys(cfg, ("transmittance", "emissivity", "temperature"), key)
        tau = P.spectrum(cfg, "transmittance", key, low=0.0, high=1.0)
        eps = P.spectrum(cfg, "emissivity", key, None, low=0.0, high=1.0)
        return cls(tau, eps if eps is not None else (1.0 - tau).with_name(P.join(key, "emissivity")),
                   P.quantity(cfg, "temperature", "temperature", key, 293.15))


@dataclass(frozen=True)
class HeatedAir:
    """Heated, compressed air in front of the dome: a grey or spectral emitter."""

    emissivity: Spectrum
    temperature: float

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "optics.heated_air") -> HeatedAir:
        P.check_keys(cfg, ("emissivity", "temperature"), key)
        return cls(P.spectrum(cfg, "emissivity", key, low=0.0, high=1.0),
                   P.quantity(cfg, "temperature", "temperature", key, 293.15))


@dataclass(frozen=True)
class Optics:
    """Imaging optics of a sensor (see the module docstring for the parameters)."""

    focal_length: float
    f_number: float
    obscuration: float = 0.0
    transmittance: Spectrum = Spectrum.constant(1.0, name="optics.transmittance")
    emissivity: Spectrum | None = None
    temperature: float = 293.15
    wavefront_error: float = 0.0
    defocus: float = 0.0
    relative_illumination: str = "none"
    mounting_temperature: float | None = None
    mounting_emissivity: Spectrum = Spectrum.constant(1.0, name="optics.mounting.emissivity")
    dome: Dome | None = None
    heated_air: HeatedAir | None = None

    def __post_init__(self):
        if not self.f_number > 0.5:
            raise ConfigError(f"must be > 0.5 (numerical aperture 1/(2N) <= 1); got "
                              f"{self.f_number!r}", key="optics.f_number")
        if not self.focal_length > 0:
            raise ConfigError(f"must be > 0 m; got {self.focal_length!r}", key="optics.focal_length")
        if not 0.0 <= self.obscuration < 1.0:
            raise ConfigError(f"must lie in [0, 1); got {self.obscuration!r}",
                              key="optics.obscuration")
        if self.relative_illumination not in RELATIVE_ILLUMINATION:
            raise ConfigError(f"unknown value {self.relative_illumination!r}; known: "
                              f"{', '.join(RELATIVE_ILLUMINATION)}"
                              f"{did_you_mean(self.relative_illumination, RELATIVE_ILLUMINATION)}",
                              key="optics.relative_illumination")

    # -- configuration ---------------------------------------------------------------------
    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "optics") -> Optics:
        """Build from a config mapping (see the module docstring)."""
        P.check_keys(cfg, ("focal_length", "f_number", "aperture_diameter", "obscuration",
                           "transmittance", "emissivity", "temperature", "wavefront_error",
                           "defocus", "relative_illumination", "mounting", "dome", "heated_air"),
                     key)
        f = P.quantity(cfg, "focal_length", "length", key, None, low=0.0, low_open=True)
        n = P.quantity(cfg, "f_number", "dimensionless", key, None, low=0.0, low_open=True)
        d = P.quantity(cfg, "aperture_diameter", "length", key, None, low=0.0, low_open=True)
        given = [v is not None for v in (f, n, d)]
        if sum(given) < 2:
            raise ConfigError("give two of focal_length [m], f_number and aperture_diameter [m]",
                              key=P.join(key, "f_number"))
        if f is None:
            f = n * d
        elif n is None:
            n = f / d
        elif d is not None and abs(f / d - n) > 1e-6 * n:
            raise ConfigError(f"focal_length / aperture_diameter = {f / d:g} contradicts "
                              f"f_number = {n:g}; give two of the three", key=P.join(key, "f_number"))
        P.check_range(n, P.join(key, "f_number"), low=0.5, low_open=True)
        temperature = P.quantity(cfg, "temperature", "temperature", key, 293.15)
        mounting = cfg.get("mounting") or {}
        mkey = P.join(key, "mounting")
        P.check_keys(mounting, ("temperature", "emissivity"), mkey)
        return cls(
            focal_length=f,
            f_number=n,
            obscuration=P.quantity(cfg, "obscuration", "dimensionless", key, 0.0, low=0.0,
                                   high=1.0, high_open=True),
            transmittance=P.spectrum(cfg, "transmittance", key, 1.0, low=0.0, high=1.0),
            emissivity=P.spectrum(cfg, "emissivity", key, None, low=0.0, high=1.0),
            temperature=temperature,
            wavefront_error=P.quantity(cfg, "wavefront_error", "wavelength", key, 0.0, low=0.0),
            defocus=P.quantity(cfg, "defocus", "wavelength", key, 0.0),
            relative_illumination=str(cfg.get("relative_illumination", "none")),
            mounting_temperature=P.quantity(mounting, "temperature", "temperature", mkey, None),
            mounting_emissivity=P.spectrum(mounting, "emissivity", mkey, 1.0, low=0.0, high=1.0),
            dome=Dome.from_config(cfg["dome"], P.join(key, "dome")) if cfg.get("dome") else None,
            heated_air=(HeatedAir.from_config(cfg["heated_air"], P.join(key, "heated_air"))
                        if cfg.get("heated_air") else None),
        )

    # -- geometry --------------------------------------------------------------------------
    @property
    def aperture_diameter(self) -> float:
        """Entrance pupil diameter D = f / N [m]."""
        return self.focal_length / self.f_number

    @property
    def optics_emissivity(self) -> Spectrum:
        """Emissivity of the optics: the configured one, else 1 - τ [-]."""
        if self.emissivity is not None:
            return self.emissivity
        return (1.0 - self.transmittance).with_name("optics.emissivity")

    @property
    def mounting_temperature_k(self) -> float:
        """Mounting temperature [K] (the optics temperature unless configured)."""
        return self.temperature if self.mounting_temperature is None else self.mounting_temperature

    def scene_transmittance(self, wavelength) -> np.ndarray:
        """Dome × optics transmittance seen by the scene flux [-] at `wavelength` [um]."""
        tau = self.transmittance(wavelength)
        if self.dome is not None:
            tau = tau * self.dome.transmittance(wavelength)
        return tau

    def aberration_otf(self, frequency, wavelength) -> np.ndarray:
        """Diffraction × wavefront-error × defocus OTF, radial.

        Parameters
        ----------
        frequency : array_like
            Radial focal-plane frequency [cycles m-1].
        wavelength : array_like
            Wavelength [um], broadcast against `frequency`.

        Returns
        -------
        numpy.ndarray
            OTF [-].
        """
        nu = np.asarray(frequency, dtype=float) * 1e-6  # cycles per um
        h = diffraction_otf(nu, wavelength, self.f_number, self.obscuration)
        if self.wavefront_error:
            try:
                h = h * wavefront_error_otf(nu, wavelength, self.f_number, self.wavefront_error)
            except ConfigError as err:
                raise ConfigError(err.message, key="optics.wavefront_error") from None
        if self.defocus:
            h = h * defocus_otf(nu, wavelength, self.f_number, self.defocus)
        return h

    def polychromatic_otf(self, frequency, wavelength, weight) -> np.ndarray:
        """Spectrally weighted aberration OTF, Σ w_i H(ν, λ_i) / Σ w_i.

        Parameters
        ----------
        frequency : array_like
            1-D radial frequencies [cycles m-1].
        wavelength : array_like
            1-D wavelengths [um] (quadrature nodes of the band).
        weight : array_like
            Weights of the wavelengths (response × transmittance × responsivity) [any].

        Returns
        -------
        numpy.ndarray
            OTF [-], shape of `frequency`.
        """
        w = np.asarray(weight, dtype=float)
        if not np.sum(w) > 0:
            raise ConfigError("the system spectral response integrates to 0 over the band",
                              key="response")
        lam = np.asarray(wavelength, dtype=float)
        lam, w = _spectral_bins(lam, w, POLYCHROMATIC_BINS)
        nu = np.asarray(frequency, dtype=float)
        out = np.zeros(nu.shape)
        for s in range(0, lam.size, 16):  # bound the memory: frequency x wavelength
            h = self.aberration_otf(nu[:, None], lam[None, s : s + 16])
            out += h @ w[s : s + 16]
        return out / w.sum()


#: Wavelength bins of the polychromatic OTF: the quadrature nodes of a band are merged into
#: at most this many (weighted mean wavelength per bin; the OTF is smooth in wavelength).
POLYCHROMATIC_BINS = 48


def _spectral_bins(wavelength, weight, bins):
    if wavelength.size <= bins:
        return wavelength, weight
    edges = np.linspace(wavelength.min(), wavelength.max(), bins + 1)
    idx = np.clip(np.searchsorted(edges, wavelength, side="right") - 1, 0, bins - 1)
    total = np.bincount(idx, weights=weight, minlength=bins)
    first = np.bincount(idx, weights=weight * wavelength, minlength=bins)
    keep = total != 0
    return first[keep] / total[keep], total[keep]
