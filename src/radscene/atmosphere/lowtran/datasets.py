"""Datasets of the ``lowtran`` engine: one line of sight, and a sky radiance map.

Functions of a :class:`~radscene.atmosphere.lowtran.engine.LowtranAtmosphere` (``atm``),
exposed as its methods :meth:`line_of_sight` and :meth:`sky_radiance`.
"""

from __future__ import annotations

import json
import math

import numpy as np

from radscene.atmosphere.base import SkyGeometry
from radscene.atmosphere.lowtran.geometry import observer_geometry, path_kind
from radscene.errors import ConfigError

__all__ = ["line_of_sight", "sky_radiance", "native_window"]

#: Observer and target closer than this in altitude form a zero-length path [m].
SAME_ALTITUDE_M = 0.5


def _number(value, key, low, unit):
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a number; got {value!r}", key=key) from None
    if not math.isfinite(x) or x <= low:
        raise ConfigError(f"must be > {low:g} {unit}; got {value!r}", key=key)
    return x


def native_window(atm, wavelength, wavelength_range):
    """Wavenumbers to report [cm-1] and the run's window: the given wavelengths, or
    LOWTRAN's own samples (V1, V1 + DV, ..., V2 for V1, V2 multiples of DV)."""
    if wavelength is not None:
        wl, window = atm._window(wavelength)
        return 1e4 / wl, window
    lo, hi = wavelength_range if wavelength_range is not None else atm.wavelength_range
    lo = _number(lo, "wavelength_range[0]", 0.0, "um")
    hi = _number(hi, "wavelength_range[1]", 0.0, "um")
    if hi <= lo:
        raise ConfigError(f"an increasing pair of wavelengths; got {wavelength_range!r}",
                          key="wavelength_range")
    atm.check_wavelength(np.array([lo, hi]), key="wavelength_range")
    dv = atm.wavenumber_step
    v1 = math.floor(1e4 / hi / dv) * dv
    v2 = math.ceil(1e4 / lo / dv) * dv
    grid = v1 + dv * np.arange(round((v2 - v1) / dv) + 1)
    inside = (grid >= 1e4 / hi - 1e-6) & (grid <= 1e4 / lo + 1e-6)
    return grid[inside], (v1, v2)


def line_of_sight(atm, observer_altitude, target_altitude, view_zenith, wavelength=None,
                  wavelength_range=None):
    """Everything LOWTRAN says about one slant path, as a Dataset over wavelength.

    Parameters
    ----------
    observer_altitude, target_altitude : float
        [m], between the ground and 100 km.
    view_zenith : float
        Zenith angle at the target of the direction towards the observer [deg].
    wavelength : array_like, optional
        Wavelengths to interpolate onto [um]; default LOWTRAN's own samples within
        ``wavelength_range``.
    wavelength_range : (float, float), optional
        [um]; default the engine's 0.25-28 um.

    Returns
    -------
    xarray.Dataset
        Over ``wavelength`` [um] (increasing; ``wavenumber`` [cm-1] alongside):
        ``transmittance`` [1], ``path_thermal_radiance``, ``path_scattered_radiance``,
        ``path_radiance`` [W m-2 sr-1 um-1], ``sun_transmittance`` [1] and
        ``direct_solar_irradiance`` at the target, normal to the beam, from LOWTRAN's
        solar spectrum [W m-2 um-1] (zero without the sun), and with
        ``ground_temperature`` set, ``boundary_radiance`` = (1 - albedo) B(T) τ
        [W m-2 sr-1 um-1]. Attributes record the engine's parameters and the decks.
        Spectra wholly beyond 6 um carry no scattered sunlight (engine docstring).
    """
    import xarray as xr

    geo = [np.asarray(x, float) for x in (observer_altitude, target_altitude, view_zenith)]
    if any(g.ndim for g in geo):
        raise ConfigError("one line of sight: scalars", key="observer_altitude")
    h_o, h_t, vz = (float(g) for g in geo)
    atm._check_altitude(h_o, "observer_altitude")
    atm._check_altitude(h_t, "target_altitude")
    if not 0.0 <= vz <= 180.0:
        raise ConfigError("must lie in [0, 180] deg", key="view_zenith")
    v_req, window = native_window(atm, wavelength, wavelength_range)
    cases, names = [], []
    r_earth = atm._earth_radius_km() * 1e3
    kind, length = path_kind(h_o, h_t, vz, r_earth, SAME_ALTITUDE_M)
    zero_path = kind == "none"
    if not zero_path:
        if kind == "slant":
            _, _, s = observer_geometry(h_o, h_t, vz, r_earth)
        if kind == "contradiction" or (kind == "slant" and not np.isfinite(s)):
            raise ConfigError("no line of sight joins observer and target at this zenith "
                              "(observer above: zenith < 90; below: > 90)", key="view_zenith")
        case, name = atm._path_case(h_o, h_t, vz, window, None, kind, length)
        cases.append(case)
        names.append(name)
    sun_up = atm.sun_zenith is not None and atm.sun_zenith < 90.0
    if sun_up:
        case, name = atm._sun_case(h_t, atm.sun_zenith, window)
        cases.append(case)
        names.append(name)
    airlight = None
    if cases and not zero_path:  # a level path's sunlight from the horizon's sky
        (first, airlight), *_ = atm._run_with_airlight(cases[:1], names[:1], window)
        results = [first] + (atm.runner.run(cases[1:], names[1:]) if len(cases) > 1 else [])
    else:
        results = atm.runner.run(cases, names) if cases else []

    def at(result, values):
        return atm._interp(result, values, v_req)

    n = v_req.size
    if zero_path:
        tau, thermal, scattered = np.ones(n), np.zeros(n), np.zeros(n)
    else:
        r = results[0]
        tau = at(r, r.transmittance)
        thermal = at(r, r.thermal_radiance)
        scattered = (at(airlight, airlight.scattered_radiance) * (1.0 - tau)
                     if airlight is not None else at(r, r.scattered_radiance)
                     if r.scattered_radiance is not None else np.zeros(n))
    if sun_up:
        r = results[-1]
        tau_sun = at(r, r.transmittance)
        e_sun = at(r, r.solar_irradiance)
    else:
        tau_sun, e_sun = np.zeros(n), np.zeros(n)
    wl = 1e4 / v_req
    order = np.argsort(wl)
    rad = "W m-2 sr-1 um-1"
    variables = {
        "transmittance": (tau, "1", "path transmittance, target to observer"),
        "path_thermal_radiance": (thermal, rad, "thermal path radiance"),
        "path_scattered_radiance": (scattered, rad, "scattered solar path radiance"),
        "path_radiance": (thermal + scattered, rad, "path radiance, thermal + scattered"),
        "sun_transmittance": (tau_sun, "1", "sun-to-target transmittance"),
        "direct_solar_irradiance": (e_sun, "W m-2 um-1",
                                    "direct solar irradiance at the target, normal to the "
                                    "beam (LOWTRAN solar spectrum)"),
    }
    if atm.ground_temperature is not None:
        from radscene.radiometry import spectral_radiance

        boundary = (1.0 - atm.albedo) * spectral_radiance(wl, atm.ground_temperature) * tau
        variables["boundary_radiance"] = (boundary, rad, "emission of the boundary at the "
                                          "target, (1 - albedo) B(T) tau")
    data = {name: ("wavelength", values[order], {"units": units, "long_name": long_name})
            for name, (values, units, long_name) in variables.items()}
    coords = {
        "wavelength": ("wavelength", wl[order], {"units": "um", "long_name": "wavelength"}),
        "wavenumber": ("wavelength", v_req[order], {"units": "cm-1",
                                                    "long_name": "wavenumber"}),
    }
    attrs = {
        "engine": "lowtran",
        "observer_altitude_m": h_o, "target_altitude_m": h_t, "view_zenith_deg": vz,
        "sun_zenith_deg": "none" if atm.sun_zenith is None else atm.sun_zenith,
        "parameters": json.dumps(atm.parameters, default=str),
        # every deck run, the sunlit level path's sky near the horizon included
        "tape5": "\n".join(r.deck for r in results + ([airlight] if airlight is not None
                                                       else [])),
    }
    return xr.Dataset(data, coords=coords, attrs=attrs)

def sky_radiance(atm, zenith, azimuth, wavelength=None, wavelength_range=None,
                 target_altitude=None, sun_zenith=None, sun_azimuth=None):
    """Sky radiance from the surface on a zenith × azimuth grid, as a Dataset.

    Parameters
    ----------
    zenith, azimuth : array_like
        1-D grids of view directions from the target [deg]; zenith in [0, 90].
    wavelength, wavelength_range
        As in :meth:`line_of_sight`.
    target_altitude : float, optional
        Where the sky is seen from [m]; default the ground.
    sun_zenith, sun_azimuth : float, optional
        [deg]; default the engine's sun (no sun: thermal sky only).

    Returns
    -------
    xarray.Dataset
        ``sky_thermal_radiance``, ``sky_scattered_radiance``, ``sky_radiance`` over
        (zenith, azimuth, wavelength) [W m-2 sr-1 um-1].
    """
    import xarray as xr

    zen = np.atleast_1d(np.asarray(zenith, float))
    azi = np.atleast_1d(np.asarray(azimuth, float))
    if zen.ndim != 1 or azi.ndim != 1:
        raise ConfigError("1-D lists of angles [deg]", key="zenith")
    h = atm.bottom_altitude if target_altitude is None else float(target_altitude)
    sz = atm.sun_zenith if sun_zenith is None else sun_zenith
    sa = atm.sun_azimuth if sun_azimuth is None else sun_azimuth
    geometry = SkyGeometry(h, 180.0 if sz is None else sz, 0.0 if sa is None else sa)
    v_req, window = native_window(atm, wavelength, wavelength_range)
    wl = 1e4 / v_req
    zz, aa = np.meshgrid(zen, azi, indexing="ij")
    thermal, scattered = atm._sky_parts(zz, aa, wl, geometry, window=window)
    order = np.argsort(wl)
    rad = "W m-2 sr-1 um-1"
    dims = ("zenith", "azimuth", "wavelength")
    data = {
        "sky_thermal_radiance": (dims, thermal[..., order], {"units": rad,
                                 "long_name": "thermal sky radiance"}),
        "sky_scattered_radiance": (dims, scattered[..., order], {"units": rad,
                                   "long_name": "scattered solar sky radiance"}),
        "sky_radiance": (dims, (thermal + scattered)[..., order], {"units": rad,
                         "long_name": "sky radiance"}),
    }
    coords = {
        "zenith": ("zenith", zen, {"units": "deg", "long_name": "view zenith from target"}),
        "azimuth": ("azimuth", azi, {"units": "deg",
                                     "long_name": "view azimuth, clockwise from north"}),
        "wavelength": ("wavelength", wl[order], {"units": "um"}),
        "wavenumber": ("wavelength", v_req[order], {"units": "cm-1"}),
    }
    attrs = {"engine": "lowtran", "target_altitude_m": h,
             "sun_zenith_deg": geometry.sun_zenith, "sun_azimuth_deg": geometry.sun_azimuth,
             "parameters": json.dumps(atm.parameters, default=str)}
    return xr.Dataset(data, coords=coords, attrs=attrs)
