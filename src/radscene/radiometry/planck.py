"""Planck's law: spectral and band radiance of a blackbody, and its inverses.

All functions are pure, broadcast their arguments by numpy rules, and take wavelength in
[um] and temperature in [K]. Spectral radiance is per micrometre, [W m-2 sr-1 um-1].

References
----------
M. Planck, "Ueber das Gesetz der Energieverteilung im Normalspectrum", Ann. Phys. 309,
553-563 (1901), https://doi.org/10.1002/andp.19013090310

W. K. Widger and M. P. Woodall, "Integration of the Planck blackbody radiation function",
Bull. Am. Meteorol. Soc. 57, 1217-1219 (1976),
https://doi.org/10.1175/1520-0477(1976)057<1217:IOTPBR>2.0.CO;2
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numba
import numpy as np
from scipy.special import bernoulli

from radscene.errors import ConfigError
from radscene.radiometry.constants import C1L, C2, SIGMA, WIEN_B

if TYPE_CHECKING:
    from radscene.radiometry.srf import SpectralResponse

__all__ = [
    "spectral_radiance",
    "spectral_radiance_wavenumber",
    "radiance_temperature_derivative",
    "band_radiance",
    "exitance",
    "peak_wavelength",
    "brightness_temperature",
    "band_brightness_temperature",
]

_UM = 1.0e-6  # metres per micrometre
_PI4_15 = math.pi**4 / 15.0  # ∫_0^∞ x³ / (e^x - 1) dx

# Series of the Planck integral (Widger & Woodall 1976); switch between them at x = 2.
_X_SPLIT = 2.0
_N_EXP = 40  # terms of the exponential series, e^(-2 n) < 1e-34 at n = 40
_BERNOULLI_ORDER = 40  # terms B_m, m <= 40, of the small-x series; (2 / 2π)^40 ~ 1e-20
_BERNOULLI = bernoulli(_BERNOULLI_ORDER)
_BERNOULLI_COEF = np.array(
    [_BERNOULLI[m] / ((m + 3) * math.factorial(m)) for m in range(_BERNOULLI_ORDER + 1)]
)
_BERNOULLI_COEF[1] = -1.0 / 8.0  # B_1 = -1/2 by the t / (e^t - 1) convention
# Narrow bands (relative width in x below this) are integrated by Gauss-Legendre instead.
_NARROW = 0.05
_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)

# Brightness-temperature table: log spacing in T, upper limit, and the largest c2/(λT).
_TABLE_LOG_STEP = 0.008
_TABLE_T_MAX = 1.0e6  # [K]
_TABLE_X_MAX = 600.0


def _temperature(temperature, key="temperature"):
    t = np.asarray(temperature, dtype=float)
    if np.any(t < 0):
        raise ConfigError(f"temperature must be >= 0 K; got min {np.nanmin(t)!r} K", key=key)
    return t


def _positive(value, key, unit):
    v = np.asarray(value, dtype=float)
    if np.any(v <= 0):
        raise ConfigError(f"must be > 0 {unit}; got min {np.nanmin(v)!r} {unit}", key=key)
    return v


def _planck_exp(x):
    """Return 1 / (e^x - 1) without overflow: e^-x / (1 - e^-x); 0 at x = inf."""
    return np.exp(-x) / -np.expm1(-x)


def spectral_radiance(wavelength, temperature):
    r"""Spectral radiance of a blackbody (Planck's law).

    Parameters
    ----------
    wavelength : array_like
        Wavelength [um], > 0.
    temperature : array_like
        Temperature [K], >= 0. Broadcast against `wavelength`.

    Returns
    -------
    numpy.ndarray
        Spectral radiance [W m-2 sr-1 um-1] (a numpy float64 for scalar input). 0 at 0 K.

    Raises
    ------
    ConfigError
        If a wavelength is <= 0 or a temperature < 0.

    Notes
    -----
    .. math:: L_\lambda = \frac{c_{1L}}{\lambda^5} \frac{1}{e^{c_2 / \lambda T} - 1}

    computed as :math:`e^{-x} / (1 - e^{-x})` so that large :math:`x = c_2/\lambda T`
    underflows quietly to 0 instead of overflowing.

    Examples
    --------
    >>> round(float(spectral_radiance(10.0, 300.0)), 6)
    9.924033
    """
    lam = _positive(wavelength, "wavelength", "um") * _UM
    t = _temperature(temperature)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        x = C2 / (lam * t)
        radiance = C1L / lam**5 * _planck_exp(x)
    return radiance * _UM


def spectral_radiance_wavenumber(wavenumber, temperature):
    r"""Spectral radiance of a blackbody per unit wavenumber.

    Parameters
    ----------
    wavenumber : array_like
        Wavenumber [cm-1], > 0.
    temperature : array_like
        Temperature [K], >= 0.

    Returns
    -------
    numpy.ndarray
        Spectral radiance [W m-2 sr-1 (cm-1)-1].

    Notes
    -----
    .. math:: L_{\tilde\nu} = c_{1L} \tilde\nu^3 \frac{1}{e^{c_2 \tilde\nu / T} - 1}

    with :math:`\tilde\nu` in m-1, then multiplied by 100 m-1 per cm-1.

    Examples
    --------
    >>> round(float(spectral_radiance_wavenumber(1000.0, 300.0)), 8)
    0.09924033
    """
    nu = _positive(wavenumber, "wavenumber", "cm-1") * 100.0  # [m-1]
    t = _temperature(temperature)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        x = C2 * nu / t
        radiance = C1L * nu**3 * _planck_exp(x)
    return radiance * 100.0


def radiance_temperature_derivative(wavelength, temperature):
    r"""Derivative of blackbody spectral radiance with respect to temperature.

    Parameters
    ----------
    wavelength : array_like
        Wavelength [um], > 0.
    temperature : array_like
        Temperature [K], >= 0.

    Returns
    -------
    numpy.ndarray
        :math:`\partial L_\lambda / \partial T` [W m-2 sr-1 um-1 K-1]; 0 at 0 K.

    Notes
    -----
    .. math:: \frac{\partial L_\lambda}{\partial T} = \frac{c_{1L}}{\lambda^5}
              \frac{x e^x}{T (e^x - 1)^2}, \quad x = \frac{c_2}{\lambda T}

    Examples
    --------
    >>> round(float(radiance_temperature_derivative(10.0, 300.0)), 6)
    0.159972
    """
    lam = _positive(wavelength, "wavelength", "um") * _UM
    t = _temperature(temperature)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        x = C2 / (lam * t)
        em = -np.expm1(-x)
        value = C1L / lam**5 * x * np.exp(-x) / (em * em * t)
        value = np.where(t == 0, 0.0, value)
    return value * _UM


def _planck_integral_series(x):
    """Return (P, Q) with P = ∫_0^x t³/(e^t-1) dt and Q = ∫_x^∞, for an array x >= 0.

    Each x uses the series that converges fast there; the other is the complement.
    """
    x = np.asarray(x, dtype=float)
    big = x >= _X_SPLIT
    q = np.zeros_like(x)
    p = np.zeros_like(x)
    # x >= 2: Q = Σ e^(-n x) (x³/n + 3x²/n² + 6x/n³ + 6/n⁴). Beyond x = 800, Q < 1e-340 = 0.
    xb = np.where(big & (x < 800.0), x, 800.0)[..., None]
    n = np.arange(1, _N_EXP + 1, dtype=float)
    terms = np.exp(-n * xb) * (xb**3 / n + 3 * xb**2 / n**2 + 6 * xb / n**3 + 6 / n**4)
    qb = terms.sum(axis=-1)
    # x < 2: P = Σ_m B_m x^(m+3) / ((m+3) m!)
    xs = np.where(big, 0.0, x)[..., None]
    ps = (_BERNOULLI_COEF * xs ** (np.arange(_BERNOULLI_ORDER + 1) + 3)).sum(axis=-1)
    q = np.where(big, qb, _PI4_15 - ps)
    p = np.where(big, _PI4_15 - qb, ps)
    return p, q


def _planck_integrand(t):
    with np.errstate(over="ignore", invalid="ignore"):
        return np.where(t > 0, t**3 * _planck_exp(t), 0.0)


def _band_x_integral(x_low, x_high):
    """∫_{x_low}^{x_high} t³ / (e^t - 1) dt for arrays 0 <= x_low <= x_high (inf allowed)."""
    finite_high = np.isfinite(x_high)
    xh = np.where(finite_high, x_high, 0.0)
    p_lo, q_lo = _planck_integral_series(x_low)
    p_hi, q_hi = _planck_integral_series(xh)
    q_hi = np.where(finite_high, q_hi, 0.0)
    p_hi = np.where(finite_high, p_hi, _PI4_15)
    series = np.where(x_low >= _X_SPLIT, q_lo - q_hi, p_hi - p_lo)
    # Narrow bands: 16-point Gauss-Legendre on [x_low, x_high] avoids cancellation.
    narrow = finite_high & (xh - x_low <= _NARROW * xh)
    if np.any(narrow):
        half = 0.5 * (xh - x_low)
        mid = 0.5 * (xh + x_low)
        nodes = mid[..., None] + half[..., None] * _GL_X
        gl = half * (_planck_integrand(nodes) @ _GL_W)
        series = np.where(narrow, gl, series)
    return series


def band_radiance(wavelength_min, wavelength_max, temperature):
    r"""Blackbody radiance integrated over a wavelength band, exactly.

    Parameters
    ----------
    wavelength_min, wavelength_max : array_like
        Band limits [um], 0 < `wavelength_min` <= `wavelength_max`; `wavelength_max` may be
        ``inf``.
    temperature : array_like
        Temperature [K], >= 0. All three arguments broadcast.

    Returns
    -------
    numpy.ndarray
        In-band radiance [W m-2 sr-1].

    Notes
    -----
    With :math:`x = c_2 / \lambda T`,

    .. math:: \int_{\lambda_1}^{\lambda_2} L_\lambda\, d\lambda
              = \frac{c_{1L} T^4}{c_2^4} \int_{x_2}^{x_1} \frac{x^3}{e^x - 1}\, dx

    The x-integral uses the series of Widger & Woodall (1976): for :math:`x \ge 2`,
    :math:`\int_x^\infty = \sum_n e^{-nx}(x^3/n + 3x^2/n^2 + 6x/n^3 + 6/n^4)`; for
    :math:`x < 2`, :math:`\int_0^x = \sum_m B_m x^{m+3} / ((m+3)\, m!)` with the Bernoulli
    numbers :math:`B_m`. Bands narrower than 5 % in x use 16-point Gauss-Legendre
    quadrature instead, which avoids cancellation. Relative accuracy is ~1e-14.

    Examples
    --------
    >>> round(float(band_radiance(8.0, 12.0, 300.0)), 6)
    38.500424
    """
    lam1 = _positive(wavelength_min, "wavelength_min", "um")
    lam2 = _positive(wavelength_max, "wavelength_max", "um")
    t = _temperature(temperature)
    if np.any(lam2 < lam1):
        raise ConfigError("wavelength_max must be >= wavelength_min", key="wavelength_max")
    lam1, lam2, t = np.broadcast_arrays(lam1 * _UM, lam2 * _UM, t)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_high = C2 / (lam1 * t)  # short wavelength: large x
        x_low = C2 / (lam2 * t)
    hot = t > 0
    x_low_safe = np.where(hot, x_low, 0.0)
    x_high_safe = np.where(hot, x_high, 1.0)
    integral = _band_x_integral(x_low_safe, x_high_safe)
    result = np.where(hot, C1L * t**4 / C2**4 * integral, np.where(np.isnan(t), np.nan, 0.0))
    return result[()] if result.ndim == 0 else result


def exitance(temperature):
    r"""Hemispherical exitance of a blackbody over all wavelengths (Stefan-Boltzmann).

    Parameters
    ----------
    temperature : array_like
        Temperature [K], >= 0.

    Returns
    -------
    numpy.ndarray
        Exitance :math:`M = \sigma T^4` [W m-2].

    Examples
    --------
    >>> round(float(exitance(300.0)), 5)
    459.30033
    """
    t = _temperature(temperature)
    return SIGMA * t**4


def peak_wavelength(temperature):
    r"""Wavelength of maximum spectral radiance (Wien's displacement law).

    Parameters
    ----------
    temperature : array_like
        Temperature [K], >= 0.

    Returns
    -------
    numpy.ndarray
        :math:`\lambda_{max} = b / T` [um]; ``inf`` at 0 K.

    Examples
    --------
    >>> round(float(peak_wavelength(300.0)), 5)
    9.65924
    """
    t = _temperature(temperature)
    with np.errstate(divide="ignore"):
        return WIEN_B / t / _UM


def brightness_temperature(wavelength, radiance):
    r"""Temperature of the blackbody with the given spectral radiance (inverse Planck).

    Parameters
    ----------
    wavelength : array_like
        Wavelength [um], > 0.
    radiance : array_like
        Spectral radiance [W m-2 sr-1 um-1], >= 0. NaN gives NaN.

    Returns
    -------
    numpy.ndarray
        Brightness temperature [K]; 0 K where `radiance` is 0.

    Notes
    -----
    .. math:: T_b = \frac{c_2}{\lambda \ln\left(1 + c_{1L} / (\lambda^5 L_\lambda)\right)}

    Examples
    --------
    >>> round(float(brightness_temperature(10.0, 9.924033)), 4)
    300.0
    """
    lam = _positive(wavelength, "wavelength", "um") * _UM
    rad = np.asarray(radiance, dtype=float)
    if np.any(rad < 0):
        raise ConfigError(
            f"radiance must be >= 0 W m-2 sr-1 µm-1; got min {np.nanmin(rad)!r}",
            key="radiance",
        )
    with np.errstate(divide="ignore", over="ignore"):
        return C2 / (lam * np.log1p(C1L / (lam**5 * (rad / _UM))))


def _brightness_table(response: SpectralResponse):
    """(ln L, 1/T, d(1/T)/d(ln L), largest L) of :func:`band_brightness_temperature`'s table.

    Built once per response and kept with its quadrature rule (both are fixed once built).
    """
    table = response.__dict__.get("_brightness_table")
    if table is not None:
        return table
    nodes, weights = response.quadrature()
    t_min = C2 / (_TABLE_X_MAX * np.max(nodes) * _UM)
    n = int(math.ceil(math.log(_TABLE_T_MAX / t_min) / _TABLE_LOG_STEP)) + 1
    t_table = np.geomspace(t_min, _TABLE_T_MAX, n)
    l_table = spectral_radiance(nodes, t_table[:, None]) @ weights
    dl_table = radiance_temperature_derivative(nodes, t_table[:, None]) @ weights
    keep = l_table > 0
    t_table, l_table, dl_table = t_table[keep], l_table[keep], dl_table[keep]
    yk, uk, mk = np.log(l_table), 1.0 / t_table, -l_table / (t_table**2 * dl_table)
    for a in (yk, uk, mk):
        a.flags.writeable = False
    table = response.__dict__["_brightness_table"] = (yk, uk, mk, float(l_table[-1]))
    return table


def band_brightness_temperature(radiance, response: SpectralResponse):
    r"""Temperature of the blackbody with the given band radiance in a spectral response.

    The exact inverse of ``response.integrate_function(lambda wl: spectral_radiance(wl, T))``.

    Parameters
    ----------
    radiance : array_like
        Band radiance weighted by the response, :math:`\int S(\lambda) L_\lambda d\lambda`
        [W m-2 sr-1], >= 0, any shape. NaN gives NaN, ``inf`` gives ``inf``.
    response : SpectralResponse
        The spectral response S(λ) the radiance was integrated with.

    Returns
    -------
    numpy.ndarray
        Brightness temperature [K], shape of `radiance`; 0 K where `radiance` is 0.

    Raises
    ------
    ConfigError
        If a radiance is negative or exceeds that of a 1e6 K blackbody.

    Notes
    -----
    Once per response (then kept with it), the band radiance :math:`L(T)` and :math:`dL/dT` are computed with the
    response's quadrature on a dense table (log step 0.008 in T, from the temperature where
    :math:`c_2 / \lambda_{max} T = 600` up to 1e6 K). The inverse :math:`u = 1/T` as a
    function of :math:`y = \ln L` is then interpolated by cubic Hermite polynomials with
    the exact slopes :math:`du/dy = -L / (T^2\, dL/dT)`, which is smooth in both the Wien
    and the Rayleigh-Jeans limit. No Newton step is needed: the relative error of the
    interpolant is below 1e-10 (1e-7 K at 1e4 K), far inside the 1e-6 K asked for.
    Radiances below the table (a few kelvin in the thermal infrared) are extrapolated
    linearly in (1/T, ln L), the Wien limit.

    Examples
    --------
    >>> from radscene.radiometry.srf import RectangularResponse
    >>> band = RectangularResponse(8.0, 12.0)
    >>> round(float(band_brightness_temperature(38.500424, band)), 4)
    300.0
    """
    rad = np.asarray(radiance, dtype=float)
    yk, uk, mk, l_max = _brightness_table(response)
    result = np.empty(rad.shape)
    status = _invert_band(np.ascontiguousarray(rad).reshape(-1), yk, uk, mk, l_max,
                          result.reshape(-1))
    if status == 1:
        raise ConfigError(
            f"band radiance must be >= 0 W m-2 sr-1; got min {np.nanmin(rad)!r}",
            key="radiance",
        )
    if status == 2:
        raise ConfigError(
            f"band radiance above {l_max:.6g} W m-2 sr-1 (a {_TABLE_T_MAX:g} K "
            f"blackbody in {response.name!r}) is not accepted",
            key="radiance",
        )
    return result[()] if result.ndim == 0 else result


@numba.njit(cache=True)
def _invert_band(rad, yk, uk, mk, l_max, out):
    """:func:`band_brightness_temperature` per value, into ``out``: the cubic Hermite
    interpolant of u = 1/T in y = ln L through the table's nodes and slopes inside it, its
    Wien-limit line below it;
    NaN for NaN, 0 K for 0, inf for inf. Returns 1 at a negative radiance, 2 at a finite one
    above ``l_max``, else 0 (``out`` is then complete)."""
    n = yk.size
    k = 0  # the interval of the last value: neighbouring pixels mostly share it
    for i in range(rad.size):
        r = rad[i]
        if r != r:
            out[i] = np.nan
        elif r < 0.0:
            return 1
        elif r == 0.0:
            out[i] = 0.0
        elif r == np.inf:
            out[i] = np.inf
        elif r > l_max:
            return 2
        else:
            y = math.log(r)
            if y >= yk[0]:
                if not (yk[k] <= y < yk[k + 1]):
                    lo, hi = 0, n  # searchsorted(yk, y, side="right")
                    while lo < hi:
                        mid = (lo + hi) // 2
                        if yk[mid] <= y:
                            lo = mid + 1
                        else:
                            hi = mid
                    k = min(max(lo - 1, 0), n - 2)
                h = yk[k + 1] - yk[k]
                s = (y - yk[k]) / h
                s2 = s * s
                s3 = s2 * s
                u = ((2 * s3 - 3 * s2 + 1) * uk[k] + (s3 - 2 * s2 + s) * h * mk[k]
                     + (-2 * s3 + 3 * s2) * uk[k + 1] + (s3 - s2) * h * mk[k + 1])
            else:
                u = uk[0] + mk[0] * (y - yk[0])
            out[i] = 1.0 / u
    return 0
