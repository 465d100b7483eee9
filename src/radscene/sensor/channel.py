"""One band's sensor chain: at-aperture radiance → optics → detector → noise → ADC.

:class:`Channel` is the sensor as one band sees it (optics, detector, electronics, motion,
processing, response); :class:`radscene.sensor.Sensor` builds one per band from its
configuration and runs :meth:`Sensor.apply`. The physics lives in the modules called here:
:mod:`~radscene.sensor.otf`, :mod:`~radscene.sensor.sampling`, :mod:`~radscene.sensor.flux`,
:mod:`~radscene.sensor.detector`, :mod:`~radscene.sensor.noise`,
:mod:`~radscene.sensor.electronics`, :mod:`~radscene.sensor.processing`.

Per band and detector (i, j), frame f:

1. L_opt = (L ⊗ PSF)(i, j): the radiance filtered with the system OTF (diffraction ×
   wavefront error × defocus × jitter × smear × footprint) and sampled at the detector centre;
2. Φ = eq. 7 (scene through dome and optics, times the relative illumination, plus the
   self-emission of optics, mounting, dome and heated air);
3. I = Φ R ΔR + I_leak (eq. 6, with PRNU and DSNU maps fixed by ``fixed_pattern_seed``);
4. signal = shot-noise realisation of I t / q − DCS skim + pedestal, clipped at the full well
   (photon detectors), or the bolometer voltage; plus white readout (Johnson, thermal
   fluctuation) noise and 1/f noise along the readout stream;
5. DN = ADC(signal / gain + offset); then NUC and AGC when configured.
"""

from __future__ import annotations

import functools
import zlib
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.srf import RectangularResponse, SpectralResponse, make_response
from radscene.sensor.noise import (
    flicker_noise,
    flicker_variance,
    quantization_variance,
    white_noise,
)
from radscene.sensor.optics import relative_illumination
from radscene.sensor.otf import detector_otf, jitter_otf, smear_otf

__all__ = ["Motion", "Channel", "fixed_pattern_rng", "default_response", "as_response"]

#: Samples of the radial (aberration) OTF table between 0 and the grid's largest frequency.
RADIAL_TABLE_SIZE = 4096


@functools.lru_cache(maxsize=8)
def _illumination(shape, pitch, focal_length, law) -> np.ndarray:
    if law == "none":
        out = np.ones(shape, dtype=np.float32)
    else:
        ny, nx = shape
        y = (np.arange(ny) + 0.5 - 0.5 * ny) * pitch
        x = (np.arange(nx) + 0.5 - 0.5 * nx) * pitch
        angle = np.degrees(np.arctan(np.hypot(y[:, None], x[None, :]) / focal_length))
        out = relative_illumination(angle, law).astype(np.float32)
    out.flags.writeable = False
    return out


@dataclass(frozen=True)
class Motion:
    """Line-of-sight motion: rms jitter [deg] and smear during one integration [pitches].

    ``jitter`` and ``smear`` are (x, y) pairs: x along the rows (columns increasing), y along
    the columns (rows increasing).
    """

    jitter: tuple[float, float] = (0.0, 0.0)
    smear: tuple[float, float] = (0.0, 0.0)


@dataclass(frozen=True)
class Channel:
    """The sensor as one band sees it: optics, detector, electronics, motion, processing."""

    optics: object
    detector: object
    electronics: object
    motion: Motion
    processing: dict
    response: SpectralResponse | None = None
    scene_weighting: str | float = "auto"

    def radiometry(self, response, key: str = "response"):
        """:func:`radscene.sensor.flux.band_radiometry` of this channel for a band response."""
        from radscene.sensor.flux import band_radiometry

        return band_radiometry(self.optics, self.detector, response, key, self.scene_weighting)

    # -- geometry ------------------------------------------------------------------------
    def otf(self, radiometry, fy, fx) -> np.ndarray:
        """System OTF at focal-plane frequencies ``fy``, ``fx`` [cycles m-1] (broadcast)."""
        rho = np.hypot(fy, fx)
        h = self.optics.polychromatic_otf(np.ravel(rho), radiometry.nodes, radiometry.otf_weights)
        h = h.reshape(np.shape(rho))
        return h * self.geometric_otf(fy, fx)

    def geometric_otf(self, fy, fx) -> np.ndarray:
        """Jitter × smear × footprint OTF at ``fy``, ``fx`` [cycles m-1]."""
        det, opt = self.detector, self.optics
        sx, sy = (np.radians(j) * opt.focal_length for j in self.motion.jitter)
        h = detector_otf(fx, fy, det.active_width)
        if sx or sy:
            h = h * jitter_otf(fx, fy, sx, sy)
        dx, dy = (s * det.pitch for s in self.motion.smear)
        if dx or dy:
            h = h * smear_otf(fx, fy, dx, dy)
        return h

    def relative_illumination_map(self, shape, pitch=None) -> np.ndarray:
        """Relative illumination of each detector of a ``shape`` array [-] (float32, read-only);
        ``pitch`` [m] is the array's spacing in the focal plane (default the detector pitch)."""
        return _illumination(tuple(shape), self.detector.pitch if pitch is None else pitch,
                             self.optics.focal_length, self.optics.relative_illumination)


    # -- the per-detector chain ------------------------------------------------------------
    def mean_rate(self, radiometry, radiance_optics, illumination, gain_map, offset_map,
                  leakage) -> np.ndarray:
        """Eq. 6 without noise: (rate_scene + rate_background) ΔR + I_leak [A or V]."""
        rate = np.asarray(radiance_optics, dtype=np.float32) * np.float32(radiometry.scene_rate_factor)
        rate *= illumination
        rate += np.float32(radiometry.background_rate_total)
        rate *= gain_map
        rate += offset_map
        rate += np.float32(leakage)
        return rate

    def pixel_rate_period(self, shape) -> float:
        """Readout period of one pixel, 1 / (frame rate × pixels) [s]."""
        rate = self.electronics.frame_rate or 1.0 / self.detector.integration_time
        return 1.0 / (rate * shape[0] * shape[1])

    def expose(self, rate, skim, pedestal, frames, rng, average: int = 1):
        """Signal of `frames` frames with all temporal noise [e- or V], and the well saturation.

        With ``average > 1`` each frame is the mean of that many frames, drawn in distribution:
        shot, white and 1/f noise as one Gaussian of the variance of their mean (the
        calibration frames of DCS and NUC), the well clipped on the mean.
        """
        det = self.detector
        mean = det.to_signal(rate)
        white = det.white_variance()
        flicker = det.flicker_corner > 0 and white > 0
        if average > 1:
            var = det.shot_variance(mean) + white
            if flicker:
                var = var + flicker_variance(np.size(mean), self.pixel_rate_period(np.shape(mean)),
                                             det.flicker_corner, np.sqrt(white))
            sigma = np.sqrt(np.asarray(var, dtype=np.float32) / np.float32(average))
            signal = rng.standard_normal((frames,) + np.shape(mean), dtype=np.float32)
            signal *= sigma
            signal += mean
            signal += np.float32(pedestal) - np.asarray(skim, dtype=np.float32)
            return det.clip(signal)
        signal, saturated = det.integrate(mean, skim, pedestal, frames, rng)
        if white > 0:
            signal += white_noise(signal.shape, np.sqrt(white), rng)
        if flicker:
            stream = flicker_noise(signal.size, self.pixel_rate_period(signal.shape[1:]),
                                   det.flicker_corner, np.sqrt(white), rng)
            signal += stream.reshape(signal.shape)
        return signal, saturated

    def temporal_variance(self, mean_signal, frames, shape) -> np.ndarray:
        """Analytic temporal noise variance of one sample, quantisation included [signal²]."""
        det = self.detector
        white = det.white_variance()
        var = det.shot_variance(mean_signal) + white
        if det.flicker_corner > 0 and white > 0:
            var = var + flicker_variance(frames * shape[0] * shape[1],
                                         self.pixel_rate_period(shape), det.flicker_corner,
                                         np.sqrt(white))
        return var + quantization_variance(self.electronics.gain)


def default_response(ds, band) -> SpectralResponse:
    """Rectangular response of the band's centre and equivalent width from the coordinates."""
    try:
        center = float(ds["wavelength_center"].sel(band=band))
        width = float(ds["equivalent_width"].sel(band=band))
    except (KeyError, ValueError):
        raise ConfigError(
            f"band {band!r}: the radiance carries no wavelength_center / equivalent_width "
            "coordinates; give the band's spectral response", key=f"bands.{band}.response") from None
    if not width > 0:
        raise ConfigError(f"band {band!r}: equivalent width {width!r} µm is not positive",
                          key=f"bands.{band}.response")
    return RectangularResponse(center - 0.5 * width, center + 0.5 * width, name=str(band))


def as_response(value, band) -> SpectralResponse:
    """A band's spectral response from a response object or a type-tagged mapping.

    Accepted: a :class:`~radscene.radiometry.SpectralResponse`; a mapping of
    :func:`radscene.radiometry.make_response` (``rectangular``, ``gaussian``, ``tabulated``);
    or ``{type: library, sensor: <name or file>, band: <band>}``, a real sensor's band from
    the bundled SRF library (:func:`radscene.sensor.srf_library.library_response`; ``type``
    may be left out when ``sensor`` is given).

    Raises
    ------
    ConfigError
        Unknown type, parameters, library sensor or band; the key is
        ``bands.<band>.response...``.
    """
    if isinstance(value, SpectralResponse):
        return value
    key = f"bands.{band}.response"
    if isinstance(value, Mapping) and str(
            value.get("type", "library" if "sensor" in value else "")).lower() == "library":
        from radscene.sensor.srf_library import library_response

        return library_response(dict(value), key)
    try:
        return make_response(value)
    except ConfigError as err:
        message = err.message
        if message.startswith("unknown spectral response type") or "'type' key" in message:
            message += " (or library: {type: library, sensor: <name>, band: <band>})"
        raise ConfigError(message, key=f"{key}.{err.key or ''}".rstrip(".")) from None


def fixed_pattern_rng(seed: int, band: str) -> np.random.Generator:
    """The generator of a band's fixed-pattern maps: stable across runs and band order."""
    return np.random.default_rng([int(seed), zlib.crc32(str(band).encode())])

