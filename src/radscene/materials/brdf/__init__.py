"""BRDF models, one module each: pure functions over arrays of unit vectors.

* :mod:`~radscene.materials.brdf.lambertian` — ρ/π, cosine-weighted sampling.
* :mod:`~radscene.materials.brdf.phong` — the normalised Phong lobe of OSSIM (Willers et al. 2011, eq. 4).

:data:`MODELS` maps a case-insensitive model name to its module; :func:`get_model` looks one up.
"""

from __future__ import annotations

from types import ModuleType

from radscene.errors import ConfigError
from radscene.materials.brdf import lambertian, phong

__all__ = ["lambertian", "phong", "MODELS", "get_model"]

#: Registered BRDF models by lower-case name.
MODELS: dict[str, ModuleType] = {"lambertian": lambertian, "phong": phong}


def get_model(name: str, key: str = "brdf.type") -> ModuleType:
    """The BRDF module registered as ``name`` (case-insensitive).

    Raises
    ------
    ConfigError
        Unknown name; the message lists the registered ones.
    """
    try:
        return MODELS[str(name).lower()]
    except KeyError:
        raise ConfigError(
            f"unknown BRDF model {name!r}; known: {', '.join(sorted(MODELS))}", key=key
        ) from None
