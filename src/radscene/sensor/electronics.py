"""Electronics: gain, offset, analogue-to-digital conversion with saturation.

==========  =============  =========  =========================================================
key         unit           default    meaning
==========  =============  =========  =========================================================
gain        e-/DN or V/DN  required   signal per digital number (photon-transfer convention:
                                      the slope of variance against mean in DN is 1 / gain)
offset      DN             0          digital offset added to every sample
bits        -              14         ADC resolution, 1 to 32
frame_rate  Hz             1 / t_int  frames per second (sets the pixel rate of the readout)
==========  =============  =========  =========================================================

Config snippet::

    electronics: {gain: 150, offset: 1000, bits: 14, frame_rate: 50 Hz}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError
from radscene.sensor import _parse as P

__all__ = ["digitize", "Electronics"]


def digitize(signal, gain, offset=0.0, bits: int = 14):
    r"""Analogue-to-digital conversion: round to the nearest DN and clip to the ADC range.

    Parameters
    ----------
    signal : array_like
        Detector signal [e-] or [V].
    gain : float
        Signal per DN [e- DN-1] or [V DN-1], > 0.
    offset : float, optional
        [DN].
    bits : int, optional
        ADC resolution.

    Returns
    -------
    dn : numpy.ndarray
        :math:`\mathrm{clip}(\lfloor s / g + o + 1/2 \rfloor, 0, 2^b - 1)` as uint16 (bits
        <= 16) or uint32 [DN].
    saturated : numpy.ndarray
        bool: the ADC clipped the sample (at either end).

    Examples
    --------
    >>> digitize([0.0, 149.0, 1e9], gain=100.0, offset=10.0, bits=8)[0]
    array([ 10,  11, 255], dtype=uint16)
    """
    if not gain > 0:
        raise ConfigError(f"must be > 0; got {gain!r}", key="electronics.gain")
    top = float(2**bits - 1)
    x = np.asarray(signal, dtype=np.float64) / gain + (offset + 0.5)
    np.floor(x, out=x)
    saturated = (x < 0.0) | (x > top)
    np.clip(x, 0.0, top, out=x)
    return x.astype(np.uint16 if bits <= 16 else np.uint32), saturated


@dataclass(frozen=True)
class Electronics:
    """Gain, offset and ADC of a sensor channel (see the module docstring)."""

    gain: float
    offset: float = 0.0
    bits: int = 14
    frame_rate: float | None = None

    def __post_init__(self):
        if not self.gain > 0:
            raise ConfigError(f"must be > 0; got {self.gain!r}", key="electronics.gain")
        if not 1 <= self.bits <= 32:
            raise ConfigError(f"must be an integer in [1, 32]; got {self.bits!r}",
                              key="electronics.bits")

    @classmethod
    def from_config(cls, cfg: Mapping, key: str = "electronics", signal_unit: str = "e-"):
        P.check_keys(cfg, ("gain", "offset", "bits", "frame_rate"), key)
        kind = "electrons" if signal_unit == "e-" else "voltage"
        return cls(
            gain=P.quantity(cfg, "gain", kind, key, low=0.0, low_open=True),
            offset=P.quantity(cfg, "offset", "dimensionless", key, 0.0),
            bits=P.integer(cfg, "bits", key, 14, low=1, high=32),
            frame_rate=P.quantity(cfg, "frame_rate", "frequency", key, None, low=0.0, low_open=True),
        )

    @property
    def max_dn(self) -> int:
        """Largest output code, 2^bits - 1 [DN]."""
        return 2**self.bits - 1

    def digitize(self, signal):
        """:func:`digitize` with this channel's gain, offset and bits."""
        return digitize(signal, self.gain, self.offset, self.bits)
