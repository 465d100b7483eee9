r"""Surface–atmosphere coupling of the ``lowtran`` engine, from LOWTRAN's own runs.

LOWTRAN7 prints no diffuse transmittance, spherical albedo or diffuse irradiance. It does
compute, in its two-stream multiple scattering (subroutine FLXADD, the adding method of
Isaacs et al. 1987, *Appl. Opt.* 26, 1272), the fluxes over a ground of albedo SALB (card 1), and two of its outputs
depend on that albedo:

* the scattered path radiance (SUMSSR, the driver's ``scattered_radiance``): light the ground
  reflects and the air scatters into the line of sight, a function of SALB = ρ of the form

  .. math:: L_\mathrm{path}(\rho) - L_\mathrm{path}(0) = \frac{\rho\,A}{1 - S_p\,\rho},
     \qquad A = \frac{E_0\,t_d}{\pi};

* the radiance the ground itself reflects along a path that ends on it (RFLSOL, TAPE7's
  ``GROUND`` column, three significant digits): SALB/π times the direct beam and the
  diffuse flux FDNSRT, times the path's transmittance τ. Over a ground of albedo ρ the
  diffuse flux is

  .. math:: D(\rho) = \frac{\pi\,\mathrm{RFLSOL}(\rho)}{\rho\,\tau} - E_\mathrm{dir}
     = \frac{D_0 + S\,\rho\,E_\mathrm{dir}}{1 - S\,\rho}.

Runs at ρ = 0, ½ and 1 along each line of sight, down to the ground, give A and S_p, and
D(½), D(1) give the diffuse irradiance over black ground D_0 = E_dif and the spherical
albedo S, each by solving two linear equations (:func:`albedo_fit`). With E_0 = E_dir + E_dif
(E_dir: μ_s times LOWTRAN's transmitted solar irradiance, from its own IEMSCT = 3 run) the
diffuse transmittance is t_d = π A / E_0, the limit ρ → 0 of the path's relation. Then a
Lambertian ground of reflectance ρ seen through LOWTRAN's radiance mode is

.. math:: L = L_\mathrm{path}(0) + \frac{\rho\,E_0}{\pi}\left(\frac{\tau}{1 - S\rho}
   + \frac{t_d}{1 - S_p\rho}\right),

which is 6S's form (:class:`~radscene.atmosphere.base.CouplingSpectra`) but for one thing:
the path's multiple reflection S_p is not the flux's S (at 0.45 um with rural aerosol,
S_p = 0.066 and S = 0.073 at 23 km visibility, 0.141 and 0.044 at 5 km). A line of sight
therefore reports the spherical albedo that gives LOWTRAN's signal to first order in S ρ,

.. math:: S_\mathrm{line} = \frac{\tau S + t_d S_p}{\tau + t_d},

within 0.1 % of the two-albedo form for ρ ≤ 0.5 (0.4 % at ρ = 1); a line of sight that
looks up, or has no length, reports the ground's S.

The molecular share of t_d comes from the same relations for a molecular atmosphere (IHAZE
= 0): t = L_path(1) − L_path(0) over the ground's reflected radiance at ρ = 1, times τ,
which is t_d (1 − S)/(1 − S_p) for either atmosphere; the share is the ratio of the two,
clipped to [0, 1].

Limits: the coupling is that of the surface at the engine's ground altitude, below each line
of sight (a target above it takes the values of the ground seen at the same view zenith);
lines of sight that look up, or have no length, get t_d = 0; without the sun (or in windows
beyond 6 um, where the engine runs no solar scattering) everything is zero. RFLSOL's three
digits leave D(ρ) with a rounding error of up to 0.5 % per spectral sample, which band
integrals average away.
"""

from __future__ import annotations

import math

import numpy as np

from radscene.atmosphere.base import CouplingSpectra
from radscene.atmosphere.lowtran.datasets import SAME_ALTITUDE_M
from radscene.atmosphere.lowtran.geometry import observer_geometry
from radscene.errors import ConfigError, EngineError

__all__ = ["ALBEDOS", "albedo_fit", "coupling"]

#: The ground albedos (card 1 SALB) of the coupling runs, besides 0.
ALBEDOS = (0.5, 1.0)
#: Path transmittances below this leave the ground's radiance unread (opaque bands) [-].
_OPAQUE = 1.0e-4


def albedo_fit(albedo_1, albedo_2, value_1, value_2):
    r"""A and S of :math:`f(\rho) = A\rho / (1 - S\rho)` through two points.

    Parameters
    ----------
    albedo_1, albedo_2 : float
        Two different albedos ρ₁, ρ₂ in (0, 1] [-].
    value_1, value_2 : array_like
        f(ρ₁), f(ρ₂), broadcast together (any unit).

    Returns
    -------
    (numpy.ndarray, numpy.ndarray)
        A (the unit of f) and S [-]; where f(ρ₂) = f(ρ₁) ρ₂/ρ₁ (a linear f) S is 0, and S
        is kept within [0, 1).

    Notes
    -----
    f (1 − S ρ) = A ρ is linear in (A, S):

    .. math:: S = \frac{\rho_1 f_2 - \rho_2 f_1}{\rho_1\rho_2 (f_2 - f_1)},\qquad
              A = f_2\,\frac{1 - S\rho_2}{\rho_2}.

    Examples
    --------
    >>> a, s = albedo_fit(0.5, 1.0, 2.0 * 0.5 / (1 - 0.1 * 0.5), 2.0 / (1 - 0.1))
    >>> round(float(a), 12), round(float(s), 12)
    (2.0, 0.1)
    """
    r1, r2 = float(albedo_1), float(albedo_2)
    if not (0.0 < r1 <= 1.0 and 0.0 < r2 <= 1.0 and r1 != r2):
        raise ValueError(f"albedo_1, albedo_2: two different albedos in (0, 1]; got {r1}, {r2}")
    f1, f2 = np.broadcast_arrays(np.asarray(value_1, float), np.asarray(value_2, float))
    den = r1 * r2 * (f2 - f1)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(np.abs(den) > 0.0, (r1 * f2 - r2 * f1) / den, 0.0)
    s = np.clip(np.nan_to_num(s), 0.0, 0.999)
    return f2 * (1.0 - s * r2) / r2, s


def _diffuse_flux(result, albedo, e_dir, wavenumber, interp):
    """D(ρ) = π RFLSOL / (ρ τ) − E_dir on the asked wavenumbers [W m-2 um-1]."""
    if result.ground_radiance is None:
        raise EngineError(f"LOWTRAN case {result.name!r} left no ground-reflected radiance "
                          "in TAPE7, which the coupling needs")
    tau = interp(result, result.transmittance, wavenumber)
    ground = interp(result, result.ground_radiance, wavenumber)
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.where(tau > _OPAQUE, math.pi * ground / (albedo * tau) - e_dir, 0.0)
    return d


def _line_coupling(atm, runs, molecular, e_dir, wavenumber):
    """(t_d, molecular share, S of the line of sight, S of the ground, E_dif) of one line of
    sight from its runs (module notes)."""
    def path(r):
        return atm._interp(r, r.scattered_radiance, wavenumber)

    def lift_over_ground(r_zero, r_one):
        # (L_path(1) - L_path(0)) tau / RFLSOL(1) = t_d (1 - S) / (1 - S_p)
        lift = path(r_one) - path(r_zero)
        ground = atm._interp(r_one, r_one.ground_radiance, wavenumber)
        tau = atm._interp(r_one, r_one.transmittance, wavenumber)
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(ground > 0.0, lift * tau / ground, 0.0)

    r0, r1, r2 = runs
    base = path(r0)
    a, s_path = albedo_fit(*ALBEDOS, path(r1) - base, path(r2) - base)
    # D(ρ) = D_0 + S ρ (E_dir + D(ρ)): two linear equations in D_0 and S
    d1 = _diffuse_flux(r1, ALBEDOS[0], e_dir, wavenumber, atm._interp)
    d2 = _diffuse_flux(r2, ALBEDOS[1], e_dir, wavenumber, atm._interp)
    e1, e2 = ALBEDOS[0] * (e_dir + d1), ALBEDOS[1] * (e_dir + d2)
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(e2 - e1 > 0.0, (d2 - d1) / (e2 - e1), 0.0)
    s = np.clip(np.nan_to_num(s), 0.0, 0.999)
    d0 = np.maximum(d2 - s * e2, 0.0)
    e0 = e_dir + d0
    with np.errstate(divide="ignore", invalid="ignore"):
        t_d = np.where(e0 > 0.0, math.pi * a / e0, 0.0)
        t_full, t_mol = lift_over_ground(r0, r2), lift_over_ground(*molecular)
        share = np.where(t_full > 0.0, t_mol / t_full, 1.0)
    t_d = np.maximum(t_d, 0.0)
    tau = atm._interp(r0, r0.transmittance, wavenumber)
    with np.errstate(divide="ignore", invalid="ignore"):
        s_line = np.where(tau + t_d > 0.0, (tau * s + t_d * s_path) / (tau + t_d), s)
    return t_d, np.clip(share, 0.0, 1.0), s_line, s, d0


def _line_cases(atm, h_obs, vz, window, bottom_km):
    """The five runs of one line of sight down to the ground: SALB 0, ½, 1, and a molecular
    atmosphere at SALB 0 and 1."""
    case, name = atm._path_case(h_obs, atm.bottom_altitude, vz, window)
    case = case.replace(h2=round(bottom_km, 7))
    runs = [(case.replace(salb=a), f"{name}, ground albedo {a:g}")
            for a in (0.0, *ALBEDOS)]
    molecular = case.replace(ihaze=0, vis=0.0)
    runs += [(molecular.replace(salb=a), f"{name}, molecules only, ground albedo {a:g}")
             for a in (0.0, 1.0)]
    return runs


def coupling(atm, observer_altitude, target_altitude, view_zenith, wavelength
             ) -> CouplingSpectra:
    """Coupling spectra of lines of sight through LOWTRAN (module docstring).

    Parameters
    ----------
    atm : LowtranAtmosphere
        The engine, its sun set (``sun_zenith``, ``sun_azimuth``, ``view_azimuth``).
    observer_altitude, target_altitude : array_like
        [m], broadcast together with ``view_zenith``.
    view_zenith : array_like
        Zenith of the direction from target to observer [deg].
    wavelength : array_like
        1-D [um].

    Returns
    -------
    CouplingSpectra
        Arrays of shape ``geometry_shape + (n_wavelength,)``.
    """
    wl, window = atm._window(wavelength)
    obs, tgt, vz = atm._check_geometry(observer_altitude, target_altitude, view_zenith)
    shape = obs.shape
    n = obs.size
    out = {k: np.zeros((n, wl.size)) for k in ("t_d", "share", "s", "dir", "dif")}

    def result():
        full = shape + wl.shape
        return CouplingSpectra(*(out[k].reshape(full) for k in ("t_d", "share", "s", "dir",
                                                                 "dif")))

    sun_zenith = atm.sun_zenith
    if sun_zenith is None or sun_zenith >= 90.0 or not atm._solar(window):
        return result()
    bottom = atm.bottom_altitude
    bottom_km = bottom / 1e3
    r_earth = atm._earth_radius_km() * 1e3
    geoms: dict[tuple, list[int]] = {}
    for i, (h_o, z) in enumerate(zip(obs.ravel(), vz.ravel(), strict=True)):
        looks_down = h_o > bottom + SAME_ALTITUDE_M and z < 90.0
        key = (round(float(h_o), 3), round(float(z), 6)) if looks_down else None
        geoms.setdefault(key, []).append(i)
    # the ground's own figures come from a nadir line of sight from the top
    lines = {key for key in geoms if key is not None} | {(1.0e5, 0.0)}
    cases, names, slots = [], [], []
    for key in sorted(lines):
        h_o, z = key
        _, _, s = observer_geometry(h_o, bottom, z, r_earth)
        if not np.isfinite(s):
            raise ConfigError(f"no line of sight joins the ground to an observer at {h_o:g} m "
                              f"with view zenith {z:g} deg", key="view_zenith")
        for case, name in _line_cases(atm, h_o, z, window, bottom_km):
            cases.append(case)
            names.append(name)
        slots.append(key)
    sun_case, sun_name = atm._sun_case(bottom, sun_zenith, window)
    results = atm.runner.run(cases + [sun_case], names + [sun_name])
    v_req = 1e4 / wl
    sun = results[-1]
    e_dir = math.cos(math.radians(sun_zenith)) * atm._interp(sun, sun.solar_irradiance, v_req)
    per_line = {}
    for k, key in enumerate(slots):
        r0, r1, r2, m0, m1 = results[5 * k: 5 * k + 5]
        per_line[key] = _line_coupling(atm, (r0, r1, r2), (m0, m1), e_dir, v_req)
    ground = per_line[(1.0e5, 0.0)]
    for key, idx in geoms.items():
        out["dir"][idx] = e_dir
        out["dif"][idx] = ground[4]
        if key is not None:
            out["t_d"][idx], out["share"][idx], out["s"][idx] = per_line[key][:3]
        else:
            out["share"][idx], out["s"][idx] = ground[1], ground[3]
    return result()
