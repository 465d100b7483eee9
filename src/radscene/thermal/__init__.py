"""Heat balance over surface elements: one module per flux term (``radiation``,
``convection``, ``exchange``, ``evaporation``, ``aerodynamic``), the layered conduction solver
(``conduction``), lateral conduction between elements (``lateral``), the time stepper
(``balance``), the weather that drives it (``weather``) and the terrain's temperature between
its cells for the render (``reconstruction``). See docs/thermal.md."""

from radscene.thermal.aerodynamic import (
    air_viscosity,
    flat_plate_coefficient,
    recovery_temperature,
    speed_of_sound,
)
from radscene.thermal.balance import (
    TERMS,
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
from radscene.thermal.evaporation import (
    evaporative_flux,
    latent_heat_of_vaporisation,
    linearised_evaporative_flux,
    vapour_transfer_coefficient,
)
from radscene.thermal.exchange import (
    check_view_factors,
    environment_longwave,
    environment_shortwave,
)
from radscene.thermal.forcing import STANDARD_PRESSURE
from radscene.thermal.lateral import (
    check_conductance,
    coupled_surface_temperature,
    grid_conductance,
    laplacian,
    mesh_conductance,
)
from radscene.thermal.radiation import (
    SIGMA,
    absorbed_shortwave,
    absorbed_sky_longwave,
    emitted_longwave,
    emitted_longwave_derivative,
)
from radscene.thermal.reconstruction import corner_temperature, limited_slopes, terrain_neighbours
from radscene.thermal.weather import (
    CLEAR_SKY_EMISSIVITY_MODELS,
    CLOUD_EMISSIVITY_MODELS,
    PARTON_LOGAN_AIR_150CM,
    WEATHER_FORMATS,
    DiurnalCoefficients,
    WeatherSeries,
    clear_sky_emissivity,
    cloud_diffuse_fraction,
    cloud_shortwave_factor,
    cloudy_sky_emissivity,
    dew_point_to_relative_humidity,
    diurnal_weather,
    read_weather,
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
    "STANDARD_PRESSURE",
    "TERMS",
    "CONVECTION_MODELS",
    "CLEAR_SKY_EMISSIVITY_MODELS",
    "CLOUD_EMISSIVITY_MODELS",
    "PARTON_LOGAN_AIR_150CM",
    "WEATHER_FORMATS",
    "ConductionGrid",
    "DiurnalCoefficients",
    "HeatBalance",
    "ImplicitConduction",
    "ThermalForcing",
    "ThermalResult",
    "WeatherSeries",
    "absorbed_shortwave",
    "absorbed_sky_longwave",
    "air_viscosity",
    "build_grid",
    "check_conductance",
    "check_view_factors",
    "clear_sky_emissivity",
    "cloud_diffuse_fraction",
    "cloud_shortwave_factor",
    "cloudy_sky_emissivity",
    "convection_coefficient",
    "convective_flux",
    "corner_temperature",
    "coupled_surface_temperature",
    "dew_point_to_relative_humidity",
    "diurnal_weather",
    "emitted_longwave",
    "emitted_longwave_derivative",
    "environment_longwave",
    "environment_shortwave",
    "evaporative_flux",
    "flat_plate_coefficient",
    "grid_conductance",
    "laplacian",
    "limited_slopes",
    "latent_heat_of_vaporisation",
    "linearised_evaporative_flux",
    "mesh_conductance",
    "penetration_depth",
    "read_weather",
    "recovery_temperature",
    "reference_step",
    "relative_humidity_to_dew_point",
    "saturation_vapour_pressure",
    "sky_longwave",
    "solve_surface_temperature",
    "specific_humidity",
    "speed_of_sound",
    "stack_depth",
    "terrain_neighbours",
    "to_utc_datetime64",
    "vapour_pressure",
    "vapour_transfer_coefficient",
]
