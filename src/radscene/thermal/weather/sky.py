"""Sky terms of the weather: the clear-sky long-wave emissivity of the atmosphere, its increase
under cloud, the downwelling long-wave irradiance, and the reduction of the sun by cloud.

Two registries of swappable formulations (case-insensitive names):

``CLEAR_SKY_EMISSIVITY_MODELS`` — effective emissivity ε_clr of a cloudless sky, so that the
long-wave irradiance on a horizontal plane is ε σ T_air⁴ (e the vapour pressure, T the air
temperature near the ground):

============== =========================================== ===================================
name           ε_clr                                        source
============== =========================================== ===================================
``brutsaert``  1.24 (e/T)^(1/7), e in hPa                   Brutsaert (1975)
``prata``      1 − (1 + w) exp(−√(1.2 + 3w)), w = 46.5 e/T  Prata (1996); w [g cm-2],
                                                            e in hPa
============== =========================================== ===================================

``CLOUD_EMISSIVITY_MODELS`` — all-sky emissivity from ε_clr and the cloud cover N [0-1]:

===================== ============================ ==========================================
name                  ε                            source
===================== ============================ ==========================================
``crawford_duchon``   N + (1 − N) ε_clr            Crawford & Duchon (1999): cloud treated as
                                                   a black body at the air temperature
``unsworth_monteith`` (1 − 0.84 N) ε_clr + 0.84 N  Unsworth & Monteith (1975)
===================== ============================ ==========================================

Flerchinger et al. (2009) compare these with other formulations against measurements.

Short-wave: Kasten & Czeplak (1980), from ten years of hourly data at Hamburg, give the global
irradiance under a cloud cover N relative to the clear-sky one and the diffuse fraction:
G(N)/G(0) = 1 − 0.75 N^3.4 and D/G = 0.3 + 0.7 N².

References
----------
Brutsaert, W. (1975). On a derivable formula for long-wave radiation from clear skies.
*Water Resour. Res.* 11(5), 742–744. doi:10.1029/WR011i005p00742
Prata, A. J. (1996). A new long-wave formula for estimating downward clear-sky radiation at the
surface. *Q. J. R. Meteorol. Soc.* 122, 1127–1151. doi:10.1002/qj.49712253306
Crawford, T. M. and Duchon, C. E. (1999). An improved parameterization for estimating effective
atmospheric emissivity for use in calculating daytime downwelling longwave radiation.
*J. Appl. Meteorol.* 38, 474–480. doi:10.1175/1520-0450(1999)038<0474:AIPFEE>2.0.CO;2
Unsworth, M. H. and Monteith, J. L. (1975). Long-wave radiation at the ground I. Angular
distribution of incoming radiation. *Q. J. R. Meteorol. Soc.* 101, 13–24.
doi:10.1002/qj.49710142703
Flerchinger, G. N., Xaio, W., Marks, D., Sauer, T. J. and Yu, Q. (2009). Comparison of
algorithms for incoming atmospheric long-wave radiation. *Water Resour. Res.* 45, W03423.
doi:10.1029/2008WR007394
Kasten, F. and Czeplak, G. (1980). Solar and terrestrial radiation dependent on the amount and
type of cloud. *Solar Energy* 24(2), 177–189. doi:10.1016/0038-092X(80)90391-6
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError, did_you_mean
from radscene.radiometry.constants import SIGMA  # σ = 2π⁵k⁴/(15h³c²) [W m-2 K-4], CODATA
from radscene.thermal.weather.humidity import vapour_pressure

__all__ = [
    "CLEAR_SKY_EMISSIVITY_MODELS",
    "CLOUD_EMISSIVITY_MODELS",
    "brutsaert",
    "clear_sky_emissivity",
    "cloud_diffuse_fraction",
    "cloud_shortwave_factor",
    "cloudy_sky_emissivity",
    "crawford_duchon",
    "prata",
    "sky_longwave",
    "unsworth_monteith",
]


def _cloud(cloud_cover):
    n = np.asarray(cloud_cover, float)
    if np.any(~np.isfinite(n)) or np.any((n < 0) | (n > 1)):
        raise ConfigError("must lie in [0, 1] (a fraction of the sky, not a percentage)", key="cloud_cover")
    return n


def _vapour(air_temperature, vapour_pressure):
    t = np.asarray(air_temperature, float)
    e = np.asarray(vapour_pressure, float)
    if np.any(t <= 0):
        raise ConfigError("must be > 0 K", key="air_temperature")
    if np.any(e < 0):
        raise ConfigError("must be >= 0 Pa", key="vapour_pressure")
    return t, e


def brutsaert(air_temperature, vapour_pressure):
    """Clear-sky emissivity of Brutsaert (1975), ε = 1.24 (e/T)^(1/7), e in hPa [-].

    Parameters
    ----------
    air_temperature : array_like
        T [K].
    vapour_pressure : array_like
        e [Pa].

    Returns
    -------
    ndarray
        ε_clr [-].

    Notes
    -----
    Brutsaert integrates the Schwarzschild equation over a standard atmosphere whose
    temperature and humidity fall off with height from their values near the ground:

    .. math:: \\varepsilon_{clr} = 1.24\\,(e/T)^{1/7},\\quad e\\ [\\mathrm{hPa}],\\ T\\ [\\mathrm{K}]

    Examples
    --------
    >>> round(float(brutsaert(293.15, 1166.72)), 4)
    0.7824
    """
    t, e = _vapour(air_temperature, vapour_pressure)
    return 1.24 * (e / 100.0 / t) ** (1.0 / 7.0)


def prata(air_temperature, vapour_pressure):
    """Clear-sky emissivity of Prata (1996), ε = 1 − (1 + w) exp(−(1.2 + 3w)^½) [-].

    Parameters
    ----------
    air_temperature : array_like
        T [K].
    vapour_pressure : array_like
        e [Pa].

    Returns
    -------
    ndarray
        ε_clr [-].

    Notes
    -----
    w is the precipitable water estimated from the surface values:

    .. math:: \\varepsilon_{clr} = 1 - (1 + w)\\exp\\left(-\\sqrt{1.2 + 3w}\\right),\\quad
              w = 46.5\\,e/T\\ [\\mathrm{g\\,cm^{-2}}],\\ e\\ [\\mathrm{hPa}]

    Examples
    --------
    >>> round(float(prata(293.15, 1166.72)), 4)
    0.7879
    """
    t, e = _vapour(air_temperature, vapour_pressure)
    w = 46.5 * (e / 100.0) / t
    return 1.0 - (1.0 + w) * np.exp(-np.sqrt(1.2 + 3.0 * w))


def crawford_duchon(clear_emissivity, cloud_cover):
    """All-sky emissivity of Crawford & Duchon (1999), ε = N + (1 − N) ε_clr [-].

    Parameters
    ----------
    clear_emissivity : array_like
        ε_clr [-].
    cloud_cover : array_like
        N [0-1].

    Returns
    -------
    ndarray
        ε [-].

    Examples
    --------
    >>> float(crawford_duchon(0.8, 0.5))
    0.9
    """
    n = _cloud(cloud_cover)
    return n + (1.0 - n) * np.asarray(clear_emissivity, float)


def unsworth_monteith(clear_emissivity, cloud_cover):
    """All-sky emissivity of Unsworth & Monteith (1975), ε = (1 − 0.84 N) ε_clr + 0.84 N [-].

    Parameters
    ----------
    clear_emissivity : array_like
        ε_clr [-].
    cloud_cover : array_like
        N [0-1].

    Returns
    -------
    ndarray
        ε [-].

    Examples
    --------
    >>> round(float(unsworth_monteith(0.8, 0.5)), 3)
    0.884
    """
    n = _cloud(cloud_cover)
    return (1.0 - 0.84 * n) * np.asarray(clear_emissivity, float) + 0.84 * n


#: Clear-sky emissivity formulations, by lower-case name: f(air_temperature [K], vapour_pressure [Pa]).
CLEAR_SKY_EMISSIVITY_MODELS = {"brutsaert": brutsaert, "prata": prata}

#: Cloud corrections, by lower-case name: f(clear_emissivity [-], cloud_cover [0-1]).
CLOUD_EMISSIVITY_MODELS = {"crawford_duchon": crawford_duchon, "unsworth_monteith": unsworth_monteith}


def _lookup(registry, name, key):
    fn = registry.get(str(name).strip().lower())
    if fn is None:
        raise ConfigError(f"unknown model {name!r}; known: {', '.join(sorted(registry))}"
                          f"{did_you_mean(name, sorted(registry))}", key=key)
    return fn


def clear_sky_emissivity(air_temperature, relative_humidity, model="brutsaert"):
    """Effective long-wave emissivity of a cloudless sky from screen-level air [-].

    Parameters
    ----------
    air_temperature : array_like
        T [K].
    relative_humidity : array_like
        RH [0-1].
    model : str, optional
        A name in ``CLEAR_SKY_EMISSIVITY_MODELS`` (case-insensitive).

    Returns
    -------
    ndarray
        ε_clr [-].

    Raises
    ------
    ConfigError
        Unknown model (the message lists the registered ones), T ≤ 0 K or RH outside [0, 1].

    Examples
    --------
    >>> round(float(clear_sky_emissivity(293.15, 0.5)), 3)
    0.782
    """
    fn = _lookup(CLEAR_SKY_EMISSIVITY_MODELS, model, "clear_sky")
    return fn(air_temperature, vapour_pressure(air_temperature, relative_humidity))


def cloudy_sky_emissivity(clear_emissivity, cloud_cover, model="crawford_duchon"):
    """All-sky long-wave emissivity from the clear-sky one and the cloud cover [-].

    Parameters
    ----------
    clear_emissivity : array_like
        ε_clr [-].
    cloud_cover : array_like
        N [0-1].
    model : str, optional
        A name in ``CLOUD_EMISSIVITY_MODELS`` (case-insensitive).

    Returns
    -------
    ndarray
        ε [-].

    Examples
    --------
    >>> float(cloudy_sky_emissivity(0.8, 1.0))
    1.0
    """
    return _lookup(CLOUD_EMISSIVITY_MODELS, model, "cloud")(clear_emissivity, cloud_cover)


def sky_longwave(air_temperature, relative_humidity, cloud_cover, *, clear_sky="brutsaert", cloud="crawford_duchon"):
    """Downwelling long-wave irradiance on a horizontal plane under a full sky [W m-2].

    Parameters
    ----------
    air_temperature : array_like
        Screen-level air temperature T [K].
    relative_humidity : array_like
        RH [0-1].
    cloud_cover : array_like
        N [0-1].
    clear_sky : str, optional
        A name in ``CLEAR_SKY_EMISSIVITY_MODELS``.
    cloud : str, optional
        A name in ``CLOUD_EMISSIVITY_MODELS``.

    Returns
    -------
    ndarray
        E_sky,LW [W m-2], broadcast over the inputs.

    Notes
    -----
    .. math:: E_{sky,LW} = \\varepsilon(\\varepsilon_{clr}(T, e), N)\\,\\sigma T^4

    Examples
    --------
    >>> round(float(sky_longwave(293.15, 0.5, 0.0)), 1)
    327.6
    >>> round(float(sky_longwave(293.15, 0.5, 1.0)), 1)
    418.8
    """
    eps = cloudy_sky_emissivity(clear_sky_emissivity(air_temperature, relative_humidity, clear_sky), cloud_cover, cloud)
    return eps * SIGMA * np.asarray(air_temperature, float) ** 4


def cloud_shortwave_factor(cloud_cover):
    """Global short-wave irradiance under cloud relative to a clear sky, 1 − 0.75 N^3.4 [-].

    Parameters
    ----------
    cloud_cover : array_like
        N [0-1] (Kasten & Czeplak use oktas/8).

    Returns
    -------
    ndarray
        G(N)/G(0) [-], from 1 (clear) to 0.25 (overcast).

    Notes
    -----
    Kasten & Czeplak (1980), fitted to Hamburg 1964–1973 for all cloud types:

    .. math:: G(N)/G(0) = 1 - 0.75\\,N^{3.4}

    Examples
    --------
    >>> float(cloud_shortwave_factor(1.0))
    0.25
    """
    return 1.0 - 0.75 * _cloud(cloud_cover) ** 3.4


def cloud_diffuse_fraction(cloud_cover):
    """Diffuse fraction of the global short-wave irradiance under cloud, 0.3 + 0.7 N² [-].

    Parameters
    ----------
    cloud_cover : array_like
        N [0-1].

    Returns
    -------
    ndarray
        D/G [-], from 0.3 (clear) to 1 (overcast).

    Notes
    -----
    Kasten & Czeplak (1980): :math:`D/G = 0.3 + 0.7\\,N^2`. Under a clear sky the
    ratio from a clear-sky model is the better one; the form serves where N > 0.

    Examples
    --------
    >>> float(cloud_diffuse_fraction(1.0))
    1.0
    """
    return 0.3 + 0.7 * _cloud(cloud_cover) ** 2
