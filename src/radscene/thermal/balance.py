"""Time stepper of the surface heat balance of many elements, with an optional spin-up.

For every element the surface node balances (seed 001, eq. 3 without Q_env; sign: into the
surface positive)

.. math::
    Q_a + Q_{sky} + Q_t + Q_k = Q_d, \\qquad
    Q_t = -\\varepsilon\\sigma T_0^4, \\quad Q_k = h(u)\\,(T_{air} - T_0),

where Q_d, the heat that goes into storage in the surface node and conduction into the
stack, comes from :mod:`radscene.thermal.conduction`: after the backward-Euler system is
eliminated from the bottom up, Q_d = A T_0' − B with A, B known per element and step. The
surface equation

.. math::
    g(T) = Q_a + Q_{sky} + h T_{air} + B - \\varepsilon\\sigma T^4 - (h + A)\\,T = 0

is then solved by Newton's method on the surface node, fully implicit in the nonlinear
emission: g decreases and is concave for T > 0, so the first Newton step lands at or above
the root and the later ones descend to it monotonically (convergence from any positive start).
The new profile follows by back-substitution. Forcing is taken at the end of each step
(backward Euler).

Measured: a whole step (short-wave, sky, convection, elimination, Newton — typically 3 to 4
iterations — and back-substitution) takes 0.015 s for 100 000 elements × 30 nodes (best of 3;
numpy 2.4, float64, one core of a shared 2-core machine under a load of 2.5; ``benchmarks/bench_thermal.py``,
docs/benchmarks.md), i.e. a day at one-minute steps in 22 s.

Spin-up repeats the forcing of the first day (the samples from ``time[0]`` to
``time[0] + 1 day``) until the surface temperatures at the same times of day change by less
than a tolerance from one day to the next, then runs the whole forcing from that state.

References
----------
Willers, C. J., Willers, M. S. and Lapierre, F. (2011). Signature modelling and radiometric
rendering equations in infrared scene simulation systems. Proc. SPIE 8187, 81870R, eqs. 3
and 5. doi:10.1117/12.903352
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError, RadsceneError
from radscene.thermal.conduction import DAY, ImplicitConduction, build_grid
from radscene.thermal.convection import convection_coefficient
from radscene.thermal.radiation import SIGMA, absorbed_shortwave, absorbed_sky_longwave

__all__ = ["ThermalForcing", "ThermalResult", "HeatBalance", "solve_surface_temperature"]

_FIELDS = ("direct_irradiance", "cos_incidence", "diffuse_irradiance", "sky_longwave", "air_temperature", "wind_speed", "lit", "sky_view_fraction")


@dataclass(frozen=True)
class ThermalForcing:
    """Forcing of every element at a sequence of times.

    Each field broadcasts to (n_times, n_elements) by numpy's rules: a scalar is constant, an
    (n_elements,) array a constant per element, an (n_times, 1) array a time series shared by
    every element.

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

    def checked(self, n_elements):
        """Validated arrays broadcast to (n_times, n_elements), as a dict (views, no copies)."""
        time = np.asarray(self.time, float)
        if time.ndim != 1 or time.size < 2 or not np.all(np.isfinite(time)) or np.any(np.diff(time) <= 0):
            raise ConfigError("must be a 1-d array of >= 2 finite, strictly increasing times [s]", key="forcing.time")
        out = {"time": time}
        for name in _FIELDS:
            value = np.asarray(getattr(self, name), float)
            try:
                value = np.broadcast_to(value, (time.size, n_elements))
            except ValueError:
                raise ConfigError(
                    f"shape {np.shape(getattr(self, name))} does not broadcast to (n_times, n_elements) = "
                    f"{(time.size, n_elements)}",
                    key=f"forcing.{name}",
                ) from None
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
            out[name] = value
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
    """

    time: np.ndarray
    surface_temperature: np.ndarray
    temperature: np.ndarray
    depth: np.ndarray
    spin_up_days: int = 0
    spin_up_change: float = float("nan")


def solve_surface_temperature(constant, slope, emissivity, start, tolerance=1e-9, max_iterations=50):
    """Root T > 0 of c − εσT⁴ − m T = 0 by Newton's method, elementwise.

    Parameters
    ----------
    constant : array_like
        c [W m-2] (> 0 for a positive root when ε > 0 or m > 0).
    slope : array_like
        m ≥ 0 [W m-2 K-1].
    emissivity : array_like
        ε [-].
    start : array_like
        First guess > 0 [K].
    tolerance : float, optional
        Stop when every update is below this [K].
    max_iterations : int, optional

    Returns
    -------
    ndarray
        T [K].

    Raises
    ------
    RadsceneError
        No convergence (a non-positive start or root).
    """
    es = np.asarray(emissivity, float) * SIGMA
    t = np.array(start, float)
    for _ in range(max_iterations):
        t3 = t**3
        g = constant - es * t3 * t - slope * t
        dt = g / (4.0 * es * t3 + slope)
        t += dt
        if np.max(np.abs(dt), initial=0.0) < tolerance:
            return t
    raise RadsceneError(f"surface temperature: Newton did not converge in {max_iterations} iterations")


class HeatBalance:
    """Heat balance of many surface elements over time.

    Parameters
    ----------
    stacks : sequence of ThermalProperties
        The distinct material stacks (``materials.get_thermal_properties``).
    material_index : array_like of int, (n_elements,), optional
        Stack of each element; default one element per stack.
    absorptance, emissivity : array_like, (n_elements,) or scalar, optional
        Solar absorptance and long-wave emissivity [-]; default each stack's
        ``solar_absorptance`` and ``longwave_emissivity``.
    n_nodes, growth, period, penetration_depths, deep_temperature
        Grid options, see :func:`radscene.thermal.conduction.build_grid`.
    convection : str, optional
        Wind correlation for h (``thermal.convection.CONVECTION_MODELS``); default McAdams.

    Examples
    --------
    >>> from radscene.materials import get_thermal_properties
    >>> hb = HeatBalance([get_thermal_properties("asphalt")])
    >>> t = np.arange(0.0, 3601.0, 600.0)
    >>> f = ThermalForcing(t, 0.0, 0.0, 0.0, 300.0, 283.15, 2.0)
    >>> r = hb.run(f, initial_temperature=283.15)
    >>> r.surface_temperature.shape
    (7, 1)
    """

    def __init__(
        self,
        stacks,
        material_index=None,
        *,
        absorptance=None,
        emissivity=None,
        n_nodes=30,
        growth=1.2,
        period=DAY,
        penetration_depths=5.0,
        deep_temperature=None,
        convection="mcadams",
    ):
        stacks = list(stacks)
        self.grid = build_grid(stacks, material_index, n_nodes, growth, period, penetration_depths, deep_temperature)
        index = np.arange(len(stacks)) if material_index is None else np.asarray(material_index)
        n = self.grid.n_elements
        self.absorptance = self._optical(absorptance, stacks, index, "solar_absorptance", "absorptance", n)
        self.emissivity = self._optical(emissivity, stacks, index, "longwave_emissivity", "emissivity", n)
        convection_coefficient(0.0, convection)  # fail early on an unknown name
        self.convection = convection
        self._solvers = {}

    @staticmethod
    def _optical(value, stacks, index, attribute, key, n):
        if value is None:
            try:
                value = np.array([getattr(s, attribute) for s in stacks])[index]
            except AttributeError:
                raise ConfigError(f"give {key} or stacks with a {attribute!r}", key=key) from None
        try:
            value = np.broadcast_to(np.asarray(value, float), (n,)).copy()
        except ValueError:
            raise ConfigError(f"shape {np.shape(value)} does not broadcast to (n_elements,) = ({n},)", key=key) from None
        if not np.all(np.isfinite(value) & (value >= 0) & (value <= 1)):
            raise ConfigError("must lie in [0, 1]", key=key)
        return value

    def _solver(self, dt):
        """The eliminated system for a step Δt [s] (rounded to 1 µs); the last 4 are kept (each
        holds two (n_nodes, n_elements) arrays)."""
        key = round(float(dt), 6)
        solver = self._solvers.pop(key, None)
        if solver is None:
            solver = ImplicitConduction(self.grid, key)
            while len(self._solvers) >= 4:
                self._solvers.pop(next(iter(self._solvers)))
        self._solvers[key] = solver  # most recently used last
        return solver

    def _step(self, state, f, k, dt):
        """Advance the node-major ``state`` in place to time index k."""
        solver = self._solver(dt)
        absorbed = absorbed_shortwave(
            self.absorptance, f["direct_irradiance"][k], f["cos_incidence"][k], f["diffuse_irradiance"][k], f["lit"][k], f["sky_view_fraction"][k]
        ) + absorbed_sky_longwave(self.emissivity, f["sky_longwave"][k], f["sky_view_fraction"][k])
        h = convection_coefficient(f["wind_speed"][k], self.convection)
        beta, b = solver.eliminate(state)
        t0 = solve_surface_temperature(
            absorbed + h * f["air_temperature"][k] + b, h + solver.surface_conductance, self.emissivity, state[0]
        )
        solver.substitute(t0, beta, out=state)

    def _initial(self, initial_temperature, f):
        n_el, n_nodes = self.grid.n_elements, self.grid.n_nodes
        if initial_temperature is None:
            first_day = f["time"] <= f["time"][0] + DAY
            value = f["air_temperature"][first_day].mean(axis=0)[:, None]
        else:
            value = np.asarray(initial_temperature, float)
            if value.ndim == 1:
                value = value[:, None]
        try:
            value = np.broadcast_to(value, (n_el, n_nodes))
        except ValueError:
            raise ConfigError(
                f"shape {value.shape} does not broadcast to (n_elements, n_nodes) = {(n_el, n_nodes)}", key="initial_temperature"
            ) from None
        if not np.all(np.isfinite(value) & (value > 0)):
            raise ConfigError("must be finite and > 0 K", key="initial_temperature")
        state = np.ascontiguousarray(value.T, dtype=float)
        fixed = np.isfinite(self.grid.deep_temperature)
        state[-1, fixed] = self.grid.deep_temperature[fixed]
        return state

    def run(self, forcing, initial_temperature=None, spin_up=False, spin_up_tolerance=0.01, max_spin_up_days=30):
        """Advance every element through the forcing.

        Parameters
        ----------
        forcing : ThermalForcing
        initial_temperature : array_like, optional
            [K], scalar, (n_elements,) or (n_elements, n_nodes); default every node at the
            element's mean air temperature over the first day.
        spin_up : bool, optional
            Repeat the first day first (module docstring); needs a forcing sample exactly one
            day after the first.
        spin_up_tolerance : float, optional
            [K] largest day-to-day change of a surface temperature to stop at.
        max_spin_up_days : int, optional

        Returns
        -------
        ThermalResult

        Raises
        ------
        ConfigError
            Invalid forcing or options.
        RadsceneError
            The spin-up did not converge within ``max_spin_up_days``.
        """
        n_el = self.grid.n_elements
        f = forcing.checked(n_el)
        time = f["time"]
        state = self._initial(initial_temperature, f)
        days, change = 0, float("nan")
        if spin_up:
            if not (np.isfinite(spin_up_tolerance) and spin_up_tolerance > 0):
                raise ConfigError(f"must be > 0 K; got {spin_up_tolerance!r}", key="spin_up_tolerance")
            end = np.flatnonzero(np.isclose(time, time[0] + DAY, rtol=0.0, atol=1e-6))
            if end.size == 0:
                raise ConfigError("spin-up needs a forcing sample exactly one day after the first", key="forcing.time")
            end = int(end[0])
            previous = None
            while True:
                record = np.empty((end, n_el))
                for k in range(1, end + 1):
                    self._step(state, f, k, time[k] - time[k - 1])
                    record[k - 1] = state[0]
                days += 1
                if previous is not None:
                    change = float(np.max(np.abs(record - previous)))
                    if change < spin_up_tolerance:
                        break
                if days >= max_spin_up_days:
                    raise RadsceneError(
                        f"spin-up: surface temperatures still changed by {change:.3g} K from day {days - 1} to day "
                        f"{days} (tolerance {spin_up_tolerance} K); raise max_spin_up_days"
                    )
                previous = record
        surface = np.empty((time.size, n_el))
        surface[0] = state[0]
        for k in range(1, time.size):
            self._step(state, f, k, time[k] - time[k - 1])
            surface[k] = state[0]
        return ThermalResult(
            time=time,
            surface_temperature=surface,
            temperature=state.T.copy(),
            depth=self.grid.depth,
            spin_up_days=days,
            spin_up_change=change,
        )
