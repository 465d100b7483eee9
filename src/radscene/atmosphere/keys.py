"""The keys each atmosphere engine takes in its mapping (scene file ``environment.atmosphere``,
:func:`radscene.atmosphere.make_atmosphere`), read from the engines' constructors, with the
names an engine knows for its name-valued keys. The scene-file reference and its JSON schema
are made from them, so an editor completes an engine's keys and names."""

from __future__ import annotations

import inspect
import math

__all__ = ["engine_keys", "known_names", "constructor_keys", "unknown_keys"]


def known_names(engine: str) -> dict[str, list[str]]:
    """The names an engine knows, by key (``profile``, ``aerosol``, ...); keys that take free
    values are absent. The database's are those of the shipped file's configuration: a file
    built by the user may hold others."""
    from radscene.atmosphere.options import ENGINE_SPECTRA

    spectra = {"solar_spectrum": list(ENGINE_SPECTRA.get(engine, ()))} if engine in ENGINE_SPECTRA else {}
    if engine == "sixs":
        from radscene.atmosphere.sixs_runner import AEROSOLS, PROFILES

        return {"profile": list(PROFILES), "aerosol": list(AEROSOLS), **spectra}
    if engine == "database":
        from radscene.atmosphere.build import DEFAULT_CONFIG

        aerosols = [a["model"] for a in DEFAULT_CONFIG["aerosols"]]
        if "rural" in aerosols:
            aerosols.append("continental")  # 6S's name of the same model
        return {"profile": list(DEFAULT_CONFIG["profiles"]), "aerosol": aerosols, **spectra}
    if engine == "lowtran":
        from radscene.atmosphere.lowtran.cards import (
            AEROSOLS,
            CLOUDS,
            MODELS,
            PHASE_FUNCTIONS,
            SEASONS,
            STRATOSPHERIC_AEROSOLS,
        )

        return {"model": list(MODELS), "aerosol": list(AEROSOLS), "season": list(SEASONS),
                "stratospheric_aerosol": list(STRATOSPHERIC_AEROSOLS), "cloud": list(CLOUDS),
                "phase_function": list(PHASE_FUNCTIONS), **spectra}
    return spectra


def engine_keys() -> dict[str, dict[str, dict]]:
    """Every registered engine's keys: ``{engine: {key: {"default": value, "names": [...]}}}``,
    ``default`` left out where a key has none that a file could state (required keys,
    ``None``: the engine decides), ``names`` where the engine knows a set of names."""
    from radscene.atmosphere import ENGINES

    out = {}
    for engine, cls in ENGINES.items():
        names = known_names(engine)
        keys = {}
        for p in constructor_keys(cls).values():
            entry = {}
            default = _json_value(p.default)
            if default is not None:
                entry["default"] = default
            if p.name in names:
                entry["names"] = names[p.name]
            keys[p.name] = entry
        out[engine] = keys
    return out


def constructor_keys(cls) -> dict[str, inspect.Parameter]:
    """The keyword parameters of an engine class's constructor, by name."""
    return {p.name: p for p in list(inspect.signature(cls.__init__).parameters.values())[1:]
            if p.kind not in (p.VAR_KEYWORD, p.VAR_POSITIONAL)}


def unknown_keys(cls, given) -> list[str]:
    """The keys of ``given`` an engine class's constructor does not take (none when it takes
    any keyword)."""
    params = inspect.signature(cls.__init__).parameters.values()
    if any(p.kind == p.VAR_KEYWORD for p in params):
        return []
    known = constructor_keys(cls)
    return [k for k in given if k not in known]


def _json_value(value):
    """A default as a scene file would state it; None for none (or one a file cannot state)."""
    if value is inspect.Parameter.empty or value is None:
        return None
    if isinstance(value, bool | str | int):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, tuple | list):
        items = [_json_value(v) for v in value]
        return None if any(v is None for v in items) else items
    return None
