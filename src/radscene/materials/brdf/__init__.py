"""BRDF models under one contract, one module each, one registry.

================================  ==============================  ============================
type (``make_brdf``)              class (module)                  model
================================  ==============================  ============================
``lambertian``                    :class:`Lambertian`             ρ/π
``phong``                         :class:`Phong`                  OSSIM lobe (Willers 2011 eq. 4)
``ggx``                           :class:`GGX` (microfacet)       Walter et al. 2007 + Fresnel
``beckmann``                      :class:`Beckmann` (microfacet)  Walter et al. 2007 + Fresnel
``rpv``                           :class:`RPV`                    Rahman, Pinty, Verstraete 1993
``rossli``                        :class:`RossLi`                 Ross-Thick/Li-Sparse(-R),
                                                                  Maignan 2004 hot spot
``hapke``                         :class:`Hapke`                  Hapke 1981/2002
``coxmunk``                       :class:`CoxMunk`                Cox & Munk 1954 sun glint
``lambertian_transmission``       :class:`LambertianTransmission` thin sheets, leaves
``tabulated``                     :class:`Tabulated`              table file
================================  ==============================  ============================

Every model has ``f(wi, wo, wavelength, normal)`` [sr-1] (also ``kernel(cos_incidence,
cos_view, cos_phase, wavelength)`` and ``f_angles(incidence_zenith, view_zenith,
relative_azimuth, wavelength)``), ``albedo(wi, wavelength)`` (ρ_dh), ``transmittance(wi,
wavelength)`` (τ_dh), ``emissivity(wi, wavelength)`` = 1 − ρ_dh − τ_dh (Kirchhoff),
``hemispherical_emissivity(wavelength)`` and ``bihemispherical_reflectance(wavelength)``,
``sample(wo, u1, u2, wavelength)`` → (wi, pdf) and ``pdf(wo, wi, wavelength)``;
frames and angle conventions are in :mod:`radscene.materials.brdf.base` (local frame z = normal,
directions pointing away from the surface, relative azimuth 0 = backscatter). The models'
parameters are documented in a table in each module.

:func:`make_brdf` builds a model from a type-tagged mapping, the same in Python, YAML and on the
command line: ``make_brdf({"type": "rpv", "rho0": 0.076, "k": 0.648, "theta": -0.29})``.

The module functions of :mod:`.lambertian` and :mod:`.phong` (``lambertian.sample``,
``phong.lobe``, ``phong.sample``, ...) are the array kernels the renderer calls; ``MODELS`` and
:func:`get_model` look those two modules up by name (kept for the renderer; new code uses
:data:`BRDFS`).
"""

from __future__ import annotations

from collections.abc import Mapping
from types import ModuleType

from radscene.errors import ConfigError, did_you_mean
from radscene.materials.brdf import (
    base,
    coxmunk,
    fresnel,
    hapke,
    lambertian,
    microfacet,
    phong,
    rossli,
    rpv,
    tabulated,
    transmission,
)
from radscene.materials.brdf.base import BRDF, Parameter
from radscene.materials.brdf.coxmunk import CoxMunk
from radscene.materials.brdf.fresnel import fresnel_reflectance
from radscene.materials.brdf.hapke import Hapke
from radscene.materials.brdf.lambertian import Lambertian
from radscene.materials.brdf.microfacet import GGX, Beckmann
from radscene.materials.brdf.phong import Phong
from radscene.materials.brdf.rossli import RossLi
from radscene.materials.brdf.rpv import RPV
from radscene.materials.brdf.tabulated import Tabulated
from radscene.materials.brdf.transmission import LambertianTransmission

__all__ = [
    "BRDF",
    "BRDFS",
    "Parameter",
    "make_brdf",
    "register_brdf",
    "plot_brdf",
    "fresnel_reflectance",
    "Lambertian",
    "Phong",
    "GGX",
    "Beckmann",
    "RPV",
    "RossLi",
    "Hapke",
    "CoxMunk",
    "LambertianTransmission",
    "Tabulated",
    "base",
    "coxmunk",
    "fresnel",
    "hapke",
    "lambertian",
    "microfacet",
    "phong",
    "rossli",
    "rpv",
    "tabulated",
    "transmission",
    "MODELS",
    "get_model",
]

#: Registered BRDF models by lower-case type name.
BRDFS: dict[str, type[BRDF]] = {}


def register_brdf(cls: type[BRDF]) -> type[BRDF]:
    """Add a :class:`BRDF` subclass to :data:`BRDFS` under ``cls.name`` (usable as a decorator).

    Raises
    ------
    ConfigError
        A class that is not a BRDF, has no name, or whose name is taken by another class.
    """
    if not (isinstance(cls, type) and issubclass(cls, BRDF)) or not cls.name:
        raise ConfigError(f"{cls!r} is not a named BRDF subclass", key="brdf.type")
    name = cls.name.lower()
    if BRDFS.get(name, cls) is not cls:
        raise ConfigError(f"BRDF type {name!r} is already registered to {BRDFS[name]!r}",
                          key="brdf.type")
    BRDFS[name] = cls
    return cls


for _cls in (Lambertian, Phong, GGX, Beckmann, RPV, RossLi, Hapke, CoxMunk,
             LambertianTransmission, Tabulated):
    register_brdf(_cls)


def make_brdf(spec, key: str = "brdf", *, base_dir=None) -> BRDF:
    """Build a registered BRDF model from a type-tagged mapping.

    Parameters
    ----------
    spec : mapping or BRDF
        ``{"type": name, **parameters}``; the type is case-insensitive, the parameters are the
        model's (see its module's table). A :class:`BRDF` is returned as it is.
    key : str, optional
        Config key path used in error messages, e.g. ``materials.paint.brdf``.
    base_dir : path-like, optional
        Directory that relative file paths (spectra, tables) are relative to.

    Returns
    -------
    BRDF

    Raises
    ------
    ConfigError
        Not a mapping, no ``type``, an unknown type (the message lists the registered ones), an
        unknown parameter (named) or an invalid value.

    Examples
    --------
    >>> m = make_brdf({"type": "RPV", "rho0": 0.076, "k": 0.648, "theta": -0.29})
    >>> type(m).__name__
    'RPV'
    """
    if isinstance(spec, BRDF):
        return spec
    if not isinstance(spec, Mapping):
        raise ConfigError(
            f"a BRDF is a mapping {{type: name, ...}}; got {type(spec).__name__} {spec!r}",
            key=key,
        )
    if "type" not in spec:
        raise ConfigError(f"a BRDF needs a type; known: {', '.join(sorted(BRDFS))}",
                          key=f"{key}.type")
    name = str(spec["type"]).lower()
    if name not in BRDFS:
        raise ConfigError(
            f"unknown BRDF type {spec['type']!r}; known: {', '.join(sorted(BRDFS))}"
            f"{did_you_mean(spec['type'], sorted(BRDFS))}",
            key=f"{key}.type",
        )
    params = {k: v for k, v in spec.items() if k != "type"}
    bad = [k for k in params if not isinstance(k, str)]
    if bad:
        raise ConfigError(f"parameter names must be strings; got {bad[0]!r}", key=key)
    return BRDFS[name](key=key, base_dir=base_dir, **params)


def plot_brdf(model, incidence_angles, path, wavelength=None, **kwargs):
    """Polar plots of a BRDF at a few incidence angles, saved as PNG (see :mod:`.plot`)."""
    from radscene.materials.brdf.plot import plot_brdf as _plot

    return _plot(model, incidence_angles, path, wavelength=wavelength, **kwargs)


# ---------------------------------------------------------------------- legacy lookup
#: The modules whose array functions the renderer calls, by lower-case name.
MODELS: dict[str, ModuleType] = {"lambertian": lambertian, "phong": phong}


def get_model(name: str, key: str = "brdf.type") -> ModuleType:
    """The renderer-kernel module registered as ``name`` (case-insensitive): ``lambertian`` or
    ``phong``. New code uses :func:`make_brdf`.

    Raises
    ------
    ConfigError
        Unknown name; the message lists the modules.
    """
    try:
        return MODELS[str(name).lower()]
    except KeyError:
        raise ConfigError(
            f"unknown BRDF model {name!r}; known: {', '.join(sorted(MODELS))}"
            f"{did_you_mean(name, sorted(MODELS))}", key=key
        ) from None
