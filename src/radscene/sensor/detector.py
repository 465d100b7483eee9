"""Detectors: photon detectors (CCD, CMOS, cooled IR) and microbolometers.

Both follow Willers et al. (2011) eq. 6, per detector element (i, j):

.. math:: I_{ij} = \\Phi_{ij}\\, \\mathcal{R}\\, \\Delta\\mathcal{R}_{ij} + I_{leak,ij}

with Φ the flux on the detector (eq. 7), R the responsivity, ΔR = 1 + PRNU·z the per-element
gain non-uniformity and I_leak the leakage (dark current with its DSNU for photon detectors;
the bias offset and its non-uniformity for bolometers). A photon detector integrates
I t / q electrons with shot noise, clipped at the full well; a bolometer's output is a voltage
with Johnson and thermal-fluctuation noise.

Photon detector (``type: photon``; aliases ``ccd``, ``cmos``, ``cooled_ir``):

==========================  ======  ========  ================================================
key                         unit    default   meaning
==========================  ======  ========  ================================================
pitch                       m       required  detector pitch (square)
fill_factor                 -       1         active area / pitch²
quantum_efficiency          -       (1 of 2)  spectrum or number, electrons per photon
responsivity                A/W     (1 of 2)  spectrum or number, instead of the QE
integration_time            s       required  integration (exposure) time
temperature                 K       required  detector temperature
dark_current                A       0         dark current at ``dark_reference_temperature``
dark_reference_temperature  K       T         temperature of ``dark_current``
activation_energy           eV      0.6       E_a of the dark current (Si ≈ Eg/2; InSb ≈ Eg)
temperature_exponent        -       1.5       p in I ∝ T^p exp(-E_a / kT) (Si 1.5, IR 3)
full_well                   e-      inf       well capacity
read_noise                  e-      0         rms white readout noise
flicker_corner              Hz      0         1/f corner of the readout chain
prnu                        -       0         rms relative gain non-uniformity
dsnu                        -       0         rms relative dark-current non-uniformity
cold_shield_f_number        -       none      cold-shield aperture; none: the mounting fills
                                              the hemisphere outside the beam
shot_noise                  -       auto      ``auto`` (Poisson below 1000 e-, Gaussian above),
                                              ``poisson`` or ``gaussian``
shape                       -       none      [rows, columns] of the array, checked on use
==========================  ======  ========  ================================================

Microbolometer (``type: microbolometer``): pitch, fill_factor, integration_time (noise
bandwidth 1 / (2 t)), temperature (substrate, K), ``absorptance`` (spectrum, default 0.8),
``tcr`` [K-1] (default -0.02), ``resistance`` [ohm] (1e5), ``bias_current`` [A] (1e-5),
``thermal_conductance`` [W/K] (1e-7), ``read_noise`` [V] (0), ``flicker_corner`` [Hz],
``prnu``, ``offset_nonuniformity`` [V rms] (0), ``shape``. Its voltage responsivity is
R_v = |α| I_b R / G (steady state; self-heating and the thermal time constant are not
modelled) and its output is referred to a blackbody enclosure at the substrate temperature:
the flux it would absorb from one is subtracted (the net radiative exchange).

References
----------
J. R. Janesick, *Scientific Charge-Coupled Devices*, SPIE Press PM83 (2001), §7.2 (dark
current), https://doi.org/10.1117/3.374903
P. W. Kruse, *Uncooled Thermal Imaging: Arrays, Systems and Applications*, SPIE Press TT51
(2001), ch. 2 (bolometer responsivity and noise), https://doi.org/10.1117/3.415351
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from scipy import constants as sc

from radscene.errors import ConfigError
from radscene.materials.spectrum import Spectrum
from radscene.sensor import _parse as P
from radscene.sensor.noise import SHOT_NOISE_METHODS, shot_noise

__all__ = [
    "dark_current",
    "photon_responsivity",
    "detector_current",
    "bolometer_responsivity",
    "johnson_noise",
    "thermal_fluctuation_noise",
    "PhotonDetector",
    "Microbolometer",
]


def dark_current(temperature, reference_current, reference_temperature, activation_energy,
                 temperature_exponent=1.5):
    r"""Dark current against detector temperature.

    Parameters
    ----------
    temperature : array_like
        Detector temperature [K], > 0.
    reference_current : array_like
        Dark current at `reference_temperature` [A].
    reference_temperature : array_like
        [K], > 0.
    activation_energy : array_like
        E_a [eV].
    temperature_exponent : array_like, optional
        p [-].

    Returns
    -------
    numpy.ndarray
        .. math:: I_d(T) = I_{ref} \left(\frac{T}{T_{ref}}\right)^p
                  \exp\left[-\frac{E_a}{k}\left(\frac{1}{T} - \frac{1}{T_{ref}}\right)\right]

        [A] (Janesick 2001, eq. 7.1: p = 1.5, E_a = E_g / 2 for silicon depletion current).

    Examples
    --------
    >>> round(float(dark_current(300.0, 1.0, 293.0, 0.6)), 3)   # ~doubles every 7 K
    1.804
    """
    t = np.asarray(temperature, dtype=float)
    t0 = np.asarray(reference_temperature, dtype=float)
    if np.any(~(t > 0)) or np.any(~(t0 > 0)):
        raise ConfigError("temperatures must be > 0 K", key="temperature")
    ea = np.asarray(activation_energy, dtype=float) * sc.e / sc.k  # [K]
    return (np.asarray(reference_current, dtype=float) * (t / t0) ** temperature_exponent
            * np.exp(-ea * (1.0 / t - 1.0 / t0)))


def photon_responsivity(wavelength, quantum_efficiency):
    r"""Current responsivity of a photon detector, :math:`\mathcal{R} = \eta q \lambda / (h c)`.

    Parameters
    ----------
    wavelength : array_like
        [um].
    quantum_efficiency : array_like
        η, electrons per incident photon [-].

    Returns
    -------
    numpy.ndarray
        [A W-1].

    Examples
    --------
    >>> round(float(photon_responsivity(1.0, 1.0)), 6)
    0.806554
    """
    lam = np.asarray(wavelength, dtype=float) * 1e-6
    return np.asarray(quantum_efficiency, dtype=float) * sc.e * lam / (sc.h * sc.c)


def detector_current(flux, responsivity, gain_nonuniformity=1.0, leakage=0.0):
    r"""Detector current by Willers et al. (2011) eq. 6.

    Parameters
    ----------
    flux : array_like
        Φ on the detector [W].
    responsivity : array_like
        R [A W-1] (or [V W-1] for a bolometer, giving volts).
    gain_nonuniformity : array_like, optional
        ΔR [-].
    leakage : array_like, optional
        I_leak [A] (or [V]).

    Returns
    -------
    numpy.ndarray
        :math:`I = \Phi \mathcal{R} \Delta\mathcal{R} + I_{leak}` [A] (or [V]).
    """
    return (np.asarray(flux, dtype=float) * np.asarray(responsivity, dtype=float)
            * np.asarray(gain_nonuniformity, dtype=float) + np.asarray(leakage, dtype=float))


def bolometer_responsivity(tcr, bias_current, resistance, thermal_conductance):
    r"""Steady-state voltage responsivity of a bolometer per absorbed watt.

    Returns
    -------
    numpy.ndarray
        :math:`R_v = |\alpha| I_b R / G` [V W-1] (Kruse 2001, eq. 2.13 at zero frequency).

    Examples
    --------
    >>> float(bolometer_responsivity(-0.02, 1e-5, 1e5, 1e-7))
    200000.0
    """
    return (np.abs(np.asarray(tcr, dtype=float)) * np.asarray(bias_current, dtype=float)
            * np.asarray(resistance, dtype=float) / np.asarray(thermal_conductance, dtype=float))


def johnson_noise(temperature, resistance, bandwidth):
    r"""Johnson (thermal) noise voltage, :math:`\sqrt{4 k T R \Delta f}` [V].

    Examples
    --------
    >>> round(float(johnson_noise(300.0, 1e5, 50.0)) * 1e6, 4)   # uV
    0.2878
    """
    return np.sqrt(4.0 * sc.k * np.asarray(temperature, dtype=float)
                   * np.asarray(resistance, dtype=float) * np.asarray(bandwidth, dtype=float))


def thermal_fluctuation_noise(temperature, thermal_conductance, bandwidth):
    r"""Temperature-fluctuation noise power of a thermal detector, :math:`\sqrt{4 k T^2 G \Delta f}` [W]."""
    t = np.asarray(temperature, dtype=float)
    return np.sqrt(4.0 * sc.k * t * t * np.asarray(thermal_conductance, dtype=float)
                   * np.asarray(bandwidth, dtype=float))


def _shape(cfg, key):
    value = cfg.get("shape")
    if value is None:
        return None
    ok = (isinstance(value, list | tuple) and len(value) == 2
          and all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in value))
    if not ok:
        raise ConfigError(f"must be two positive integers [rows, columns]; got {value!r}",
                          key=P.join(key, "shape"))
    return (int(value[0]), int(value[1]))


@dataclass(frozen=True)
class _Common:
    pitch: float
    fill_factor: float
    integration_time: float
    temperature: float
    read_noise: float
    flicker_corner: float
    prnu: float
    shape: tuple[int, int] | None

    @property
    def active_area(self) -> float:
        """Active area pitch² × fill factor [m2]."""
        return self.pitch**2 * self.fill_factor

    @property
    def active_width(self) -> float:
        """Side of the (square) active area, pitch √(fill factor) [m]."""
        return self.pitch * math.sqrt(self.fill_factor)

    def gain_map(self, shape, rng: np.random.Generator) -> np.ndarray:
        """ΔR = 1 + prnu z per element [-] (float32)."""
        z = rng.standard_normal(shape, dtype=np.float32)
        z *= np.float32(self.prnu)
        z += np.float32(1.0)
        return z


def _common(cfg, key):
    return dict(
        pitch=P.quantity(cfg, "pitch", "length", key, low=0.0, low_open=True),
        fill_factor=P.quantity(cfg, "fill_factor", "dimensionless", key, 1.0, low=0.0,
                               high=1.0, low_open=True),
        integration_time=P.quantity(cfg, "integration_time", "time", key, low=0.0, low_open=True),
        read_noise=0.0,
        flicker_corner=P.quantity(cfg, "flicker_corner", "frequency", key, 0.0, low=0.0),
        prnu=P.quantity(cfg, "prnu", "dimensionless", key, 0.0, low=0.0, high=0.5),
        shape=_shape(cfg, key),
    )


@dataclass(frozen=True)
class PhotonDetector(_Common):
    """A photon (quantum) detector: CCD, CMOS or cooled IR (see the module docstring)."""

    quantum_efficiency: Spectrum | None = None
    responsivity: Spectrum | None = None
    dark_current: float = 0.0
    dark_reference_temperature: float | None = None
    activation_energy: float = 0.6
    temperature_exponent: float = 1.5
    full_well: float = math.inf
    dsnu: float = 0.0
    cold_shield_f_number: float | None = None
    shot_noise: str = "auto"

    kind = "photon"
    signal_unit = "e-"
    rate_unit = "A"

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "detector") -> PhotonDetector:
        P.check_keys(cfg, ("type", "pitch", "fill_factor", "quantum_efficiency", "responsivity",
                           "integration_time", "temperature", "dark_current",
                           "dark_reference_temperature", "activation_energy",
                           "temperature_exponent", "full_well", "read_noise", "flicker_corner",
                           "prnu", "dsnu", "cold_shield_f_number", "shot_noise", "shape"), key)
        qe = P.spectrum(cfg, "quantum_efficiency", key, None, low=0.0, high=1.0)
        resp = P.spectrum(cfg, "responsivity", key, None, low=0.0)
        if (qe is None) == (resp is None):
            raise ConfigError("give exactly one of quantum_efficiency [-] and responsivity [A/W]",
                              key=P.join(key, "quantum_efficiency"))
        method = str(cfg.get("shot_noise", "auto")).lower()
        if method not in SHOT_NOISE_METHODS:
            raise ConfigError(f"unknown method {cfg['shot_noise']!r}; known: "
                              f"{', '.join(SHOT_NOISE_METHODS)}", key=P.join(key, "shot_noise"))
        common = _common(cfg, key)
        common["read_noise"] = P.quantity(cfg, "read_noise", "electrons", key, 0.0, low=0.0)
        return cls(
            **common,
            temperature=P.quantity(cfg, "temperature", "temperature", key, low=0.0, low_open=True),
            quantum_efficiency=qe,
            responsivity=resp,
            dark_current=P.quantity(cfg, "dark_current", "current", key, 0.0, low=0.0),
            dark_reference_temperature=P.quantity(cfg, "dark_reference_temperature",
                                                  "temperature", key, None, low=0.0, low_open=True),
            activation_energy=P.quantity(cfg, "activation_energy", "energy", key, 0.6, low=0.0),
            temperature_exponent=P.quantity(cfg, "temperature_exponent", "dimensionless", key, 1.5),
            full_well=P.quantity(cfg, "full_well", "electrons", key, math.inf, low=0.0, low_open=True),
            dsnu=P.quantity(cfg, "dsnu", "dimensionless", key, 0.0, low=0.0, high=1.0),
            cold_shield_f_number=P.quantity(cfg, "cold_shield_f_number", "dimensionless", key,
                                            None, low=0.5, low_open=True),
            shot_noise=method,
        )

    def spectral_responsivity(self, wavelength) -> np.ndarray:
        """R(λ) [A W-1] at `wavelength` [um]."""
        if self.responsivity is not None:
            return self.responsivity(wavelength)
        return photon_responsivity(wavelength, self.quantum_efficiency(wavelength))

    def spectra(self) -> list[Spectrum]:
        """The spectral tables of the detector (for quadrature breakpoints)."""
        return [s for s in (self.quantum_efficiency, self.responsivity) if s is not None]

    def leakage(self, band_integral=None) -> float:
        """Mean leakage: the dark current at the detector temperature [A]."""
        t_ref = self.dark_reference_temperature or self.temperature
        return float(dark_current(self.temperature, self.dark_current, t_ref,
                                  self.activation_energy, self.temperature_exponent))

    def offset_map(self, shape, rng: np.random.Generator) -> np.ndarray:
        """Per-element leakage deviation, I_dark dsnu z [A] (DSNU; float32)."""
        z = rng.standard_normal(shape, dtype=np.float32)
        z *= np.float32(self.leakage() * self.dsnu)
        return z

    def to_signal(self, rate):
        """Integrated signal of a current: I t / q [e-]."""
        return np.asarray(rate) * (self.integration_time / sc.e)

    def white_variance(self) -> float:
        """Variance of the white readout noise [e-²]."""
        return self.read_noise**2

    def integrate(self, mean, skim, pedestal, frames, rng, average: int = 1):
        """Integrate `frames` frames: shot noise on the total, skim subtracted, well clipped.

        Parameters
        ----------
        mean : numpy.ndarray
            Expected electrons of the total current per integration [e-], (y, x).
        skim, pedestal : array_like
            Electrons removed by DCS, and added back as a pedestal [e-].
        frames : int
            Frames to return.
        rng : numpy.random.Generator
        average : int
            Each returned frame is the mean of this many frames, drawn in distribution (the
            sum of n Poisson counts is Poisson of n times the mean); the well is clipped on
            the mean.

        Returns
        -------
        signal : numpy.ndarray
            float32 (frames, y, x) [e-], in [0, full_well].
        saturated : numpy.ndarray
            bool (frames, y, x): the well is full.
        """
        total = np.maximum(np.broadcast_to(mean, (frames,) + np.shape(mean)), 0.0)
        if average > 1:
            counts = shot_noise(total * average, rng, self.shot_noise)
            counts *= np.float32(1.0 / average)
        else:
            counts = shot_noise(total, rng, self.shot_noise)
        shift = np.asarray(pedestal, dtype=np.float32) - np.asarray(skim, dtype=np.float32)
        if np.any(shift != 0):
            counts += shift
        saturated = counts >= self.full_well
        np.clip(counts, 0.0, self.full_well, out=counts)
        return counts, saturated

    def clip(self, signal):
        """Clip a signal to the well, in place: (signal in [0, full_well] [e-], saturated)."""
        saturated = signal >= self.full_well
        np.clip(signal, 0.0, self.full_well, out=signal)
        return signal, saturated

    def shot_variance(self, mean):
        """Shot-noise variance of the total signal [e-²]."""
        return np.maximum(np.asarray(mean, dtype=float), 0.0)


@dataclass(frozen=True)
class Microbolometer(_Common):
    """An uncooled resistive microbolometer (see the module docstring)."""

    absorptance: Spectrum = Spectrum.constant(0.8, name="detector.absorptance")
    tcr: float = -0.02
    resistance: float = 1e5
    bias_current: float = 1e-5
    thermal_conductance: float = 1e-7
    offset_nonuniformity: float = 0.0

    kind = "microbolometer"
    signal_unit = "V"
    rate_unit = "V"
    cold_shield_f_number = None
    full_well = math.inf

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "detector") -> Microbolometer:
        P.check_keys(cfg, ("type", "pitch", "fill_factor", "absorptance", "integration_time",
                           "temperature", "tcr", "resistance", "bias_current",
                           "thermal_conductance", "read_noise", "flicker_corner", "prnu",
                           "offset_nonuniformity", "shape"), key)
        common = _common(cfg, key)
        common["read_noise"] = P.quantity(cfg, "read_noise", "voltage", key, 0.0, low=0.0)
        tcr = P.quantity(cfg, "tcr", "temperature_coefficient", key, -0.02)
        if tcr == 0:
            raise ConfigError("must be non-zero", key=P.join(key, "tcr"))
        return cls(
            **common,
            temperature=P.quantity(cfg, "temperature", "temperature", key, 300.0, low=0.0,
                                   low_open=True),
            absorptance=P.spectrum(cfg, "absorptance", key, 0.8, low=0.0, high=1.0),
            tcr=tcr,
            resistance=P.quantity(cfg, "resistance", "resistance", key, 1e5, low=0.0, low_open=True),
            bias_current=P.quantity(cfg, "bias_current", "current", key, 1e-5, low=0.0,
                                    low_open=True),
            thermal_conductance=P.quantity(cfg, "thermal_conductance", "thermal_conductance", key,
                                           1e-7, low=0.0, low_open=True),
            offset_nonuniformity=P.quantity(cfg, "offset_nonuniformity", "voltage", key, 0.0,
                                            low=0.0),
        )

    @property
    def voltage_responsivity(self) -> float:
        """R_v per absorbed watt [V W-1]."""
        return float(bolometer_responsivity(self.tcr, self.bias_current, self.resistance,
                                            self.thermal_conductance))

    @property
    def bandwidth(self) -> float:
        """Noise bandwidth 1 / (2 t_int) [Hz]."""
        return 0.5 / self.integration_time

    def spectral_responsivity(self, wavelength) -> np.ndarray:
        """R(λ) = absorptance(λ) R_v [V W-1] at `wavelength` [um]."""
        return self.absorptance(wavelength) * self.voltage_responsivity

    def spectra(self) -> list[Spectrum]:
        return [self.absorptance]

    def leakage(self, band_integral=None) -> float:
        """Output referred to an enclosure at the substrate temperature: -R_v A π ∫S α B dλ [V].

        Parameters
        ----------
        band_integral : callable
            ``band_integral(f)`` -> ∫ S(λ) f(λ) dλ over the band for ``f(wavelength [um])``.
        """
        if band_integral is None:
            return 0.0
        from radscene.radiometry.planck import spectral_radiance

        absorbed = band_integral(lambda wl: self.spectral_responsivity(wl)
                                 * spectral_radiance(wl, self.temperature))
        return -float(self.active_area * np.pi * absorbed)

    def offset_map(self, shape, rng: np.random.Generator) -> np.ndarray:
        """Per-element offset, offset_nonuniformity z [V] (float32)."""
        z = rng.standard_normal(shape, dtype=np.float32)
        z *= np.float32(self.offset_nonuniformity)
        return z

    def to_signal(self, rate):
        """A bolometer's 'rate' is already its output voltage [V]."""
        return np.asarray(rate)

    def white_variance(self) -> float:
        """Johnson + thermal-fluctuation + readout noise variance [V²]."""
        bw = self.bandwidth
        vj = johnson_noise(self.temperature, self.resistance, bw)
        vt = thermal_fluctuation_noise(self.temperature, self.thermal_conductance, bw) \
            * self.voltage_responsivity
        return float(vj**2 + vt**2 + self.read_noise**2)

    def integrate(self, mean, skim, pedestal, frames, rng, average: int = 1):
        """Output voltage of `frames` frames, before the white and 1/f noise (added by the chain)."""
        out = np.broadcast_to(np.asarray(mean, dtype=np.float32) - np.asarray(skim, dtype=np.float32)
                              + np.float32(pedestal), (frames,) + np.shape(mean)).copy()
        return out, np.zeros(out.shape, dtype=bool)

    def clip(self, signal):
        """A bolometer has no well: (signal [V], no saturation)."""
        return signal, np.zeros(np.shape(signal), dtype=bool)

    def shot_variance(self, mean):
        """No shot noise term (photon noise is far below the thermal noise) [V²]."""
        return np.zeros(np.shape(mean))
