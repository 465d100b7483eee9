"""Figures of one material: its spectra over 0.4-20 um and polar plots of its BRDF.

:func:`material_brdf` is the material's BRDF as a registered model (Lambert + Phong lobe), the
one :func:`plot_material_brdf` draws. ``radscene materials plot`` writes both figures.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

__all__ = ["material_brdf", "plot_material_brdf", "plot_material_spectrum"]


def material_brdf(material):
    """The material's BRDF as a registered model: Phong (Lambertian ρ_d + OSSIM lobe ρ_s, n)."""
    from radscene.materials.brdf import make_brdf

    return make_brdf(
        {
            "type": "phong",
            "diffuse_reflectance": material.diffuse_reflectance,
            "specular_reflectance": material.specular_reflectance,
            "specular_exponent": material.specular_exponent,
        },
        key=f"{material.name}.brdf",
    )


def plot_material_spectrum(material, path, dpi: int = 110) -> Path:
    """PNG of ρ_d + ρ_s, ρ_s, τ and ε of ``material`` over its range within 0.4-20 um.

    Parameters
    ----------
    material : Material
    path : path-like
        Output PNG.
    dpi : int

    Returns
    -------
    pathlib.Path
    """
    from matplotlib.figure import Figure

    from radscene.materials.spectrum import union_wavelengths

    lo, hi = material.wavelength_range
    lo, hi = max(lo, 0.4), min(hi, 20.0)
    knots = union_wavelengths(material.spectra)
    grid = np.union1d(np.geomspace(lo, hi, 800), knots[(knots >= lo) & (knots <= hi)])
    comps = material.components(grid)
    fig = Figure(figsize=(11, 4.2), layout="constrained")
    fig.suptitle(f"{material.name}: spectra (emissivity by Kirchhoff, eps = 1 - rho - tau)")
    panels = [(lo, min(hi, 2.5), "VSWIR"), (max(lo, 2.5), hi, "thermal infrared")]
    for k, (a, b, label) in enumerate(panels):
        ax = fig.add_subplot(1, 2, k + 1)
        if a >= b:
            ax.set_visible(False)
            continue
        sel = (grid >= a) & (grid <= b)
        ax.plot(grid[sel], comps["diffuse_reflectance"][sel] + comps["specular_reflectance"][sel],
                label="reflectance rho_d + rho_s", color="tab:blue")
        if np.any(comps["specular_reflectance"] > 0):
            ax.plot(grid[sel], comps["specular_reflectance"][sel], label="specular rho_s",
                    color="tab:cyan", linestyle="--")
        if np.any(comps["transmittance"] > 0):
            ax.plot(grid[sel], comps["transmittance"][sel], label="transmittance", color="tab:green")
        ax.plot(grid[sel], comps["emissivity"][sel], label="emissivity", color="tab:red")
        ax.set_xlim(a, b)
        ax.set_ylim(0.0, 1.0)
        ax.set_xlabel("wavelength [µm]")
        ax.set_ylabel("[-]")
        ax.set_title(label)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    return path


def plot_material_brdf(material, incidence_angles, path, wavelength: float = 0.55,
                       resolution: int = 61) -> Path:
    """Polar BRDF plots of ``material`` (see :func:`radscene.materials.brdf.plot_brdf`).

    ``resolution`` is the number of view-zenith samples from 0 to 90 deg.
    """
    from radscene.materials.brdf import plot_brdf

    return plot_brdf(
        material_brdf(material),
        incidence_angles,
        path,
        wavelength=wavelength,
        resolution=resolution,
        title=f"{material.name}: BRF = pi f at {wavelength:g} µm (Lambert + Phong lobe)",
    )
