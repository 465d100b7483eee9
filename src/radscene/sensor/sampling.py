"""From an oversampled radiance image to the detector grid: OTF filtering and sampling.

The renderer draws the scene on a grid ``oversample`` times finer than the detector pitch.
:func:`apply_otf` filters that image with the system OTF in the Fourier domain and samples
the result at the detector centres; with the detector footprint inside the OTF, each output
value is the footprint-averaged, PSF-blurred radiance of one detector. The OTF is 1 at zero
frequency, so the image mean is preserved (energy conservation); the boundary is periodic.

Sample ``n`` of the fine grid covers ``[n, n + 1)`` in sample units; detector ``m`` covers
``[m k, (m + 1) k)`` and is centred at ``m k + k / 2``. The filtered image between samples is
the trigonometric (band-limited) interpolation of the samples, with the Nyquist row and column
of the fine grid dropped (so that the interpolation is real and unique; for an even ``k`` and a
100 % fill factor the footprint OTF is 0 there anyway).

:func:`apply_otf` is the optimised version: one real FFT of the fine image, the OTF, a phase
ramp to the detector centres, folding (aliasing) of the spectrum onto the detector grid and a
small inverse FFT. :func:`apply_otf_reference` is the slow, obvious oracle: a full complex FFT
and an explicit inverse DFT evaluated at the detector centres.
"""

from __future__ import annotations

import numpy as np
import scipy.fft as sfft

from radscene.errors import ConfigError

__all__ = [
    "detector_grid_shape",
    "rfft_frequencies",
    "apply_otf",
    "apply_otf_reference",
    "block_mean",
    "block_centre",
]


def detector_grid_shape(shape, oversample: int) -> tuple[int, int]:
    """Detector grid of an oversampled image.

    Parameters
    ----------
    shape : tuple of int
        ``(ny, nx)`` of the fine image [samples].
    oversample : int
        Fine samples per detector pitch, >= 1.

    Returns
    -------
    tuple of int
        ``(ny // oversample, nx // oversample)`` [detectors].

    Raises
    ------
    ConfigError
        ``detector.pitch`` when one pitch spans more samples than the image has, and
        ``oversample`` when the image is not a whole number of detectors.
    """
    k = _oversample(oversample)
    ny, nx = (int(n) for n in shape[-2:])
    if k > ny or k > nx:
        raise ConfigError(
            f"the detector pitch ({k} rendered samples) is larger than the radiance image "
            f"({ny} x {nx} samples); render at least one pitch, or lower 'oversample'",
            key="detector.pitch")
    if ny % k or nx % k:
        raise ConfigError(
            f"the radiance image ({ny} x {nx} samples) is not a whole number of detectors of "
            f"{k} x {k} samples; render a multiple of {k} samples in each direction",
            key="oversample")
    return ny // k, nx // k


def _oversample(oversample) -> int:
    if isinstance(oversample, bool) or not isinstance(oversample, int | np.integer) or oversample < 1:
        raise ConfigError(f"must be an integer >= 1 (rendered samples per detector pitch); "
                          f"got {oversample!r}", key="oversample")
    return int(oversample)


def rfft_frequencies(shape) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies of the half-spectrum of :func:`scipy.fft.rfft2` of an image.

    Parameters
    ----------
    shape : tuple of int
        ``(ny, nx)`` [samples].

    Returns
    -------
    fy : numpy.ndarray
        Shape ``(ny, 1)``, signed [cycles sample-1].
    fx : numpy.ndarray
        Shape ``(1, nx // 2 + 1)``, >= 0 [cycles sample-1].
    """
    ny, nx = shape
    return sfft.fftfreq(ny)[:, None], sfft.rfftfreq(nx)[None, :]


def _fold_phases(n: int, k: int):
    """Phase ramp to the detector centres, factorised over the spectral folding.

    For the index n = u' + j M of an axis of length N = k M (signed frequency u: n, or n - N
    on the negative half), exp(2πi u s / N) with s = (k - 1) / 2 equals p0(u') c_j, with
    p0(u') = exp(2πi u' s / N) and c_j = exp(2πi j s / k), times (-1)^(k-1) on the negative
    half, which for an even k begins exactly at block j = k / 2.
    """
    m = n // k
    s = 0.5 * (k - 1)
    j = np.arange(k)
    c = np.exp(2j * np.pi * j * s / k)
    if k % 2 == 0:
        c[j >= k // 2] *= -1.0
    p0 = np.exp(2j * np.pi * np.arange(m) * s / n)
    return c.astype(np.complex64), p0.astype(np.complex64)


def _fold(blocks, weights, axis):
    """Σ_j weights[j] · blocks.take(j, axis) without temporaries of the full size."""
    out = np.take(blocks, 0, axis=axis) * weights[0]
    tmp = np.empty_like(out)
    for j in range(1, len(weights)):
        np.multiply(np.take(blocks, j, axis=axis), weights[j], out=tmp)
        out += tmp
    return out


def apply_otf(image, otf, oversample: int, workers: int | None = None) -> np.ndarray:
    """Filter a fine image with an OTF and sample it at the detector centres (optimised).

    Parameters
    ----------
    image : array_like
        Fine image, shape ``(..., ny, nx)``, any unit (radiance [W m-2 sr-1] in the chain).
        Computed in single precision.
    otf : array_like or None
        Real OTF on the half-spectrum grid of :func:`rfft_frequencies`, shape broadcastable
        to ``(..., ny, nx // 2 + 1)`` [-]; it must be even, H(-f) = H(f), as the OTF of
        every symmetric PSF is. An OTF that is also even in ``fy`` alone may be given for the
        rows ``fy >= 0`` only, shape ``(..., ny // 2 + 1, nx // 2 + 1)``; the other rows are
        read from them. None: no filtering (sampling only).
    oversample : int
        Fine samples per detector pitch ``k``; ``ny`` and ``nx`` must be multiples of it.
    workers : int, optional
        Threads for the FFTs (:mod:`scipy.fft`); default all cores.

    Returns
    -------
    numpy.ndarray
        float32, shape ``(..., ny // k, nx // k)``, same unit as `image`.
    """
    a = np.asarray(image, dtype=np.float32)
    k = _oversample(oversample)
    my, mx = detector_grid_shape(a.shape, k)
    ny, nx = a.shape[-2:]
    workers = workers if workers is not None else -1
    spec = sfft.rfft2(a, workers=workers)
    if otf is not None:
        h = np.asarray(otf, dtype=np.float32)
        half = ny // 2 + 1
        if h.ndim >= 2 and h.shape[-2] == half and half != ny:
            spec[..., :half, :] *= h
            spec[..., half:, :] *= h[..., ny - half : 0 : -1, :]
        else:
            spec *= h
    if ny % 2 == 0:
        spec[..., ny // 2, :] = 0.0
    if nx % 2 == 0:
        spec[..., :, nx // 2] = 0.0
    nxh = spec.shape[-1]
    lead = spec.shape[:-2]
    # fold (alias) the y-frequencies onto the detector grid, with the phase to the centres
    cy, py = _fold_phases(ny, k)
    fold_y = _fold(spec.reshape(lead + (k, my, nxh)), cy, axis=-3)
    fold_y *= py[:, None]
    # complete the x-spectrum by Hermitian symmetry: Y(u', -v) = conj(Y(-u' mod my, v))
    full = np.empty(lead + (my, nx), dtype=np.complex64)
    full[..., :nxh] = fold_y
    n_neg = nx - nxh
    if n_neg:
        neg = (-np.arange(my)) % my
        full[..., nxh:] = np.conj(fold_y[..., neg, 1 : n_neg + 1])[..., ::-1]
    cx, px = _fold_phases(nx, k)
    folded = _fold(full.reshape(lead + (my, k, mx)), cx, axis=-2)
    folded *= px
    out = sfft.ifft2(folded, workers=workers).real
    out *= np.float32(1.0 / (k * k))
    return out.astype(np.float32, copy=False)


def apply_otf_reference(image, otf, oversample: int) -> np.ndarray:
    """Slow reference of :func:`apply_otf`: full FFT and an explicit inverse DFT at the centres.

    Parameters
    ----------
    image : array_like
        Fine image, shape ``(ny, nx)``.
    otf : callable
        ``otf(fy, fx)`` -> real OTF for signed frequencies [cycles sample-1] (arrays of
        shapes ``(ny, 1)`` and ``(1, nx)``).
    oversample : int
        Fine samples per detector pitch.

    Returns
    -------
    numpy.ndarray
        float64, shape ``(ny // k, nx // k)``.
    """
    a = np.asarray(image, dtype=float)
    k = _oversample(oversample)
    my, mx = detector_grid_shape(a.shape, k)
    ny, nx = a.shape
    fy = np.fft.fftfreq(ny)
    fx = np.fft.fftfreq(nx)
    h = np.broadcast_to(np.asarray(otf(fy[:, None], fx[None, :]), dtype=float), (ny, nx)).copy()
    if ny % 2 == 0:
        h[ny // 2, :] = 0.0
    if nx % 2 == 0:
        h[:, nx // 2] = 0.0
    spectrum = np.fft.fft2(a) * h
    yc = np.arange(my) * k + 0.5 * (k - 1)  # detector centres in sample-index coordinates
    xc = np.arange(mx) * k + 0.5 * (k - 1)
    ey = np.exp(2j * np.pi * yc[:, None] * fy[None, :])
    ex = np.exp(2j * np.pi * xc[:, None] * fx[None, :])
    return (ey @ spectrum @ ex.T).real / (ny * nx)


def block_mean(image, oversample: int) -> np.ndarray:
    """Mean over each detector's ``k x k`` block of fine samples, NaN samples left out.

    Parameters
    ----------
    image : array_like
        Shape ``(..., ny, nx)``, any unit.
    oversample : int
        ``k``.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., ny // k, nx // k)``, same unit (float32 for float32 input, else
        float64); NaN where a block holds only NaN.
    """
    a = np.asarray(image)
    k = _oversample(oversample)
    detector_grid_shape(a.shape, k)
    dtype = np.float32 if a.dtype == np.float32 else np.float64
    if k == 1:
        return a.astype(dtype, copy=False)
    total = a[..., 0::k, 0::k].astype(dtype)
    for i in range(k):
        for j in range(k):
            if i or j:
                total += a[..., i::k, j::k]
    if not np.isnan(total).any():
        total *= dtype(1.0 / (k * k))
        return total
    finite = np.isfinite(a)
    clean = np.where(finite, a, 0).astype(dtype)
    total = np.zeros_like(total)
    count = np.zeros(total.shape, dtype=np.int32)
    for i in range(k):
        for j in range(k):
            total += clean[..., i::k, j::k]
            count += finite[..., i::k, j::k]
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(count > 0, total / np.maximum(count, 1), np.nan).astype(dtype)


def block_centre(image, oversample: int) -> np.ndarray:
    """The fine sample at (or just below-right of) each detector centre.

    For labels such as object or material ids, which must not be averaged.

    Parameters
    ----------
    image : array_like
        Shape ``(..., ny, nx)``.
    oversample : int
        ``k``; the sample taken is ``(m k + k // 2, n k + k // 2)``.

    Returns
    -------
    numpy.ndarray
        Shape ``(..., ny // k, nx // k)``, same dtype.
    """
    a = np.asarray(image)
    k = _oversample(oversample)
    detector_grid_shape(a.shape, k)
    return a[..., k // 2 :: k, k // 2 :: k]
