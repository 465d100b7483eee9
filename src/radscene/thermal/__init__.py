"""Heat balance over surface elements: one module per flux term (``radiation``,
``convection``), the layered conduction solver (``conduction``), the time stepper
(``balance``) and the weather that drives it (``weather``). See docs/thermal.md."""

from radscene.thermal.balance import (
    HeatBalance,
    ThermalForcing,
    ThermalResult,
    solve_surface_temperature,
)
from radscene.thermal.conduction import (
    DAY,
    ConductionGrid,
    ImplicitConduction,
    build_grid,
    penetration_depth,
    reference_step,
    stack_depth,
)
from radscene.thermal.convection import CONVECTION_MODELS, convection_coefficient, convective_flux
from radscene.thermal.radiation import (
    SIGMA,
    absorbed_shortwave,
    absorbed_sky_longwave,
    emitted_longwave,
    emitted_longwave_derivative,
)
from radscene.thermal.weather import (
    CLEAR_SKY_EMISSIVITY_MODELS,
    CLOUD_EMISSIVITY_MODELS,
    WeatherSeries,
    clear_sky_emissivity,
    cloud_diffuse_fraction,
    cloud_shortwave_factor,
    cloudy_sky_emissivity,
    dew_point_to_relative_humidity,
    relative_humidity_to_dew_point,
    saturation_vapour_pressure,
    sky_longwave,
    specific_humidity,
    to_utc_datetime64,
    vapour_pressure,
)

__all__ = [
    "DAY",
    "SIGMA",
    "CONVECTION_MODELS",
    "CLEAR_SKY_EMISSIVITY_MODELS",
    "CLOUD_EMISSIVITY_MODELS",
    "ConductionGrid",
    "HeatBalance",
    "ImplicitConduction",
    "ThermalForcing",
    "ThermalResult",
    "WeatherSeries",
    "absorbed_shortwave",
    "absorbed_sky_longwave",
    "build_grid",
    "clear_sky_emissivity",
    "cloud_diffuse_fraction",
    "cloud_shortwave_factor",
    "cloudy_sky_emissivity",
    "convection_coefficient",
    "convective_flux",
    "dew_point_to_relative_humidity",
    "emitted_longwave",
    "emitted_longwave_derivative",
    "penetration_depth",
    "reference_step",
    "relative_humidity_to_dew_point",
    "saturation_vapour_pressure",
    "sky_longwave",
    "solve_surface_temperature",
    "specific_humidity",
    "stack_depth",
    "to_utc_datetime64",
    "vapour_pressure",
]
