"""The channels of a hyperspectral grid: triangular responses that partition unity.

A grid of evenly spaced centres λ_0 < λ_1 < … < λ_N (step Δ) gets one channel per centre,
the piecewise-linear "hat" response

.. math::

    \\varphi_c(\\lambda) = \\max\\left(0,\\ 1 - \\frac{|\\lambda - \\lambda_c|}{\\Delta}\\right)
    \\quad \\text{on } [\\lambda_0, \\lambda_N],\\qquad 0 \\text{ outside,}

so the first and last channels are half triangles. The hats sum to 1 on [λ_0, λ_N]: a
channel's full width at half maximum and its equivalent width ∫φ_c dλ are both Δ (Δ/2 for
the two end channels). A channel's value is the response-weighted mean spectral radiance

.. math:: L_c = \\frac{\\int \\varphi_c L\\, d\\lambda}{\\int \\varphi_c\\, d\\lambda}
          \\quad [\\mathrm{W\\,m^{-2}\\,sr^{-1}\\,\\mu m^{-1}}]

and for any band response S that is linear between the grid's centres and zero outside
[λ_0, λ_N], S = Σ_c S(λ_c) φ_c, hence

.. math:: \\int S L\\, d\\lambda = \\sum_c S(\\lambda_c)\\, w_c\\, L_c, \\qquad
          w_c = \\int \\varphi_c\\, d\\lambda

exactly: the trapezoidal rule on the grid, applied to the channel values, gives the band
radiance (:meth:`ChannelGrid.band_weights`). For any other response the same sum integrates
S's linear interpolant on the grid instead of S.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.grids import wavelength_grid
from radscene.radiometry.srf import SpectralResponse, TabulatedResponse

__all__ = ["ChannelGrid", "channel_grid"]


@dataclass(frozen=True, eq=False)
class ChannelGrid:
    """Evenly spaced channel centres with triangular responses (see the module's notes).

    Attributes
    ----------
    wavelength : numpy.ndarray
        Channel centres [um], shape (n,), n >= 2, evenly spaced.
    step : float
        Spacing of the centres [um].
    """

    wavelength: np.ndarray
    step: float

    def __len__(self) -> int:
        return int(self.wavelength.size)

    @property
    def width(self) -> np.ndarray:
        """Equivalent width ∫φ_c dλ of each channel [um], shape (n,): Δ, Δ/2 at the ends.
        Equal to each channel's full width at half maximum."""
        w = np.full(self.wavelength.size, self.step)
        w[[0, -1]] = 0.5 * self.step
        return w

    @property
    def names(self) -> list[str]:
        """Channel names, ``"0.4000 um"`` style (enough digits to tell the centres apart)."""
        digits = max(0, -int(math.floor(math.log10(self.step)))) + 2
        return [f"{wl:.{digits}f} um" for wl in self.wavelength]

    def responses(self) -> list[TabulatedResponse]:
        """The channels' triangular responses φ_c, in grid order."""
        wl, names = self.wavelength, self.names
        out = []
        for c in range(wl.size):
            lo, hi = max(c - 1, 0), min(c + 1, wl.size - 1)
            knots = wl[lo:hi + 1]
            values = (knots == wl[c]).astype(float)
            out.append(TabulatedResponse(knots, values, name=names[c]))
        return out

    def band_weights(self, response: SpectralResponse) -> np.ndarray:
        """Weights [um] that turn channel values into the band radiance of ``response``.

        Parameters
        ----------
        response : radscene.radiometry.SpectralResponse
            A band's response S; its support must lie inside the grid.

        Returns
        -------
        numpy.ndarray
            ``S(λ_c) w_c`` [um], shape (n,): ``weights @ L_c`` is ∫ S L dλ [W m-2 sr-1] for
            channel values L_c [W m-2 sr-1 um-1] — exact when S is linear between the
            centres, else the integral of S's linear interpolant on the grid.

        Raises
        ------
        ConfigError
            If the response reaches outside the grid.

        Examples
        --------
        >>> grid = channel_grid(0.4, 0.7, 0.1)
        >>> grid.band_weights(TabulatedResponse([0.4, 0.5, 0.6], [0.0, 1.0, 0.0])).tolist()
        [0.0, 0.1, 0.0, 0.0]
        """
        lo, hi = response.support
        first, last = float(self.wavelength[0]), float(self.wavelength[-1])
        if lo < first - 1e-12 or hi > last + 1e-12:
            raise ConfigError(
                f"response {response.name!r} spans {lo:g}–{hi:g} µm, beyond the grid's "
                f"{first:g}–{last:g} µm", key="response")
        return np.asarray(response(self.wavelength), dtype=float) * self.width


def channel_grid(minimum, maximum, step, key: str = "spectral") -> ChannelGrid:
    """The channel grid from ``minimum`` to ``maximum`` at ``step``.

    Parameters
    ----------
    minimum, maximum : float
        First and last channel centres [um], 0 < minimum < maximum. ``maximum`` is the last
        centre when (maximum − minimum) / step is a whole number (to 1e-9); otherwise the
        grid ends at the last centre below it.
    step : float
        Spacing [um], > 0.
    key : str
        Key path named in errors (``observers[0].spectral``).

    Returns
    -------
    ChannelGrid

    Raises
    ------
    ConfigError
        A step <= 0, a minimum <= 0, a maximum not above the minimum, or fewer than two
        channels; the message names ``key.min``, ``key.max`` or ``key.step``.

    Examples
    --------
    >>> grid = channel_grid(8.0, 12.0, 0.5)
    >>> len(grid), grid.width[:2].tolist()
    (9, [0.25, 0.5])
    """
    values = {}
    for name, v in (("min", minimum), ("max", maximum), ("step", step)):
        try:
            values[name] = float(v)
        except (TypeError, ValueError):
            raise ConfigError(f"must be a wavelength [µm]; got {v!r}", key=f"{key}.{name}") from None
        if not math.isfinite(values[name]):
            raise ConfigError(f"must be finite; got {v!r}", key=f"{key}.{name}")
    lo, hi, dl = values["min"], values["max"], values["step"]
    if dl <= 0:
        raise ConfigError(f"must be > 0 µm; got {dl!r}", key=f"{key}.step")
    if lo <= 0:
        raise ConfigError(f"must be > 0 µm; got {lo!r}", key=f"{key}.min")
    if hi <= lo:
        raise ConfigError(f"must be above min = {lo:g} µm, or the grid is empty; got {hi!r}",
                          key=f"{key}.max")
    if hi - lo < dl * (1.0 - 1e-9):
        raise ConfigError(f"{dl:g} µm leaves fewer than two channels between {lo:g} and "
                          f"{hi:g} µm", key=f"{key}.step")
    return ChannelGrid(wavelength_grid(lo, hi, dl), dl)
