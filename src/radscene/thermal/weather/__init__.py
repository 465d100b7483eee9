"""The weather that drives the heat balance: a time series interpolated in time (read from a
file or built by a diurnal model), moist-air relations, and the sky's long-wave and cloud
formulations. See docs/thermal.md, section "Weather"."""

from radscene.thermal.weather.diurnal import (
    PARTON_LOGAN_AIR_150CM,
    DiurnalCoefficients,
    diurnal_air_temperature,
    diurnal_weather,
)
from radscene.thermal.weather.humidity import (
    dew_point_to_relative_humidity,
    relative_humidity_to_dew_point,
    saturation_vapour_pressure,
    specific_humidity,
    vapour_pressure,
)
from radscene.thermal.weather.readers import (
    WEATHER_FORMATS,
    read_weather,
    read_weather_csv,
    read_weather_netcdf,
)
from radscene.thermal.weather.series import WeatherSeries, to_utc_datetime64
from radscene.thermal.weather.sky import (
    CLEAR_SKY_EMISSIVITY_MODELS,
    CLOUD_EMISSIVITY_MODELS,
    clear_sky_emissivity,
    cloud_diffuse_fraction,
    cloud_shortwave_factor,
    cloudy_sky_emissivity,
    sky_longwave,
)

__all__ = [
    "CLEAR_SKY_EMISSIVITY_MODELS",
    "CLOUD_EMISSIVITY_MODELS",
    "DiurnalCoefficients",
    "PARTON_LOGAN_AIR_150CM",
    "WEATHER_FORMATS",
    "WeatherSeries",
    "clear_sky_emissivity",
    "cloud_diffuse_fraction",
    "cloud_shortwave_factor",
    "cloudy_sky_emissivity",
    "dew_point_to_relative_humidity",
    "diurnal_air_temperature",
    "diurnal_weather",
    "read_weather",
    "read_weather_csv",
    "read_weather_netcdf",
    "relative_humidity_to_dew_point",
    "saturation_vapour_pressure",
    "sky_longwave",
    "specific_humidity",
    "to_utc_datetime64",
    "vapour_pressure",
]
