"""The formulas that turn 6S's printed quantities into radscene's spectra (pure functions).

6S describes a cloud-free atmosphere over a Lambertian surface of reflectance ρ by
(Vermote et al. 1997, eq. 1 and §II.D):

.. math::

    \\rho_{toa} = T_g^{nw}\\,\\rho_R + T_g\\,(\\rho_{R+A} - \\rho_R)
                 + T_g \\frac{T^{\\downarrow}(\\theta_s) T^{\\uparrow}(\\theta_v)\\,\\rho}{1 - S\\rho}

with ρ_R and ρ_{R+A} the path reflectances of the molecular and of the whole scattering
atmosphere, T^↓, T^↑ the total (direct + diffuse) scattering transmittances, S the spherical
albedo, T_g the two-way gaseous transmittance and T_g^{nw} the same without water vapour (6S
puts the water vapour under the molecules, mixed with the aerosol). Radiances follow as
L = ρ E_0 cos θ_s / π. This module holds those formulas, the direct transmittances
exp(-τ/μ), the sky-radiance model and the interpolation rules; :mod:`radscene.atmosphere.sixs`
and :mod:`radscene.atmosphere.database` share them.

Sky radiance
------------
6S prints the diffuse irradiance at the ground but no radiance distribution over the sky. The
sky is modelled as single scattering in a plane-parallel layer of molecular optical depth τ_R
and aerosol optical depth τ_A (6S's phase functions P_R, P_A and aerosol single-scattering
albedo ω_A, sampled from 6S at several scattering angles), plus the rest of 6S's diffuse
irradiance (multiple scattering) spread with the angular shape M of multiply scattered light,
plus the isotropic light of the surroundings of albedo ρ_b re-scattered by the atmosphere:

.. math::

    L(\\mu, \\phi) = \\frac{E_0 T_g^{\\downarrow}}{4\\pi\\mu}
        \\left[\\tau_R P_R(\\Theta) + \\omega_A \\tau_A P_A(\\Theta)\\right] h(\\mu)
        + (E_d - E_{ss}) \\frac{M(\\mu, \\Theta)}{\\int M \\mu\\,d\\Omega}
        + \\frac{(E_s + E_d)\\,\\rho_b S}{\\pi (1 - \\rho_b S)},

    h(\\mu) = \\frac{e^{-\\tau/\\mu} - e^{-\\tau/\\mu_s}}{\\tau (1/\\mu_s - 1/\\mu)},

where E_ss is the hemispherical integral of the single-scattering term, E_d = E_0 μ_s
(T^↓ - e^{-τ/μ_s}) T_g^↓ the diffuse and E_s = E_0 μ_s e^{-τ/μ_s} T_g^↓ the direct irradiance
on a horizontal surface. The model integrates exactly to 6S's downwelling diffuse irradiance
(with the surroundings' contribution). Where single scattering alone would exceed E_d (not
seen for τ < 3) it is scaled down to E_d.

The multiply scattered light (:func:`multiple_scattering_shape`) is that of a source that
grows linearly with optical depth through the layer, seen from its bottom, and that keeps a
memory of the sun's direction through the aerosol's forward scattering:

.. math::

    M(\\mu, \\Theta) = \\left[1 - \\frac{\\mu}{\\tau}\\left(1 - e^{-\\tau/\\mu}\\right)\\right]
        \\left[(1 - w) + w\\,P_{HG}(\\Theta; g^3)\\right],\\qquad
    w = \\frac{\\omega_A \\tau_A}{\\tau_R + \\omega_A \\tau_A},

with g the asymmetry parameter of the aerosol phase function and P_HG the Henyey-Greenstein
function. Light scattered n times by a Henyey-Greenstein aerosol keeps an asymmetry g^n; g^3
stands for the orders beyond the first, chosen against a Monte Carlo of the same atmosphere
(``tests/validation/scripts/sky_monte_carlo.py``): 6S's continental aerosol at 23 and 5 km
visibility, 0.55 um, sun at 30 and 60 deg, where it brings the sky within 10 % (23 km) and
12 % (5 km) of the Monte Carlo in every direction up to 75 deg from the zenith and 20 deg or
more from the sun, the zenith within 11 % (an isotropic rest, the model's earlier form, was
up to 37 % too bright at the zenith, up to 76 % in the anti-solar sky and 20 % too dark near
the horizon under the sun; ``tests/validation/test_sky_reference.py``).

References
----------
E. F. Vermote et al., IEEE TGRS 35, 675-686 (1997), https://doi.org/10.1109/36.581987
S. Chandrasekhar, *Radiative Transfer*, Dover (1960), §§ 1, 6 (single scattering in a
plane-parallel layer).
"""

from __future__ import annotations

import functools
import math

import numba
import numpy as np

__all__ = [
    "loglog_interp",
    "bracket",
    "direct_transmittance",
    "path_reflectance",
    "radiance_from_reflectance",
    "azimuth_fourier",
    "scattering_angle_sky",
    "scattering_angle_view",
    "phase_interp",
    "fill_phase_function",
    "single_scattering_sky",
    "sky_radiance",
    "hemisphere_quadrature",
    "aerosol_asymmetry",
    "multiple_scattering_shape",
    "axis_weights",
    "multilinear_nodes",
    "single_scattering_reflectance",
    "single_scattering_grid",
    "earth_sun_factor_6s",
    "TOP_OF_ATMOSPHERE",
    "GROUND_TOLERANCE",
    "check_path_geometry",
]

#: Altitude [m] at and above which an observer is outside the atmosphere of every engine.
TOP_OF_ATMOSPHERE = 100_000.0
#: How far [m] below an engine's lowest altitude a path end is still taken to lie on it (and
#: moved up to it): ray hits on a surface at that altitude carry float32 noise (about 1e-7 of
#: the scene's size), and LOWTRAN allows the same 0.5 m below its ground.
GROUND_TOLERANCE = 0.5


def earth_sun_factor_6s(month: int, day: int) -> float:
    """6S's (1/d)² Earth-Sun distance factor of a date (6S source ``varsol``)."""
    if month <= 2:
        j = 31 * (month - 1) + day
    elif month > 8:
        j = 31 * (month - 1) - ((month - 2) // 2) - 2 + day
    else:
        j = 31 * (month - 1) - ((month - 1) // 2) - 2 + day
    om = np.radians(0.9856 * (j - 4))
    return float(1.0 / (1.0 - 0.01673 * np.cos(om)) ** 2)


def check_path_geometry(observer_altitude, target_altitude, view_zenith, min_target=0.0):
    """Validate line-of-sight geometry and put it in downward form.

    Parameters
    ----------
    observer_altitude, target_altitude : array_like
        Altitudes above sea level [m]; an observer at or above :data:`TOP_OF_ATMOSPHERE` is in
        space.
    view_zenith : array_like
        Zenith angle of the direction from target to observer [deg], in [0, 180].
    min_target : float
        Lowest altitude the engine accepts [m]; an end up to :data:`GROUND_TOLERANCE` below it
        (ray-hit noise on a surface at that altitude) is taken to lie at it.

    Returns
    -------
    upper, lower, zenith : numpy.ndarray
        Broadcast arrays: the upper and lower end of each path [m], neither below
        ``min_target``, and the zenith angle seen from the lower end [deg], < 90. A path
        whose observer is below its target is turned round (transmittance is reciprocal; for
        path radiance this is an approximation).

    Raises
    ------
    ConfigError
        Non-finite values, an end more than :data:`GROUND_TOLERANCE` below ``min_target`` or
        a target above 100 km, a zenith outside [0, 180] or one that contradicts the
        altitudes.
    """
    from radscene.errors import ConfigError

    o, t, z = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                    for x in (observer_altitude, target_altitude, view_zenith)))
    shape = o.shape
    upper, lower, zenith = (np.empty(shape) for _ in range(3))
    flat = (np.ascontiguousarray(a).reshape(-1) for a in (o, t, z))
    finite, low, top, z_lo, z_hi, bad = _path_geometry(
        *flat, float(min_target), upper.reshape(-1), lower.reshape(-1), zenith.reshape(-1))
    for name, ok in zip(("observer_altitude", "target_altitude", "view_zenith"), finite,
                        strict=True):
        if not ok:
            raise ConfigError("must be finite", key=name)
    if not o.size:
        return upper, lower, zenith
    if low < min_target - GROUND_TOLERANCE:
        raise ConfigError(f"a path below the ground: {low:g} m is under the engine's lowest "
                          f"altitude {min_target:g} m", key="target_altitude")
    if top >= TOP_OF_ATMOSPHERE:
        raise ConfigError(f"a target at {top:g} m is above the atmosphere's top "
                          f"({TOP_OF_ATMOSPHERE:g} m)", key="target_altitude")
    if z_lo < 0 or z_hi > 180:
        raise ConfigError("must lie in [0, 180] deg", key="view_zenith")
    if bad:
        raise ConfigError("the zenith angle contradicts the altitudes: an observer above its "
                          "target must be seen at < 90 deg from it, one below at > 90 deg",
                          key="view_zenith")
    return upper, lower, zenith


@numba.njit(cache=True)
def _path_geometry(o, t, z, min_target, upper, lower, zenith):  # pragma: no cover - compiled
    """:func:`check_path_geometry`'s one pass: the downward form into ``upper``, ``lower``,
    ``zenith``, and what its checks read: whether each input is finite, the lowest end, the
    highest target (both ends held at ``min_target``), the zenith's range, and whether a
    zenith contradicts its altitudes."""
    finite = [True, True, True]
    low = np.inf
    top = -np.inf
    z_lo = np.inf
    z_hi = -np.inf
    bad = False
    for i in range(o.size):
        oi, ti, zi = o[i], t[i], z[i]
        if not np.isfinite(oi):
            finite[0] = False
        if not np.isfinite(ti):
            finite[1] = False
        if not np.isfinite(zi):
            finite[2] = False
        low = min(low, ti, oi)
        oi = max(oi, min_target)  # on the ground, within noise
        ti = max(ti, min_target)
        top = max(top, ti)
        z_lo = min(z_lo, zi)
        z_hi = max(z_hi, zi)
        if oi >= ti:
            bad = bad or (oi - ti > 0.5 and zi >= 90.0)
            u, lo_, zen = oi, ti, zi
        else:
            bad = bad or (ti - oi > 0.5 and zi <= 90.0)
            u, lo_, zen = ti, oi, 180.0 - zi
        if u - lo_ <= 0.5:
            zen = min(zen, 89.0)
        upper[i] = u
        lower[i] = lo_
        zenith[i] = zen
    return (finite[0], finite[1], finite[2]), low, top, z_lo, z_hi, bad


def bracket(wavelength, nodes):
    """Indices (i, i+1) of the nodes bracketing each wavelength, ends extended.

    Parameters
    ----------
    wavelength : array_like
        Wavelengths [um], 1-D.
    nodes : array_like
        Increasing node wavelengths [um], at least two.

    Returns
    -------
    numpy.ndarray
        Lower indices, shape (n,), in [0, len(nodes) - 2].
    """
    wl = np.asarray(wavelength, dtype=float)
    nodes = np.asarray(nodes, dtype=float)
    return np.clip(np.searchsorted(nodes, wl, side="right") - 1, 0, nodes.size - 2)


def loglog_interp(wavelength, nodes, values):
    """Interpolate along the last axis, linear in log(value) over log(wavelength).

    This is 6S's own rule between its 20 discrete wavelengths (and beyond them it extrapolates
    the same way). Where a bracketing value is not positive it falls back to linear
    interpolation in log(wavelength).

    Parameters
    ----------
    wavelength : array_like
        Wavelengths [um], 1-D.
    nodes : array_like
        Increasing node wavelengths [um], shape (k,), k >= 2.
    values : array_like
        Shape (..., k).

    Returns
    -------
    numpy.ndarray
        Shape (..., n).
    """
    wl = np.asarray(wavelength, dtype=float)
    nodes = np.asarray(nodes, dtype=float)
    v = np.asarray(values, dtype=float)
    i = bracket(wl, nodes)
    t = np.log(wl / nodes[i]) / np.log(nodes[i + 1] / nodes[i])
    a = v[..., i]
    b = v[..., i + 1]
    positive = (a > 0) & (b > 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        log_form = np.exp(np.log(np.where(positive, a, 1.0)) * (1 - t)
                          + np.log(np.where(positive, b, 1.0)) * t)
    return np.where(positive, log_form, a + t * (b - a))


def direct_transmittance(optical_depth, zenith):
    """Beer's law along a slant path of a plane-parallel atmosphere.

    Parameters
    ----------
    optical_depth : array_like
        Vertical extinction optical depth of the layer [-].
    zenith : array_like
        Zenith angle of the path [deg], < 90.

    Returns
    -------
    numpy.ndarray
        exp(-τ / cos θ) [-].
    """
    mu = np.cos(np.radians(np.asarray(zenith, dtype=float)))
    return np.exp(-np.asarray(optical_depth, dtype=float) / mu)


def path_reflectance(rho_mixture, rho_rayleigh, gas_total, gas_no_water):
    """6S's path reflectance with gaseous absorption (water vapour mixed with the aerosol).

    Parameters
    ----------
    rho_mixture, rho_rayleigh : array_like
        Path reflectance of the molecules + aerosol and of the molecules alone [-].
    gas_total, gas_no_water : array_like
        Two-way gaseous transmittance, all gases and all but water vapour [-].

    Returns
    -------
    numpy.ndarray
        T_g^nw ρ_R + T_g (ρ_R+A - ρ_R) [-].
    """
    rho_r = np.asarray(rho_rayleigh, dtype=float)
    return gas_no_water * rho_r + gas_total * (np.asarray(rho_mixture, dtype=float) - rho_r)


def radiance_from_reflectance(reflectance, toa_irradiance, sun_zenith):
    """L = ρ E_0 cos θ_s / π [W m-2 sr-1 um-1] for E_0 in [W m-2 um-1]."""
    mu_s = np.cos(np.radians(np.asarray(sun_zenith, dtype=float)))
    return np.asarray(reflectance, dtype=float) * toa_irradiance * mu_s / np.pi


def azimuth_fourier(relative_azimuth, at_0, at_90, at_180):
    """Three-term cosine series a0 + a1 cos φ + a2 cos 2φ through values at 0, 90, 180 deg.

    Parameters
    ----------
    relative_azimuth : array_like
        φ [deg]; NaN gives the azimuthal mean a0 = (v0 + 2 v90 + v180) / 4.
    at_0, at_90, at_180 : array_like
        Values at φ = 0, 90, 180 deg (broadcast).

    Returns
    -------
    numpy.ndarray
    """
    phi = np.radians(np.asarray(relative_azimuth, dtype=float))
    # v(0) = a0 + a1 + a2, v(90) = a0 - a2, v(180) = a0 - a1 + a2
    a0 = (at_0 + 2.0 * at_90 + at_180) / 4.0
    a1 = (at_0 - at_180) / 2.0
    a2 = (at_0 + at_180 - 2.0 * at_90) / 4.0
    c1 = np.where(np.isnan(phi), 0.0, np.cos(phi))
    c2 = np.where(np.isnan(phi), 0.0, np.cos(2.0 * phi))
    return a0 + a1 * c1 + a2 * c2


def scattering_angle_view(sun_zenith, view_zenith, relative_azimuth):
    """Scattering angle of sunlight reflected to a downward-looking sensor [deg] (6S rule).

    ``relative_azimuth`` is the azimuth of the sensor seen from the target minus that of the
    sun [deg]: 0 puts the sensor on the sun's side (backscatter).
    """
    ts, tv, p = (np.radians(np.asarray(x, dtype=float))
                 for x in (sun_zenith, view_zenith, relative_azimuth))
    c = -np.cos(ts) * np.cos(tv) - np.sin(ts) * np.sin(tv) * np.cos(p)
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def scattering_angle_sky(sun_zenith, zenith, relative_azimuth):
    """Scattering angle of sunlight scattered down towards a ground observer [deg].

    ``zenith`` and ``relative_azimuth`` give the direction of view up into the sky, the
    azimuth relative to the sun's (0: looking towards the sun, forward scattering).
    """
    ts, t, p = (np.radians(np.asarray(x, dtype=float))
                for x in (sun_zenith, zenith, relative_azimuth))
    c = np.cos(ts) * np.cos(t) + np.sin(ts) * np.sin(t) * np.cos(p)
    return np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))


def phase_interp(angle, angle_nodes, phase):
    """Phase function at scattering angles, log-linear in angle between the nodes.

    Parameters
    ----------
    angle : array_like
        Scattering angles [deg], shape S.
    angle_nodes : array_like
        Increasing node angles [deg], shape (k,).
    phase : array_like
        Phase function (6S normalisation, mean 1 over the sphere) at the nodes, shape (k, n)
        for n wavelengths.

    Returns
    -------
    numpy.ndarray
        Shape S + (n,); below the first node the first value (stated rule), likewise above
        the last.
    """
    a = np.clip(np.asarray(angle, dtype=float), angle_nodes[0], angle_nodes[-1])
    nodes = np.asarray(angle_nodes, dtype=float)
    logp = np.log(np.maximum(np.asarray(phase, dtype=float), 1e-12))
    i = np.clip(np.searchsorted(nodes, a, side="right") - 1, 0, nodes.size - 2)
    t = ((a - nodes[i]) / (nodes[i + 1] - nodes[i]))[..., None]
    return np.exp(logp[i] * (1.0 - t) + logp[i + 1] * t)


def fill_phase_function(angle_nodes, phase):
    """Phase functions with the entries 6S printed as NaN (or not positive) filled.

    Each such entry is extrapolated log-linearly in angle from the two nearest valid angles
    on the side of larger angles (of smaller ones if there are not two larger). 6S prints NaN
    for its maritime model at 3 deg at its wavelengths from 0.35 to 0.76 um (its values there
    are erratic below about 4 deg: 89 at 3.5 deg, 52 at 4 deg, 41 at 5 deg for 0.4 um); the
    other entries are kept as they are.

    Parameters
    ----------
    angle_nodes : array_like
        Increasing scattering angles [deg], shape (k,).
    phase : array_like
        Phase function at the angles, shape (k, n) for n wavelengths.

    Returns
    -------
    numpy.ndarray
        A filled copy, shape (k, n).

    Raises
    ------
    EngineError
        A wavelength with fewer than two valid values.
    """
    from radscene.errors import EngineError

    angles = np.asarray(angle_nodes, dtype=float)
    out = np.array(phase, dtype=float)
    for j in range(out.shape[1]):
        ok = np.isfinite(out[:, j]) & (out[:, j] > 0.0)
        if ok.all():
            continue
        if ok.sum() < 2:
            raise EngineError(f"6S gave fewer than two valid phase-function values at "
                              f"wavelength index {j}")
        good = np.nonzero(ok)[0]
        for i in np.nonzero(~ok)[0]:
            after = good[good > i][:2]
            pair = after if after.size == 2 else good[good < i][-2:]
            a0, a1 = angles[pair]
            l0, l1 = np.log(out[pair, j])
            out[i, j] = np.exp(l0 + (l1 - l0) * (angles[i] - a0) / (a1 - a0))
    return out


def single_scattering_reflectance(sun_zenith, view_zenith, phase_rayleigh, phase_aerosol,
                                  tau_rayleigh, tau_aerosol, omega_aerosol,
                                  fraction_rayleigh=1.0, fraction_aerosol=1.0):
    r"""Singly scattered path reflectance of a plane-parallel atmosphere over a black surface.

    The layer between the target and an observer holds the fractions f_R = ``fraction_rayleigh``
    and f_A = ``fraction_aerosol`` of the column's optical depths τ_R, τ_A; sunlight reaches it
    through the rest of the column. With τ_l = f_R τ_R + f_A τ_A the layer's optical depth,
    P̄ = (f_R τ_R P_R + f_A ω_A τ_A P_A) / τ_l the phase function of the layer's own mixture
    and m = 1/μ_s + 1/μ_v:

    .. math::

        \rho_{ss} = \frac{\bar P\, e^{-(\tau - \tau_l)/\mu_s}
                     \left(1 - e^{-\tau_l m}\right)}{4 (\mu_s + \mu_v)}

    (Chandrasekhar 1960; at the top of the atmosphere the classic single-scattering
    reflectance). The database divides 6S's path reflectance by it before interpolating, so
    that only the smooth multiple-scattering factor is interpolated between angles and
    observer heights. The layer's mixture matters there: the aerosol (scale height 2 km) lies
    lower than the molecules (8 km), so below an aircraft it scatters a larger share than in
    the column. With the column's P̄ in its place the factor was not linear between the
    database's aircraft nodes 1 and 4 km: its path reflectance 3 km up (all else on nodes)
    came out 0.8-2.4 % above 6S at 0.44-0.67 um (continental and maritime, AOT550 0.1-0.3),
    with the layer's mixture -0.8 to +0.1 %.

    Parameters
    ----------
    sun_zenith, view_zenith : array_like
        [deg], < 90.
    phase_rayleigh, phase_aerosol : array_like
        Phase functions at the scattering angle (mean 1 over the sphere) [-].
    tau_rayleigh, tau_aerosol, omega_aerosol : array_like
        Column optical depths above the target and aerosol single-scattering albedo [-].
    fraction_rayleigh, fraction_aerosol : array_like
        Share of each column below the observer [-] (1 at the top of the atmosphere).

    Returns
    -------
    numpy.ndarray
        ρ_ss [-], broadcast over the inputs.
    """
    mu_s = np.cos(np.radians(np.asarray(sun_zenith, dtype=float)))
    mu_v = np.cos(np.radians(np.asarray(view_zenith, dtype=float)))
    tau = tau_rayleigh + tau_aerosol
    tau_r_l = tau_rayleigh * fraction_rayleigh
    tau_a_l = tau_aerosol * fraction_aerosol
    tau_l = tau_r_l + tau_a_l
    source = tau_r_l * phase_rayleigh + omega_aerosol * tau_a_l * phase_aerosol
    with np.errstate(divide="ignore", invalid="ignore"):
        pbar = np.where(tau_l > 0, source / np.where(tau_l > 0, tau_l, 1.0), 0.0)
    m = 1.0 / mu_s + 1.0 / mu_v
    return (pbar * np.exp(-(tau - tau_l) / mu_s) * -np.expm1(-tau_l * m)
            / (4.0 * (mu_s + mu_v)))


def layer_share(sun_zenith, view_zenith, tau_rayleigh, tau_aerosol, fraction_rayleigh,
                fraction_aerosol):
    r"""The share of the column's single scattering (phase function aside) that an observer
    inside the atmosphere sees: h(τ_l) / h(τ) with h(t) = e^{-(τ - t)/μ_s} (1 - e^{-t m}),
    τ_l = f_R τ_R + f_A τ_A the optical depth below the observer, m = 1/μ_s + 1/μ_v
    (:func:`single_scattering_reflectance` with an isotropic phase function, over its value
    at the top of the atmosphere). 1 at the top; 0 at the ground.
    """
    mu_s = np.cos(np.radians(np.asarray(sun_zenith, dtype=float)))
    mu_v = np.cos(np.radians(np.asarray(view_zenith, dtype=float)))
    m = 1.0 / mu_s + 1.0 / mu_v
    tau = np.asarray(tau_rayleigh, dtype=float) + np.asarray(tau_aerosol, dtype=float)
    tau_l = tau_rayleigh * fraction_rayleigh + tau_aerosol * fraction_aerosol
    with np.errstate(divide="ignore", invalid="ignore"):
        top = -np.expm1(-tau * m)
        out = np.exp(-(tau - tau_l) / mu_s) * -np.expm1(-tau_l * m) / np.where(top > 0, top, 1.0)
    return np.where(top > 0, out, 1.0)


def single_scattering_grid(sun_zenith, view_zenith, relative_azimuth, angle_nodes,
                           phase_rayleigh, phase_aerosol, tau_rayleigh, tau_aerosol,
                           omega_aerosol, fraction_rayleigh, fraction_aerosol,
                           rayleigh_only=False):
    """:func:`single_scattering_reflectance` on a (θ_s, θ_v, φ) grid, per wavelength.

    Parameters
    ----------
    sun_zenith, view_zenith, relative_azimuth : array_like
        1-D node angles [deg].
    angle_nodes, phase_rayleigh, phase_aerosol
        Phase tables, shape (k, n) for n wavelengths (see :func:`phase_interp`).
    tau_rayleigh, tau_aerosol, omega_aerosol : array_like
        Shape (n,) or (n, 1, 1, 1)-broadcastable.
    fraction_rayleigh, fraction_aerosol : float
    rayleigh_only : bool
        The molecules alone (τ_A = 0).

    Returns
    -------
    numpy.ndarray
        Shape (n, n_sun, n_view, n_azimuth).
    """
    zs, zv, ph = np.meshgrid(np.asarray(sun_zenith, float), np.asarray(view_zenith, float),
                             np.asarray(relative_azimuth, float), indexing="ij")
    theta = scattering_angle_view(zs, zv, ph)
    pr = np.moveaxis(phase_interp(theta, angle_nodes, phase_rayleigh), -1, 0)
    pa = np.moveaxis(phase_interp(theta, angle_nodes, phase_aerosol), -1, 0)
    col = (slice(None), None, None, None)
    tr = np.asarray(tau_rayleigh, float)[col]
    ta = 0.0 * tr if rayleigh_only else np.asarray(tau_aerosol, float)[col]
    om = np.asarray(omega_aerosol, float)[col]
    return single_scattering_reflectance(zs, np.minimum(zv, 89.0), pr, pa, tr, ta, om,
                                         fraction_rayleigh, fraction_aerosol)


def axis_weights(values, nodes):
    """Lower node index and fraction of values on an increasing node axis (ends held).

    Returns
    -------
    index : numpy.ndarray of int
        In [0, k - 2] (0 when k == 1).
    fraction : numpy.ndarray
        Weight of node ``index + 1``; outside the axis the end node takes the whole weight.
    """
    v = np.asarray(values, dtype=float)
    nodes = np.asarray(nodes, dtype=float)
    if nodes.size == 1:
        return np.zeros(v.shape, dtype=np.int64), np.zeros(v.shape)
    vc = np.clip(v, nodes[0], nodes[-1])
    i = np.clip(np.searchsorted(nodes, vc, side="right") - 1, 0, nodes.size - 2)
    return i, (vc - nodes[i]) / (nodes[i + 1] - nodes[i])


def multilinear_nodes(coordinates, axes):
    """Grid nodes that each point mixes, and their multilinear weights.

    Parameters
    ----------
    coordinates : sequence of array_like
        One 1-D array per axis, the points' coordinates (same length N).
    axes : sequence of array_like
        The increasing node values of each axis.

    Returns
    -------
    node_coordinates : list of numpy.ndarray
        For each axis, the coordinate of each *used* node, shape (n_nodes,).
    index : numpy.ndarray
        Shape (N, 2**d) int, into the used nodes, with d the number of axes of more than one
        node (an axis of one node adds no corner).
    weight : numpy.ndarray
        Shape (N, 2**d), rows summing to 1.
    """
    axes = [np.asarray(a, dtype=float) for a in axes]
    n = len(np.asarray(coordinates[0]))
    flat = np.zeros((n, 1), dtype=np.int64)
    weight = np.ones((n, 1))
    for values, nodes in zip(coordinates, axes, strict=True):
        if nodes.size == 1:  # every point sits on the one node
            continue
        # each corner splits in two: the lower node's corners first, then the upper's
        wider = (np.empty((n, 2 * flat.shape[1]), dtype=np.int64),
                 np.empty((n, 2 * flat.shape[1])))
        _split_corners(np.ascontiguousarray(values, dtype=float).reshape(-1),
                       np.ascontiguousarray(nodes), flat, weight, *wider)
        flat, weight = wider
    sizes = [a.size for a in axes]
    # the grid is small: compact the used nodes with a lookup table (no sort of N rows)
    present = np.zeros(int(np.prod(sizes)), dtype=np.bool_)
    _mark(flat, present)
    used = np.flatnonzero(present)
    lookup = np.cumsum(present) - 1
    _relabel(flat, lookup)  # in place: flat indices become indices of the used nodes
    multi = np.unravel_index(used, sizes) if used.size else [np.zeros(0, int)] * len(axes)
    return [a[m] for a, m in zip(axes, multi, strict=True)], flat, weight


@numba.njit(cache=True)
def _split_corners(values, nodes, flat, weight, out_flat, out_weight):  # pragma: no cover
    """One more axis of :func:`multilinear_nodes`: each point's corners (flat grid indices
    ``flat`` and weights, (N, m)) times its bracketing nodes on ``nodes`` (as
    :func:`axis_weights`: ends held), into (N, 2m)."""
    k = nodes.size
    m = flat.shape[1]
    for p in range(values.size):
        v = min(max(values[p], nodes[0]), nodes[k - 1])
        lo, hi = 0, k  # searchsorted(nodes, v, "right")
        while lo < hi:
            mid = (lo + hi) // 2
            if nodes[mid] <= v:
                lo = mid + 1
            else:
                hi = mid
        i = min(max(lo - 1, 0), k - 2)
        f = (v - nodes[i]) / (nodes[i + 1] - nodes[i])
        up = min(i + 1, k - 1)
        for c in range(m):
            out_flat[p, c] = flat[p, c] * k + i
            out_flat[p, m + c] = flat[p, c] * k + up
            out_weight[p, c] = weight[p, c] * (1.0 - f)
            out_weight[p, m + c] = weight[p, c] * f


@numba.njit(cache=True)
def _mark(flat, present):  # pragma: no cover - compiled
    for p in range(flat.shape[0]):
        for c in range(flat.shape[1]):
            present[flat[p, c]] = True


@numba.njit(cache=True)
def _relabel(flat, lookup):  # pragma: no cover - compiled
    for p in range(flat.shape[0]):
        for c in range(flat.shape[1]):
            flat[p, c] = lookup[flat[p, c]]


def single_scattering_sky(zenith, relative_azimuth, sun_zenith, toa_irradiance, gas_down,
                          tau_rayleigh, tau_aerosol, omega_aerosol, angle_nodes, phase_rayleigh,
                          phase_aerosol):
    r"""Singly scattered sky radiance at the bottom of a plane-parallel layer.

    Parameters
    ----------
    zenith, relative_azimuth : array_like
        Direction of view into the sky [deg], zenith < 90, azimuth relative to the sun's.
        Broadcast together, shape S.
    sun_zenith : float
        [deg], < 90.
    toa_irradiance : array_like
        E_0 normal to the beam [W m-2 um-1], shape (n,).
    gas_down : array_like
        Gaseous transmittance along the sun's path [-], shape (n,).
    tau_rayleigh, tau_aerosol, omega_aerosol : array_like
        Optical depths above the observer and aerosol single-scattering albedo, shape (n,).
    angle_nodes, phase_rayleigh, phase_aerosol
        See :func:`phase_interp`.

    Returns
    -------
    numpy.ndarray
        Radiance, shape S + (n,) [W m-2 sr-1 um-1].

    Notes
    -----
    .. math:: L = \frac{E_0 T_g}{4\pi\mu} (\tau_R P_R(\Theta) + \omega_A \tau_A P_A(\Theta))
              \, e^{-\tau/\max(\mu, \mu_s)} \frac{1 - e^{-y}}{y},\quad
              y = \tau \left|\frac{1}{\mu_s} - \frac{1}{\mu}\right|

    (the layer integral of single scattering; :math:`(1 - e^{-y})/y \to 1 - y/2` for small
    :math:`y`), with the phase functions log-linear in angle as :func:`phase_interp`.
    """
    z, p = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(relative_azimuth, float))
    out = np.empty(z.size * np.size(toa_irradiance))
    _sky_terms(z.ravel(), p.ravel(), np.zeros(0), sun_zenith, toa_irradiance, gas_down,
               tau_rayleigh, tau_aerosol, omega_aerosol, angle_nodes, phase_rayleigh,
               phase_aerosol, out)
    return out.reshape(z.shape + (np.size(toa_irradiance),))


def _sky_terms(zenith, relative_azimuth, weight, sun_zenith, toa_irradiance, gas_down,
               tau_rayleigh, tau_aerosol, omega_aerosol, angle_nodes, phase_rayleigh,
               phase_aerosol, out):
    """:func:`single_scattering_sky` of flat directions into ``out`` (K·n,), or, with
    ``weight`` (K,), only Σ_k weight_k L_k into ``out`` (n,)."""
    e0g = (np.asarray(toa_irradiance, dtype=float)
           * np.asarray(gas_down, dtype=float)).reshape(-1)
    n = e0g.size
    tau_r, tau_a, om = (np.broadcast_to(np.asarray(x, dtype=float), (n,)).copy()
                        for x in (tau_rayleigh, tau_aerosol, omega_aerosol))
    nodes = np.ascontiguousarray(angle_nodes, dtype=float)
    logs = [np.ascontiguousarray(np.log(np.maximum(np.asarray(ph, dtype=float), 1e-12))
                                 .reshape(nodes.size, n)) for ph in (phase_rayleigh, phase_aerosol)]
    theta = np.ascontiguousarray(scattering_angle_sky(sun_zenith, zenith, relative_azimuth))
    mu = np.cos(np.radians(zenith))
    _sky_kernel(theta, mu, np.ascontiguousarray(weight, dtype=float),
                float(np.cos(np.radians(sun_zenith))), nodes, logs[0], logs[1], e0g, tau_r,
                tau_a, om, out)


@numba.njit(parallel=True, cache=True)
def _sky_kernel(theta, mu, weight, mu_s, nodes, log_pr, log_pa, e0g, tau_r, tau_a, om, out):
    k_n = nodes.size
    n = e0g.size
    n_dir = theta.size
    summed = weight.size > 0
    # per direction: the phase-table interval and weight, |1/μs - 1/μ|, max(μ, μs)
    lower = np.empty(n_dir, np.int64)
    frac = np.empty(n_dir)
    slant = np.empty(n_dir)
    longest = np.empty(n_dir)
    for k in range(n_dir):
        a = min(max(theta[k], nodes[0]), nodes[k_n - 1])
        i = 0  # searchsorted(nodes, a, "right") - 1, within [0, k_n - 2]
        while i < k_n - 2 and nodes[i + 1] <= a:
            i += 1
        lower[k] = i
        frac[k] = (a - nodes[i]) / (nodes[i + 1] - nodes[i])
        slant[k] = abs(1.0 / mu_s - 1.0 / mu[k])
        longest[k] = max(mu[k], mu_s)
    for j in numba.prange(n):
        tau = tau_r[j] + tau_a[j]
        total = 0.0
        h = 0.0
        for k in range(n_dir):
            i, t = lower[k], frac[k]
            pr = math.exp(log_pr[i, j] * (1.0 - t) + log_pr[i + 1, j] * t)
            pa = math.exp(log_pa[i, j] * (1.0 - t) + log_pa[i + 1, j] * t)
            if k == 0 or mu[k] != mu[k - 1]:  # the layer factor depends on the zenith only
                y = tau * slant[k]
                phi = -math.expm1(-y) / y if y > 1e-8 else 1.0 - 0.5 * y
                h = math.exp(-tau / longest[k]) * phi
            source = tau_r[j] * pr + om[j] * tau_a[j] * pa
            value = e0g[j] / (4.0 * np.pi * mu[k]) * source * h
            if summed:
                total += weight[k] * value
            else:
                out[k * n + j] = value
        if summed:
            out[j] = total


#: Scattering angles [deg] of the integrals of :func:`aerosol_asymmetry`.
_ASYMMETRY_ANGLES = np.linspace(0.0, 180.0, 1801)


def aerosol_asymmetry(angle_nodes, phase):
    """Asymmetry parameter g = <cos Θ> of tabulated phase functions.

    Parameters
    ----------
    angle_nodes : array_like
        Increasing scattering angles [deg] from 0 to 180 (see :func:`phase_interp`).
    phase : array_like
        Phase functions at the nodes, shape (k, n).

    Returns
    -------
    numpy.ndarray
        g [-], shape (n,): the mean cosine weighted by P sin Θ over the phase function
        interpolated log-linearly in angle (1 801 points, trapezoidal rule).

    Examples
    --------
    >>> nodes = np.linspace(0.0, 180.0, 721)
    >>> c = np.cos(np.radians(nodes))
    >>> hg = (1 - 0.7**2) / (1 + 0.7**2 - 2 * 0.7 * c) ** 1.5
    >>> round(float(aerosol_asymmetry(nodes, hg[:, None])[0]), 3)
    0.7
    """
    nodes = np.asarray(angle_nodes, dtype=float)
    p = np.asarray(phase, dtype=float)
    logp = np.ascontiguousarray(np.log(np.maximum(p, 1e-12)).reshape(nodes.size, -1))
    fine = _ASYMMETRY_ANGLES
    a = np.clip(fine, nodes[0], nodes[-1])
    i = np.clip(np.searchsorted(nodes, a, side="right") - 1, 0, nodes.size - 2)
    t = (a - nodes[i]) / (nodes[i + 1] - nodes[i])
    theta = np.radians(fine)
    out = np.empty(logp.shape[1])
    _asymmetry_kernel(i, t, np.sin(theta), np.cos(theta), np.diff(theta), logp, out)
    return out


@numba.njit(parallel=True, cache=True)
def _asymmetry_kernel(lower, frac, sin_t, cos_t, step, logp, out):  # pragma: no cover
    """Trapezoidal ∫ P cos Θ sin Θ dΘ / ∫ P sin Θ dΘ per wavelength, P log-linear between the
    nodes: within a node interval the fine angles' values form a geometric sequence (one
    exponential per interval, the rest products)."""
    m = lower.size
    for j in numba.prange(logp.shape[1]):
        num = 0.0
        den = 0.0
        prev_d = 0.0
        prev_n = 0.0
        p = 0.0
        ratio = 1.0
        for k in range(m):
            i = lower[k]
            if k == 0 or i != lower[k - 1] or frac[k] <= frac[k - 1]:
                p = math.exp(logp[i, j] * (1.0 - frac[k]) + logp[i + 1, j] * frac[k])
                ratio = 1.0
                if k + 1 < m and lower[k + 1] == i and frac[k + 1] > frac[k]:
                    ratio = math.exp((logp[i + 1, j] - logp[i, j]) * (frac[k + 1] - frac[k]))
            else:
                p = p * ratio
            d = p * sin_t[k]
            c = d * cos_t[k]
            if k > 0:
                den += step[k - 1] * (d + prev_d) / 2.0
                num += step[k - 1] * (c + prev_n) / 2.0
            prev_d = d
            prev_n = c
        out[j] = num / den


def multiple_scattering_shape(zenith, relative_azimuth, sun_zenith, tau, aerosol_share,
                              asymmetry):
    r"""Angular shape of the multiply scattered sky seen from the ground (unnormalised).

    Parameters
    ----------
    zenith, relative_azimuth : array_like
        Directions of view into the sky [deg], shape S; azimuth relative to the sun's.
    sun_zenith : float
        [deg].
    tau : array_like
        Optical depth of the layer above [-], shape (n,).
    aerosol_share : array_like
        w = ω_A τ_A / (τ_R + ω_A τ_A) [-], shape (n,).
    asymmetry : array_like
        Aerosol asymmetry parameter g [-], shape (n,).

    Returns
    -------
    numpy.ndarray
        M, shape S + (n,) [-] (module notes).

    Notes
    -----
    .. math:: M = \left[1 - \frac{\mu}{\tau}(1 - e^{-\tau/\mu})\right]
              \left[(1 - w) + w\,\frac{1 - g^6}{(1 + g^6 - 2 g^3 \cos\Theta)^{3/2}}\right]
    """
    z, p = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(relative_azimuth, float))
    args = _shape_arguments(z.ravel(), p.ravel(), sun_zenith, tau, aerosol_share, asymmetry)
    out = np.empty((z.size, args[2].size))
    _shape_kernel(*args, np.zeros(0), out)
    return out.reshape(z.shape + (args[2].size,))


def _shape_arguments(zenith, relative_azimuth, sun_zenith, tau, aerosol_share, asymmetry):
    """μ and cos Θ of flat directions, and τ, w, g³ per wavelength, for :func:`_shape_kernel`."""
    mu = np.cos(np.radians(np.minimum(zenith, 89.999)))
    c = np.cos(np.radians(scattering_angle_sky(sun_zenith, zenith, relative_azimuth)))
    tau, w, g = np.broadcast_arrays(*(np.asarray(x, dtype=float).ravel()
                                      for x in (tau, aerosol_share, asymmetry)))
    return (np.ascontiguousarray(mu), np.ascontiguousarray(c), np.ascontiguousarray(tau),
            np.ascontiguousarray(w), np.ascontiguousarray(g) ** 3)


@numba.njit(parallel=True, cache=True)
def _shape_kernel(mu, c, tau, w, g3, weight, out):  # pragma: no cover - compiled
    """M of :func:`multiple_scattering_shape` at directions (μ, cos Θ) and wavelengths into
    ``out`` (K, n), or, with ``weight`` (K,), only Σ_k weight_k M_k into ``out`` (n,)."""
    summed = weight.size > 0
    for j in numba.prange(tau.size):
        g = g3[j]
        total = 0.0
        depth = 0.0
        for k in range(mu.size):
            if k == 0 or mu[k] != mu[k - 1]:  # the depth factor depends on the zenith only
                x = tau[j] / mu[k]
                depth = 1.0 - (-math.expm1(-x)) / x if x > 1e-6 else 0.5 * x
            base = 1.0 + g * g - 2.0 * g * c[k]
            hg = (1.0 - g * g) / (base * math.sqrt(base))
            value = depth * ((1.0 - w[j]) + w[j] * hg)
            if summed:
                total += weight[k] * value
            else:
                out[k, j] = value
        if summed:
            out[0, j] = total


def hemisphere_quadrature(n_mu: int = 24, n_phi: int = 48):
    """Directions and weights for ∫ f(μ, φ) μ dΩ over the upper hemisphere.

    Returns
    -------
    zenith, relative_azimuth : numpy.ndarray
        Shape (n_mu * n_phi,) [deg]; azimuth in [0, 180] (the sky is symmetric about the sun's
        vertical plane).
    weight : numpy.ndarray
        μ dΩ weights [sr], summing to π.
    """
    return tuple(a.copy() for a in _quadrature(int(n_mu), int(n_phi)))


@functools.lru_cache(maxsize=4)
def _quadrature(n_mu, n_phi):
    """:func:`hemisphere_quadrature`, computed once per order."""
    x, w = np.polynomial.legendre.leggauss(n_mu)
    mu = 0.5 * (x + 1.0)
    wmu = 0.5 * w
    y, v = np.polynomial.legendre.leggauss(n_phi)
    phi = 0.5 * np.pi * (y + 1.0)  # 0..π, doubled by symmetry
    wphi = 0.5 * np.pi * v * 2.0
    zen = np.degrees(np.arccos(mu))
    zz, pp = np.meshgrid(zen, np.degrees(phi), indexing="ij")
    ww = (wmu * mu)[:, None] * wphi[None, :]
    return zz.ravel(), pp.ravel(), ww.ravel()


def sky_radiance(zenith, relative_azimuth, sun_zenith, toa_irradiance, gas_down, tau_rayleigh,
                 tau_aerosol, omega_aerosol, angle_nodes, phase_rayleigh, phase_aerosol,
                 total_down, spherical_albedo, background_albedo=0.0):
    """Sky radiance seen from the ground: single scattering + multiply scattered rest (module
    notes).

    Parameters
    ----------
    zenith, relative_azimuth : array_like
        Directions of view into the sky [deg], azimuth relative to the sun's.
    sun_zenith : float
        [deg]. At or beyond 90 the sky is dark (0).
    toa_irradiance, gas_down, tau_rayleigh, tau_aerosol, omega_aerosol : array_like
        Shape (n,): E_0 [W m-2 um-1], T_g^↓, τ_R, τ_A, ω_A [-].
    angle_nodes, phase_rayleigh, phase_aerosol
        Phase-function tables (see :func:`phase_interp`).
    total_down : array_like
        6S total scattering transmittance T^↓ along the sun's path [-], shape (n,).
    spherical_albedo : array_like
        S [-], shape (n,).
    background_albedo : float
        Albedo of the surroundings ρ_b [-].

    Returns
    -------
    numpy.ndarray
        Shape ``broadcast(zenith, relative_azimuth).shape + (n,)`` [W m-2 sr-1 um-1].
    """
    z, p = np.broadcast_arrays(np.asarray(zenith, float), np.asarray(relative_azimuth, float))
    e0 = np.asarray(toa_irradiance, dtype=float)
    if sun_zenith >= 90.0:
        return np.zeros(z.shape + e0.shape)
    mu_s = np.cos(np.radians(sun_zenith))
    tau = tau_rayleigh + tau_aerosol
    direct = np.exp(-tau / mu_s)
    e_dir = e0 * mu_s * direct * gas_down
    e_dif = e0 * mu_s * np.maximum(total_down - direct, 0.0) * gas_down
    args = (sun_zenith, e0, gas_down, tau_rayleigh, tau_aerosol, omega_aerosol, angle_nodes,
            phase_rayleigh, phase_aerosol)
    qz, qp, qw = hemisphere_quadrature()
    e_ss = np.empty(e0.size)  # Σ_q w_q L_ss(q), without the (directions × n) array
    _sky_terms(qz, qp, qw, *args, e_ss)
    e_ss = e_ss.reshape(e0.shape)
    scale = np.where(e_ss > e_dif, e_dif / np.maximum(e_ss, 1e-300), 1.0)
    rest = np.maximum(e_dif - e_ss, 0.0)
    rb = float(background_albedo) * np.asarray(spherical_albedo, dtype=float)
    env = (e_dir + e_dif) * rb / (1.0 - rb)
    ss = single_scattering_sky(np.minimum(z, 89.999), p, *args)
    # the multiply scattered rest, spread with its own angular shape
    om = np.asarray(omega_aerosol, dtype=float)
    scattering_a = om * np.asarray(tau_aerosol, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        share = np.where(tau_rayleigh + scattering_a > 0.0,
                         scattering_a / (tau_rayleigh + scattering_a), 0.0)
    g = aerosol_asymmetry(angle_nodes, np.asarray(phase_aerosol, dtype=float).reshape(
        np.size(angle_nodes), -1)).reshape(e0.shape)
    shape_args = (sun_zenith, np.broadcast_to(tau, e0.shape), np.broadcast_to(share, e0.shape),
                  g)
    norm = np.empty((1, e0.size))  # Σ_q w_q M(q), without the (directions × n) array
    _shape_kernel(*_shape_arguments(qz, qp, *shape_args), qw, norm)
    norm = norm.reshape(e0.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        ms = np.where(norm > 0.0, rest / norm, 0.0)
    return ss * scale + ms * multiple_scattering_shape(z, p, *shape_args) + env / np.pi
