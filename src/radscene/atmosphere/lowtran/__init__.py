"""LOWTRAN7 atmosphere engine: card decks, runner, parser, engine and build.

LOWTRAN7 (Kneizys et al. 1988, AFGL-TR-88-0177) computes transmittance and radiance,
thermal and solar, 0-50000 cm-1 at 20 cm-1 resolution. radscene drives it through TAPE5
card decks (:mod:`.cards`), runs each case as its own process of an executable built by
``make lowtran`` (:mod:`.build`, :mod:`.runner`), reads the result (:mod:`.parser`) and
answers the :class:`~radscene.atmosphere.base.Atmosphere` queries (:mod:`.engine`), the
surface–atmosphere coupling among them (:mod:`.coupling`).

Register with ``ENGINES["lowtran"] = LowtranAtmosphere``.
"""

from radscene.atmosphere.lowtran.cards import (
    AEROSOLS,
    CLOUDS,
    MODELS,
    LowtranCase,
    ProfileLevel,
    UserAerosolRegion,
    write_tape5,
)
from radscene.atmosphere.lowtran.engine import (
    LowtranAtmosphere,
    lowtran_line_of_sight,
    lowtran_sky_radiance,
)
from radscene.atmosphere.lowtran.geometry import observer_geometry, path_node_grid
from radscene.atmosphere.lowtran.profiles import profile_levels
from radscene.atmosphere.lowtran.runner import (
    NOT_BUILT,
    LowtranResult,
    LowtranRunner,
    find_executable,
    lowtran_available,
    run_case,
    run_cases,
)

__all__ = [
    "LowtranAtmosphere",
    "lowtran_line_of_sight",
    "lowtran_sky_radiance",
    "observer_geometry",
    "path_node_grid",
    "profile_levels",
    "LowtranCase",
    "ProfileLevel",
    "UserAerosolRegion",
    "write_tape5",
    "MODELS",
    "AEROSOLS",
    "CLOUDS",
    "LowtranResult",
    "LowtranRunner",
    "run_case",
    "run_cases",
    "find_executable",
    "lowtran_available",
    "NOT_BUILT",
]
