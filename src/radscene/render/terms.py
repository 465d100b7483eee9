"""The signature terms, one pure function each, per ray sample and band.

Symbols follow the seven-term equation (1) and Willers et al. 2011, eq. 4 (OSSIM): τ_a target→sensor, τ_so
sun→target, Δρ and Δε the texture multipliers. Spectral factors arrive already integrated over
the band with the sensor response S (:mod:`radscene.render.spectral`); what is left per sample
is geometry. Every function returns band radiance [W m-2 sr-1], shape (N, n_bands).

==================  ================================================================
term                spectral integrand (× geometry)
==================  ================================================================
sun_diffuse         Δρ · ∫ S E_sun τ_so (ρ_d/π) τ_a dλ · cos θ_i · lit
sun_specular        Δρ · ∫ S E_sun τ_so ρ_s τ_a dλ · (n+1)/(2π) cosⁿ θ_r · lit
thermal_emission    Δε · ∫ S ε B(λ, T) τ_a dλ
sky_reflected       Δρ · Σ_k [∫ S ρ_d L_sky,k τ_a dλ · F_k + ∫ S ρ_s L_sky,k τ_a dλ · G_k]
path_radiance       ∫ S L_path dλ
==================  ================================================================

``sky_reflected`` is also written as its two parts, the sky's scattered sunlight and its
emission (``sky_reflected_solar``, ``sky_reflected_thermal``: the same sums with each part of
L_sky; :mod:`radscene.render.sky_split`).

F_k is the cosine-weighted fraction of the hemisphere that sees sky node k,
(1/π)∫_visible sky h_k(ω) cos θ dω, and G_k the same fraction under the Phong lobe; with
E_sun the irradiance normal to the beam, the OSSIM diffuse term α_s cos θ_s ∫ε_s L(T_s) ρ_o
(α_s = Ω_sun/π) is E_sun ρ_d cos θ_i / π, and its specular term is E_sun ρ_s (n+1)/(2π) cosⁿθ_r.
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere import sky_node_weights

__all__ = ["sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected", "path_radiance",
           "phong_geometry", "leaving_sky"]


def sun_diffuse(coefficient, cos_incidence, lit, texture):
    """Directly reflected sunlight, Lambertian part [W m-2 sr-1].

    Parameters
    ----------
    coefficient : (N, n_b) ∫ S E_sun τ_so (ρ_d/π) τ_a dλ [W m-2 sr-1]
    cos_incidence : (N,) cosine of the sun's incidence angle on the surface [-]
    lit : (N,) 1 where the sun is seen, 0 in cast shadow [-]
    texture : (N,) Δρ [-]
    """
    geometry = np.maximum(cos_incidence, 0.0) * lit * texture
    return coefficient * geometry[:, None]


def phong_geometry(cos_reflection, exponent, cos_incidence, cos_view):
    """The OSSIM lobe (n+1)/(2π) cosⁿ θ_r where sun and sensor are both above the surface [sr-1]."""
    from radscene.materials.brdf import phong

    above = (cos_incidence > 0.0) & (cos_view > 0.0)
    return np.where(above, phong.lobe(cos_reflection, exponent), 0.0)


def sun_specular(coefficient, lobe, lit, texture):
    """Directly reflected sunlight, specular (Phong) lobe [W m-2 sr-1].

    Parameters
    ----------
    coefficient : (N, n_b) ∫ S E_sun τ_so ρ_s τ_a dλ [W m-2 sr-1 sr]
    lobe : (N,) (n+1)/(2π) cosⁿ θ_r [sr-1]
    lit, texture : (N,) as in :func:`sun_diffuse`
    """
    return coefficient * (lobe * lit * texture)[:, None]


def thermal_emission(coefficient, texture):
    """Self-emitted radiance Δε ∫ S ε B(T) τ_a dλ [W m-2 sr-1]; ``coefficient`` (N, n_b)."""
    return coefficient * texture[:, None]


def sky_reflected(diffuse_coefficient, sky_fraction, specular_coefficient, lobe_sky_fraction,
                  texture):
    """Reflected sky radiance, diffuse and specular [W m-2 sr-1].

    Parameters
    ----------
    diffuse_coefficient, specular_coefficient : (N, n_b, n_k) [W m-2 sr-1]; the specular
        one may be None: no specular part
    sky_fraction : (N, n_k) F_k [-]
    lobe_sky_fraction : (N, n_k) G_k [-]
    texture : (N,) Δρ [-]
    """
    total = np.einsum("nbk,nk->nb", diffuse_coefficient, sky_fraction)
    if specular_coefficient is not None:
        total += np.einsum("nbk,nk->nb", specular_coefficient, lobe_sky_fraction)
    return total * texture[:, None]


def path_radiance(coefficient):
    """Atmospheric path radiance ∫ S L_path dλ [W m-2 sr-1]; ``coefficient`` (N, n_b)."""
    return np.asarray(coefficient)


def leaving_sky(directions, sky_nodes, sky_view):
    """The sky radiance seen along rays that leave the scene [W m-2 sr-1], (N, n_b): the sky
    table interpolated at each direction upwards, zero downwards.

    Parameters
    ----------
    directions : (N, 3) unit vectors of the rays (east, north, up)
    sky_nodes : (zenith nodes, azimuth nodes) of the sky table [deg]
    sky_view : (n_b, n_k) ∫ S L_sky,k dλ [W m-2 sr-1]
    """
    dz = directions[:, 2]
    zenith = np.degrees(np.arccos(np.clip(dz, -1.0, 1.0)))
    azimuth = np.degrees(np.arctan2(directions[:, 0], directions[:, 1]))
    return (sky_node_weights(zenith, azimuth, *sky_nodes) @ sky_view.T) * (dz > 0)[:, None]
