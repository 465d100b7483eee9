"""Materials from type-tagged mappings: one registry for Python, YAML and the command line.

=============  ================================================================================
type           keys (besides ``type``)
=============  ================================================================================
``library``    ``name``: a built-in material (:func:`~radscene.materials.list_materials`)
``custom``     ``reflectance`` and/or ``emissivity``, ``transmittance``, ``specular_reflectance``,
               ``specular_exponent``, ``description``, ``source``
               (:meth:`~radscene.materials.Material.create`)
``file``       ``path`` (ECOSTRESS/ASTER, USGS splib07 or ENVI library), ``spectrum`` (name or
               index; optional for one-spectrum files), ``format``, ``wavelength_file`` (USGS),
               ``thermal_emissivity``, ``transmittance``, ``specular_reflectance``,
               ``specular_exponent``
``earthlib``   ``spectrum`` (name or index in earthlib's library), ``thermal_emissivity``,
               ``specular_reflectance``, ``specular_exponent``
``leaf``       PROSPECT-D parameters (``structure``, ``chlorophyll``, ``carotenoids``,
               ``anthocyanins``, ``brown_pigments``, ``water``, ``dry_matter``),
               ``leaf_emissivity``
``canopy``     the leaf's parameters plus ``lai``, ``leaf_angle``, ``hotspot``, ``soil`` (a
               material name or number), ``leaf_emissivity``
``water``      ``diffuse_reflectance``, ``specular_exponent``
``mixture``    ``parts``: list of ``{fraction, material}`` (material: a name or a mapping)
=============  ================================================================================

Thermal extension of VSWIR-only spectra (``file``, ``earthlib``): a measured VSWIR spectrum
(e.g. earthlib's, 0.40-2.45 um) covers no thermal infrared. With ``thermal_emissivity`` (a
number or a spectrum mapping, e.g. ``{wavelength: [3, 8, 14, 20], values: [...]}``) the
reflectance is extended by one stated rule: from 3 um on it is 1 − ε_thermal (τ = 0 there) at
the thermal table's wavelengths (3, 4, 5, 8, 10, 12, 14, 20 um for a number), and linear in
wavelength across the gap from the last measured point to 3 um. Without it the material is
defined only where it was measured, and any query outside raises.

Examples
--------
>>> m = make_material({"type": "library", "name": "asphalt"})
>>> m.name
'asphalt'
>>> g = make_material({"type": "custom", "reflectance": 0.3, "specular_reflectance": 0.04,
...                    "specular_exponent": 50}, key="materials.paint")
>>> round(float(g.emissivity(10.0)), 6)
0.7
"""

from __future__ import annotations

import numbers
from collections.abc import Mapping

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = ["make_material", "MATERIAL_TYPES", "material_keys", "extend_with_thermal", "THERMAL_START"]

#: Wavelength where a thermal extension starts [um].
THERMAL_START = 3.0
#: Wavelengths of a constant thermal emissivity's table [um].
_THERMAL_NODES = (3.0, 4.0, 5.0, 8.0, 10.0, 12.0, 14.0, 20.0)

_PROSPECT = {"structure", "chlorophyll", "carotenoids", "anthocyanins", "brown_pigments", "water",
             "dry_matter"}
_KEYS = {
    "library": {"name"},
    "custom": {"reflectance", "emissivity", "transmittance", "specular_reflectance",
               "specular_exponent", "description", "source", "category"},
    "file": {"path", "spectrum", "format", "wavelength_file", "thermal_emissivity", "transmittance",
             "specular_reflectance", "specular_exponent"},
    "earthlib": {"spectrum", "thermal_emissivity", "specular_reflectance", "specular_exponent"},
    "leaf": _PROSPECT | {"leaf_emissivity"},
    "canopy": _PROSPECT | {"lai", "leaf_angle", "hotspot", "soil", "leaf_emissivity"},
    "water": {"diffuse_reflectance", "specular_exponent"},
    "mixture": {"parts"},
}


def extend_with_thermal(spectrum, thermal_emissivity, key: str = "thermal_emissivity"):
    """A VSWIR reflectance spectrum extended into the thermal infrared by the stated rule.

    Parameters
    ----------
    spectrum : Spectrum
        Measured reflectance, tabulated, ending below 3 um [-].
    thermal_emissivity : number, Spectrum or mapping
        ε from 3 um on [-]; a table must start at or before 3 um.
    key : str

    Returns
    -------
    Spectrum
        The measured points, then 1 − ε at the thermal nodes (≥ 3 um); linear in between.
    """
    from radscene.materials.spectrum import Spectrum, make_spectrum

    if spectrum.is_constant or spectrum.range[1] >= THERMAL_START:
        raise ConfigError(
            f"a thermal extension needs a tabulated spectrum that ends below {THERMAL_START:g} µm; "
            f"{spectrum.name!r} covers {spectrum.range}",
            key=key,
        )
    eps = make_spectrum(thermal_emissivity, key=key)
    if eps.is_constant:
        nodes = np.array(_THERMAL_NODES)
    else:
        lo, _ = eps.range
        if lo > THERMAL_START:
            raise ConfigError(f"the thermal emissivity must start at or before {THERMAL_START:g} µm; "
                              f"it starts at {lo:g} µm", key=key)
        nodes = eps.wavelength[eps.wavelength >= THERMAL_START]
        if nodes[0] > THERMAL_START:
            nodes = np.concatenate([[THERMAL_START], nodes])
    values = np.asarray(eps(nodes), dtype=float)
    if np.any(values < 0) or np.any(values > 1):
        raise ConfigError("thermal emissivity must be in [0, 1]", key=key)
    return Spectrum.from_table(
        np.concatenate([spectrum.wavelength, nodes]),
        np.concatenate([spectrum.values, 1.0 - values]),
        name=spectrum.name,
        source=f"{spectrum.source}; from {THERMAL_START:g} µm 1 - thermal emissivity, linear across the gap",
    )


def material_keys() -> dict[str, list[str]]:
    """The keys each material type takes besides ``type``, by type (sorted): what
    :func:`make_material` accepts, for the scene-file reference and its JSON schema."""
    return {kind: sorted(_KEYS[kind]) for kind in MATERIAL_TYPES}


def _check_keys(spec, kind, key):
    unknown = set(spec) - _KEYS[kind] - {"type"}
    if unknown:
        raise ConfigError(
            f"unknown keys {sorted(unknown)} for a {kind} material; accepted: {sorted(_KEYS[kind])}",
            key=key,
        )


def _from_library_spectrum(spec, s, key):
    from radscene.materials.material import Material

    thermal = spec.get("thermal_emissivity")
    if thermal is None:
        return s.to_material(
            key.rsplit(".", 1)[-1],
            transmittance=spec.get("transmittance", 0.0),
            specular_reflectance=spec.get("specular_reflectance", 0.0),
            specular_exponent=spec.get("specular_exponent", 0.0),
        )
    if s.quantity != "reflectance":
        raise ConfigError("thermal_emissivity extends reflectance spectra only", key=f"{key}.thermal_emissivity")
    if spec.get("transmittance", 0.0) != 0.0:
        raise ConfigError("a thermally extended material is opaque (transmittance 0)", key=f"{key}.transmittance")
    # bounds and file:line messages of the measured part first
    s.to_material(key.rsplit(".", 1)[-1])
    rho = extend_with_thermal(s.to_spectrum(), thermal, key=f"{key}.thermal_emissivity")
    return Material.create(
        key.rsplit(".", 1)[-1],
        reflectance=rho,
        specular_reflectance=spec.get("specular_reflectance", 0.0),
        specular_exponent=spec.get("specular_exponent", 0.0),
        source=rho.source,
        description=s.metadata.get("description", ""),
        category=s.metadata.get("class", s.metadata.get("level_3", "")),
        key=key,
    )


def _pick(lib, which, key):
    if which is None:
        if len(lib) != 1:
            raise ConfigError(f"the library holds {len(lib)} spectra; give 'spectrum' (a name or an index)",
                              key=f"{key}.spectrum")
        return lib[0]
    if isinstance(which, numbers.Integral) and not isinstance(which, bool):
        if not 0 <= which < len(lib):
            raise ConfigError(f"index {which} is outside 0..{len(lib) - 1}", key=f"{key}.spectrum")
        return lib[int(which)]
    try:
        return lib.get(str(which))
    except ConfigError as err:
        raise ConfigError(err.message, key=f"{key}.spectrum") from None


def _library(spec, key, base_dir):
    from radscene.materials.library import get_material

    if "name" not in spec:
        raise ConfigError("missing 'name'", key=key)
    return get_material(spec["name"], key=f"{key}.name")


def _custom(spec, key, base_dir):
    from radscene.materials.material import Material

    kwargs = {k: v for k, v in spec.items() if k != "type"}
    return Material.create(key.rsplit(".", 1)[-1], key=key, base_dir=base_dir, **kwargs)


def _file(spec, key, base_dir):
    from pathlib import Path

    from radscene.materials.libraries import read_library

    if "path" not in spec:
        raise ConfigError("missing 'path'", key=key)
    path = Path(spec["path"])
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    extra = {"wavelength_file": spec["wavelength_file"]} if "wavelength_file" in spec else {}
    lib = read_library(path, format=spec.get("format"), **extra)
    return _from_library_spectrum(spec, _pick(lib, spec.get("spectrum"), key), key)


def _earthlib(spec, key, base_dir):
    from radscene.materials.libraries import earthlib_library

    return _from_library_spectrum(spec, _pick(earthlib_library(), spec.get("spectrum"), key), key)


def _vegetation_kwargs(spec, key):
    out = {k: v for k, v in spec.items() if k != "type"}
    return out


def _leaf(spec, key, base_dir):
    from radscene.materials.vegetation import leaf_material

    return leaf_material(key.rsplit(".", 1)[-1], **_vegetation_kwargs(spec, key))


def _canopy(spec, key, base_dir):
    from radscene.materials.library import get_material
    from radscene.materials.vegetation import canopy_material

    kwargs = _vegetation_kwargs(spec, key)
    soil = kwargs.get("soil", "bare_soil")
    if isinstance(soil, str):
        kwargs["soil"] = get_material(soil, key=f"{key}.soil")
    return canopy_material(key.rsplit(".", 1)[-1], **kwargs)


def _water(spec, key, base_dir):
    from radscene.materials.water import water_material

    kwargs = {k: v for k, v in spec.items() if k != "type"}
    return water_material(name=key.rsplit(".", 1)[-1], **kwargs)


def _mixture(spec, key, base_dir):
    from radscene.materials.maps import mix_materials

    parts = spec.get("parts")
    if not isinstance(parts, list) or not parts:
        raise ConfigError("'parts' must be a list of {fraction, material}", key=f"{key}.parts")
    built = []
    for i, part in enumerate(parts):
        k = f"{key}.parts[{i}]"
        if not isinstance(part, Mapping) or set(part) != {"fraction", "material"}:
            raise ConfigError("each part is {fraction: f, material: name or mapping}", key=k)
        m = part["material"]
        m = make_material({"type": "library", "name": m} if isinstance(m, str) else m, key=f"{k}.material",
                          base_dir=base_dir)
        built.append((part["fraction"], m))
    return mix_materials(built, name=key.rsplit(".", 1)[-1])


#: Registered material types: name -> factory(spec, key, base_dir).
MATERIAL_TYPES = {
    "library": _library,
    "custom": _custom,
    "file": _file,
    "earthlib": _earthlib,
    "leaf": _leaf,
    "canopy": _canopy,
    "water": _water,
    "mixture": _mixture,
}


def make_material(spec, key: str = "material", base_dir=None):
    """Build a :class:`~radscene.materials.Material` from a type-tagged mapping.

    Parameters
    ----------
    spec : mapping, str or Material
        ``{"type": ..., ...}`` (see the module table); a string is a built-in material's name; a
        Material is returned as it is.
    key : str
        Config key path; its last part names the material (``materials.verge`` → ``verge``).
    base_dir : path-like, optional
        Folder of relative paths.

    Returns
    -------
    Material

    Raises
    ------
    ConfigError
        Unknown type (listing the registered ones), unknown keys (listing the accepted ones), or
        any error of the builders (naming the material, the file and line, or the key).
    """
    from radscene.materials.material import Material

    if isinstance(spec, Material):
        return spec
    if isinstance(spec, str):
        spec = {"type": "library", "name": spec}
    if not isinstance(spec, Mapping):
        raise ConfigError(f"a material is a name or a mapping with a 'type'; got {type(spec).__name__}", key=key)
    kind = str(spec.get("type", "")).lower()
    if kind not in MATERIAL_TYPES:
        raise ConfigError(
            f"unknown material type {spec.get('type')!r}; known: {', '.join(sorted(MATERIAL_TYPES))}"
            f"{did_you_mean(spec.get('type'), sorted(MATERIAL_TYPES))}",
            key=f"{key}.type",
        )
    _check_keys(spec, kind, key)
    try:
        return MATERIAL_TYPES[kind](spec, key, base_dir)
    except TypeError as exc:  # a wrong value type reaching a builder
        raise ConfigError(f"invalid {kind} material: {exc}", key=key) from None
