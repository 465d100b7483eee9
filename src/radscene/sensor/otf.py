"""Optical transfer functions of an imaging sensor, one factor per blur mechanism.

Every function is pure, broadcasts its arguments by numpy rules, and returns the real OTF
(signed where the factor changes sign; its modulus is the MTF). Spatial frequencies are in
the focal plane: in cycles um-1 for the aberration factors, whose wavelength is in um; in
cycles per length unit for the geometric factors (jitter, smear, footprint), whose lengths
must share that unit.

===========================  ============================================================
function                     factor
===========================  ============================================================
:func:`diffraction_otf`      incoherent diffraction of a clear or annular circular pupil
:func:`wavefront_error_otf`  random wavefront error (Shannon's aberration transfer factor)
:func:`defocus_otf`          defocus (Hopkins-type approximation)
:func:`jitter_otf`           Gaussian line-of-sight jitter
:func:`smear_otf`            uniform linear motion during the integration time
:func:`detector_otf`         a rectangular detector footprint
:func:`pupil_otf`            reference: numerical autocorrelation of a sampled pupil
===========================  ============================================================

The system OTF is the product of the factors (the cascade is exact for the linear-shift-
invariant factors jitter, smear and footprint; the aberration factors are the usual
approximations and are checked against :func:`pupil_otf`).

References
----------
J. W. Goodman, *Introduction to Fourier Optics*, 3rd ed., Roberts & Co. (2005), §6.3.
E. L. O'Neill, "Transfer function for an annular aperture", J. Opt. Soc. Am. 46, 285-288
(1956), https://doi.org/10.1364/JOSA.46.000285
R. R. Shannon, *The Art and Science of Optical Design*, Cambridge University Press (1997).
H. H. Hopkins, "The frequency response of a defocused optical system", Proc. R. Soc. A 231,
91-103 (1955), https://doi.org/10.1098/rspa.1955.0158
G. D. Boreman, *Modulation Transfer Function in Optical and Electro-Optical Systems*, SPIE
Press TT52 (2001), https://doi.org/10.1117/3.419857
"""

from __future__ import annotations

import numpy as np
from scipy.special import j1

from radscene.errors import ConfigError

__all__ = [
    "diffraction_otf",
    "wavefront_error_otf",
    "defocus_otf",
    "jitter_otf",
    "smear_otf",
    "detector_otf",
    "pupil_otf",
    "MAX_WAVEFRONT_ERROR",
]

#: Largest rms wavefront error [waves] for which Shannon's quadratic factor stays >= 0.
MAX_WAVEFRONT_ERROR = 0.18


def _check_obscuration(obscuration):
    eta = np.asarray(obscuration, dtype=float)
    if np.any(~np.isfinite(eta)) or np.any((eta < 0) | (eta >= 1)):
        raise ConfigError(f"the linear obscuration ratio must lie in [0, 1); got {obscuration!r}",
                          key="obscuration")
    return eta


def _disc_overlap(r1, r2, d):
    """Area of the intersection of two discs of radii r1, r2 whose centres are d apart."""
    r1, r2, d = np.broadcast_arrays(r1, r2, d)
    small = np.minimum(r1, r2)
    out = np.where(d <= np.abs(r1 - r2), np.pi * small**2, 0.0)
    lens = (d > np.abs(r1 - r2)) & (d < r1 + r2)
    if np.any(lens):
        a, b, s = r1[lens], r2[lens], d[lens]
        c1 = np.clip((s * s + a * a - b * b) / (2.0 * s * a), -1.0, 1.0)
        c2 = np.clip((s * s + b * b - a * a) / (2.0 * s * b), -1.0, 1.0)
        k = (-s + a + b) * (s + a - b) * (s - a + b) * (s + a + b)
        out = out.copy()
        out[lens] = a * a * np.arccos(c1) + b * b * np.arccos(c2) - 0.5 * np.sqrt(np.maximum(k, 0))
    return out


def diffraction_otf(frequency, wavelength, f_number, obscuration=0.0):
    r"""Incoherent diffraction OTF of an aberration-free circular or annular pupil.

    Parameters
    ----------
    frequency : array_like
        Radial spatial frequency in the focal plane [cycles um-1], >= 0 (the sign is ignored).
    wavelength : array_like
        Wavelength [um], > 0.
    f_number : array_like
        Working f-number N = f / D [-], > 0.
    obscuration : array_like, optional
        Linear central obscuration ratio ε = D_obscuration / D, in [0, 1) [-].

    Returns
    -------
    numpy.ndarray
        OTF [-], in [0, 1], 1 at zero frequency and 0 at and beyond the cut-off
        :math:`\nu_c = 1 / (\lambda N)`.

    Notes
    -----
    With :math:`x = \nu / \nu_c` and :math:`A(r_1, r_2, d)` the overlap area of two discs of
    radii :math:`r_1, r_2` whose centres lie :math:`d` apart, the OTF is the normalised
    autocorrelation of the annular pupil (unit outer radius):

    .. math:: H(x) = \frac{A(1, 1, 2x) + A(\epsilon, \epsilon, 2x) - 2 A(1, \epsilon, 2x)}
                          {\pi (1 - \epsilon^2)}

    which for ε = 0 is :math:`\frac{2}{\pi}(\arccos x - x \sqrt{1 - x^2})` (Goodman eq. 6-32;
    O'Neill 1956 for the annulus).

    Examples
    --------
    >>> round(float(diffraction_otf(0.025, 10.0, 2.0)), 6)   # 25 cy/mm at F/2, 10 um
    0.391002
    """
    nu = np.abs(np.asarray(frequency, dtype=float))
    lam = np.asarray(wavelength, dtype=float)
    n = np.asarray(f_number, dtype=float)
    if np.any(~(lam > 0)):
        raise ConfigError(f"must be > 0 µm; got {wavelength!r}", key="wavelength")
    if np.any(~(n > 0)):
        raise ConfigError(f"must be > 0; got {f_number!r}", key="f_number")
    eta = _check_obscuration(obscuration)
    x = nu * lam * n
    if eta.ndim == 0 and eta == 0.0:  # clear pupil: the closed form
        x = np.minimum(x, 1.0)
        return 2.0 / np.pi * (np.arccos(x) - x * np.sqrt(1.0 - x * x))
    x, eta = np.broadcast_arrays(x, eta)
    x = np.minimum(x, 1.0)
    d = 2.0 * x
    one = np.ones_like(x)
    num = _disc_overlap(one, one, d) + _disc_overlap(eta, eta, d) - 2.0 * _disc_overlap(one, eta, d)
    return np.clip(num / (np.pi * (1.0 - eta * eta)), 0.0, 1.0)


def wavefront_error_otf(frequency, wavelength, f_number, rms_error):
    r"""Aberration transfer factor of a random wavefront error (Shannon's approximation).

    Parameters
    ----------
    frequency : array_like
        Radial spatial frequency [cycles um-1].
    wavelength : array_like
        Wavelength [um], > 0.
    f_number : array_like
        Working f-number [-], > 0.
    rms_error : array_like
        Root-mean-square wavefront error [um] (a length; ``rms_error / wavelength`` waves),
        at most ``MAX_WAVEFRONT_ERROR`` waves at every wavelength.

    Returns
    -------
    numpy.ndarray
        Factor [-] multiplying the diffraction OTF; 1 at zero frequency and at the cut-off.

    Notes
    -----
    .. math:: H_W(x) = 1 - \left(\frac{W_{rms}}{0.18}\right)^2 \left[1 - 4 (x - 0.5)^2\right],
              \quad x = \nu \lambda N \le 1

    (Shannon 1997; also Fiete, *Modeling the Imaging Chain of Digital Cameras*, SPIE TT92,
    2010, §5.) It is 1 for x >= 1, where the diffraction OTF is 0 anyway.

    Examples
    --------
    >>> round(float(wavefront_error_otf(0.025, 10.0, 2.0, 0.9)), 6)   # 0.09 waves at x = 0.5
    0.75
    """
    lam = np.asarray(wavelength, dtype=float)
    if np.any(~(lam > 0)):
        raise ConfigError(f"must be > 0 µm; got {wavelength!r}", key="wavelength")
    w = np.asarray(rms_error, dtype=float) / lam
    if np.any(~np.isfinite(w)) or np.any(w < 0) or np.any(w > MAX_WAVEFRONT_ERROR + 1e-12):
        worst = np.unravel_index(np.nanargmax(np.where(np.isfinite(w), np.abs(w), np.inf)), w.shape)
        at = float(np.broadcast_to(lam, w.shape)[worst])
        raise ConfigError(
            f"rms wavefront error must be in [0, {MAX_WAVEFRONT_ERROR}] waves for Shannon's "
            f"approximation; got {float(w[worst]):.4g} waves at {at:g} µm", key="wavefront_error")
    x = np.minimum(np.abs(np.asarray(frequency, dtype=float)) * lam * np.asarray(f_number), 1.0)
    return 1.0 - (w / MAX_WAVEFRONT_ERROR) ** 2 * (1.0 - 4.0 * (x - 0.5) ** 2)


def defocus_otf(frequency, wavelength, f_number, defocus):
    r"""Defocus transfer factor (Hopkins-type approximation).

    Parameters
    ----------
    frequency : array_like
        Radial spatial frequency [cycles um-1].
    wavelength : array_like
        Wavelength [um], > 0.
    f_number : array_like
        Working f-number [-], > 0.
    defocus : array_like
        Peak defocus wavefront coefficient W020 at the pupil edge [um] (a length).

    Returns
    -------
    numpy.ndarray
        Factor [-] multiplying the diffraction OTF; 1 at zero frequency and at the cut-off.

    Notes
    -----
    .. math:: H_D(x) = \frac{2 J_1(a)}{a}, \quad a = 8 \pi \frac{W_{020}}{\lambda} x (1 - x),
              \quad x = \nu \lambda N \le 1

    The geometric blur disc of diameter 8 N W020 has the OTF 2 J1(a)/a with a = 8π(W020/λ)x;
    the factor (1 - x) accounts for the shrinking pupil overlap (Hopkins 1955). Checked against
    the exact :func:`pupil_otf` in the tests (within 0.03 for W020 <= 0.5 waves).

    Examples
    --------
    >>> float(defocus_otf(0.0, 4.0, 2.0, 1.0))
    1.0
    """
    lam = np.asarray(wavelength, dtype=float)
    if np.any(~(lam > 0)):
        raise ConfigError(f"must be > 0 µm; got {wavelength!r}", key="wavelength")
    x = np.minimum(np.abs(np.asarray(frequency, dtype=float)) * lam * np.asarray(f_number), 1.0)
    a = 8.0 * np.pi * np.abs(np.asarray(defocus, dtype=float)) / lam * x * (1.0 - x)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = np.where(a > 1e-8, 2.0 * j1(a) / np.where(a > 1e-8, a, 1.0), 1.0 - a * a / 8.0)
    return out


def jitter_otf(frequency_x, frequency_y, sigma_x, sigma_y=None):
    r"""OTF of Gaussian random line-of-sight jitter.

    Parameters
    ----------
    frequency_x, frequency_y : array_like
        Spatial frequency along x and y [cycles per length unit].
    sigma_x : array_like
        Rms jitter along x in the focal plane [length unit] (angle [rad] × focal length).
    sigma_y : array_like, optional
        Rms jitter along y; default ``sigma_x``.

    Returns
    -------
    numpy.ndarray
        OTF [-].

    Notes
    -----
    .. math:: H_J = \exp\left[-2\pi^2 (\sigma_x^2 \nu_x^2 + \sigma_y^2 \nu_y^2)\right]

    (Boreman 2001, ch. 2; Holst, *Electro-Optical Imaging System Performance*.)

    Examples
    --------
    >>> round(float(jitter_otf(0.5, 0.0, 1.0 / np.pi)), 6)   # exp(-1/2)
    0.606531
    """
    sx = np.asarray(sigma_x, dtype=float)
    sy = sx if sigma_y is None else np.asarray(sigma_y, dtype=float)
    if np.any(sx < 0) or np.any(sy < 0):
        raise ConfigError(f"rms jitter must be >= 0; got {sigma_x!r}, {sigma_y!r}", key="jitter")
    fx = np.asarray(frequency_x, dtype=float)
    fy = np.asarray(frequency_y, dtype=float)
    return np.exp(-2.0 * np.pi**2 * ((sx * fx) ** 2 + (sy * fy) ** 2))


def smear_otf(frequency_x, frequency_y, length_x, length_y=0.0):
    r"""OTF of uniform linear image motion during the integration time.

    Parameters
    ----------
    frequency_x, frequency_y : array_like
        Spatial frequency along x and y [cycles per length unit].
    length_x, length_y : array_like
        Components of the image displacement during one integration [length unit].

    Returns
    -------
    numpy.ndarray
        OTF [-], :math:`\mathrm{sinc}(d_x \nu_x + d_y \nu_y)` (negative lobes kept: the phase
        reversal of a box blur).

    Examples
    --------
    >>> round(float(smear_otf(0.25, 0.0, 2.0)), 6)   # sinc(0.5) = 2 / pi
    0.63662
    """
    fx = np.asarray(frequency_x, dtype=float)
    fy = np.asarray(frequency_y, dtype=float)
    return np.sinc(np.asarray(length_x, dtype=float) * fx + np.asarray(length_y, dtype=float) * fy)


def detector_otf(frequency_x, frequency_y, width_x, width_y=None):
    r"""OTF of a uniform rectangular detector footprint.

    Parameters
    ----------
    frequency_x, frequency_y : array_like
        Spatial frequency [cycles per length unit].
    width_x : array_like
        Active width along x [length unit], > 0.
    width_y : array_like, optional
        Active width along y; default ``width_x``.

    Returns
    -------
    numpy.ndarray
        :math:`\mathrm{sinc}(w_x \nu_x)\,\mathrm{sinc}(w_y \nu_y)` [-] with
        sinc(u) = sin(πu)/(πu); its modulus is the footprint MTF (Boreman 2001, §2.1).

    Examples
    --------
    >>> round(float(detector_otf(0.5, 0.0, 1.0)), 6)   # Nyquist of a 100 % fill array
    0.63662
    """
    wx = np.asarray(width_x, dtype=float)
    wy = wx if width_y is None else np.asarray(width_y, dtype=float)
    if np.any(~(wx > 0)) or np.any(~(wy > 0)):
        raise ConfigError(f"detector width must be > 0; got {width_x!r}, {width_y!r}",
                          key="pitch")
    return np.sinc(wx * np.asarray(frequency_x, dtype=float)) * np.sinc(
        wy * np.asarray(frequency_y, dtype=float))


def pupil_otf(normalized_frequency, obscuration=0.0, defocus_waves=0.0, samples: int = 256):
    r"""Reference OTF from the numerical autocorrelation of a sampled circular pupil.

    The slow, obvious oracle for :func:`diffraction_otf` (and for the product with
    :func:`defocus_otf`): the pupil :math:`P = \exp(2\pi i W_{020} \rho^2)` on a clear or
    annular aperture is sampled on a square grid, autocorrelated by FFT, and the OTF is read
    along one axis.

    Parameters
    ----------
    normalized_frequency : array_like
        :math:`x = \nu \lambda N` [-], in [0, 1].
    obscuration : float, optional
        Linear obscuration ratio, in [0, 1) [-].
    defocus_waves : float, optional
        Defocus W020 at the pupil edge [waves].
    samples : int, optional
        Pupil samples across the diameter; the error is of order 1 / samples.

    Returns
    -------
    numpy.ndarray
        OTF (real part; the autocorrelation of a pupil with a symmetric phase is real) [-],
        same shape as `normalized_frequency`.
    """
    eta = float(_check_obscuration(obscuration))
    n = int(samples)
    size = 2 * n + 8
    coord = (np.arange(size) - size / 2 + 0.5) / (n / 2)  # units of the pupil radius
    rho2 = coord[:, None] ** 2 + coord[None, :] ** 2
    aperture = (rho2 <= 1.0) & (rho2 >= eta * eta)
    pupil = np.where(aperture, np.exp(2j * np.pi * defocus_waves * rho2), 0.0)
    spectrum = np.fft.fft2(pupil)
    auto = np.fft.ifft2(np.abs(spectrum) ** 2)  # autocorrelation, shift (0, 0) at [0, 0]
    profile = auto[0, : n + 2].real / auto[0, 0].real
    shift = np.arange(profile.size) / n  # shift in pupil diameters = x
    x = np.asarray(normalized_frequency, dtype=float)
    return np.interp(x, shift, profile, right=0.0)
