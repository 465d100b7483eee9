"""Noise generators and their analytic variances: shot, white (read, Johnson), 1/f, quantisation.

All generators take a :class:`numpy.random.Generator` and return new arrays; the variances
are the exact expectations of what the generators produce, so that an image's measured noise
can be checked against the analytic budget.

1/f noise of the readout chain is generated along the readout stream (pixels read in raster
order, frame after frame, at the pixel rate) with the one-sided power spectral density

.. math:: S(f) = S_w \\frac{f_c}{f}, \\qquad S_w = 2 \\sigma_w^2 \\Delta t

where σ_w is the white (read) noise, Δt the pixel period and f_c the corner frequency at which
the 1/f density equals the white density. On a stream of L samples (frequency bins
f_j = j / (L Δt), j = 1 ... ⌊(L-1)/2⌋; the mean and the Nyquist bin are left out) the variance
is

.. math:: \\sigma_{1/f}^2 = 2 \\sigma_w^2 f_c \\Delta t \\sum_j \\frac{1}{j}

References
----------
J. R. Janesick, *Photon Transfer: DN → λ*, SPIE Press PM170 (2007),
https://doi.org/10.1117/3.725073
G. C. Holst and T. S. Lomheim, *CMOS/CCD Sensors and Camera Systems*, 2nd ed., SPIE Press
(2011), ch. 6.
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from radscene.errors import ConfigError, did_you_mean

__all__ = [
    "SHOT_NOISE_METHODS",
    "shot_noise",
    "white_noise",
    "flicker_noise",
    "flicker_noise_reference",
    "flicker_variance",
    "quantization_variance",
]

#: Accepted shot-noise samplers: exact Poisson counts, the Gaussian of equal mean and
#: variance, or ``auto``: Poisson below ``POISSON_LIMIT`` electrons, Gaussian above.
SHOT_NOISE_METHODS = ("auto", "poisson", "gaussian")
#: Mean count [e-] from which ``auto`` draws the Gaussian (skewness 1/sqrt(mean) <= 0.03).
POISSON_LIMIT = 1000.0


def shot_noise(mean, rng: np.random.Generator, method: str = "poisson") -> np.ndarray:
    """Shot-noise realisation of a mean count.

    Parameters
    ----------
    mean : array_like
        Expected count [e-], >= 0.
    rng : numpy.random.Generator
        Random source.
    method : {"auto", "poisson", "gaussian"}
        ``poisson``: exact counts; ``gaussian``: mean + sqrt(mean) z (faster; equal mean and
        variance, not integer); ``auto``: Poisson where the mean is below
        ``POISSON_LIMIT``, Gaussian elsewhere.

    Returns
    -------
    numpy.ndarray
        float32 counts [e-], shape of `mean`; variance = mean.
    """
    m = np.asarray(mean, dtype=float)
    if np.any(m < 0) or np.any(~np.isfinite(m)):
        raise ConfigError("the mean count must be finite and >= 0", key="mean")
    if method == "poisson":
        return rng.poisson(m).astype(np.float32)
    if method in ("gaussian", "auto"):
        m32 = m.astype(np.float32)
        out = rng.standard_normal(m.shape, dtype=np.float32)
        out *= np.sqrt(m32)
        out += m32
        if method == "auto":
            low = m < POISSON_LIMIT
            if low.any():
                out[low] = rng.poisson(m[low])
        return out
    raise ConfigError(f"unknown shot-noise method {method!r}; known: {', '.join(SHOT_NOISE_METHODS)}"
                      f"{did_you_mean(method, SHOT_NOISE_METHODS)}",
                      key="shot_noise")


def white_noise(shape, rms, rng: np.random.Generator) -> np.ndarray:
    """Zero-mean Gaussian white noise of standard deviation `rms` (float32, same unit)."""
    out = rng.standard_normal(shape, dtype=np.float32)
    out *= np.float32(rms)
    return out


def _flicker_bins(n_samples: int, sample_period: float, corner_frequency: float, white_rms: float):
    """Variance per frequency bin j = 1 .. ceil(L/2) - 1 (DC and Nyquist excluded)."""
    j = np.arange(1, (n_samples + 1) // 2, dtype=float)
    return 2.0 * white_rms**2 * corner_frequency * sample_period / j


def flicker_variance(n_samples: int, sample_period, corner_frequency, white_rms) -> float:
    """Expected variance of :func:`flicker_noise` over a stream of `n_samples` samples.

    Parameters
    ----------
    n_samples : int
        Stream length L (frames × rows × columns).
    sample_period : float
        Pixel period Δt [s].
    corner_frequency : float
        1/f corner f_c [Hz], >= 0.
    white_rms : float
        White noise σ_w [signal unit].

    Returns
    -------
    float
        :math:`2 \\sigma_w^2 f_c \\Delta t H_{\\lceil L/2 \\rceil - 1}` [signal unit²].

    Examples
    --------
    >>> flicker_variance(5, 1.0, 0.5, 1.0)   # bins j = 1, 2: 1 + 1/2
    1.5
    """
    return float(_flicker_bins(int(n_samples), float(sample_period), float(corner_frequency),
                               float(white_rms)).sum())


def flicker_noise(n_samples: int, sample_period, corner_frequency, white_rms,
                  rng: np.random.Generator, count: int = 1) -> np.ndarray:
    """1/f noise streams with the density of the module docstring (optimised, by FFT).

    Parameters
    ----------
    n_samples : int
        Samples per stream L.
    sample_period : float
        Δt [s].
    corner_frequency : float
        f_c [Hz].
    white_rms : float
        σ_w [signal unit].
    rng : numpy.random.Generator
        Random source.
    count : int
        Independent streams.

    Returns
    -------
    numpy.ndarray
        float32, shape ``(count, n_samples)`` [signal unit]; zero mean, Gaussian, variance
        :func:`flicker_variance`.
    """
    n = int(n_samples)
    v = _flicker_bins(n, sample_period, corner_frequency, white_rms)
    spectrum = np.zeros((count, n // 2 + 1), dtype=np.complex64)
    if v.size:
        amp = (0.5 * n * np.sqrt(v)).astype(np.float32)
        z = rng.standard_normal((count, v.size, 2), dtype=np.float32)
        spectrum[:, 1 : v.size + 1].real = amp * z[..., 0]
        spectrum[:, 1 : v.size + 1].imag = -amp * z[..., 1]
    return sfft.irfft(spectrum, n=n, axis=-1, workers=-1).astype(np.float32, copy=False)


def flicker_noise_reference(n_samples: int, sample_period, corner_frequency, white_rms,
                            rng: np.random.Generator, count: int = 1) -> np.ndarray:
    """Slow reference of :func:`flicker_noise`: an explicit sum of random-phase sinusoids.

    Draws the same random numbers in the same order, so it reproduces :func:`flicker_noise`
    to rounding for the same generator state.
    """
    n = int(n_samples)
    v = _flicker_bins(n, sample_period, corner_frequency, white_rms)
    z = rng.standard_normal((count, v.size, 2), dtype=np.float32).astype(float)
    t = np.arange(n)
    out = np.zeros((count, n))
    for j in range(1, v.size + 1):
        arg = 2.0 * np.pi * j * t / n
        out += np.sqrt(v[j - 1]) * (z[:, j - 1, 0:1] * np.cos(arg) + z[:, j - 1, 1:2] * np.sin(arg))
    return out


def quantization_variance(gain) -> np.ndarray:
    """Variance of uniform rounding to the nearest DN, gain² / 12 [signal unit²].

    Parameters
    ----------
    gain : array_like
        Signal per DN [e- DN-1 or V DN-1].

    Examples
    --------
    >>> float(quantization_variance(2.0)) == 4.0 / 12.0
    True
    """
    g = np.asarray(gain, dtype=float)
    return g * g / 12.0
