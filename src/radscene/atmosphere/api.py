"""One line of sight, or one sky, through any atmosphere engine: the Python face of
``radscene atmosphere los`` and ``radscene atmosphere sky``.

:func:`line_of_sight` and :func:`sky_radiance` build an engine from plain options (the same
names for every engine), run it, and return an :class:`xarray.Dataset` over wavelength [um]
with radiances in W m-2 sr-1 um-1 and CF attributes, plus band values
(:mod:`radscene.atmosphere.bands`: response-weighted integrals and means, brightness
temperatures of thermal bands).

Options shared by both:

========================  ==========  ===============  ==============================================
name                      unit        default          meaning
========================  ==========  ===============  ==============================================
``engine``                -           ``database``     ``database``, ``sixs`` or ``lowtran``
``profile``               -           ``us_standard``  gas profile (LOWTRAN's ``model``)
``aerosol``               -           ``rural``        aerosol model
``visibility``            m           23 km            horizontal visibility (> 0; "23 km" accepted),
                                                       or ...
``aot550``                -           (none)           ... aerosol optical thickness at 550 nm (not
                                                       with ``visibility``; not LOWTRAN)
``water``                 g cm-2      (profile's)      water vapour column (not LOWTRAN; 6S: with
``ozone``                 cm-atm      (profile's)      ``ozone``, scaling the US 1962 profile)
``multiple_scattering``   -           true             (6S and the database always scatter multiply)
``sun_zenith``            deg         30               sun position (≥ 90: night)
``sun_azimuth``           deg         180              clockwise from north
``date``                  -           (none)           calendar date (``YYYY-MM-DD``): the
                                                       Earth–Sun distance (NREL SPA, 12:00 UTC), or
                                                       LOWTRAN's day of year
``earth_sun_distance``    AU          1                instead of ``date`` (not LOWTRAN)
``solar_spectrum``        -           engine's         E_0: ``radscene``, ``tsis1``, ``6s``,
                                                       ``lowtran`` (:data:`SOLAR_SPECTRA`,
                                                       :data:`ENGINE_SPECTRA`)
``surface_albedo``        -           0                albedo of the surroundings the engine's sky
                                                       sees (LOWTRAN: SALB)
``ground_albedo``         -           surface_albedo   (``line_of_sight``) albedo of the uniform
                                                       Lambertian ground in ``apparent_radiance``
``surface_temperature``   K           (none)           for the ground's emission in
                                                       ``apparent_radiance``
``wavelength``            um          (grid)           explicit wavelengths, or ...
``wavelength_range``      um          engine's/bands'  ... a (min, max) range sampled every ``step``
``step``                  um          0.005 / 0.05     grid step below / above 4 um
``bands``                 um / -      the range        (min, max) pairs and/or spectral responses
                                                       (:class:`~radscene.radiometry.srf.
                                                       SpectralResponse`, e.g. a sensor's band)
``database``              -           ``default``      database file or name (engine ``database``)
========================  ==========  ===============  ==============================================

Solar spectra and where they come from: :mod:`radscene.atmosphere.options`
(:data:`SOLAR_SPECTRA`): ASTM G173-03/Gueymard (``radscene``), TSIS-1 HSRS v2 (``tsis1``),
6S's and LOWTRAN7's own.

Example
-------
>>> ds = line_of_sight(100_000, 0, 30, wavelength=[0.55, 0.65])   # doctest: +SKIP
>>> float(ds["transmittance"].sel(wavelength=0.55))                # doctest: +SKIP

References
----------
E. F. Vermote et al., IEEE Trans. Geosci. Remote Sens. 35, 675-686 (1997) (6S, the coupling
of the ground), https://doi.org/10.1109/36.581987
"""

from __future__ import annotations

import json

import numpy as np
import xarray as xr

from radscene.atmosphere import sixs_model as model
from radscene.atmosphere.bands import attach_bands, band_responses
from radscene.atmosphere.options import (
    ENGINE_SPECTRA,
    SOLAR_SPECTRA,
    check_options,
    database_keywords,
    option_attrs,
    sun_date,
)
from radscene.errors import ConfigError, did_you_mean

__all__ = ["line_of_sight", "sky_radiance", "make_engine", "sun_date", "ENGINE_NAMES",
           "SOLAR_SPECTRA", "ENGINE_SPECTRA"]

#: Engines the API and the CLI drive.
ENGINE_NAMES = ("database", "sixs", "lowtran")
_RAD = "W m-2 sr-1 um-1"


def _make(engine, profile, aerosol, visibility, multiple_scattering, sun_zenith, sun_azimuth,
          view_azimuth, surface_albedo, surface_temperature, database, aot550=None, water=None,
          ozone=None, date=None, earth_sun_distance=None, solar_spectrum=None):
    """(engine, settings) of :func:`make_engine`."""
    name = str(engine).lower()
    if name not in ENGINE_NAMES:
        raise ConfigError(f"unknown engine {engine!r}; known: {', '.join(ENGINE_NAMES)}"
                          f"{did_you_mean(engine, ENGINE_NAMES)}",
                          key="engine")
    settings = check_options(name, visibility, aot550, water, ozone, date,
                             earth_sun_distance, solar_spectrum)
    vis = settings["visibility"]
    sz, sa = float(sun_zenith), float(sun_azimuth)
    if not 0.0 <= sz <= 180.0:
        raise ConfigError(f"must lie in [0, 180] deg; got {sun_zenith!r}", key="sun_zenith")
    albedo = float(surface_albedo)
    if not 0.0 <= albedo <= 1.0:
        raise ConfigError(f"must lie in [0, 1]; got {surface_albedo!r}", key="surface_albedo")
    if surface_temperature is not None and not float(surface_temperature) > 0:
        raise ConfigError(f"must be > 0 K; got {surface_temperature!r}",
                          key="surface_temperature")
    if name == "lowtran":
        from radscene.atmosphere.lowtran import LowtranAtmosphere

        return LowtranAtmosphere(model=profile, aerosol=aerosol, visibility=vis / 1000.0,
                                 multiple_scattering=bool(multiple_scattering),
                                 albedo=albedo, ground_temperature=surface_temperature,
                                 sun_zenith=sz if sz < 90 else None,
                                 sun_azimuth=sa if sz < 90 else None, view_azimuth=view_azimuth,
                                 day_of_year=settings["day_of_year"], water=settings["water"],
                                 ozone=settings["ozone"]), settings
    if not multiple_scattering:
        raise ConfigError(f"the {name} engine always includes multiple scattering; "
                          "use engine lowtran to switch it off", key="multiple_scattering")
    if name == "sixs":
        from radscene.atmosphere.sixs import SixSAtmosphere

        return SixSAtmosphere(profile=profile, aerosol=aerosol, visibility=vis,
                              aot550=settings["aot550"], water=settings["water"],
                              ozone=settings["ozone"], surface_albedo=albedo, sun_zenith=sz,
                              sun_azimuth=sa, view_azimuth=view_azimuth,
                              earth_sun_distance=settings["distance"],
                              solar_spectrum=settings["solar_spectrum"]), settings
    from radscene.atmosphere.database import DatabaseAtmosphere

    return DatabaseAtmosphere(file=database, profile=profile, aerosol=aerosol, visibility=vis,
                              surface_albedo=albedo, sun_zenith=sz, sun_azimuth=sa,
                              view_azimuth=view_azimuth, earth_sun_distance=settings["distance"],
                              **database_keywords(settings)), settings


def make_engine(engine="database", profile="us_standard", aerosol="rural", visibility=None,
                multiple_scattering=True, sun_zenith=30.0, sun_azimuth=180.0, view_azimuth=None,
                surface_albedo=0.0, surface_temperature=None, database=None, *, aot550=None,
                water=None, ozone=None, date=None, earth_sun_distance=None,
                solar_spectrum=None):
    """Build an engine from the shared options (module table); checks them all first.

    ``visibility`` None means 23 km unless ``aot550`` is given. An option the engine does
    not take (``aot550`` with LOWTRAN, the ``6s`` spectrum with the database, ...) raises
    :class:`~radscene.errors.ConfigError` naming it.
    """
    return _make(engine, profile, aerosol, visibility, multiple_scattering, sun_zenith,
                 sun_azimuth, view_azimuth, surface_albedo, surface_temperature, database,
                 aot550, water, ozone, date, earth_sun_distance, solar_spectrum)[0]


def _toa(atm, settings, target_altitude, wavelength):
    """The engine's top-of-atmosphere solar irradiance at the settings' distance
    [W m-2 um-1]: from the engine itself for 6S and the database (their spectrum), LOWTRAN's
    own spectrum for LOWTRAN's direct beam (the one that lights its sky)."""
    if atm.name == "lowtran":
        from radscene.sun import engine_distance, engine_spectrum, toa_solar_irradiance

        return toa_solar_irradiance(wavelength, engine_distance(atm, settings["distance"]),
                                    engine_spectrum(atm))
    comp = atm.components(model.TOP_OF_ATMOSPHERE, target_altitude, 0.0, wavelength,
                          sun_zenith=min(float(atm.sun_zenith), 89.0), relative_azimuth=0.0)
    toa = comp["toa_irradiance"]
    return np.asarray(getattr(toa, "values", toa), dtype=float).reshape(-1, wavelength.size)[0]


def _band_range(atm, bands):
    """(min, max) [um] over the bands' supports, each checked against the engine's range."""
    responses = band_responses(bands, np.array([0.0, np.inf]))
    for i, response in enumerate(responses):
        atm.check_wavelength(np.array(response.support), key=f"bands[{i}]")
    return (min(r.support[0] for r in responses), max(r.support[1] for r in responses))


def _grid(atm, wavelength, wavelength_range, step, bands=None):
    """The wavelengths [um]: given, or a range (given, else the bands', else the engine's)
    sampled every ``step``."""
    if wavelength is not None:
        wl = np.atleast_1d(np.asarray(wavelength, dtype=float))
        if wl.ndim != 1 or wl.size == 0 or np.any(~np.isfinite(wl)) or np.any(wl <= 0):
            raise ConfigError("a non-empty list of positive wavelengths [µm]", key="wavelength")
        return atm.check_wavelength(np.unique(wl))
    if wavelength_range is None and bands:
        wavelength_range = _band_range(atm, bands)
    if wavelength_range is None:
        lo, hi = atm.wavelength_range
        lo, hi = max(float(lo), 0.4), min(float(hi), 20.0)
    else:
        lo, hi = float(wavelength_range[0]), float(wavelength_range[1])
    if not (np.isfinite(lo) and np.isfinite(hi) and 0 < lo < hi):
        raise ConfigError(f"an increasing (min, max) pair [µm]; got {wavelength_range!r}",
                          key="wavelength_range")
    atm.check_wavelength(np.array([lo, hi]), key="wavelength_range")
    if step is not None:
        if not float(step) > 0:
            raise ConfigError(f"must be > 0 µm; got {step!r}", key="step")
        wl = np.arange(lo, hi + 1e-9, float(step))
    else:
        short = np.arange(lo, min(hi, 4.0) + 1e-9, 0.005) if lo < 4.0 else np.zeros(0)
        long_ = (np.arange(max(lo, 4.0), hi + 1e-9, 0.05) if hi > 4.0 else np.zeros(0))
        wl = np.unique(np.round(np.concatenate([short, long_, [lo, hi]]), 6))
    return np.unique(np.clip(np.concatenate([wl, [lo, hi]]), lo, hi))


def _planck(wl, temperature):
    from radscene.radiometry import spectral_radiance

    return spectral_radiance(wl, float(temperature))


def _one_number(name, value):
    if np.ndim(value) or not np.isfinite(float(value)):
        raise ConfigError("one finite number", key=name)
    return float(value)


def line_of_sight(observer_altitude, target_altitude=0.0, view_zenith=0.0, *, engine="database",
                  profile="us_standard", aerosol="rural", visibility=None, aot550=None,
                  water=None, ozone=None, multiple_scattering=True, sun_zenith=30.0,
                  sun_azimuth=180.0, view_azimuth=None, date=None, earth_sun_distance=None,
                  solar_spectrum=None, surface_albedo=0.0, ground_albedo=None,
                  surface_temperature=None, wavelength=None, wavelength_range=None, step=None,
                  bands=None, database=None) -> xr.Dataset:
    """One slant path: transmittance and path radiance, thermal and solar, per wavelength.

    Parameters
    ----------
    observer_altitude, target_altitude : float
        [m]; an observer at or above 100 km is in space.
    view_zenith : float
        Zenith of the direction from target to observer [deg].
    view_azimuth : float, optional
        Azimuth of that direction [deg, clockwise from north]; default: azimuthal mean
        (6S/database) or the engine's rule (LOWTRAN).
    ground_albedo : float, optional
        Albedo ρ of the uniform Lambertian ground whose radiance ``apparent_radiance`` is
        [0-1]; default ``surface_albedo``.
    others
        See the module table.

    Returns
    -------
    xarray.Dataset
        Over ``wavelength`` [um]: ``transmittance`` [1], ``path_thermal_radiance``,
        ``path_scattered_radiance``, ``path_radiance`` [W m-2 sr-1 um-1],
        ``sun_transmittance`` [1], ``direct_solar_irradiance`` (normal to the beam)
        [W m-2 um-1], ``apparent_radiance`` at the observer of the ground (see Notes)
        [W m-2 sr-1 um-1]; for every engine that couples (6S, the database, LOWTRAN) also (from its ``coupling``)
        ``diffuse_irradiance`` (horizontal, over black ground), ``spherical_albedo`` and
        ``diffuse_transmittance``; and over ``band`` the band values of
        :mod:`radscene.atmosphere.bands`. Attributes record the engine, geometry,
        atmosphere, Earth–Sun distance and solar spectrum.

    Raises
    ------
    ConfigError
        Bad options, a path below the ground or a target above 100 km, wavelengths or bands
        outside the engine's range, an option the engine does not take — before any engine
        runs.

    Notes
    -----
    With an engine that couples the ground to the atmosphere (6S, the database, LOWTRAN: its
    :meth:`~radscene.atmosphere.base.Atmosphere.coupling`), the ground of albedo ρ at
    temperature T gives (Vermote et al. 1997; ρ_e = ρ in
    :class:`~radscene.atmosphere.base.CouplingSpectra`)

    .. math:: L = L_{path} + \\frac{\\rho}{1 - S\\rho} \\frac{E_{dir} + E_{dif}}{\\pi}
              (T_{dir} + t_d) + T_{dir} (1 - \\rho) B(\\lambda, T)

    with S the spherical albedo, T_dir and t_d the direct and diffuse transmittances ground to
    observer (LOWTRAN's from its runs at three ground albedos,
    :mod:`radscene.atmosphere.lowtran.coupling`).
    """
    o = _one_number("observer_altitude", observer_altitude)
    t = _one_number("target_altitude", target_altitude)
    z = _one_number("view_zenith", view_zenith)
    atm, settings = _make(engine, profile, aerosol, visibility, multiple_scattering, sun_zenith,
                          sun_azimuth, view_azimuth, surface_albedo, surface_temperature,
                          database, aot550, water, ozone, date, earth_sun_distance,
                          solar_spectrum)
    rho = float(surface_albedo) if ground_albedo is None else float(ground_albedo)
    if not 0.0 <= rho <= 1.0:
        raise ConfigError(f"must lie in [0, 1]; got {ground_albedo!r}", key="ground_albedo")
    if str(engine).lower() == "lowtran":
        # LOWTRAN's path over black ground, as the other engines': its coupling adds the
        # ground of ground_albedo
        atm, settings = _make(engine, profile, aerosol, visibility, multiple_scattering,
                              sun_zenith, sun_azimuth, view_azimuth, 0.0, surface_temperature,
                              database, aot550, water, ozone, date, earth_sun_distance,
                              solar_spectrum)
    min_target = getattr(atm, "bottom_altitude", 0.0) if atm.name == "lowtran" else (
        atm.axes["surface_altitude"][0] - 500.0 if atm.name == "database" else 0.0)
    model.check_path_geometry(o, t, z, min_target=min_target)
    wl = _grid(atm, wavelength, wavelength_range, step, bands)
    band_responses(bands, wl)
    sz = float(sun_zenith)
    sun_up = sz < 90.0
    if atm.name == "lowtran":
        ds = atm.line_of_sight(o, t, z, wavelength=wl)
        # (its boundary_radiance is that of a black ground: the emission is added below)
        ds = ds.sortby("wavelength").drop_vars("boundary_radiance", errors="ignore")
        cp = atm.coupling(o, t, z, ds["wavelength"].values)
        for name, values, long_name in (
                ("direct_irradiance", cp.direct_irradiance, "direct solar irradiance on a "
                 "horizontal surface"),
                ("diffuse_irradiance", cp.diffuse_irradiance, "diffuse sky irradiance on a "
                 "horizontal surface over black ground (LOWTRAN's two-stream flux)"),
                ("spherical_albedo", cp.spherical_albedo, "spherical albedo (of the line of "
                 "sight, see radscene.atmosphere.lowtran.coupling)"),
                ("diffuse_transmittance", cp.diffuse_transmittance, "diffuse transmittance "
                 "target to observer, gases included (the adjacency effect)")):
            ds[name] = ("wavelength", np.asarray(values, float),
                        {"units": "W m-2 um-1" if name.endswith("irradiance") else "1",
                         "long_name": long_name})
        attrs = {"parameters": ds.attrs.get("parameters", "")}
        note = ("LOWTRAN: apparent_radiance = L_path(black ground) + (tau + t_d) rho/pi "
                "(E_dir + E_dif) / (1 - rho S) + tau (1 - rho) B(T), the coupling from LOWTRAN "
                "runs at ground albedos 0, 1/2, 1: LOWTRAN's own radiance of the surface "
                "within 0.3 %")
        e_total = ds["direct_irradiance"].values + ds["diffuse_irradiance"].values
        t_all = ds["transmittance"].values + ds["diffuse_transmittance"].values
        reflected = (rho / (1.0 - ds["spherical_albedo"].values * rho) * e_total / np.pi
                     * t_all)
    else:
        path = atm.path(o, t, z, wl)
        zero = np.zeros(wl.size)
        if sun_up:
            toa = _toa(atm, settings, t, wl)
            sun = atm.sun(t, sz, wl, toa)
            tau_sun, e_sun = sun.transmittance, sun.irradiance
        else:
            tau_sun, e_sun = zero, zero
        cp = atm.coupling(o, t, z, wl)
        variables = {
            "transmittance": (path.transmittance, "1",
                              "path transmittance, target to observer (direct)"),
            "path_thermal_radiance": (path.thermal_radiance, _RAD, "thermal path radiance"),
            "path_scattered_radiance": (path.scattered_radiance, _RAD,
                                        "scattered solar path radiance"),
            "path_radiance": (path.radiance, _RAD, "path radiance, thermal + scattered"),
            "sun_transmittance": (tau_sun, "1", "sun-to-target transmittance (direct)"),
            "direct_solar_irradiance": (e_sun, "W m-2 um-1",
                                        "direct solar irradiance at the target, normal to "
                                        "the beam"),
            "direct_irradiance": (cp.direct_irradiance, "W m-2 um-1",
                                  "direct solar irradiance on a horizontal surface"),
            "diffuse_irradiance": (cp.diffuse_irradiance, "W m-2 um-1",
                                   "diffuse sky irradiance on a horizontal surface over "
                                   "black ground"),
            "spherical_albedo": (cp.spherical_albedo, "1", "spherical albedo"),
            "diffuse_transmittance": (cp.diffuse_transmittance, "1",
                                      "diffuse transmittance target to observer, gases "
                                      "included"),
        }
        ds = xr.Dataset({k: ("wavelength", np.asarray(v, float).reshape(wl.size),
                             {"units": u, "long_name": ln})
                         for k, (v, u, ln) in variables.items()},
                        coords={"wavelength": ("wavelength", wl, {"units": "um"})})
        describe = atm.describe() if hasattr(atm, "describe") else dict(atm.conditions)
        attrs = {"parameters": json.dumps(describe, default=str)}
        note = ("coupled (engine coupling()): apparent_radiance = L_path + rho / (1 - S rho) "
                "(E_dir + E_dif) / pi (T_dir + t_d) + T_dir (1 - rho) B(T), for a uniform "
                "Lambertian ground of albedo rho")
        e_total = ds["direct_irradiance"].values + ds["diffuse_irradiance"].values
        t_all = ds["transmittance"].values + ds["diffuse_transmittance"].values
        reflected = (rho / (1.0 - ds["spherical_albedo"].values * rho) * e_total / np.pi
                     * t_all)
    emitted = ((1.0 - rho) * _planck(wl, surface_temperature)
               if surface_temperature is not None else np.zeros(wl.size))
    ds["apparent_radiance"] = ("wavelength", ds["path_radiance"].values + reflected
                               + ds["transmittance"].values * emitted,
                               {"units": _RAD, "long_name": "radiance at the observer of a "
                                "uniform Lambertian ground of ground_albedo (and its "
                                "emission)"})
    ds = attach_bands(ds, bands)
    ds.attrs.update({
        "engine": atm.name, "observer_altitude_m": o, "target_altitude_m": t,
        "view_zenith_deg": z, "sun_zenith_deg": sz, "sun_azimuth_deg": float(sun_azimuth),
        "surface_albedo": float(surface_albedo), "ground_albedo": rho,
        **option_attrs(settings, profile, aerosol), "note": note, **attrs,
    })
    if surface_temperature is not None:
        ds.attrs["surface_temperature_K"] = float(surface_temperature)
    return ds


def sky_radiance(zenith=None, azimuth=None, *, target_altitude=0.0, engine="database",
                 profile="us_standard", aerosol="rural", visibility=None, aot550=None,
                 water=None, ozone=None, multiple_scattering=True, sun_zenith=30.0,
                 sun_azimuth=180.0, date=None, earth_sun_distance=None, solar_spectrum=None,
                 surface_albedo=0.0, wavelength=None, wavelength_range=None, step=None,
                 bands=None, database=None) -> xr.Dataset:
    """Sky radiance seen from the surface on a zenith × azimuth grid, and the downwelling
    irradiance.

    Parameters
    ----------
    zenith, azimuth : array_like, optional
        1-D grids of view directions from the target [deg]; default 0-85 by 5 and 0-330 by 30.
    target_altitude : float
        Where the sky is seen from [m].
    others
        See the module table.

    Returns
    -------
    xarray.Dataset
        ``sky_radiance`` over (zenith, azimuth, wavelength) [W m-2 sr-1 um-1];
        ``downwelling_irradiance`` (sky, on a horizontal surface; a Gauss quadrature of the
        engine's sky: 24 × 48 directions, 8 × 12 for LOWTRAN), ``direct_irradiance`` (sun,
        horizontal) [W m-2 um-1]; and over ``band`` the band values of
        :mod:`radscene.atmosphere.bands` (brightness temperatures of the sky map in thermal
        bands). Attributes as :func:`line_of_sight`'s.
    """
    from radscene.atmosphere.base import SkyGeometry

    zen = np.arange(0.0, 86.0, 5.0) if zenith is None else np.atleast_1d(
        np.asarray(zenith, float))
    azi = np.arange(0.0, 360.0, 30.0) if azimuth is None else np.atleast_1d(
        np.asarray(azimuth, float))
    if zen.ndim != 1 or zen.size == 0 or np.any(~np.isfinite(zen)) or zen.min() < 0 or \
            zen.max() > 90:
        raise ConfigError("a list of zenith angles in [0, 90] deg", key="zenith")
    if azi.ndim != 1 or azi.size == 0 or np.any(~np.isfinite(azi)):
        raise ConfigError("a list of finite azimuths [deg]", key="azimuth")
    h = float(target_altitude)
    if not np.isfinite(h) or h < 0 or h >= model.TOP_OF_ATMOSPHERE:
        raise ConfigError(f"must lie in [0, 100000) m; got {target_altitude!r}",
                          key="target_altitude")
    atm, settings = _make(engine, profile, aerosol, visibility, multiple_scattering, sun_zenith,
                          sun_azimuth, None, surface_albedo, None, database, aot550, water,
                          ozone, date, earth_sun_distance, solar_spectrum)
    wl = _grid(atm, wavelength, wavelength_range, step, bands)
    band_responses(bands, wl)
    sz, sa = float(sun_zenith), float(sun_azimuth)
    geom = SkyGeometry(h, sz, sa)
    zz, aa = np.meshgrid(zen, azi, indexing="ij")
    sky = atm.sky(zz, aa, wl, geom)
    n_mu, n_phi = (8, 12) if atm.name == "lowtran" else (24, 48)  # LOWTRAN: one run each
    qz, qp, qw = model.hemisphere_quadrature(n_mu, n_phi)
    # full circle of azimuths for the quadrature: mirror about the sun's vertical plane
    q_sky = 0.5 * (atm.sky(qz, sa + qp, wl, geom) + atm.sky(qz, sa - qp, wl, geom))
    e_down = np.einsum("q,qn->n", qw, q_sky)
    if sz < 90.0:
        e_dir = (atm.sun(h, sz, wl, _toa(atm, settings, h, wl)).irradiance
                 * np.cos(np.radians(sz)))
    else:
        e_dir = np.zeros(wl.size)
    ds = xr.Dataset(
        {"sky_radiance": (("zenith", "azimuth", "wavelength"), sky,
                          {"units": _RAD, "long_name": "sky radiance seen from the surface"}),
         "downwelling_irradiance": ("wavelength", e_down, {
             "units": "W m-2 um-1", "long_name": "diffuse sky irradiance, horizontal"}),
         "direct_irradiance": ("wavelength", np.asarray(e_dir, float).reshape(wl.size), {
             "units": "W m-2 um-1", "long_name": "direct solar irradiance, horizontal"})},
        coords={"zenith": ("zenith", zen, {"units": "deg"}),
                "azimuth": ("azimuth", azi, {"units": "deg",
                                             "long_name": "azimuth, clockwise from north"}),
                "wavelength": ("wavelength", wl, {"units": "um"})},
    )
    ds = attach_bands(ds, bands)
    ds.attrs.update({"engine": atm.name, "target_altitude_m": h, "sun_zenith_deg": sz,
                     "sun_azimuth_deg": sa, "surface_albedo": float(surface_albedo),
                     **option_attrs(settings, profile, aerosol)})
    if atm.name == "lowtran":
        ds.attrs["note"] = ("LOWTRAN: sky radiance and direct_irradiance with LOWTRAN7's "
                            "solar spectrum (the direct beam: its transmittance times "
                            "radscene.sun.toa_solar_irradiance(spectrum='lowtran'))")
    return ds
