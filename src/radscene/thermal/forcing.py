"""What drives the heat balance (:class:`ThermalForcing`) and what it returns
(:class:`ThermalResult`).

Every forcing field broadcasts to (n_times, n_elements) by numpy's rules: a scalar is constant,
an (n_elements,) array a constant per element, an (n_times, 1) array a time series shared by
every element. The fields after ``sky_view_fraction`` are optional and switch on terms of the
balance that are absent by default (docs/thermal.md).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = ["ThermalForcing", "ThermalResult", "STANDARD_PRESSURE"]

#: Sea-level pressure of the ICAO standard atmosphere [Pa], the default ``pressure``.
STANDARD_PRESSURE = 101325.0

_FIELDS = ("direct_irradiance", "cos_incidence", "diffuse_irradiance", "sky_longwave", "air_temperature", "wind_speed", "lit", "sky_view_fraction")


def _broadcast(value, name, shape):
    """(given values, broadcast view): the checks run on the former, which holds the same values
    in (often far) fewer elements."""
    value = np.asarray(value, float)
    try:
        return value, np.broadcast_to(value, shape)
    except ValueError:
        raise ConfigError(
            f"shape {value.shape} does not broadcast to (n_times, n_elements) = {shape}", key=f"forcing.{name}"
        ) from None


@dataclass(frozen=True)
class ThermalForcing:
    """Forcing of every element at a sequence of times.

    Attributes
    ----------
    time : ndarray, (n_times,)
        Seconds from an origin, strictly increasing [s].
    direct_irradiance : array_like
        Beam irradiance normal to the sun's direction [W m-2].
    cos_incidence : array_like
        Cosine of the sun's incidence angle on the element [-] (≤ 0: sun behind it).
    diffuse_irradiance : array_like
        Diffuse short-wave irradiance on a horizontal plane, full sky [W m-2].
    sky_longwave : array_like
        Downwelling long-wave irradiance on a horizontal plane, full sky [W m-2].
    air_temperature : array_like
        [K].
    wind_speed : array_like
        [m s-1].
    lit : array_like, optional
        Sunlit fraction [-]; default 1.
    sky_view_fraction : array_like, optional
        Sky view factor [-]; default 1.
    sky_view_shortwave : array_like, optional
        Sky view factor of the diffuse short-wave sky [-] where it differs from
        ``sky_view_fraction`` (semi-transparent sheets that pass the sun's light and hide the
        sky's long-wave); default ``sky_view_fraction``.
    relative_humidity : array_like, optional
        Relative humidity of the air over water, [0, 1] [-]; default none given, which the
        evaporation term Q_v needs wherever the moisture availability is > 0.
    pressure : array_like, optional
        Air pressure [Pa]; default ``STANDARD_PRESSURE`` (sea level). It enters the specific
        humidities of Q_v and the air density of the airspeed convection: give it for
        elements above the ground, airborne ones especially.
    internal_flux : array_like, optional
        Heat released inside the element and delivered to its surface node [W m-2] (engines,
        heated rooms behind a thin skin: a power P [W] spread over an area S [m2] is P/S);
        default 0. Either sign.
    air_speed : array_like, optional
        Speed of the element relative to the air [m s-1] for airborne elements (NaN: not
        airborne, the wind correlation applies); default none airborne. It replaces the wind
        correlation by the turbulent flat-plate coefficient and convection to the recovery
        temperature (``thermal.aerodynamic``).
    environment_irradiance : array_like, optional
        Long-wave irradiance on the element from surfaces that are not in the balance (objects
        of fixed temperature: Σ_f F_if ε_f σ T_f⁴) [W m-2], absorbed with the element's
        emissivity and counted in Q_env; default 0.
    direct_absorptance, diffuse_absorptance : array_like, optional
        The element's solar absorptance of the beam and of the diffuse sky at each time [-],
        from its spectrum against each one's spectrum at that time; default the heat
        balance's broadband ``absorptance`` for both.
    """

    time: np.ndarray
    direct_irradiance: np.ndarray
    cos_incidence: np.ndarray
    diffuse_irradiance: np.ndarray
    sky_longwave: np.ndarray
    air_temperature: np.ndarray
    wind_speed: np.ndarray
    lit: np.ndarray = 1.0
    sky_view_fraction: np.ndarray = 1.0
    relative_humidity: np.ndarray | None = None
    pressure: np.ndarray | None = None
    internal_flux: np.ndarray = 0.0
    air_speed: np.ndarray | None = None
    environment_irradiance: np.ndarray = 0.0
    sky_view_shortwave: np.ndarray | None = None
    direct_absorptance: np.ndarray | None = None
    diffuse_absorptance: np.ndarray | None = None

    def checked(self, n_elements):
        """Validated arrays broadcast to (n_times, n_elements), as a dict (views, no copies).

        ``relative_humidity`` and ``air_speed`` are None when not given; ``pressure`` is then
        ``STANDARD_PRESSURE`` broadcast.
        """
        time = np.asarray(self.time, float)
        if time.ndim != 1 or time.size < 2 or not np.all(np.isfinite(time)) or np.any(np.diff(time) <= 0):
            raise ConfigError("must be a 1-d array of >= 2 finite, strictly increasing times [s]", key="forcing.time")
        shape = (time.size, n_elements)
        out = {"time": time}
        for name in _FIELDS:
            value, out[name] = _broadcast(getattr(self, name), name, shape)
            if not np.all(np.isfinite(value)):
                raise ConfigError("must be finite", key=f"forcing.{name}")
            if name in ("lit", "sky_view_fraction") and (value.min() < 0 or value.max() > 1):
                raise ConfigError("must lie in [0, 1]", key=f"forcing.{name}")
            if name == "cos_incidence" and (value.min() < -1 or value.max() > 1):
                raise ConfigError("must lie in [-1, 1]", key=f"forcing.{name}")
            if name == "air_temperature" and value.min() <= 0:
                raise ConfigError("must be > 0 K", key=f"forcing.{name}")
            if name not in ("cos_incidence", "air_temperature") and value.min() < 0:
                raise ConfigError("must be >= 0", key=f"forcing.{name}")
        out["relative_humidity"] = None
        if self.relative_humidity is not None:
            value, out["relative_humidity"] = _broadcast(self.relative_humidity, "relative_humidity", shape)
            if not np.all(np.isfinite(value) & (value >= 0) & (value <= 1)):
                raise ConfigError("must lie in [0, 1] (a fraction, not per cent)", key="forcing.relative_humidity")
        pressure = STANDARD_PRESSURE if self.pressure is None else self.pressure
        value, out["pressure"] = _broadcast(pressure, "pressure", shape)
        if not np.all(np.isfinite(value) & (value > 0)):
            raise ConfigError("must be finite and > 0 Pa", key="forcing.pressure")
        value, out["internal_flux"] = _broadcast(self.internal_flux, "internal_flux", shape)
        if not np.all(np.isfinite(value)):
            raise ConfigError("must be finite", key="forcing.internal_flux")
        value, out["environment_irradiance"] = _broadcast(self.environment_irradiance, "environment_irradiance", shape)
        if not np.all(np.isfinite(value) & (value >= 0)):
            raise ConfigError("must be finite and >= 0 W m-2", key="forcing.environment_irradiance")
        out["has_environment"] = bool(np.any(value != 0.0))
        out["sky_view_shortwave"] = out["sky_view_fraction"]
        if self.sky_view_shortwave is not None:
            value, out["sky_view_shortwave"] = _broadcast(self.sky_view_shortwave,
                                                          "sky_view_shortwave", shape)
            if not np.all(np.isfinite(value) & (value >= 0) & (value <= 1)):
                raise ConfigError("must lie in [0, 1]", key="forcing.sky_view_shortwave")
        for name in ("direct_absorptance", "diffuse_absorptance"):
            out[name] = None
            if getattr(self, name) is not None:
                value, out[name] = _broadcast(getattr(self, name), name, shape)
                if not np.all(np.isfinite(value) & (value >= 0) & (value <= 1)):
                    raise ConfigError("must lie in [0, 1]", key=f"forcing.{name}")
        out["air_speed"] = None
        if self.air_speed is not None:
            value, out["air_speed"] = _broadcast(self.air_speed, "air_speed", shape)
            if np.any(np.isinf(value)) or np.any(value < 0):
                raise ConfigError("must be >= 0 m s-1, or NaN where an element is not airborne", key="forcing.air_speed")
        return out


@dataclass(frozen=True)
class ThermalResult:
    """What :meth:`HeatBalance.run` returns.

    Attributes
    ----------
    time : ndarray, (n_times,)
        [s], as in the forcing.
    surface_temperature : ndarray, (n_times, n_elements)
        [K]; row 0 is the initial (or spun-up) state.
    temperature : ndarray, (n_elements, n_nodes)
        The profile at the last time [K].
    depth : ndarray, (n_elements, n_nodes)
        Node depths [m].
    spin_up_days : int
        Days of spin-up simulated (0: none).
    spin_up_change : float
        Largest change of a surface temperature at the same time of day between the last two
        spin-up days [K] (NaN: none).
    terms : dict of str to ndarray, or None
        With ``run(..., record_terms=True)``: each term of the balance, (n_times, n_elements)
        [W m-2], over the step that ends at each time (row 0 NaN): ``q_a``, ``q_sky``,
        ``q_env``, ``q_t``, ``q_k``, ``q_v``, ``q_i`` into the surface positive, ``q_lat``
        (with lateral conduction) the heat from the neighbouring elements, and ``q_d`` the
        heat that flows from the stack into the surface node (minus the storage and
        conduction below the surface), so that q_a + q_sky + q_env + q_t + q_k + q_v + q_i
        (+ q_lat) + q_d = 0, the balance of seed eq. 5 with every term into the surface
        positive.
    canopy_temperature, ground_temperature : ndarray, (n_times, n_elements), or None
        With leaves (``thermal.canopy``): the leaf layer's and the soil surface's temperatures
        [K], NaN for the elements without leaves, whose ``surface_temperature`` is then the
        nadir radiometric temperature of leaves and soil. None without leaves.
    probe_temperature : ndarray, (n_times, n_elements, n_probes), float32, or None
        With ``run(..., probe_depth=...)``: the temperature at the probe depths [K], NaN
        where an element has no probe. None without probes.
    closure : ndarray, (n_times,), or None
        With ``record_terms``: the energy closure of the step that ends at each time (row 0
        NaN) [-], Σ_e a_e |Σ surface terms · Δt − (ΔΣ C_i T_i + bottom flux · Δt)| /
        Σ_e a_e Σ |terms| · Δt over the elements e (areas a_e, 1 without ``area``): each
        element's error counts, none cancels another's, and elements with no flux at all do
        not divide by zero.
    """

    time: np.ndarray
    surface_temperature: np.ndarray
    temperature: np.ndarray
    depth: np.ndarray
    spin_up_days: int = 0
    spin_up_change: float = float("nan")
    terms: dict | None = None
    closure: np.ndarray | None = None
    canopy_temperature: np.ndarray | None = None
    ground_temperature: np.ndarray | None = None
    probe_temperature: np.ndarray | None = None
