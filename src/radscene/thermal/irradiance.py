"""Short-wave and long-wave irradiance at the ground from a scene's atmosphere engine, through
the day.

The heat balance needs, at each time, the direct solar irradiance normal to the beam, the
diffuse short-wave irradiance on a horizontal plane and the downwelling long-wave irradiance.
They come from the same engine the renderer uses, asked once per sun-zenith node and
interpolated in the cosine of the sun's zenith angle at each time of the run:

.. math::
    E_{dir} = \\int_{0.3}^{4} E_{0}(λ)\\, τ_{so}(λ)\\, dλ, \\qquad
    E_{dif} = \\int_{0.3}^{4} E_{d}(λ)\\, dλ, \\qquad
    E_{LW} = \\int_{4}^{20} \\int_{2π} L_{sky}(λ, ω) \\cos θ\\, dω\\, dλ
             + π \\int_{20}^{∞} B(λ, T_{air})\\, dλ,

with E_d the engine's diffuse irradiance over black ground (its coupling query, or the
cosine-weighted integral of its sky radiance for engines that do not couple). Beyond 20 µm the
lower atmosphere is opaque (water vapour's rotation band) and radiates as a blackbody at the air
temperature near the ground (Liou 2002, *An Introduction to Atmospheric Radiation*, 2nd ed.,
§4.2). Engines that cannot give the thermal sky (``sixs``; a database without thermal tables)
leave the long-wave to the weather's clear-sky formulation. Engines whose spectra the user
sets over the whole long-wave (``uniform``, ``none``: 0.2-100 µm) give all of it, from 4 to
100 µm, with no blackbody added.

Where the engine's range stops short of 0.3-4 µm (the ``uniform`` engine's tables often start at
0.4 µm), the ratio of its irradiance to the top-of-atmosphere spectrum at the end of its range
is held beyond it.

The solar absorptance of each material is weighted by the engine's irradiance spectra at the
ground: the beam's and the diffuse sky's at each sun-zenith node (``direct_spectrum`` and
``diffuse_spectrum`` of :class:`ShortwaveTable`), interpolated to the sun of each step, and the
global spectrum integrated over the day (``spectrum``) for the run's mean, not a fixed
reference spectrum.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = ["ShortwaveTable", "shortwave_table", "sky_longwave_irradiance"]

#: Sun-zenith nodes of the short-wave table [deg].
ZENITH_NODES = np.array([0.0, 20.0, 35.0, 45.0, 55.0, 62.0, 68.0, 73.0, 77.0, 80.0, 83.0, 85.0, 87.0, 89.0])

#: Short-wave integration grid [um].
SHORTWAVE = np.concatenate([np.arange(0.3, 1.0, 0.005), np.arange(1.0, 2.5, 0.01), np.arange(2.5, 4.0001, 0.02)])

#: Long-wave grid of the engine's sky [um] (the rest of the long-wave from the air temperature).
LONGWAVE = np.concatenate([np.arange(4.0, 8.0, 0.05), np.arange(8.0, 20.0001, 0.1)])

# Gauss–Legendre nodes in cos(zenith) over (0, 1) and regular azimuths for the sky integrals.
_MU, _MU_W = np.polynomial.legendre.leggauss(8)
_MU, _MU_W = 0.5 * (_MU + 1.0), 0.5 * _MU_W
_AZ = np.arange(0.0, 360.0, 30.0)


@dataclass(frozen=True)
class ShortwaveTable:
    """Broadband short-wave irradiance at the ground per sun-zenith node.

    Attributes
    ----------
    zenith : ndarray, (n,)
        Sun-zenith nodes [deg].
    direct_normal : ndarray, (n,)
        Direct irradiance normal to the beam [W m-2].
    diffuse : ndarray, (n,)
        Diffuse irradiance on a horizontal plane [W m-2].
    wavelength : ndarray, (m,)
        [um].
    spectrum : ndarray, (n, m)
        Global irradiance on a horizontal plane per node [W m-2 um-1].
    direct_spectrum, diffuse_spectrum : ndarray, (n, m), optional
        The beam's irradiance normal to it and the diffuse irradiance on a horizontal plane
        per node [W m-2 um-1], the weights of the beam's and the sky's absorptance.
    """

    zenith: np.ndarray
    direct_normal: np.ndarray
    diffuse: np.ndarray
    wavelength: np.ndarray
    spectrum: np.ndarray
    direct_spectrum: np.ndarray | None = None
    diffuse_spectrum: np.ndarray | None = None

    def weights(self, sun_zenith):
        """(n_times, n) weights of the zenith nodes at the sun zeniths [deg], linear in cos θ_s
        as :meth:`at` (held at the last node below it)."""
        mu = np.cos(np.radians(np.minimum(np.asarray(sun_zenith, float).ravel(), 90.0)))
        nodes = np.cos(np.radians(self.zenith))[::-1]
        eye = np.eye(nodes.size)
        return np.stack([np.interp(mu, nodes, eye[j]) for j in range(nodes.size)], axis=1)[:, ::-1]

    def at(self, sun_zenith):
        """(direct normal, diffuse horizontal) [W m-2] at sun zeniths [deg]; zero below the
        horizon. Linear in cos θ_s between nodes."""
        z = np.asarray(sun_zenith, float)
        mu = np.cos(np.radians(np.minimum(z, 90.0)))
        nodes = np.cos(np.radians(self.zenith))[::-1]
        up = z < 90.0
        edge = np.cos(np.radians(self.zenith[-1]))
        # below the last node the beam fades to zero at the horizon, linearly in cos θ_s
        fade = np.clip(mu / edge, 0.0, 1.0)
        direct = np.where(up, np.interp(mu, nodes, self.direct_normal[::-1]) * np.where(mu < edge, fade, 1.0), 0.0)
        diffuse = np.where(up, np.interp(mu, nodes, self.diffuse[::-1]) * np.where(mu < edge, fade, 1.0), 0.0)
        return direct, diffuse

    def daily_spectrum(self, sun_zenith):
        """Global irradiance spectrum summed over the given sun zeniths (a day's samples)
        [W m-2 um-1], the weight of the day's solar absorptance."""
        z = np.asarray(sun_zenith, float).ravel()
        z = z[z < 90.0]
        if z.size == 0:
            return self.spectrum[0]
        mu = np.cos(np.radians(z))
        nodes = np.cos(np.radians(self.zenith))[::-1]
        w = np.stack([np.interp(mu, nodes, np.eye(len(nodes))[k]) for k in range(len(nodes))], axis=1)
        return (w.sum(axis=0) @ self.spectrum[::-1]) / z.size


def _diffuse_spectrum(atm, altitude, wavelength, zenith, azimuth):
    from radscene.atmosphere.base import SkyGeometry

    if getattr(atm, "couples", False):
        c = atm.coupling(1.0e6, altitude, 0.0, wavelength)
        return np.asarray(c.diffuse_irradiance, float).reshape(-1, wavelength.size)[0]
    zen = np.degrees(np.arccos(_MU))
    zz, aa = np.meshgrid(zen, _AZ, indexing="ij")
    sky = np.asarray(atm.sky(zz, aa, wavelength, SkyGeometry(altitude, zenith, azimuth)), float)
    w = (_MU * _MU_W)[:, None] * (2.0 * np.pi / _AZ.size)
    return np.einsum("za,zal->l", w * np.ones_like(zz), sky)


def shortwave_table(atmosphere, altitude, day_of_year, earth_sun_distance, sun_azimuth=180.0):
    """Ask the engine for the ground's short-wave irradiance at every sun-zenith node.

    Parameters
    ----------
    atmosphere : radscene.atmosphere.Atmosphere
        The scene's engine.
    altitude : float
        Altitude of the ground [m].
    day_of_year : int
    earth_sun_distance : float
        [AU].
    sun_azimuth : float, optional
        [deg]; the irradiance of a horizontal plane does not depend on it.

    Returns
    -------
    ShortwaveTable
    """
    from radscene.sun import engine_distance, engine_spectrum, toa_solar_irradiance

    full = SHORTWAVE
    lo, hi = atmosphere.wavelength_range
    inside = (full >= lo) & (full <= hi)
    if inside.sum() < 2:
        raise ConfigError(f"the {atmosphere.name!r} atmosphere covers {lo:g}-{hi:g} µm: no short-wave for the heat balance",
                          key="environment.atmosphere")
    wl = full[inside]
    direct, diffuse, spectrum, beams, skies = [], [], [], [], []
    for z in ZENITH_NODES:
        atm = atmosphere.with_sun(float(z), float(sun_azimuth), day_of_year=day_of_year,
                                  earth_sun_distance=earth_sun_distance)
        # the engine's own sun: its spectrum, at the distance its scattered light comes from
        toa_full = toa_solar_irradiance(full, engine_distance(atm, earth_sun_distance),
                                        engine_spectrum(atm))
        toa = toa_full[inside]
        beam = _extend(full, inside, toa_full,
                       np.asarray(atm.sun(altitude, float(z), wl, toa).irradiance, float).reshape(-1, wl.size)[0])
        dif = _extend(full, inside, toa_full, _diffuse_spectrum(atm, altitude, wl, float(z), float(sun_azimuth)))
        direct.append(np.trapezoid(beam, full))
        diffuse.append(np.trapezoid(dif, full))
        spectrum.append(beam * np.cos(np.radians(z)) + dif)
        beams.append(beam)
        skies.append(dif)
    direct, diffuse = np.array(direct), np.array(diffuse)
    if not (np.all(np.isfinite(direct)) and np.all(np.isfinite(diffuse)) and direct.min() >= 0 and diffuse.min() >= 0):
        raise ConfigError("the atmosphere engine gave a negative or non-finite ground irradiance", key="environment.atmosphere")
    return ShortwaveTable(ZENITH_NODES.copy(), direct, diffuse, full, np.array(spectrum), np.array(beams),
                          np.array(skies))


def _extend(full, inside, toa, values):
    """Values on the whole short-wave grid: beyond the engine's range, the ratio to the
    top-of-atmosphere spectrum at the nearest end of the range is held."""
    out = np.empty(full.size)
    out[inside] = values
    first, last = np.flatnonzero(inside)[[0, -1]]
    out[:first] = toa[:first] * values[0] / toa[first]
    out[last + 1:] = toa[last + 1:] * values[-1] / toa[last]
    return out


def sky_longwave_irradiance(atmosphere, altitude, air_temperature):
    """Downwelling long-wave irradiance on a horizontal plane under a clear sky [W m-2], or
    None when the engine cannot give its thermal sky.

    Parameters
    ----------
    atmosphere : radscene.atmosphere.Atmosphere
    altitude : float
        [m].
    air_temperature : array_like
        Air temperature near the ground [K], for the part beyond 20 µm.

    Returns
    -------
    ndarray or None
        Shape of ``air_temperature``.
    """
    from radscene.atmosphere.base import SkyGeometry
    from radscene.radiometry.planck import band_radiance

    lo, hi = atmosphere.wavelength_range
    if lo > LONGWAVE[0] or hi < LONGWAVE[-1]:
        return None
    # an engine set by the user over the whole long-wave (uniform, none) gives it all
    grid = np.concatenate([LONGWAVE, np.arange(21.0, 100.0001, 1.0)]) if hi >= 100.0 else LONGWAVE
    zen = np.degrees(np.arccos(_MU))
    sky = np.asarray(atmosphere.sky(zen, 0.0, grid, SkyGeometry(altitude, 0.0, 0.0)), float)
    if not np.all(np.isfinite(sky)):
        return None
    engine_part = 2.0 * np.pi * np.trapezoid((_MU * _MU_W) @ sky, grid)
    t = np.asarray(air_temperature, float)
    if hi >= 100.0:
        return np.full(t.shape, engine_part)
    return engine_part + np.pi * band_radiance(20.0, 1.0e5, t)
