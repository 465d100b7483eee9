"""Materials: spectra, reflectance/emissivity/transmittance, BRDF models, libraries, textures.

Public API
----------
:class:`Spectrum`, :func:`make_spectrum`
    Dimensionless spectral quantities, constant or piecewise linear in wavelength [um].
:class:`Material`
    ρ_d, ρ_s (Phong lobe), n, τ; emissivity by Kirchhoff, ε = 1 − ρ_d − ρ_s − τ.
:mod:`~radscene.materials.brdf`
    BRDF models, one module each, and their registry.
:func:`get_material`, :func:`list_materials`, :func:`list_categories`, :func:`library_info`
    The built-in library: 33 materials spanning 0.4-20 um, each with its sources.
:func:`get_thermal_properties`, :func:`solar_absorptance`, :func:`longwave_emissivity`
    Layered thermal stacks (k, ρ, c), broadband solar absorptance and long-wave emissivity.
:mod:`~radscene.materials.libraries`
    Spectral-library readers (ECOSTRESS/ASTER, USGS splib07, ENVI .sli) and earthlib's 7261
    spectra: :func:`read_library`, :func:`earthlib_library`.
:mod:`~radscene.materials.vegetation`
    PROSPECT-D leaves and 4SAIL canopies (optional ``prosail``): :func:`leaf_material`,
    :func:`canopy_material`, :func:`canopy_emissivity`.
:mod:`~radscene.materials.water`, :mod:`~radscene.materials.snow`
    Fresnel reflection from complex refractive indices, absorption, directional emissivity.
:class:`Texture`, :class:`TextureSet`, :func:`make_texture`, :class:`NoiseTexture`
    Δρ/Δε/Δτ multiplier fields: images, tiles, procedural noise.
:class:`MaterialMap`, :class:`MaterialFractions`, :func:`mix_materials`
    Classified images → materials, per-class fractions, areal mixtures.
:mod:`~radscene.materials.gas`
    Absorbing gases: Edwards's wide-band model of CO₂ and H₂O, :class:`~radscene.materials.gas.GasAbsorption`
    (a gas plume's k(λ) and line overlap β(λ)).
:func:`make_material`
    Any material from a type-tagged mapping (``library``, ``custom``, ``file``, ``earthlib``,
    ``leaf``, ``canopy``, ``water``, ``mixture``; registry ``MATERIAL_TYPES``).
"""

from radscene.materials import brdf, libraries, snow, vegetation, water
from radscene.materials.brdf import BRDFS, make_brdf, plot_brdf
from radscene.materials.factory import MATERIAL_TYPES, make_material
from radscene.materials.libraries import earthlib_library, read_library, read_spectrum
from radscene.materials.library import (
    get_material,
    library_info,
    list_categories,
    list_materials,
)
from radscene.materials.maps import MaterialFractions, MaterialMap, mix_materials
from radscene.materials.material import Material
from radscene.materials.noise import NoiseTexture, fractal_noise, gradient_noise, noise_elevation
from radscene.materials.spectrum import Spectrum, make_spectrum
from radscene.materials.texture import Texture, TextureSet, make_texture
from radscene.materials.thermal import (
    Layer,
    ThermalProperties,
    get_thermal_properties,
    longwave_emissivity,
    solar_absorptance,
)
from radscene.materials.vegetation import (
    canopy_emissivity,
    canopy_material,
    leaf_material,
    leaf_optics,
)

__all__ = [
    "BRDFS",
    "make_brdf",
    "plot_brdf",
    "Spectrum",
    "make_spectrum",
    "Material",
    "make_material",
    "MATERIAL_TYPES",
    "brdf",
    "libraries",
    "vegetation",
    "water",
    "snow",
    "Texture",
    "TextureSet",
    "make_texture",
    "NoiseTexture",
    "gradient_noise",
    "fractal_noise",
    "noise_elevation",
    "MaterialMap",
    "MaterialFractions",
    "mix_materials",
    "get_material",
    "list_materials",
    "list_categories",
    "library_info",
    "Layer",
    "ThermalProperties",
    "get_thermal_properties",
    "solar_absorptance",
    "longwave_emissivity",
    "read_library",
    "read_spectrum",
    "earthlib_library",
    "leaf_optics",
    "leaf_material",
    "canopy_material",
    "canopy_emissivity",
]
