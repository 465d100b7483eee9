"""Heat balance over surface elements: one module per flux term (``radiation``,
``convection``), the layered conduction solver (``conduction``) and the time stepper
(``balance``). See docs/thermal.md."""

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

__all__ = [
    "DAY",
    "SIGMA",
    "CONVECTION_MODELS",
    "ConductionGrid",
    "HeatBalance",
    "ImplicitConduction",
    "ThermalForcing",
    "ThermalResult",
    "absorbed_shortwave",
    "absorbed_sky_longwave",
    "build_grid",
    "convection_coefficient",
    "convective_flux",
    "emitted_longwave",
    "emitted_longwave_derivative",
    "penetration_depth",
    "reference_step",
    "solve_surface_temperature",
    "stack_depth",
]
