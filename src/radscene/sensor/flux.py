"""The flux on a detector, Willers et al. (2011) eq. 7, band by band.

.. math:: \\Phi_{detector} = \\Phi_{scene} \\otimes PSF + \\Phi_{optics} + \\Phi_{mounting}
          + \\Phi_{heated\\,air} + \\Phi_{heated\\,dome}

For a band of response S(λ), a detector of active area A and spectral responsivity R(λ), an
optical cone of projected solid angle Ω_o = π / (4N²) and obscuration ε:

=============  =======================================================================
term           flux [W] (the current [A] or voltage [V] has R(λ) inside the integral)
=============  =======================================================================
scene          A Ω_o (1 - ε²) L_band ⟨τ_dome τ_optics⟩, with ⟨f⟩ = ∫ S f dλ / ∫ S dλ
heated air     A Ω_o (1 - ε²) ∫ S τ_dome τ_optics ε_air B(T_air) dλ
heated dome    A Ω_o (1 - ε²) ∫ S τ_optics ε_dome B(T_dome) dλ
optics         A Ω_o ∫ S [(1 - ε²) ε_optics + ε²] B(T_optics) dλ (the obscuration radiates as a
               blackbody at the optics temperature)
mounting       A (Ω_enclosure - Ω_o) ∫ S ε_mount B(T_mount) dλ, Ω_enclosure = π / (4 N_cs²)
               behind a cold shield of f-number N_cs, else π (the hemisphere)
=============  =======================================================================

The scene term uses the band radiance L_band = ∫ S L dλ from the renderer and the means of
τ and R over the band weighted by S and an assumed scene spectrum w(λ):

.. math:: \\langle f \\rangle = \\frac{\\int S\\, w\\, f\\, d\\lambda}{\\int S\\, w\\, d\\lambda}

exact when the scene spectrum has the shape of w (or τ R is flat over the band). ``w`` is a
blackbody at the ``scene_weighting`` temperature: ``auto`` takes 300 K for bands centred at
or beyond 2.5 um (emission) and 5772 K below (reflected sunlight); ``flat`` takes w = 1. S is
the band's filter response; the optics transmittance and the detector response are separate
factors, not folded into S. The other terms are spectral integrals of Planck functions, exact
to the quadrature.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.planck import spectral_radiance
from radscene.sensor.optics import projected_solid_angle

__all__ = ["BandRadiometry", "band_radiometry", "scene_weighting_temperature",
           "BACKGROUND_TERMS", "SCENE_WEIGHTING"]

#: The self-emission terms of eq. 7 besides the scene.
BACKGROUND_TERMS = ("optics", "mounting", "heated_dome", "heated_air")
#: Named scene weightings; a temperature [K] is accepted too.
SCENE_WEIGHTING = ("auto", "flat")
#: Band centre [um] from which ``auto`` weights by a 300 K blackbody (else by the sun's 5772 K).
THERMAL_WEIGHTING_START = 2.5


def scene_weighting_temperature(weighting, center: float) -> float | None:
    """Blackbody temperature [K] of the scene weighting of a band centred at `center` [um].

    Returns None for ``flat``.
    """
    if weighting is None or weighting == "flat":
        return None
    if weighting == "auto":
        return 300.0 if center >= THERMAL_WEIGHTING_START else 5772.0
    return float(weighting)


@dataclass(frozen=True)
class BandRadiometry:
    """Band-integrated radiometry of one channel (see the module docstring).

    Attributes
    ----------
    nodes, weights : numpy.ndarray
        Band quadrature: wavelengths [um] and weights with S folded in [um].
    equivalent_width : float
        ∫ S dλ [um].
    scene_flux_factor : float
        Flux on the detector per unit band radiance [W / (W m-2 sr-1)] = [m2 sr].
    scene_rate_factor : float
        Detector current (or voltage) per unit band radiance [A or V / (W m-2 sr-1)].
    responsivity : float
        Effective responsivity of the scene term, rate / flux [A W-1 or V W-1].
    background_flux, background_rate : dict
        Per term of :data:`BACKGROUND_TERMS`: flux [W] and current [A] (or voltage [V]).
    shutter_rate : float
        Rate from a blackbody shutter filling the optical cone (DCS reference), without the
        mounting term [A or V]; a function of its temperature, see :meth:`shutter`.
    system_weights : numpy.ndarray
        Quadrature weights of S τ R at the nodes [um A W-1] (or [um V W-1]).
    otf_weights : numpy.ndarray
        ``system_weights`` times the scene weighting, for the polychromatic OTF.
    scene_etendue : float
        A Ω_o (1 - ε²) [m2 sr].
    cone_weights : numpy.ndarray
        Rate per unit spectral radiance at the nodes of a source filling the optical cone,
        quadrature weights included [A or V / (W m-2 sr-1 um-1)]: :meth:`shutter_rate` is
        their product with a blackbody's spectral radiance.
    """

    nodes: np.ndarray
    weights: np.ndarray
    equivalent_width: float
    scene_flux_factor: float
    scene_rate_factor: float
    responsivity: float
    background_flux: dict = field(default_factory=dict)
    background_rate: dict = field(default_factory=dict)
    system_weights: np.ndarray | None = None
    otf_weights: np.ndarray | None = None
    scene_etendue: float = 0.0
    cone_weights: np.ndarray | None = None

    @property
    def background_rate_total(self) -> float:
        """Sum of the self-emission rates [A or V]."""
        return float(sum(self.background_rate.values()))

    def shutter_rate(self, temperature: float) -> float:
        """Rate from a blackbody at `temperature` [K] filling the optical cone [A or V]."""
        return float(self.cone_weights @ spectral_radiance(self.nodes, temperature))

    def scene_rate_of_spectrum(self, spectral_radiance_values) -> np.ndarray:
        """Exact scene rate of a scene spectrum given at :attr:`nodes` [W m-2 sr-1 um-1].

        Returns G ∫ S τ R L dλ [A or V]; values may carry leading axes (..., nodes).
        """
        return self.scene_etendue * (np.asarray(spectral_radiance_values, dtype=float)
                                     @ self.system_weights)

    def blackbody_radiance(self, temperature: float) -> float:
        """Band radiance ∫ S B(λ, T) dλ of a blackbody [W m-2 sr-1]."""
        return float(self.weights @ spectral_radiance(self.nodes, temperature))

    def band_integral(self, function) -> float:
        """∫ S f dλ for ``function(wavelength [um])`` [unit of f × um]."""
        return float(self.weights @ np.asarray(function(self.nodes), dtype=float))


def _breakpoints(spectra) -> np.ndarray:
    points = [s.wavelength for s in spectra if s is not None and s.wavelength is not None]
    return np.concatenate(points) if points else np.empty(0)


def band_radiometry(optics, detector, response, key: str = "response",
                    scene_weighting="auto") -> BandRadiometry:
    """Integrate the radiometry of one channel over a band.

    Parameters
    ----------
    optics : radscene.sensor.Optics
    detector : radscene.sensor.PhotonDetector or radscene.sensor.Microbolometer
    response : radscene.radiometry.SpectralResponse
        The band's response S.
    key : str
        Config key of the response, for errors.
    scene_weighting : {"auto", "flat"} or float
        Assumed scene spectrum of the band means (see the module docstring), or a
        blackbody temperature [K].

    Returns
    -------
    BandRadiometry

    Raises
    ------
    ConfigError
        When S, or S τ R, does not integrate to a positive value over the band (`key`), or
        the cold shield is narrower than the optical beam.
    """
    from radscene.render.spectral import band_quadrature

    spectra = [optics.transmittance, optics.emissivity, optics.mounting_emissivity,
               *(detector.spectra())]
    if optics.dome is not None:
        spectra += [optics.dome.transmittance, optics.dome.emissivity]
    if optics.heated_air is not None:
        spectra.append(optics.heated_air.emissivity)
    nodes, weights = band_quadrature(response, _breakpoints(spectra))
    width = float(weights.sum())
    if not width > 0:
        raise ConfigError(f"the spectral response {getattr(response, 'name', '')!r} does not "
                          "integrate to a positive value", key=key)
    resp = detector.spectral_responsivity(nodes)
    tau_optics = optics.transmittance(nodes)
    tau_dome = optics.dome.transmittance(nodes) if optics.dome is not None else 1.0
    tau_scene = tau_optics * tau_dome
    eps = optics.obscuration
    area = detector.active_area
    omega = float(projected_solid_angle(optics.f_number))
    g_cone = area * omega
    g_scene = g_cone * (1.0 - eps * eps)
    system = weights * tau_scene * resp
    if not system.sum() > 0:
        raise ConfigError("the system response S(λ) τ(λ) R(λ) (band × optics transmittance × "
                          "detector responsivity) does not integrate to a positive value",
                          key=key)
    t_w = scene_weighting_temperature(scene_weighting, float(nodes @ weights) / width)
    w_scene = weights * spectral_radiance(nodes, t_w) if t_w is not None else weights
    flux_factor = g_scene * float(w_scene @ tau_scene) / float(w_scene.sum())
    rate_factor = g_scene * float(w_scene @ (tau_scene * resp)) / float(w_scene.sum())

    def planck(t):
        return spectral_radiance(nodes, t)

    flux, rate = {}, {}

    def add(term, geometry, spectral):
        flux[term] = float(geometry * (weights @ spectral))
        rate[term] = float(geometry * (weights @ (spectral * resp)))

    eps_optics = optics.optics_emissivity(nodes)
    add("optics", g_cone, ((1.0 - eps * eps) * eps_optics + eps * eps) * planck(optics.temperature))
    if detector.cold_shield_f_number is not None:
        if detector.cold_shield_f_number > optics.f_number * (1 + 1e-12):
            raise ConfigError(
                f"the cold shield (F/{detector.cold_shield_f_number:g}) is narrower than the "
                f"optical beam (F/{optics.f_number:g}); it must not exceed optics.f_number",
                key="detector.cold_shield_f_number")
        omega_enclosure = float(projected_solid_angle(detector.cold_shield_f_number))
    else:
        omega_enclosure = np.pi
    add("mounting", area * (omega_enclosure - omega),
        optics.mounting_emissivity(nodes) * planck(optics.mounting_temperature_k))
    if optics.dome is not None:
        add("heated_dome", g_scene,
            tau_optics * optics.dome.emissivity(nodes) * planck(optics.dome.temperature))
    else:
        flux["heated_dome"] = rate["heated_dome"] = 0.0
    if optics.heated_air is not None:
        add("heated_air", g_scene,
            tau_scene * optics.heated_air.emissivity(nodes) * planck(optics.heated_air.temperature))
    else:
        flux["heated_air"] = rate["heated_air"] = 0.0
    return BandRadiometry(
        nodes=nodes, weights=weights, equivalent_width=width, scene_flux_factor=flux_factor,
        scene_rate_factor=rate_factor, responsivity=rate_factor / flux_factor if flux_factor else 0.0,
        background_flux=flux, background_rate=rate, system_weights=system,
        otf_weights=system if t_w is None else system * spectral_radiance(nodes, t_w),
        scene_etendue=g_scene,
        cone_weights=g_cone * weights * resp)
