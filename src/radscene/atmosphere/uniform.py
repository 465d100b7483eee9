"""Engines with a user-set atmosphere: ``none`` (vacuum) and ``uniform``.

``uniform`` takes its spectra from the user: a constant or a spectrum for each quantity, the
same for every line of sight. It is the engine of closed-form tests and of scenes where the
user has the atmosphere from elsewhere.

Parameters of ``uniform`` (scene file ``environment.atmosphere``):

==========================  ====================  =========  =======================================
name                        unit                  default    meaning
==========================  ====================  =========  =======================================
``transmittance``           -                     1          τ_a, target to observer
``sun_transmittance``       -                     τ_a        τ_so, sun to target
``path_radiance``           W m-2 sr-1 um-1       0          path radiance, thermal + scattered
``sky_radiance``            W m-2 sr-1 um-1       0          sky radiance seen from the ground
``sky_solar_radiance``      W m-2 sr-1 um-1       (none)     its scattered sunlight, given apart
``sky_thermal_radiance``    W m-2 sr-1 um-1       (none)     its emission, given apart
``sky_zenith``              deg                   (none)     zenith nodes of a tabulated sky
``sky_profile``             -                     (none)     multiplier of ``sky_radiance`` there
==========================  ====================  =========  =======================================

Each spectral value is a number or ``{wavelength: [...], values: [...]}``. The sky is either
``sky_radiance``, or its two parts (either or both; a missing one is 0): the sky's scattered
sunlight and its emission, which the render keeps apart (``sky_reflected_solar``,
``sky_reflected_thermal``). A ``sky_radiance`` the engine cannot split: it counts as
scattered sunlight below :data:`~radscene.atmosphere.base.SKY_CROSSOVER_WAVELENGTH` (4 µm)
and as emission beyond (:meth:`~radscene.atmosphere.base.Atmosphere.sky_parts`). Example::

    atmosphere:
      type: uniform
      transmittance: 0.9
      path_radiance: {wavelength: [0.4, 20], values: [5.0, 1.0]}
      sky_radiance: 2.0
      sky_zenith: [0, 60, 90]
      sky_profile: [1.0, 1.5, 3.0]
"""

from __future__ import annotations

import numpy as np

from radscene.atmosphere.base import (
    Atmosphere,
    PathSpectra,
    SkyGeometry,
    SkyParts,
    SunSpectra,
    zenith_hat_weights,
)
from radscene.errors import ConfigError

__all__ = ["VacuumAtmosphere", "UniformAtmosphere"]


def _sky_parts_given(total, solar, thermal):
    """The sky's parts (solar, thermal), each a spectrum or None, where the user gave them;
    None where the sky is ``total`` alone."""
    if solar is None and thermal is None:
        return None
    if total is not None:
        raise ConfigError("give sky_radiance or its parts sky_solar_radiance and "
                          "sky_thermal_radiance, not both", key="atmosphere.sky_radiance")
    return tuple(None if v is None else _spectrum(v, f"atmosphere.sky_{n}_radiance")
                 for v, n in ((solar, "solar"), (thermal, "thermal")))


class _SkySum:
    """The sky's two given parts summed, a spectrum as ``make_spectrum`` makes them."""

    def __init__(self, solar, thermal):
        self.parts = tuple(p for p in (solar, thermal) if p is not None)
        self.values = np.concatenate([np.atleast_1d(p.values) for p in self.parts])
        grids = [np.asarray(p.wavelength, float) for p in self.parts if p.wavelength is not None]
        self.wavelength = np.unique(np.concatenate(grids)) if grids else None  # breakpoints
        ranges = [p.defined_range for p in self.parts]
        self.defined_range = (max(r[0] for r in ranges), min(r[1] for r in ranges))

    def __call__(self, wavelength):
        return sum(p(wavelength) for p in self.parts)


def _spectrum(value, key):
    from radscene.materials.spectrum import make_spectrum

    return make_spectrum(value, key=key)


class UniformAtmosphere(Atmosphere):
    """The same user-set spectra for every line of sight; see the module table."""

    name = "uniform"
    geometry_dependent = False

    @property
    def wavelength_range(self) -> tuple[float, float]:
        """Where every one of its spectra can be evaluated, within 0.2-100 um [um]."""
        lo, hi = 0.2, 100.0
        for spec in (self.transmittance, self.sun_transmittance, self.path_radiance,
                     self.sky_radiance, *(p for p in self._sky_given if p is not None)):
            a, b = spec.defined_range
            lo, hi = max(lo, a), min(hi, b)
        return (lo, hi)

    def __init__(
        self,
        transmittance=1.0,
        sun_transmittance=None,
        path_radiance=0.0,
        sky_radiance=None,
        sky_zenith=None,
        sky_profile=None,
        sky_solar_radiance=None,
        sky_thermal_radiance=None,
    ):
        self.transmittance = _spectrum(transmittance, "atmosphere.transmittance")
        self.sun_transmittance = (
            self.transmittance
            if sun_transmittance is None
            else _spectrum(sun_transmittance, "atmosphere.sun_transmittance")
        )
        self.path_radiance = _spectrum(path_radiance, "atmosphere.path_radiance")
        self._sky_given = _sky_parts_given(sky_radiance, sky_solar_radiance,
                                           sky_thermal_radiance)
        self.sky_radiance = (_spectrum(0.0 if sky_radiance is None else sky_radiance,
                                       "atmosphere.sky_radiance")
                             if self._sky_given is None else _SkySum(*self._sky_given))
        self._sky_given = self._sky_given or ()
        for key, spec in (
            ("transmittance", self.transmittance),
            ("sun_transmittance", self.sun_transmittance),
        ):
            values = np.asarray(spec.values, dtype=float)
            if np.any(values < 0) or np.any(values > 1):
                raise ConfigError("transmittance must lie in [0, 1]", key=f"atmosphere.{key}")
        for key, spec in (("path_radiance", self.path_radiance), ("sky_radiance", self.sky_radiance)):
            if np.any(np.asarray(spec.values, dtype=float) < 0):
                raise ConfigError("radiance must be >= 0", key=f"atmosphere.{key}")
        if (sky_zenith is None) != (sky_profile is None):
            raise ConfigError(
                "give both sky_zenith and sky_profile, or neither", key="atmosphere.sky_zenith"
            )
        if sky_zenith is None:
            self._sky_nodes = np.array([0.0])
            self._sky_profile = np.array([1.0])
        else:
            nodes = np.asarray(sky_zenith, dtype=float)
            profile = np.asarray(sky_profile, dtype=float)
            if nodes.ndim != 1 or nodes.size < 2 or np.any(np.diff(nodes) <= 0):
                raise ConfigError(
                    "a list of at least two increasing zenith angles in [0, 90] deg",
                    key="atmosphere.sky_zenith",
                )
            if nodes[0] < 0 or nodes[-1] > 90:
                raise ConfigError("zenith angles must lie in [0, 90] deg", key="atmosphere.sky_zenith")
            if profile.shape != nodes.shape or np.any(profile < 0):
                raise ConfigError(
                    f"{nodes.size} non-negative multipliers, one per sky_zenith node",
                    key="atmosphere.sky_profile",
                )
            self._sky_nodes = nodes
            self._sky_profile = profile

    def path(self, observer_altitude, target_altitude, view_zenith, wavelength,
             view_azimuth=None) -> PathSpectra:
        """The same spectra for every line of sight (``view_azimuth`` is not used)."""
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(
            np.asarray(observer_altitude), np.asarray(target_altitude), np.asarray(view_zenith)
        ).shape
        full = shape + wl.shape
        return PathSpectra(
            transmittance=np.broadcast_to(self.transmittance(wl), full).copy(),
            thermal_radiance=np.broadcast_to(self.path_radiance(wl), full).copy(),
            scattered_radiance=np.zeros(full),
        )

    def sun(self, target_altitude, sun_zenith, wavelength, toa_irradiance) -> SunSpectra:
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(target_altitude), np.asarray(sun_zenith)).shape
        tau = np.broadcast_to(self.sun_transmittance(wl), shape + wl.shape).copy()
        return SunSpectra(transmittance=tau, irradiance=tau * np.asarray(toa_irradiance, float))

    def sky(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None) -> np.ndarray:
        wl = self.check_wavelength(wavelength)
        zenith, _ = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
        return self._sky_factor(zenith, azimuth)[..., None] * self.sky_radiance(wl)

    def sky_parts(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None
                  ) -> SkyParts:
        """The user's ``sky_solar_radiance`` and ``sky_thermal_radiance``, where given; else
        ``sky_radiance`` split at the crossover wavelength (the module's description)."""
        if not self._sky_given:
            return super().sky_parts(zenith, azimuth, wavelength, geometry)
        wl = self.check_wavelength(wavelength)
        factor = self._sky_factor(zenith, azimuth)[..., None]
        solar, thermal = (factor * (0.0 if p is None else p(wl)) for p in self._sky_given)
        return SkyParts(solar=np.broadcast_to(solar, factor.shape[:-1] + wl.shape).copy(),
                        thermal=np.broadcast_to(thermal, factor.shape[:-1] + wl.shape).copy())

    def _sky_factor(self, zenith, azimuth) -> np.ndarray:
        """The sky profile's multiplier in each direction (broadcast zenith, azimuth)."""
        zenith, _ = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
        return zenith_hat_weights(zenith, self._sky_nodes) @ self._sky_profile

    def sky_zenith_nodes(self) -> np.ndarray:
        return self._sky_nodes.copy()


class VacuumAtmosphere(UniformAtmosphere):
    """No atmosphere: τ = 1, no path radiance, a black sky (engine ``none``)."""

    name = "none"

    def __init__(self):
        super().__init__()
