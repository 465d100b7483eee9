"""Signal processing stages: DCS (background current subtraction), two-point NUC, AGC.

Each stage is optional, configured under ``processing:``, and leaves its own truth in the
signal Dataset. The order is fixed by where each acts: DCS in the analogue domain, before the
well and the ADC; NUC and AGC on the digital numbers.

======  ==================  ========  =======================================================
stage   key                 default   meaning
======  ==================  ========  =======================================================
dcs     shutter_temperature 293.15 K  a shutter in front of the detector block, filling the
                                      optical beam, at this temperature, is the background
                                      reference
dcs     frames              16        shutter frames averaged into the reference
dcs     pedestal            max/4     DN added back after the subtraction (keeps the signal
                                      above zero)
nuc     low, high           required  reference sources filling the aperture: a blackbody
                                      temperature [K], or ``{radiance: L}`` [W m-2 sr-1]
nuc     frames              16        frames averaged at each reference
agc     low_percentile      0.5       percentile mapped to output 0 [%]
agc     high_percentile     99.5      percentile mapped to the top output code [%]
agc     bits                8         output resolution
======  ==================  ========  =======================================================

The calibration frames (the shutter of DCS, the references of NUC) are averaged in
distribution: one frame whose shot noise is that of the mean of ``frames`` frames (exact for
Poisson counts) and whose white and 1/f noise are scaled by 1 / sqrt(frames).

Truth: ``dcs_background`` (band, y, x), the signal subtracted (net of the pedestal);
``nuc_gain``, ``nuc_offset`` (band, y, x), the coefficients estimated from the references
(``nuc_bad_pixel`` where the two references do not differ); ``agc_gain``, ``agc_offset``
(frame, band), the stretch applied.

Config snippet::

    processing:
      dcs: {shutter_temperature: 300 K, frames: 16}
      nuc: {low: 293 K, high: 323 K, frames: 16}
      agc: {low_percentile: 1, high_percentile: 99, bits: 8}

References
----------
C. J. Willers, M. S. Willers and F. Lapierre, Proc. SPIE 8187, 81870R (2011), §7.1 and Fig. 8.
D. L. Perry and E. L. Dereniak, "Linear theory of nonuniformity correction in infrared
staring sensors", Opt. Eng. 32, 1854-1859 (1993), https://doi.org/10.1117/12.145601
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.sensor import _parse as P

__all__ = [
    "two_point_nuc_coefficients",
    "apply_nuc",
    "agc_stretch",
    "DCS",
    "NUC",
    "AGC",
    "PROCESSING",
    "make_processing",
]


def two_point_nuc_coefficients(low, high):
    r"""Two-point non-uniformity correction from two uniform references.

    Parameters
    ----------
    low, high : array_like
        Mean frames of the low and high reference, shape (..., y, x) [DN].

    Returns
    -------
    gain : numpy.ndarray
        :math:`g_{ij} = (\bar H - \bar L) / (H_{ij} - L_{ij})` [-] (0 at bad pixels).
    offset : numpy.ndarray
        :math:`o_{ij} = \bar L - g_{ij} L_{ij}` [DN], so that the corrected frame is
        g × raw + o; the spatial means are taken over (y, x).
    bad : numpy.ndarray
        bool: H_ij <= L_ij (dead or saturated); those pixels are replaced by the mean level.

    Examples
    --------
    >>> g, o, bad = two_point_nuc_coefficients([[10.0, 20.0]], [[30.0, 60.0]])
    >>> (g * [[20.0, 40.0]] + o).tolist()   # a mid-level frame comes out flat
    [[30.0, 30.0]]
    """
    lo = np.asarray(low, dtype=float)
    hi = np.asarray(high, dtype=float)
    diff = hi - lo
    bad = ~(diff > 0)
    mean_lo = lo.mean(axis=(-2, -1), keepdims=True)
    mean_hi = hi.mean(axis=(-2, -1), keepdims=True)
    gain = np.where(bad, 0.0, (mean_hi - mean_lo) / np.where(bad, 1.0, diff))
    offset = mean_lo - gain * lo
    return gain, offset, bad


def apply_nuc(raw, gain, offset) -> np.ndarray:
    """Corrected frames gain × raw + offset [DN] (float32)."""
    return (np.asarray(raw, dtype=np.float32) * np.asarray(gain, dtype=np.float32)
            + np.asarray(offset, dtype=np.float32))


def agc_stretch(image, low_percentile=0.5, high_percentile=99.5, bits=8):
    """Linear automatic gain control of each frame between two percentiles.

    Parameters
    ----------
    image : array_like
        Frames, shape (..., y, x) [DN].
    low_percentile, high_percentile : float
        Percentiles [%] mapped to 0 and 2^bits - 1.
    bits : int
        Output resolution.

    Returns
    -------
    out : numpy.ndarray
        float32 integer codes in [0, 2^bits - 1], shape of `image`.
    gain : numpy.ndarray
        Output DN per input DN, shape (...) [-].
    offset : numpy.ndarray
        Input level mapped to 0, shape (...) [DN].
    """
    a = np.asarray(image, dtype=np.float32)
    top = float(2**bits - 1)
    flat = a.reshape(a.shape[:-2] + (-1,))
    lo, hi = np.percentile(flat, [low_percentile, high_percentile], axis=-1)
    span = np.where(hi > lo, hi - lo, 1.0)
    gain = top / span
    out = np.floor((a - lo[..., None, None]) * gain[..., None, None] + 0.5)
    np.clip(out, 0.0, top, out=out)
    return out.astype(np.float32), gain, lo


def _reference(cfg, name, key):
    path = P.join(key, name)
    value = cfg.get(name)
    if value is None:
        raise ConfigError("missing reference: a blackbody temperature [K] or {radiance: L}",
                          key=path)
    if isinstance(value, Mapping):
        P.check_keys(value, ("radiance",), path)
        return ("radiance", P.quantity(value, "radiance", "radiance", path, low=0.0))
    return ("temperature", P.quantity(cfg, name, "temperature", key, low=0.0, low_open=True))


@dataclass(frozen=True)
class DCS:
    """Background current subtraction with a shutter reference (see the module docstring)."""

    shutter_temperature: float = 293.15
    frames: int = 16
    pedestal: float | None = None

    name = "dcs"

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "processing.dcs") -> DCS:
        cfg = cfg or {}
        P.check_keys(cfg, ("shutter_temperature", "frames", "pedestal"), key)
        return cls(P.quantity(cfg, "shutter_temperature", "temperature", key, 293.15, low=0.0,
                              low_open=True),
                   P.integer(cfg, "frames", key, 16, low=1),
                   P.quantity(cfg, "pedestal", "dimensionless", key, None, low=0.0))


@dataclass(frozen=True)
class NUC:
    """Two-point non-uniformity correction (see the module docstring)."""

    low: tuple[str, float]
    high: tuple[str, float]
    frames: int = 16

    name = "nuc"

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "processing.nuc") -> NUC:
        P.check_keys(cfg, ("low", "high", "frames"), key)
        low = _reference(cfg, "low", key)
        high = _reference(cfg, "high", key)
        if low[0] == high[0] and not high[1] > low[1]:
            raise ConfigError(f"the high reference must exceed the low one ({low[1]:g})",
                              key=P.join(key, "high"))
        return cls(low, high, P.integer(cfg, "frames", key, 16, low=1))


@dataclass(frozen=True)
class AGC:
    """Percentile-based linear automatic gain control (see the module docstring)."""

    low_percentile: float = 0.5
    high_percentile: float = 99.5
    bits: int = 8

    name = "agc"

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "processing.agc") -> AGC:
        cfg = cfg or {}
        P.check_keys(cfg, ("low_percentile", "high_percentile", "bits"), key)
        lo = P.quantity(cfg, "low_percentile", "dimensionless", key, 0.5, low=0.0, high=100.0)
        hi = P.quantity(cfg, "high_percentile", "dimensionless", key, 99.5, low=0.0, high=100.0)
        if not hi > lo:
            raise ConfigError(f"must exceed low_percentile ({lo:g}); got {hi:g}",
                              key=P.join(key, "high_percentile"))
        return cls(lo, hi, P.integer(cfg, "bits", key, 8, low=1, high=32))

    def __call__(self, image):
        return agc_stretch(image, self.low_percentile, self.high_percentile, self.bits)


#: Registry of processing stages, in the order they act on the signal.
PROCESSING: dict[str, type] = {"dcs": DCS, "nuc": NUC, "agc": AGC}


def make_processing(cfg: Mapping | None, key: str = "processing") -> dict:
    """Build the enabled stages from ``{stage name: parameters}`` (a null stage is disabled).

    Returns
    -------
    dict
        ``{name: stage}`` in the order of :data:`PROCESSING`.
    """
    if cfg is None:
        return {}
    if not isinstance(cfg, Mapping):
        raise ConfigError(f"must be a mapping of stages ({', '.join(PROCESSING)}); got {cfg!r}",
                          key=key)
    stages = {}
    for name in cfg:
        if str(name).lower() not in PROCESSING:
            raise ConfigError(f"unknown processing stage {name!r}; known: {', '.join(PROCESSING)}"
                              f"{did_you_mean(name, PROCESSING)}",
                              key=P.join(key, str(name)))
    lowered = {str(k).lower(): v for k, v in cfg.items()}
    for name, cls in PROCESSING.items():
        if name in lowered and lowered[name] is not False:
            stages[name] = cls.from_config(lowered[name] or {}, P.join(key, name))
    return stages
