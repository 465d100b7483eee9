"""Time stepper of the surface heat balance of many elements, with an optional spin-up.

For every element the surface node balances every term of seed 001's balance (eq. 5, with
Q_env of eq. 3; sign: into the surface positive)

.. math::
    Q_a + Q_{sky} + Q_{env} + Q_t + Q_k + Q_v + Q_i\\,(+\\,Q_{lat}) = Q_d

where Q_d, the heat that goes into storage in the surface node and conduction into the stack,
comes from :mod:`radscene.thermal.conduction`: after the backward-Euler system is eliminated
from the bottom up, Q_d = A T_0' − B with A, B known per element and step (the recorded
``q_d`` is −Q_d, into the surface positive like the other terms, so that they sum to zero). The terms
(docs/thermal.md has the table, with their modules and sources):

* Q_a, Q_sky absorbed short-wave and sky long-wave, Q_t = −εσT⁴ (``radiation``);
* Q_env long-wave from and short-wave reflected by the neighbouring elements, from caller-given
  view factors, explicit in the neighbours' temperatures (``exchange``);
* Q_k = h (T_air − T), h from the wind (``convection``), for a canopy with a height and no leaf
  layer its aerodynamic conductance (``canopy.aerodynamic_conductance``) or, for airborne
  elements, the turbulent flat-plate coefficient of the airspeed (``aerodynamic``);
* Q_v = −β ρ_a L_v C_E u (q_sat(T) − q_a), linear in T about the temperature at the start of the
  step (``evaporation``);
* Q_i internal sources given as a flux, plus the aerodynamic heating h (T_r − T_air) of airborne
  elements (``aerodynamic``);
* Q_lat lateral conduction from neighbouring elements (``lateral``; optional).

Stacks whose ``canopy`` has a ``height`` and a ``leaf_width`` carry a leaf layer above their surface node
(``canopy``): its linear equation is eliminated into the surface equation, so the form below
holds for them too; their recorded terms are those of leaves and soil together, Q_d including
the leaves' storage, and their surface temperature the nadir radiometric one.

Everything but Q_t is linear in the new surface temperature within a step, so the surface
equation of each element keeps the form

.. math::
    g(T) = c + B - \\varepsilon\\sigma T^4 - (m + A)\\,T = 0

and is solved by Newton's method, fully implicit in the nonlinear emission: g decreases and is
concave for T > 0, so the first Newton step lands at or above the root and the later ones
descend to it monotonically (convergence from any positive start). The new profile follows by
back-substitution. Forcing is taken at the end of each step (backward Euler). With lateral
conduction the surface equations of all elements are solved together
(:func:`radscene.thermal.lateral.coupled_surface_temperature`).

The default step is compiled (:mod:`radscene.thermal._compiled`, numba): elimination, Newton and
back-substitution fused per element. ``HeatBalance(..., compiled=False)`` runs the numpy path
(the same arithmetic over arrays of elements), the reference.

Spin-up repeats the forcing of the first day (the samples from ``time[0]`` to
``time[0] + 1 day``) until the surface temperatures at the same times of day change by less
than a tolerance from one day to the next, then runs the whole forcing from that state. After
the first day every node of an element is set to that day's mean surface temperature: in the
periodic state the daily mean temperature is the same at every depth when no heat leaves
through the bottom (zero mean flux at every depth), so this removes the slow transient of the
deep nodes (a road and a roof from the air's mean: 4 days to 0.05 K instead of 10, 10 to
0.01 K instead of 21; tests/unit/test_thermal_balance.py).

References
----------
Willers, C. J., Willers, M. S. and Lapierre, F. (2011). Signature modelling and radiometric
rendering equations in infrared scene simulation systems. Proc. SPIE 8187, 81870R, eqs. 3
and 5. doi:10.1117/12.903352
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError, RadsceneError
from radscene.thermal import _compiled
from radscene.thermal.aerodynamic import flat_plate_coefficient, recovery_temperature
from radscene.thermal.canopy import (
    CANOPY_MIN_WIND,
    CanopyLayer,
    aerodynamic_conductance,
    beam_transmittance,
    canopy_conductances,
    leaf_equation,
    transpiration_availability,
)
from radscene.thermal.conduction import DAY, ImplicitConduction, build_grid
from radscene.thermal.convection import FREE_CONVECTION_MODELS, convection_coefficient
from radscene.thermal.evaporation import linearised_evaporative_flux
from radscene.thermal.exchange import (
    check_view_factors,
    environment_longwave,
    environment_shortwave,
)
from radscene.thermal.forcing import ThermalForcing, ThermalResult
from radscene.thermal.lateral import check_conductance, coupled_surface_temperature, laplacian
from radscene.thermal.radiation import SIGMA, absorbed_shortwave, absorbed_sky_longwave

__all__ = ["ThermalForcing", "ThermalResult", "HeatBalance", "solve_surface_temperature", "TERMS"]

#: Names of the recorded terms (``ThermalResult.terms``), ``q_lat`` only with lateral conduction.
TERMS = ("q_a", "q_sky", "q_env", "q_t", "q_k", "q_v", "q_i", "q_lat", "q_d")

_TOLERANCE, _MAX_ITERATIONS = 1e-9, 50  # K, - : Newton on the surface node


def solve_surface_temperature(constant, slope, emissivity, start, tolerance=_TOLERANCE, max_iterations=_MAX_ITERATIONS):
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


def _lumped_canopy_height(stack, leaf_layer):
    """The height [m] of a stack's canopy where it is solved without a leaf layer and has one
    (its exchange with the air is then the canopy's aerodynamic conductance); NaN otherwise."""
    spec = getattr(stack, "canopy", None) or {}
    if "height" not in spec or (leaf_layer and "leaf_width" in spec):
        return np.nan
    return float(spec["height"])


class _Coefficients:
    """The eliminated systems of one Δt: per stack (compiled path) and, on demand, per element
    (numpy path)."""

    def __init__(self, balance, dt):
        self.stack = ImplicitConduction(balance._stack_grid, dt)
        self.surface_conductance = self.stack.surface_conductance[balance._index]
        self._balance, self._dt, self._element = balance, dt, None
        s = self.stack
        self.tables = (s._a, s._g, s._e, 1.0 / s._e, s._alpha, s._fixed, s._deep, np.ascontiguousarray(s._inside, dtype=float))

    @property
    def element(self):
        if self._element is None:
            self._element = ImplicitConduction(self._balance.grid, self._dt)
        return self._element


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
    cos_tilt : array_like, optional
        Vertical component of each element's outward normal, for the correlations with free
        convection (``thermal.convection.FREE_CONVECTION_MODELS``); default 1 (facing up).
    exchange : scipy.sparse matrix, (n_elements, n_elements), optional
        View factors F_ij from element i to element j [-] (row sums ≤ 1 − sky view), which
        switch on Q_env (``thermal.exchange``); default none.
    exchange_reflections : int, optional
        Reflections followed in Q_env (1: long-wave emitted or reflected once by the
        neighbours, short-wave reflected once).
    moisture_availability : array_like or "stacks", optional
        β ∈ [0, 1] per element or scalar for Q_v (``thermal.evaporation``), or ``"stacks"``
        for each stack's ``moisture_availability`` (1 for water); default 0: no evaporation.
        β > 0 needs ``forcing.relative_humidity``.
    characteristic_length : array_like, optional
        Length of each element along the relative airflow [m] for the airspeed convection
        coefficient; default 1.
    lateral : scipy.sparse matrix, (n_elements, n_elements), optional
        Symmetric lateral conductances G_ij [W K-1] (``thermal.lateral.grid_conductance``,
        ``mesh_conductance``); default none. Needs ``area``.
    area : array_like, optional
        Element areas [m2] (with ``lateral``).
    compiled : bool, optional
        Run the compiled step (default) or the numpy reference path.
    canopy : bool, optional
        Solve the leaf layer of stacks whose ``canopy`` has a ``height`` and a ``leaf_width``
        (default; ``thermal.canopy``); False: such stacks are a lumped surface that meets the
        air through the canopy's aerodynamic conductance, as one with a height alone does.

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
        cos_tilt=1.0,
        exchange=None,
        exchange_reflections=1,
        moisture_availability=None,
        characteristic_length=1.0,
        lateral=None,
        area=None,
        compiled=True,
        canopy=True,
    ):
        stacks = list(stacks)
        self.grid = build_grid(stacks, material_index, n_nodes, growth, period, penetration_depths, deep_temperature)
        self._stack_grid = build_grid(stacks, None, n_nodes, growth, period, penetration_depths, deep_temperature)
        index = np.arange(len(stacks)) if material_index is None else np.asarray(material_index)
        self._index = np.ascontiguousarray(index, dtype=np.int64)
        n = self.grid.n_elements
        self.absorptance = self._optical(absorptance, stacks, index, "solar_absorptance", "absorptance", n)
        self.emissivity = self._optical(emissivity, stacks, index, "longwave_emissivity", "emissivity", n)
        convection_coefficient(0.0, convection)  # fail early on an unknown name
        self.convection = convection
        self._free = str(convection).strip().lower() in FREE_CONVECTION_MODELS
        try:
            self.cos_tilt = np.broadcast_to(np.asarray(cos_tilt, float), (n,)).copy()
        except ValueError:
            raise ConfigError(f"shape {np.shape(cos_tilt)} does not broadcast to (n_elements,) = ({n},)",
                              key="cos_tilt") from None
        if not np.all(np.isfinite(self.cos_tilt) & (np.abs(self.cos_tilt) <= 1.0 + 1e-9)):
            raise ConfigError("must lie in [-1, 1]", key="cos_tilt")
        self.exchange = None if exchange is None else check_view_factors(exchange, n)
        if isinstance(exchange_reflections, bool) or not isinstance(exchange_reflections, (int, np.integer)) or exchange_reflections < 0:
            raise ConfigError(f"must be an integer >= 0; got {exchange_reflections!r}", key="exchange_reflections")
        self.exchange_reflections = int(exchange_reflections)
        if isinstance(moisture_availability, str):
            if moisture_availability != "stacks":
                raise ConfigError(f"expected 'stacks', a number or an array; got {moisture_availability!r}", key="moisture_availability")
            moisture_availability = np.array([float(getattr(s, "moisture_availability", 0.0)) for s in stacks])[index]
        self.moisture_availability = self._optical(0.0 if moisture_availability is None else moisture_availability, stacks, index, None, "moisture_availability", n)
        self.characteristic_length = self._per_element(characteristic_length, "characteristic_length", n)
        self.lateral = None
        if lateral is not None:
            if area is None:
                raise ConfigError("lateral conduction needs the element areas [m2]", key="area")
            self.lateral = laplacian(check_conductance(lateral, n))
        self.area = None if area is None else self._per_element(area, "area", n)
        self.compiled = bool(compiled)
        self.canopy = CanopyLayer.from_stacks(stacks, index) if canopy else None
        # canopies without a leaf layer whose height is given meet the air through their
        # aerodynamic conductance, not the scene's flat-plate correlation (module canopy)
        heights = np.array([_lumped_canopy_height(s, canopy) for s in stacks])[index]
        rough = np.flatnonzero(np.isfinite(heights))
        # (not with convection "none": no air, no exchange)
        self._rough = (rough, heights[rough]) if rough.size and str(convection).lower() != "none" else None
        self._es = np.ascontiguousarray(self.emissivity * SIGMA)
        self._leaf = None  # leaf temperatures [K] of the canopy elements, set by run
        if self.canopy is not None:
            # the soil under leaves emits to the sky through the gaps only (module canopy)
            c = self.canopy.index
            self._es[c] = self.canopy.diffuse * self.emissivity[c] * SIGMA
        # the compiled path keeps the elements sorted by stack (module _compiled); None: as given
        order = np.argsort(self._index, kind="stable")
        self._order = None if not self.compiled or np.all(order == np.arange(n)) else order
        self._inverse = None if self._order is None else np.argsort(self._order)
        self._blocks = _compiled.blocks_of(self._internal(self._index))
        self._es_internal = np.ascontiguousarray(self._internal(self._es))
        self._stepper = _compiled.Stepper()  # serial or parallel, whichever runs faster
        self._wet = np.flatnonzero(self.moisture_availability > 0)
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

    @staticmethod
    def _per_element(value, key, n):
        try:
            value = np.broadcast_to(np.asarray(value, float), (n,)).copy()
        except ValueError:
            raise ConfigError(f"shape {np.shape(value)} does not broadcast to (n_elements,) = ({n},)", key=key) from None
        if not np.all(np.isfinite(value) & (value > 0)):
            raise ConfigError("must be finite and > 0", key=key)
        return value

    def _internal(self, values):
        """Element values (last axis) in the order the state is kept in."""
        return values if self._order is None else values[..., self._order]

    def _external(self, values):
        """Element values (last axis) of the state back in the caller's order."""
        return values if self._inverse is None else values[..., self._inverse]

    def _solver(self, dt):
        """The eliminated systems for a step Δt [s] (rounded to 1 µs); the last 4 are kept."""
        key = round(float(dt), 6)
        solver = self._solvers.pop(key, None)
        if solver is None:
            solver = _Coefficients(self, key)
            while len(self._solvers) >= 4:
                self._solvers.pop(next(iter(self._solvers)))
        self._solvers[key] = solver  # most recently used last
        return solver

    def _fluxes(self, f, k, previous):
        """The terms known at the start of step k, and the linear coefficients of the rest;
        ``previous`` the surface temperatures at the start of the step (caller's order; only
        read with Q_env or Q_v).

        Returns a dict: q_a, q_sky, q_env, q_i [W m-2] (or None when absent), h
        [W m-2 K-1], the evaporation's linear coefficients v_c [W m-2] and v_s [W m-2 K-1]
        (None when no element is wet).
        """
        shape = (self.grid.n_elements,)
        lit, view, view_sw = f["lit"][k], f["sky_view_fraction"][k], f["sky_view_shortwave"][k]
        air = f["air_temperature"][k]
        if f["direct_absorptance"] is None and f["diffuse_absorptance"] is None:
            q_a = absorbed_shortwave(self.absorptance, f["direct_irradiance"][k], f["cos_incidence"][k], f["diffuse_irradiance"][k], lit, view_sw)
        else:
            a_dir = self.absorptance if f["direct_absorptance"] is None else f["direct_absorptance"][k]
            a_dif = self.absorptance if f["diffuse_absorptance"] is None else f["diffuse_absorptance"][k]
            q_a = (absorbed_shortwave(a_dir, f["direct_irradiance"][k], f["cos_incidence"][k], 0.0, lit, view_sw)
                   + absorbed_shortwave(a_dif, 0.0, f["cos_incidence"][k], f["diffuse_irradiance"][k], lit, view_sw))
        q_sky = absorbed_sky_longwave(self.emissivity, f["sky_longwave"][k], view)
        if self._free:
            h = convection_coefficient(f["wind_speed"][k], self.convection, previous - air, self.cos_tilt)
        else:
            h = convection_coefficient(f["wind_speed"][k], self.convection)
        if self._rough is not None:
            r, height = self._rough
            h = np.array(np.broadcast_to(h, shape), dtype=float)
            h[r] = aerodynamic_conductance(height, np.broadcast_to(f["wind_speed"][k], shape)[r],
                                           np.broadcast_to(air, shape)[r], f["pressure"][k][r],
                                           None if previous is None else previous[r],
                                           CANOPY_MIN_WIND)
        out = {"q_a": q_a, "q_sky": q_sky, "q_env": None, "q_i": None, "h": h, "v_c": None, "v_s": None, "canopy": None}
        if self.exchange is not None:
            irradiance = absorbed_shortwave(1.0, f["direct_irradiance"][k], f["cos_incidence"][k], f["diffuse_irradiance"][k], lit, view_sw)
            sky = np.broadcast_to(f["sky_longwave"][k] * view, shape)
            out["q_env"] = environment_longwave(self.exchange, self.emissivity, self._exitance(previous), sky, self.exchange_reflections) + environment_shortwave(
                self.exchange, self.absorptance, irradiance, self.exchange_reflections
            )
        if f["has_environment"]:
            fixed = self.emissivity * f["environment_irradiance"][k]
            out["q_env"] = fixed if out["q_env"] is None else out["q_env"] + fixed
        internal = f["internal_flux"][k] if f["has_internal"] else None
        if f["air_speed"] is not None:
            speed = f["air_speed"][k]
            airborne = np.flatnonzero(np.isfinite(speed))
            if airborne.size:
                h = out["h"] = np.array(np.broadcast_to(h, shape))
                t_air, u = np.broadcast_to(air, shape)[airborne], speed[airborne]
                h[airborne] = flat_plate_coefficient(u, self.characteristic_length[airborne], t_air, f["pressure"][k][airborne])
                aero = np.zeros(shape)
                aero[airborne] = h[airborne] * (recovery_temperature(t_air, u) - t_air)
                internal = aero if internal is None else internal + aero
        out["q_i"] = internal
        if self.canopy is not None:
            c = self.canopy.index
            h = out["h"] = np.array(np.broadcast_to(h, shape), dtype=float)
            leaf_air, soil_air, leaf_soil = canopy_conductances(
                self.canopy.lai, self.canopy.height, self.canopy.leaf_width, np.broadcast_to(f["wind_speed"][k], shape)[c],
                h[c], np.broadcast_to(air, shape)[c], f["pressure"][k][c], self._leaf)
            h[c] = soil_air  # the soil's convection (and its evaporation) through the canopy air
            out["canopy"] = {"leaf_air": leaf_air, "leaf_soil": leaf_soil}
        if self._wet.size:
            wet = self._wet
            c, s = linearised_evaporative_flux(
                self.moisture_availability[wet], np.broadcast_to(h, shape)[wet], previous[wet],
                np.broadcast_to(air, shape)[wet], f["relative_humidity"][k][wet], f["pressure"][k][wet],
            )
            out["v_c"], out["v_s"] = np.zeros(shape), np.zeros(shape)
            out["v_c"][wet], out["v_s"][wet] = c, s
        return out

    def _step(self, state, f, k, dt, record=None, out=None):
        """Advance the node-major ``state`` (internal order) in place to time index k; fill row
        k of ``record``; return the new surface temperatures in the caller's order (in ``out``
        if given): the radiometric temperature of canopy elements (``thermal.canopy``)."""
        solver = self._solver(dt)
        needs_previous = (not self.compiled or self.exchange is not None or self._wet.size or self.lateral is not None
                          or self._rough is not None or self._free
                          or self.canopy is not None)
        previous = np.array(self._external(state[0])) if needs_previous else None
        old = np.array(self._external(state)) if record is not None else None
        p = self._fluxes(f, k, previous)
        h, air = p["h"], f["air_temperature"][k]
        constant = p["q_a"] + p["q_sky"] + h * air
        for name in ("q_env", "q_i", "v_c"):
            if p[name] is not None:
                constant = constant + p[name]
        slope = h if p["v_s"] is None else h + p["v_s"]
        n = self.grid.n_elements
        leaf = None
        if self.canopy is not None:
            constant, slope = np.array(np.broadcast_to(constant, (n,))), np.array(np.broadcast_to(slope, (n,)))
            leaf = self._leaf_terms(f, k, p, previous, dt)
            c = self.canopy.index
            constant[c] += leaf["soil_constant"]
            slope[c] += leaf["soil_slope"]
        if self.compiled:
            constant = np.broadcast_to(constant, (n,))
            slope = np.broadcast_to(slope, (n,))
            surface, b = np.empty(n), np.empty(n)
            failures = self._stepper.step(
                state, self._blocks, *solver.tables, np.ascontiguousarray(self._internal(constant), dtype=float),
                np.ascontiguousarray(self._internal(slope), dtype=float), self._es_internal, _TOLERANCE, _MAX_ITERATIONS,
                self.lateral is None, surface, b,
            )
            if failures:
                raise RadsceneError(f"surface temperature: Newton did not converge in {_MAX_ITERATIONS} iterations in {failures} blocks of elements")
            own = out if leaf is None else None  # with leaves, ``out`` receives the radiometric temperature
            surface = self._external(surface) if own is None or self._inverse is None else np.take(surface, self._inverse, out=own)
            if record is not None or self.lateral is not None:
                b = self._external(b)
            if self.lateral is not None:
                surface = self._coupled(constant + b, slope + solver.surface_conductance, previous)
                self._stepper.substitute(state, self._blocks, solver.stack._alpha, np.ascontiguousarray(self._internal(surface)))
        else:
            beta, b = solver.element.eliminate(state)
            if self.lateral is None:
                surface = solve_surface_temperature(constant + b, slope + solver.surface_conductance, self._es / SIGMA, previous)
            else:
                surface = self._coupled(constant + b, slope + solver.surface_conductance, previous)
            solver.element.substitute(surface, beta, out=state)
        seen = surface
        if leaf is not None:
            c = self.canopy.index
            leaf_old = self._leaf.copy()
            self._leaf[...] = (leaf["p"] + leaf["w"] * surface[c]) / leaf["d"]
            leaf["old"] = leaf_old
            seen = np.array(surface)
            seen[c] = self._radiometric(surface[c])
        if record is not None:
            self._record(record, k, dt, p, air, surface, solver.surface_conductance * surface - b, old, self._external(state), leaf)
        if out is not None and seen is not out:
            out[...] = seen
        return seen

    def _radiometric(self, soil):
        """Nadir radiometric temperature of the canopy elements [K] (``thermal.canopy``)."""
        gap = beam_transmittance(self.canopy.lai, 1.0)
        return ((1.0 - gap) * self._leaf**4 + gap * soil**4) ** 0.25

    def _exitance(self, previous):
        """Long-wave exitance of every element [W m-2] at its start-of-step temperatures: of
        canopy elements the leaves' upward emission plus the soil's through the gaps."""
        exitance = self._es * previous**4
        if self.canopy is not None:
            c = self.canopy.index
            exitance[c] += (1.0 - self.canopy.diffuse) * self.emissivity[c] * SIGMA * self._leaf**4
        return exitance

    def _leaf_terms(self, f, k, p, previous, dt):
        """The leaf equation of the canopy elements for step k and what it adds to the soil's
        surface equation (module ``thermal.canopy``)."""
        cl = self.canopy
        c, n = cl.index, self.grid.n_elements
        shape = (n,)
        tau = cl.diffuse
        eps = self.emissivity[c]
        lit, view = np.broadcast_to(f["lit"][k], shape)[c], np.broadcast_to(f["sky_view_fraction"][k], shape)[c]
        view_sw = np.broadcast_to(f["sky_view_shortwave"][k], shape)[c]
        direct = np.broadcast_to(f["direct_irradiance"][k], shape)[c] * np.maximum(np.broadcast_to(f["cos_incidence"][k], shape)[c], 0.0) * lit
        diffuse = np.broadcast_to(f["diffuse_irradiance"][k], shape)[c] * view_sw
        gap = beam_transmittance(cl.lai, np.broadcast_to(f["cos_incidence"][k], shape)[c])
        a_dir = self.absorptance[c] if f["direct_absorptance"] is None else np.broadcast_to(f["direct_absorptance"][k], shape)[c]
        a_dif = self.absorptance[c] if f["diffuse_absorptance"] is None else np.broadcast_to(f["diffuse_absorptance"][k], shape)[c]
        q_a = a_dir * direct * (1.0 - gap) + a_dif * diffuse * (1.0 - tau)
        q_sky = eps * (1.0 - tau) * view * np.broadcast_to(f["sky_longwave"][k], shape)[c]
        q_env = np.zeros(c.size) if p["q_env"] is None else np.broadcast_to(p["q_env"], shape)[c]
        air = np.broadcast_to(f["air_temperature"][k], shape)[c]
        pressure = np.broadcast_to(f["pressure"][k], shape)[c]
        leaf_air, leaf_soil = p["canopy"]["leaf_air"], p["canopy"]["leaf_soil"]
        beta = transpiration_availability(leaf_air, cl.lai, cl.leaf_resistance, direct + diffuse, air, pressure)
        v_c, v_s = linearised_evaporative_flux(beta, leaf_air, self._leaf, air, np.broadcast_to(f["relative_humidity"][k], shape)[c], pressure)
        emission = eps * (1.0 - tau) * SIGMA
        d, p_leaf, w = leaf_equation(cl.capacity, dt, self._leaf, previous[c], q_a + q_sky + q_env + v_c, emission, eps * emission,
                                     leaf_soil, air, leaf_air, v_s)
        return {"d": d, "p": p_leaf, "w": w, "q_a": q_a, "q_sky": q_sky, "q_env": q_env, "v_c": v_c, "v_s": v_s,
                "emission": emission, "leaf_air": leaf_air, "air": air,
                # the leaves' shares leave the soil's equation; the eliminated leaf enters it
                "soil_constant": w * p_leaf / d - q_a - q_sky - q_env, "soil_slope": w * (d - w) / d}

    def _coupled(self, constant, slope, start):
        start = solve_surface_temperature(constant, slope, self._es / SIGMA, start)
        return coupled_surface_temperature(constant, slope, self._es / SIGMA, self.lateral, self.area, start, _TOLERANCE, _MAX_ITERATIONS)

    def _record(self, record, k, dt, p, air, surface, into_stack, old, new, leaf=None):
        terms = record["terms"]
        zero = np.zeros(surface.shape)
        terms["q_a"][k] = p["q_a"]
        terms["q_sky"][k] = p["q_sky"]
        terms["q_env"][k] = zero if p["q_env"] is None else p["q_env"]
        terms["q_t"][k] = -self._es * surface**4
        terms["q_k"][k] = p["h"] * (air - surface)
        terms["q_v"][k] = zero if p["v_c"] is None else p["v_c"] - p["v_s"] * surface
        terms["q_i"][k] = zero if p["q_i"] is None else p["q_i"]
        if "q_lat" in terms:
            terms["q_lat"][k] = -(self.lateral @ surface) / self.area
        terms["q_d"][k] = -into_stack
        stored = np.einsum("ij,ij->j", self.grid.capacity.T, new - old) + self.grid.bottom_flux(new.T) * dt
        if leaf is not None:
            # the leaves: their emission to the sky (linearised as the step used it), their
            # exchange with the air and their transpiration; their storage counts in q_d
            c, tc, tc0 = self.canopy.index, self._leaf, leaf["old"]
            terms["q_t"][k, c] -= leaf["emission"] * (4.0 * tc0**3 * tc - 3.0 * tc0**4)
            terms["q_k"][k, c] += leaf["leaf_air"] * (leaf["air"] - tc)
            terms["q_v"][k, c] += leaf["v_c"] - leaf["v_s"] * tc
            held = self.canopy.capacity * (tc - tc0)
            terms["q_d"][k, c] -= held / dt
            stored[c] += held
        supplied = sum(terms[name][k] for name in terms if name != "q_d")
        magnitude = sum(np.abs(terms[name][k]) for name in terms)
        weight = 1.0 if self.area is None else self.area
        error = float(np.sum(weight * np.abs(supplied * dt - stored)))
        scale = float(np.sum(weight * magnitude * dt))
        record["closure"][k] = error / scale if scale > 0 else error

    def _initial(self, initial_temperature, f):
        n_el, n_nodes = self.grid.n_elements, self.grid.n_nodes
        if initial_temperature is None:
            first_day = int(np.count_nonzero(f["time"] <= f["time"][0] + DAY))  # a prefix: times increase
            value = f["air_temperature"][:first_day].mean(axis=0)[:, None]
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
        state = np.array(value.T, dtype=float, order="C")
        fixed = np.isfinite(self.grid.deep_temperature)
        state[-1, fixed] = self.grid.deep_temperature[fixed]
        return state

    def _checked(self, forcing):
        n_el = self.grid.n_elements
        f = forcing.checked(n_el)
        f["has_internal"] = bool(np.any(np.asarray(forcing.internal_flux, float) != 0.0))
        if self._wet.size and f["relative_humidity"] is None:
            raise ConfigError(
                f"{self._wet.size} elements have moisture_availability > 0 (e.g. element {self._wet[0]}): the evaporation "
                "term needs the air's relative humidity [0-1]; give it, or moisture_availability=0",
                key="forcing.relative_humidity",
            )
        if self.canopy is not None and f["relative_humidity"] is None:
            raise ConfigError(
                f"{self.canopy.index.size} elements carry leaves (e.g. element {self.canopy.index[0]}): their transpiration "
                "needs the air's relative humidity [0-1]; give it, or HeatBalance(..., canopy=False)",
                key="forcing.relative_humidity",
            )
        if self.exchange is not None:
            rows = np.asarray(self.exchange.sum(axis=1)).ravel() + f["sky_view_fraction"].max(axis=0)
            if rows.max() > 1.0 + 1e-9:
                i = int(np.argmax(rows))
                raise ConfigError(
                    f"element {i}: view factors to other elements plus the sky view fraction sum to {rows[i]:.6g} > 1",
                    key="exchange",
                )
        return f

    def run(self, forcing, initial_temperature=None, spin_up=False, spin_up_tolerance=0.01, max_spin_up_days=30, record_terms=False,
            progress=None, probe_depth=None, spin_up_forcing=None):
        """Advance every element through the forcing.

        Parameters
        ----------
        forcing : ThermalForcing
        initial_temperature : array_like, optional
            [K], scalar, (n_elements,) or (n_elements, n_nodes); default every node at the
            element's mean air temperature over the first day.
        spin_up : bool, optional
            Repeat the first day first (module docstring); needs a forcing sample exactly one
            day after the first, in ``forcing`` or in ``spin_up_forcing``.
        spin_up_forcing : ThermalForcing, optional
            The day the spin-up repeats, from the same start as ``forcing`` (default the first
            day of ``forcing``): for runs shorter than a day, or whose steps miss the instant a
            day after the start.
        spin_up_tolerance : float, optional
            [K] largest day-to-day change of a surface temperature to stop at.
        max_spin_up_days : int, optional
        record_terms : bool, optional
            Fill ``ThermalResult.terms`` and ``closure`` (memory: 9 arrays of
            (n_times, n_elements)).
        progress : callable(stage, done, total), optional
            Called after each spin-up day (``"spin-up days"``, out of ``max_spin_up_days``)
            and every 20 steps of the run (``"steps"``).
        probe_depth : array_like, (n_elements, n_probes), optional
            Depths below the surface [m] at which to record the temperature at every time,
            linear in depth between the nodes; NaN where an element has no probe. Fills
            ``ThermalResult.probe_temperature``.

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
        f = self._checked(forcing)
        time = f["time"]
        state = np.ascontiguousarray(self._internal(self._initial(initial_temperature, f)))
        if self.canopy is not None:
            self._leaf = np.array(self._external(state[0])[self.canopy.index])  # leaves start at the soil's surface
        days, change = 0, float("nan")
        if spin_up:
            if not (np.isfinite(spin_up_tolerance) and spin_up_tolerance > 0):
                raise ConfigError(f"must be > 0 K; got {spin_up_tolerance!r}", key="spin_up_tolerance")
            g, key = (f, "forcing.time") if spin_up_forcing is None else (self._checked(spin_up_forcing), "spin_up_forcing.time")
            day_time = g["time"]
            end = np.flatnonzero(np.isclose(day_time, day_time[0] + DAY, rtol=0.0, atol=1e-6))
            if end.size == 0:
                raise ConfigError("spin-up needs a forcing sample exactly one day after the first", key=key)
            end = int(end[0])
            previous = None
            while True:
                record = np.empty((end, n_el))
                for k in range(1, end + 1):
                    self._step(state, g, k, day_time[k] - day_time[k - 1], out=record[k - 1])
                days += 1
                if progress is not None:
                    progress("spin-up days", days, max_spin_up_days)
                if days == 1:
                    # the periodic state's daily mean is the same at every depth when no heat
                    # leaves through the bottom: start every node from the first day's mean
                    # surface temperature, which removes the slow transient of the deep nodes
                    state[...] = self._internal(self._initial(record.mean(axis=0), g))
                    if self.canopy is not None:
                        self._leaf[...] = record.mean(axis=0)[self.canopy.index]
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
        recorder = None
        if record_terms:
            names = [t for t in TERMS if t != "q_lat" or self.lateral is not None]
            recorder = {"terms": {t: np.full((time.size, n_el), np.nan) for t in names}, "closure": np.full(time.size, np.nan)}
        surface = np.empty((time.size, n_el))
        surface[0] = self._external(state[0])
        probes = None
        if probe_depth is not None:
            probe = self._probes(probe_depth)
            probes = np.full((time.size,) + probe[0].shape, np.nan, np.float32)
            probes[0] = self._probed(state, probe)
        leaves = ground = None
        if self.canopy is not None:
            c = self.canopy.index
            leaves, ground = np.full((time.size, n_el), np.nan), np.full((time.size, n_el), np.nan)
            leaves[0, c], ground[0, c] = self._leaf, surface[0, c]
            surface[0, c] = self._radiometric(ground[0, c])
        for k in range(1, time.size):
            self._step(state, f, k, time[k] - time[k - 1], recorder, out=surface[k])
            if leaves is not None:
                leaves[k, c], ground[k, c] = self._leaf, self._external(state[0])[c]
            if probes is not None:
                probes[k] = self._probed(state, probe)
            if progress is not None and (k % 20 == 0 or k == time.size - 1):
                progress("steps", k, time.size - 1)
        return ThermalResult(
            time=time,
            surface_temperature=surface,
            temperature=self._external(state).T.copy(),
            depth=self.grid.depth,
            spin_up_days=days,
            spin_up_change=change,
            terms=None if recorder is None else recorder["terms"],
            closure=None if recorder is None else recorder["closure"],
            canopy_temperature=leaves,
            ground_temperature=ground,
            probe_temperature=probes,
        )

    def _probes(self, probe_depth):
        """Node index and weight of each probe depth (n_elements, n_probes), and where it holds."""
        depth = self.grid.depth
        given = np.asarray(probe_depth, float)
        if given.ndim != 2 or given.shape[0] != depth.shape[0]:
            raise ConfigError(f"must have shape (n_elements, n_probes) = ({depth.shape[0]}, n); got {given.shape}",
                              key="probe_depth")
        valid = np.isfinite(given)
        if np.any(given[valid] < 0) or np.any(given > depth[:, -1:] * (1 + 1e-9)):
            raise ConfigError("must lie between the surface and the bottom of each stack", key="probe_depth")
        z = np.where(valid, given, 0.0)
        below = (depth[:, None, :] <= z[:, :, None]).sum(axis=-1) - 1
        index = np.clip(below, 0, depth.shape[1] - 2)
        rows = np.arange(depth.shape[0])[:, None]
        top, bottom = depth[rows, index], depth[rows, index + 1]
        weight = np.clip((z - top) / (bottom - top), 0.0, 1.0)
        return index, weight, valid

    def _probed(self, state, probe):
        """The temperatures [K] at the probes (:meth:`_probes`) of the state."""
        index, weight, valid = probe
        profile = self._external(state)
        rows = np.arange(index.shape[0])[:, None]
        value = (1.0 - weight) * profile[index, rows] + weight * profile[index + 1, rows]
        return np.where(valid, value, np.nan)
