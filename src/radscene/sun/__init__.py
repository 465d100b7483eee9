"""The Sun: position (NREL SPA via pvlib), Earth-Sun distance, and the top-of-atmosphere
solar spectrum 0.25-20 µm (ASTM G173-03/Gueymard 2004, TSIS-1 HSRS or LOWTRAN7's)."""

from radscene.sun.position import SunPosition, earth_sun_distance, sun_position
from radscene.sun.spectrum import (
    ASTRONOMICAL_UNIT,
    SOLAR_SPECTRUM_NAMES,
    SOLAR_WAVELENGTH_RANGE,
    SUN_RADIUS,
    SUN_SOLID_ANGLE,
    SUN_TEMPERATURE,
    engine_distance,
    engine_spectrum,
    solar_constant,
    sun_radiance,
    toa_solar_irradiance,
    toa_solar_spectrum,
)

__all__ = [
    "SunPosition",
    "sun_position",
    "earth_sun_distance",
    "toa_solar_irradiance",
    "toa_solar_spectrum",
    "solar_constant",
    "engine_spectrum",
    "engine_distance",
    "sun_radiance",
    "SUN_SOLID_ANGLE",
    "SUN_RADIUS",
    "SUN_TEMPERATURE",
    "ASTRONOMICAL_UNIT",
    "SOLAR_WAVELENGTH_RANGE",
    "SOLAR_SPECTRUM_NAMES",
]
