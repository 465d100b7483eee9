"""Analytic performance of a configured sensor: noise budget, SNR, NEΔT, system MTF.

For a uniform scene of band radiance L (or a blackbody at T) seen on the optical axis, in
signal units (electrons for photon detectors, volts for bolometers):

.. math::

    s = \\frac{t}{q} G \\int S \\tau R L\\, d\\lambda, \\qquad
    b = \\frac{t}{q}\\left(\\sum_k I_k + I_{leak}\\right)

    \\sigma^2_{temporal} = \\sigma^2_{shot}(s + b) + \\sigma^2_{white} + \\sigma^2_{1/f}
                          + g^2 / 12, \\qquad \\mathrm{SNR} = s / \\sigma_{temporal}

(for a bolometer t/q is dropped, the shot term is 0 and the white term holds Johnson,
thermal-fluctuation and readout noise). The fixed-pattern part, σ_FPN² = (PRNU (s + b))² +
(DSNU I_leak t/q)², is reported apart. NEΔT = σ_temporal / (∂s/∂T).

References
----------
G. C. Holst, *Electro-Optical Imaging System Performance*, 5th ed., JCD/SPIE (2008), ch. 12.
C. J. Willers, *Electro-Optical System Analysis and Design*, SPIE Press PM236 (2013), ch. 7.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.planck import radiance_temperature_derivative, spectral_radiance
from radscene.radiometry.srf import SpectralResponse
from radscene.sensor.channel import as_response
from radscene.sensor.noise import flicker_variance, quantization_variance

__all__ = ["NoiseBudget", "noise_budget", "netd", "system_mtf"]


@dataclass(frozen=True)
class NoiseBudget:
    """Analytic noise budget of a uniform scene (see the module docstring).

    Every field is an array of the shape of the scene input, in the signal unit ``unit``
    (``e-`` or ``V``); the ``*_rms`` fields are standard deviations.
    """

    unit: str
    signal: np.ndarray
    background: np.ndarray
    shot_rms: np.ndarray
    white_rms: float
    flicker_rms: float
    quantization_rms: float
    fixed_pattern_rms: np.ndarray
    temporal_rms: np.ndarray
    gain: float

    @property
    def snr(self) -> np.ndarray:
        """Signal over temporal noise [-]."""
        return self.signal / self.temporal_rms

    @property
    def total_rms(self) -> np.ndarray:
        """Temporal and fixed-pattern noise together [signal unit]."""
        return np.sqrt(self.temporal_rms**2 + self.fixed_pattern_rms**2)


def _setup(sensor, band, response):
    from radscene.sensor.config import make_sensor

    sensor = make_sensor(sensor)
    ch = sensor.channel(band) if band is not None else sensor.base
    resp = response if response is not None else ch.response
    if resp is None:
        raise ConfigError("give the band's spectral response (or set bands.<band>.response)",
                          key="response")
    resp = resp if isinstance(resp, SpectralResponse) else as_response(resp, band or "band")
    return sensor, ch, ch.radiometry(resp)


def noise_budget(sensor, band=None, *, radiance=None, temperature=None, response=None,
                 frames: int = 1, shape=None) -> NoiseBudget:
    """Analytic noise budget of a uniform scene.

    Parameters
    ----------
    sensor : Sensor or mapping
    band : str, optional
        Band name (selects its overrides); default the base channel.
    radiance : array_like, optional
        Scene band radiance ∫ S L dλ [W m-2 sr-1] (band-mean τ R, as the chain uses).
    temperature : array_like, optional
        Or a blackbody scene [K] (exact spectral integral). Exactly one of the two.
    response : SpectralResponse or mapping, optional
        The band's response; default ``bands.<band>.response``.
    frames : int
        Frames in the sequence (sets the 1/f variance).
    shape : tuple of int, optional
        Detector array (rows, columns) for the 1/f variance; default ``detector.shape``.

    Returns
    -------
    NoiseBudget
    """
    sensor, ch, rad = _setup(sensor, band, response)
    det = ch.detector
    if (radiance is None) == (temperature is None):
        raise ConfigError("give exactly one of radiance [W m-2 sr-1] and temperature [K]",
                          key="radiance")
    if radiance is not None:
        scene_rate = rad.scene_rate_factor * np.asarray(radiance, dtype=float)
    else:
        t = np.asarray(temperature, dtype=float)
        scene_rate = rad.scene_rate_of_spectrum(spectral_radiance(rad.nodes, t[..., None]))
    leakage = det.leakage(rad.band_integral)
    background_rate = rad.background_rate_total + leakage
    signal = det.to_signal(scene_rate)
    background = det.to_signal(np.full(np.shape(scene_rate), background_rate))
    total = signal + background
    shot = det.shot_variance(total)
    white = det.white_variance()
    flicker = 0.0
    if det.flicker_corner > 0 and white > 0:
        shape = shape or det.shape
        if shape is None:
            raise ConfigError("the 1/f variance needs the array shape (rows, columns)",
                              key="detector.shape")
        flicker = flicker_variance(frames * shape[0] * shape[1], ch.pixel_rate_period(shape),
                                   det.flicker_corner, np.sqrt(white))
    quant = float(quantization_variance(ch.electronics.gain))
    if det.kind == "photon":
        dsnu = det.to_signal(det.dsnu * leakage)
    else:
        dsnu = det.offset_nonuniformity
    fixed = np.sqrt((det.prnu * total) ** 2 + dsnu**2)
    temporal = np.sqrt(shot + white + flicker + quant)
    return NoiseBudget(unit=det.signal_unit, signal=np.asarray(signal), background=background,
                       shot_rms=np.sqrt(shot), white_rms=float(np.sqrt(white)),
                       flicker_rms=float(np.sqrt(flicker)), quantization_rms=float(np.sqrt(quant)),
                       fixed_pattern_rms=np.asarray(fixed), temporal_rms=np.asarray(temporal),
                       gain=ch.electronics.gain)


def netd(sensor, band=None, temperature=300.0, *, response=None, frames: int = 1,
         shape=None) -> np.ndarray:
    """Noise-equivalent temperature difference of a blackbody scene [K].

    Parameters
    ----------
    sensor : Sensor or mapping
    band : str, optional
    temperature : array_like
        Scene blackbody temperature [K].
    response, frames, shape
        As :func:`noise_budget`.

    Returns
    -------
    numpy.ndarray
        σ_temporal / (∂s/∂T) [K].
    """
    sensor, ch, rad = _setup(sensor, band, response)
    t = np.asarray(temperature, dtype=float)
    budget = noise_budget(sensor, band, temperature=t, response=response, frames=frames,
                          shape=shape)
    slope = ch.detector.to_signal(
        rad.scene_rate_of_spectrum(radiance_temperature_derivative(rad.nodes, t[..., None])))
    return budget.temporal_rms / slope


def system_mtf(sensor, frequency_x, frequency_y=0.0, band=None, *, response=None) -> np.ndarray:
    """Analytic system MTF (the modulus of the chain's OTF) on the detector grid.

    Parameters
    ----------
    sensor : Sensor or mapping
    frequency_x, frequency_y : array_like
        Spatial frequency along rows and columns [cycles pixel-1]: cycles per pixel of the
        sensor's output grid (:meth:`~radscene.sensor.Sensor.grid_pitch`; the band's detector
        pitch unless its IFOV differs from the base channel's).
    band : str, optional
    response : SpectralResponse, mapping or float, optional
        The band's response (polychromatic diffraction), or a wavelength [um].

    Returns
    -------
    numpy.ndarray
        |OTF| [-] (diffraction × wavefront error × defocus × jitter × smear × footprint).
    """
    from radscene.radiometry.srf import RectangularResponse

    if isinstance(response, int | float) and not isinstance(response, bool):
        lam = float(response)
        response = RectangularResponse(lam * (1 - 1e-9), lam * (1 + 1e-9))
    sensor, ch, rad = _setup(sensor, band, response)
    pitch = sensor.grid_pitch(band) if band is not None else ch.detector.pitch
    fx = np.asarray(frequency_x, dtype=float) / pitch
    fy = np.asarray(frequency_y, dtype=float) / pitch
    return np.abs(ch.otf(rad, fy, fx))
