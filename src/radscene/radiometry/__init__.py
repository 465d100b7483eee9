"""Radiometry: CODATA constants, Planck functions and band integrals, brightness
temperature, spectral grids and the channels of a hyperspectral grid, spectral response
functions, and unit parsing."""

from radscene.radiometry.channels import ChannelGrid, channel_grid
from radscene.radiometry.constants import C1, C1L, C2, SIGMA, WIEN_B
from radscene.radiometry.grids import RESAMPLE_METHODS, resample, wavelength_grid
from radscene.radiometry.planck import (
    band_brightness_temperature,
    band_radiance,
    brightness_temperature,
    exitance,
    peak_wavelength,
    radiance_temperature_derivative,
    spectral_radiance,
    spectral_radiance_wavenumber,
)
from radscene.radiometry.srf import (
    RESPONSES,
    GaussianResponse,
    RectangularResponse,
    SpectralResponse,
    TabulatedResponse,
    make_response,
)
from radscene.radiometry.units import CANONICAL_UNITS, UNITS, parse_quantity

__all__ = [
    "C1",
    "C1L",
    "C2",
    "SIGMA",
    "WIEN_B",
    "spectral_radiance",
    "spectral_radiance_wavenumber",
    "radiance_temperature_derivative",
    "band_radiance",
    "exitance",
    "peak_wavelength",
    "brightness_temperature",
    "band_brightness_temperature",
    "SpectralResponse",
    "RectangularResponse",
    "GaussianResponse",
    "TabulatedResponse",
    "RESPONSES",
    "make_response",
    "wavelength_grid",
    "ChannelGrid",
    "channel_grid",
    "resample",
    "RESAMPLE_METHODS",
    "parse_quantity",
    "UNITS",
    "CANONICAL_UNITS",
]
