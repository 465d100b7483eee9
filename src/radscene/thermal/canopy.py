"""A vegetation canopy over the ground: a leaf layer of small heat capacity in the heat balance
(a two-source model: leaves and soil exchange with the air through a canopy air space).

The leaves of a canopy material (``canopy`` entry of ``thermal_properties.yaml`` with a
``height`` and a ``leaf_width``) are one node per element above the stack's surface node (the
soil). Per unit ground area, with L the leaf area index:

* **Radiation.** Black leaves, spherical leaf-angle distribution (extinction coefficient
  0.5/cos θ): a beam at zenith θ from the element's normal passes the leaves with
  τ_b = exp(−0.5 L / cos θ), isotropic diffuse radiation with
  τ_d = 2 ∫₀¹ exp(−0.5 L/μ) μ dμ = 2 E₃(0.5 L) (Campbell & Norman 1998, eqs. 15.1 and 15.5).
  The material's solar absorptance α is split between the leaves (the intercepted share) and
  the soil (the transmitted share), so that the element absorbs what the bare lumped surface
  did: Q_a,c = α (E_dir cos i lit (1 − τ_b) + E_dif V (1 − τ_d)), Q_a,s = Q_a − Q_a,c.
  Sky long-wave: ε (1 − τ_d) V E_sky on the leaves, ε τ_d V E_sky on the soil. The leaves
  emit ε (1 − τ_d) σ T_c⁴ upwards; the soil τ_d ε σ T_s⁴ through the gaps; leaves and soil
  exchange ε² (1 − τ_d) σ (T_c⁴ − T_s⁴) (the leaf layer's downward emission against the
  soil's emission it absorbs; second reflections neglected), the two-source partition of
  Kustas & Norman (1999) with one emissivity for leaves and soil.
* **Sensible heat** through a star of conductances to the canopy air (no heat capacity), in
  the manner of Shuttleworth & Wallace (1985) and Norman et al. (1995):
  leaves → canopy air g_x = L · 2 · 1.4 · 0.135 √(u_c/d) · c_p,mol with d = 0.72 w
  (Campbell & Norman 1998, eq. 7.30 and Table 7.5: both faces of a leaf of width w, 1.4 for
  outdoor turbulence, c_p,mol = 29.3 J mol-1 K-1); soil → canopy air
  1/r_s = ρ c_p (a' + b' u_s), a' = 0.004 m s-1, b' = 0.012 (Norman et al. 1995, appendix B,
  from Sauer et al. 1995); canopy air → the air at the reference height 2 m, a closed
  canopy's aerodynamic resistance r_a = ln((z − d_0)/z_om) ln((z − d_0)/z_oh)/(κ² u) with
  d_0 = 2/3 h, z_om = 0.123 h, z_oh = 0.1 z_om (Allen et al. 1998, FAO-56 eq. 4), its
  conductance times the stability factor F_h of Louis (1979) for the bulk Richardson number
  Ri = g (z − d_0)(T_a − T_c)/(T̄ u²) at the start of the step (:func:`stability_factor`;
  stable nights weaken the exchange, unstable days strengthen it). Below L = 4 both r_a and r_s are interpolated linearly in L between the
  closed canopy and bare soil (r_s = 0, r_a = 1/h of the scene's wind correlation), as
  Shuttleworth & Wallace (1985) interpolate theirs. Winds: u_c at the canopy top from the log
  profile through u at 2 m, mean in the canopy u_c (1 − e^{−a})/a and near the soil (0.05 m)
  u_c exp(a (0.05/h − 1)) of an exponential in-canopy profile with a = 2.5 (Cionco 1965,
  ASSUMED for every canopy). Eliminating the canopy air gives the conductances
  leaves–air G_ac, soil–air G_as and leaves–soil G_cs (:func:`canopy_conductances`).
* **Transpiration**: Q_v of :mod:`radscene.thermal.evaporation` from the leaves with the
  conductance G_ac and β = g_st/(g_st + g_a,v), g_a,v = G_ac/(c_p Le^{2/3}) the vapour
  conductance of the path leaves–air and g_st = ρ/r_st, r_st the bulk stomatal resistance
  r_l/(0.5 L)/F₁ (Allen et al. 1998, FAO-56 eq. 5, r_l = 100 s m-1) with the light response
  F₁ = (f + r_min/r_max)/(1 + f), f = 0.55 (S/R_gl)(2/L), R_gl = 100 W m-2,
  r_max = 5000 s m-1 (Noilhan & Planton 1989, eq. 34 and Table 1), S the short-wave
  irradiance on the element: stomata close in the dark. Dew is limited by the same β
  (a simplification: dew on a leaf is not limited by its stomata).
* **Heat capacity** of the leaves per ground area, C = ``areal_heat_capacity``.

The leaf node is eliminated into the soil's surface equation, so that the layered conduction
and the surface Newton (compiled or not) are unchanged: the leaves' emission to the sky and
the leaf–soil radiative exchange are linearised about the temperatures at the start of the
step (as Q_v is), which leaves the leaf equation linear,

.. math::
    D\\,T_c = P + W\\,T_s, \\qquad W = G_{cs} + K_r

(:func:`leaf_equation`), and adds W P/D to the soil equation's constant and W (D − W)/D to
its slope. The recorded terms are those the step used, so the energy closure is exact; the
linearisation's error is 6 ε σ T² ΔT² per unit of the linearised terms, 0.1 W m-2 for a leaf
that changes by 2 K in a step.

The sensor sees the radiometric temperature T_r⁴ = f T_c⁴ + (1 − f) T_s⁴ with the leaves'
view fraction f = 1 − exp(−0.5 L / cos θ_v) (Norman et al. 1995, eq. 1 form); the heat
balance reports it for a view along the element's normal (θ_v = 0, nadir over flat ground).

References
----------
Campbell, G. S. and Norman, J. M. (1998). *An Introduction to Environmental Biophysics*, 2nd
ed. Springer, ch. 7 (eq. 7.30, Table 7.5), ch. 15 (eqs. 15.1, 15.5).
doi:10.1007/978-1-4612-1626-1
Shuttleworth, W. J. and Wallace, J. S. (1985). Evaporation from sparse crops — an energy
combination theory. *Q. J. R. Meteorol. Soc.* 111, 839–855. doi:10.1002/qj.49711146910
Norman, J. M., Kustas, W. P. and Humes, K. S. (1995). Source approach for estimating soil and
vegetation energy fluxes in observations of directional radiometric surface temperature.
*Agric. For. Meteorol.* 77, 263–293. doi:10.1016/0168-1923(95)02265-Y
Kustas, W. P. and Norman, J. M. (1999). Evaluation of soil and vegetation heat flux
predictions using a simple two-source model with radiometric temperatures for partial canopy
cover. *Agric. For. Meteorol.* 94, 13–29. doi:10.1016/S0168-1923(99)00005-2
Allen, R. G., Pereira, L. S., Raes, D. and Smith, M. (1998). *Crop evapotranspiration*, FAO
Irrigation and Drainage Paper 56, ch. 2 (eqs. 4 and 5).
Noilhan, J. and Planton, S. (1989). A simple parameterization of land surface processes for
meteorological models. *Mon. Wea. Rev.* 117, 536–549.
doi:10.1175/1520-0493(1989)117<0536:ASPOLS>2.0.CO;2
Louis, J.-F. (1979). A parametric model of vertical eddy fluxes in the atmosphere.
*Boundary-Layer Meteorol.* 17, 187–202. doi:10.1007/BF00117978
Cionco, R. M. (1965). A mathematical model for air flow in a vegetative canopy. *J. Appl.
Meteor.* 4, 517–522. doi:10.1175/1520-0450(1965)004<0517:AMMFAF>2.0.CO;2
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import expn

from radscene.errors import ConfigError
from radscene.thermal.aerodynamic import GAS_CONSTANT_AIR
from radscene.thermal.evaporation import AIR_SPECIFIC_HEAT, LEWIS_NUMBER

__all__ = [
    "CANOPY_MIN_WIND",
    "CanopyLayer",
    "aerodynamic_conductance",
    "beam_transmittance",
    "diffuse_transmittance",
    "leaf_boundary_layer_conductance",
    "canopy_conductances",
    "stomatal_resistance",
    "radiometric_temperature",
    "leaf_equation",
    "stability_factor",
    "transpiration_availability",
    "REFERENCE_HEIGHT",
]

#: Height of the weather's wind speed and air temperature [m].
#: The least wind [m s-1] with which a lumped canopy's aerodynamic conductance is taken: calm
#: air still exchanges heat and vapour by buoyancy, and FAO-56 limits u2 to >= 0.5 m/s in its
#: reference equation for that reason (Allen et al. 1998, chapter 4).
CANOPY_MIN_WIND = 0.5
REFERENCE_HEIGHT = 2.0
#: von Kármán constant [-].
KARMAN = 0.41
#: Molar heat capacity of air [J mol-1 K-1] (Campbell & Norman 1998, Table A.1).
MOLAR_HEAT_CAPACITY = 29.3
#: Closed-canopy leaf area index of the linear interpolation (Shuttleworth & Wallace 1985) [-].
CLOSED_LAI = 4.0
#: Wind attenuation coefficient of the exponential in-canopy profile [-] (ASSUMED).
ATTENUATION = 2.5
#: Soil-surface resistance coefficients a' [m s-1], b' [-] (Norman et al. 1995, appendix B).
SOIL_A, SOIL_B = 0.004, 0.012
#: Light response of the stomata: R_gl [W m-2], r_max [s m-1] (Noilhan & Planton 1989).
LIGHT_SCALE, MAX_STOMATAL_RESISTANCE = 100.0, 5000.0


def beam_transmittance(lai, cos_zenith):
    """Share of a beam passing black leaves of a spherical distribution, exp(−0.5 L/cos θ) [-];
    0 for cos θ ≤ 0.

    Examples
    --------
    >>> round(float(beam_transmittance(2.5, 1.0)), 4)
    0.2865
    """
    mu = np.asarray(cos_zenith, float)
    lai = np.asarray(lai, float)
    safe = np.where(mu > 0, mu, 1.0)
    return np.where(mu > 0, np.exp(-0.5 * lai / safe), 0.0)


def diffuse_transmittance(lai):
    """Share of isotropic diffuse radiation passing black leaves of a spherical distribution,
    τ_d = 2 E₃(0.5 L) [-] (Campbell & Norman 1998, eq. 15.5).

    Examples
    --------
    >>> round(float(diffuse_transmittance(0.0)), 6)
    1.0
    >>> round(float(diffuse_transmittance(2.5)), 4)
    0.1571
    """
    return 2.0 * expn(3, 0.5 * np.asarray(lai, float))


def leaf_boundary_layer_conductance(wind_speed, leaf_width):
    """Heat conductance of both faces of a leaf [W m-2 K-1 per m2 of leaf]:
    2 · 1.4 · 0.135 √(u/d) · c_p,mol, d = 0.72 w (Campbell & Norman 1998, eq. 7.30).

    Examples
    --------
    >>> round(float(leaf_boundary_layer_conductance(1.0, 0.01)), 1)
    130.5
    """
    u = np.asarray(wind_speed, float)
    return 2.0 * 1.4 * 0.135 * np.sqrt(u / (0.72 * np.asarray(leaf_width, float))) * MOLAR_HEAT_CAPACITY


def _air_heat_capacity(air_temperature, pressure):
    """ρ c_p of the air [J m-3 K-1]."""
    return np.asarray(pressure, float) / (GAS_CONSTANT_AIR * np.asarray(air_temperature, float)) * AIR_SPECIFIC_HEAT


def stability_factor(richardson, roughness_ratio):
    """Louis (1979) factor F_h of the neutral heat-transfer conductance [-] for a bulk
    Richardson number Ri and z/z_0: stable (Ri ≥ 0) 1/(1 + 3b Ri √(1 + d Ri)); unstable
    1 − 3b Ri/(1 + 3b c √(−Ri)), c = 5.3 κ² √(z/z_0)/ln²(z/z_0); b = d = 5.

    Examples
    --------
    >>> float(stability_factor(0.0, 100.0))
    1.0
    >>> round(float(stability_factor(0.1, 100.0)), 3)
    0.352
    """
    ri = np.asarray(richardson, float)
    ratio = np.asarray(roughness_ratio, float)
    c = 5.3 * KARMAN**2 * np.sqrt(ratio) / np.log(ratio) ** 2
    stable = 1.0 / (1.0 + 15.0 * np.maximum(ri, 0.0) * np.sqrt(1.0 + 5.0 * np.maximum(ri, 0.0)))
    unstable = 1.0 - 15.0 * ri / (1.0 + 15.0 * c * np.sqrt(np.maximum(-ri, 0.0)))
    return np.where(ri >= 0.0, stable, unstable)


def aerodynamic_conductance(height, wind_speed, air_temperature, pressure, surface_temperature=None,
                            min_wind=0.0):
    """ρ c_p / r_a [W m-2 K-1] of a closed canopy of height h to the air at 2 m, r_a of
    FAO-56 eq. 4 (d_0 = 2/3 h, z_om = 0.123 h, z_oh = 0.1 z_om), times the Louis (1979)
    stability factor of the bulk Richardson number where the ``surface_temperature`` [K] is
    given; the wind [m s-1] at 2 m is taken as at least ``min_wind`` (the lumped canopy of
    the heat balance: :data:`CANOPY_MIN_WIND`).

    Examples
    --------
    The reference grass (h = 0.12 m) at u = 2 m/s: r_a = 208/u ≈ 104 s/m (FAO-56 eq. 4, which
    rounds the logarithms' product over κ² to 208).

    >>> rc = _air_heat_capacity(293.15, 101325.0)  # ρ c_p [J m-3 K-1]
    >>> round(float(rc / aerodynamic_conductance(0.12, 2.0, 293.15, 101325.0)), 1)
    103.8
    """
    h = np.asarray(height, float)
    u = np.maximum(np.asarray(wind_speed, float), float(min_wind))
    d0, z_om = 2.0 / 3.0 * h, 0.123 * h
    z = REFERENCE_HEIGHT
    g = _air_heat_capacity(air_temperature, pressure) * KARMAN**2 * u / (
        np.log((z - d0) / z_om) * np.log((z - d0) / (0.1 * z_om)))
    if surface_temperature is None:
        return g
    ta = np.asarray(air_temperature, float)
    ts = np.asarray(surface_temperature, float)
    safe = np.where(u > 0, u, 1.0)
    ri = np.where(u > 0, 9.80665 * (z - d0) * (ta - ts) / (0.5 * (ta + ts) * safe**2), 0.0)
    return g * stability_factor(ri, (z - d0) / z_om)


def canopy_conductances(lai, height, leaf_width, wind_speed, bare_coefficient, air_temperature, pressure,
                        surface_temperature=None):
    """The conductances of the canopy's star network, the canopy air eliminated.

    Parameters
    ----------
    lai, height, leaf_width : array_like
        L [-], h [m], w [m].
    wind_speed : array_like
        u at 2 m [m s-1].
    bare_coefficient : array_like
        h of the scene's wind correlation for bare ground [W m-2 K-1].
    air_temperature, pressure : array_like
        [K], [Pa].

    Returns
    -------
    leaf_air, soil_air, leaf_soil : ndarray
        G_ac, G_as, G_cs [W m-2 K-1] per unit ground area.

    Notes
    -----
    With the leaves' g_x, the canopy air's g_a to the reference height and the soil's r_s,
    G_as = g_a/N, G_cs = g_x/N, G_ac = g_a g_x r_s/N with N = 1 + r_s (g_a + g_x).
    """
    lai, h = np.asarray(lai, float), np.asarray(height, float)
    u = np.asarray(wind_speed, float)
    rc = _air_heat_capacity(air_temperature, pressure)
    d0, z_om = 2.0 / 3.0 * h, 0.123 * h
    u_top = u * np.log((h - d0) / z_om) / np.log((REFERENCE_HEIGHT - d0) / z_om)
    closed_g = aerodynamic_conductance(h, u, air_temperature, pressure, surface_temperature)
    share = np.minimum(lai / CLOSED_LAI, 1.0)
    bare = np.asarray(bare_coefficient, float)
    # 1/g_a = share/closed_g + (1 − share)/bare, written to allow either conductance to be 0
    denominator = share * bare + (1.0 - share) * closed_g
    g_a = np.divide(closed_g * bare, denominator, out=np.zeros(np.broadcast(denominator, lai).shape),
                    where=denominator > 0)
    u_leaf = u_top * (1.0 - np.exp(-ATTENUATION)) / ATTENUATION
    g_x = lai * leaf_boundary_layer_conductance(u_leaf, leaf_width)
    u_soil = u_top * np.exp(ATTENUATION * (0.05 / h - 1.0))
    r_s = share / (rc * (SOIL_A + SOIL_B * u_soil))
    n = 1.0 + r_s * (g_a + g_x)
    return g_a * g_x * r_s / n, g_a / n, g_x / n


def stomatal_resistance(lai, leaf_resistance, shortwave):
    """Bulk stomatal resistance of the canopy r_st = r_l/(0.5 L)/F₁ [s m-1], F₁ the light
    response of Noilhan & Planton (1989) with R_gl = 100 W m-2, r_max = 5000 s m-1.

    Parameters
    ----------
    lai : array_like
        L > 0 [-].
    leaf_resistance : array_like
        r_l of a single active leaf [s m-1] (FAO-56: 100).
    shortwave : array_like
        S ≥ 0, short-wave irradiance on the canopy [W m-2].

    Examples
    --------
    >>> round(float(stomatal_resistance(2.5, 100.0, 0.0)), 1)  # closed in the dark
    5000.0
    >>> round(float(stomatal_resistance(2.5, 100.0, 800.0)), 1)
    102.3
    """
    lai = np.asarray(lai, float)
    r_min = np.asarray(leaf_resistance, float) / (0.5 * lai)
    f = 0.55 * np.asarray(shortwave, float) / LIGHT_SCALE * 2.0 / lai
    f1 = (f + r_min / MAX_STOMATAL_RESISTANCE) / (1.0 + f)
    return r_min / f1


def transpiration_availability(leaf_air, lai, leaf_resistance, shortwave, air_temperature, pressure):
    """β of the leaves' Q_v with the conductance G_ac: g_st/(g_st + G_ac/(c_p Le^{2/3})) [-]."""
    g_st = np.asarray(pressure, float) / (GAS_CONSTANT_AIR * np.asarray(air_temperature, float)) / stomatal_resistance(
        lai, leaf_resistance, shortwave)
    g_v = np.asarray(leaf_air, float) / (AIR_SPECIFIC_HEAT * LEWIS_NUMBER ** (2.0 / 3.0))
    return g_st / (g_st + g_v)


def radiometric_temperature(leaf_temperature, soil_temperature, lai, view_zenith=0.0):
    """T_r = (f T_c⁴ + (1 − f) T_s⁴)^{1/4} [K], f = 1 − exp(−0.5 L/cos θ_v) the leaves' share of
    the view (Norman et al. 1995).

    Parameters
    ----------
    leaf_temperature, soil_temperature : array_like
        [K].
    lai : array_like
        [-].
    view_zenith : array_like, optional
        θ_v from the element's normal [deg], < 90.

    Examples
    --------
    >>> round(float(radiometric_temperature(280.0, 290.0, 2.5)), 2)
    282.97
    """
    theta = np.asarray(view_zenith, float)
    if np.any(~(np.abs(theta) < 90.0)):
        raise ConfigError(f"must be in (-90, 90) deg; got {theta!r}", key="view_zenith")
    f = 1.0 - beam_transmittance(lai, np.cos(np.radians(theta)))
    tc, ts = np.asarray(leaf_temperature, float), np.asarray(soil_temperature, float)
    return (f * tc**4 + (1.0 - f) * ts**4) ** 0.25


def leaf_equation(capacity, dt, previous_leaf, previous_soil, source, emission, exchange, conductance, air_temperature,
                  leaf_air, evaporation_slope):
    """The linear leaf equation D T_c = P + W T_s of one backward-Euler step.

    Parameters
    ----------
    capacity : array_like
        C of the leaves [J m-2 K-1].
    dt : float
        [s].
    previous_leaf, previous_soil : array_like
        T_c, T_s at the start of the step [K].
    source : array_like
        Heat into the leaves that does not depend on their temperature [W m-2] (absorbed
        short-wave and sky long-wave, Q_env, the evaporation's constant).
    emission : array_like
        e_c = ε (1 − τ_d) σ of the leaves' emission to the sky [W m-2 K-4].
    exchange : array_like
        ε² (1 − τ_d) σ of the leaf–soil exchange [W m-2 K-4].
    conductance : array_like
        G_cs [W m-2 K-1].
    air_temperature : array_like
        [K].
    leaf_air : array_like
        G_ac [W m-2 K-1].
    evaporation_slope : array_like
        s of the leaves' Q_v ≈ c − s T_c [W m-2 K-1].

    Returns
    -------
    d, p, w : ndarray
        D [W m-2 K-1], P [W m-2], W = G_cs + K_r [W m-2 K-1] with the radiative conductance
        K_r = 4 ε² (1 − τ_d) σ T̄³ about T̄ = (T_c + T_s)/2 at the start of the step.
    """
    tc0 = np.asarray(previous_leaf, float)
    mean = 0.5 * (tc0 + np.asarray(previous_soil, float))
    k_r = 4.0 * np.asarray(exchange, float) * mean**3
    w = np.asarray(conductance, float) + k_r
    store = np.asarray(capacity, float) / dt
    e3 = np.asarray(emission, float) * tc0**3
    d = store + 4.0 * e3 + leaf_air + w + evaporation_slope
    p = store * tc0 + source + 3.0 * e3 * tc0 + leaf_air * np.asarray(air_temperature, float)
    return d, p, w


@dataclass(frozen=True)
class CanopyLayer:
    """The leaf layers of the canopy elements of a heat balance.

    Attributes
    ----------
    index : ndarray of int, (n_canopy,)
        The elements that carry leaves.
    lai, height, leaf_width, capacity, leaf_resistance : ndarray, (n_canopy,)
        L [-], h [m], w [m], C [J m-2 K-1], r_l [s m-1].
    diffuse : ndarray, (n_canopy,)
        τ_d [-].
    """

    index: np.ndarray
    lai: np.ndarray
    height: np.ndarray
    leaf_width: np.ndarray
    capacity: np.ndarray
    leaf_resistance: np.ndarray
    diffuse: np.ndarray

    @classmethod
    def from_stacks(cls, stacks, stack_index):
        """The canopy elements of stacks whose ``canopy`` has a ``height`` and a ``leaf_width``
        (None if none)."""
        stack_index = np.asarray(stack_index)
        rows = []
        for s, stack in enumerate(stacks):
            spec = getattr(stack, "canopy", None)
            if not spec or "leaf_width" not in spec:
                continue
            rows.append((s, float(spec["lai"]), float(spec["height"]), float(spec["leaf_width"]),
                         float(spec["areal_heat_capacity"]), float(spec.get("leaf_resistance", 100.0))))
        if not rows:
            return None
        table = np.array(rows)
        which = np.full(len(stacks), -1)
        which[table[:, 0].astype(int)] = np.arange(len(rows))
        row = which[stack_index]
        index = np.flatnonzero(row >= 0)
        if index.size == 0:
            return None
        values = table[row[index]]
        return cls(index=index, lai=values[:, 1], height=values[:, 2], leaf_width=values[:, 3],
                   capacity=values[:, 4], leaf_resistance=values[:, 5], diffuse=diffuse_transmittance(values[:, 1]))
