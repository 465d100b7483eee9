"""Materials: spectra, reflectance/emissivity/transmittance, BRDF models, textures, the library.

Public API
----------
:class:`Spectrum`, :func:`make_spectrum`
    Dimensionless spectral quantities, constant or piecewise linear in wavelength [um].
:class:`Material`
    ρ_d, ρ_s (Phong lobe), n, τ; emissivity by Kirchhoff, ε = 1 − ρ_d − ρ_s − τ.
:mod:`~radscene.materials.brdf`
    ``lambertian`` and ``phong`` (OSSIM, Willers et al. 2011, eq. 4) BRDFs and samplers.
:class:`Texture`
    Multiplier fields over the ground plane.
:func:`get_material`, :func:`list_materials`, :func:`library_info`
    The built-in library (0.4–20 um).
"""

from radscene.materials import brdf
from radscene.materials.library import get_material, library_info, list_materials
from radscene.materials.material import Material
from radscene.materials.spectrum import Spectrum, make_spectrum
from radscene.materials.texture import Texture

__all__ = [
    "Spectrum",
    "make_spectrum",
    "Material",
    "brdf",
    "Texture",
    "get_material",
    "list_materials",
    "library_info",
]
