"""Absorbing and emitting gases: band models of CO₂ and H₂O.

:mod:`~radscene.materials.gas.edwards`
    Edwards's exponential wide-band model (Edwards 1976; Modest 2013, Table 11.3), the mean
    absorption of each band from temperature, pressure and composition.
:class:`GasAbsorption`
    A mixture at one state, callable as a volume's extinction k(λ) [m-1] with its line
    overlap β(λ) (:mod:`radscene.render.volumes`); registry :data:`GAS_MODELS`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from radscene.errors import ConfigError
from radscene.materials.gas import edwards

__all__ = ["GAS_MODELS", "GasAbsorption", "edwards"]

#: Band models by name (case-insensitive): modules with ``band_parameters``, ``absorption``,
#: ``absorptance``, ``transmittance``, ``spectral_nodes`` and ``GASES``.
GAS_MODELS = {"edwards": edwards}


@dataclass(frozen=True)
class GasAbsorption:
    """A homogeneous gas mixture's band absorption at one temperature and pressure.

    Called with wavelengths [um] it returns the merged weak-line absorption coefficient k(λ)
    [m-1]; :meth:`line_overlap` gives the β(λ) [-] that goes with it, so that a path of
    density-weighted length X [m] transmits 1 − :meth:`absorptance` (k X, β). Density profiles
    scale the absorber amount at constant line width.

    Parameters
    ----------
    mole_fractions : tuple of (str, float)
        Gas → mole fraction [-].
    temperature : float
        [K].
    pressure : float
        [Pa].
    model : str
        A key of :data:`GAS_MODELS`.
    """

    mole_fractions: tuple
    temperature: float
    pressure: float
    model: str = "edwards"
    bands: object = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        name = str(self.model).lower()
        if name not in GAS_MODELS:
            raise ConfigError(f"unknown gas model {self.model!r}; known: "
                              f"{', '.join(GAS_MODELS)}", key="model")
        object.__setattr__(self, "model", name)
        object.__setattr__(self, "bands", GAS_MODELS[name].band_parameters(
            self.temperature, self.pressure, dict(self.mole_fractions)))

    def __call__(self, wavelength) -> np.ndarray:
        return GAS_MODELS[self.model].absorption(wavelength, self.bands)[0]

    def line_overlap(self, wavelength) -> np.ndarray:
        """β(λ) [-] of the merged band (``inf`` where nothing absorbs)."""
        return GAS_MODELS[self.model].absorption(wavelength, self.bands)[1]

    def absorptance(self, weak_depth, line_overlap) -> np.ndarray:
        """Mean absorptance [-] of a path of weak-line optical depth k X [-] and overlap β."""
        return GAS_MODELS[self.model].absorptance(weak_depth, line_overlap)

    def transmittance(self, wavelength, path_length) -> np.ndarray:
        """Π_bands (1 − ā) of a path [m] at relative density 1 [-] (the reference)."""
        return GAS_MODELS[self.model].transmittance(wavelength, path_length, self.bands)

    @property
    def wavelength(self) -> np.ndarray:
        """Where band integrals are split [um] (the model's spectral nodes)."""
        return GAS_MODELS[self.model].spectral_nodes()
