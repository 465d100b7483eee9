"""Heat balance over surface elements: flux terms, layered conduction, the time stepper."""

from radscene.thermal.conduction import (
    DAY,
    ConductionGrid,
    ImplicitConduction,
    build_grid,
    penetration_depth,
    stack_depth,
)

__all__ = [
    "DAY",
    "ConductionGrid",
    "ImplicitConduction",
    "build_grid",
    "penetration_depth",
    "stack_depth",
]
