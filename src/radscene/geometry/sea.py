"""A wind-driven sea surface: wave spectra, directional spreading, FFT synthesis on a periodic tile.

Spectra
-------
Frequency spectra S(ω) [m2 s rad-1] of the surface elevation, ω the angular frequency:

* Pierson & Moskowitz (1964), the fully developed sea (:func:`pierson_moskowitz`):

  .. math:: S(\\omega) = \\alpha g^2 \\omega^{-5} \\exp[-\\beta (\\omega_0/\\omega)^4],
            \\quad \\alpha = 8.1\\times10^{-3},\\ \\beta = 0.74,\\ \\omega_0 = g / U_{19.5}.

* JONSWAP (Hasselmann et al. 1973), the fetch-limited sea (:func:`jonswap`):

  .. math:: S(\\omega) = \\alpha g^2 \\omega^{-5} \\exp[-\\tfrac54 (\\omega_p/\\omega)^4]\\,
            \\gamma^{\\exp[-(\\omega-\\omega_p)^2 / (2\\sigma^2\\omega_p^2)]},

  :math:`\\tilde x = g F / U_{10}^2`, :math:`\\alpha = 0.076\\,\\tilde x^{-0.22}`,
  :math:`\\omega_p = 22\\,(g/U_{10})\\,\\tilde x^{-0.33}`, γ = 3.3, σ = 0.07 (ω ≤ ω_p) or 0.09.
  Beyond :math:`\\tilde x \\approx 2\\times10^4` the sea is fully developed: use
  Pierson–Moskowitz.

The wind speed given is U₁₀, 10 m above the sea; other heights follow the neutral logarithmic
profile :math:`U(z) = U_{10} \\ln(z/z_0) / \\ln(10/z_0)` with the roughness length
z₀ = 2×10⁻⁴ m of the open sea (:func:`wind_at_height`).

Directions
----------
The cos-2s spreading function of Longuet-Higgins, Cartwright & Smith (1963)
(:func:`spreading`), over the full circle:

.. math:: D(\\theta) = \\frac{\\Gamma(s+1)}{2\\sqrt\\pi\\,\\Gamma(s+\\tfrac12)}
          \\cos^{2s}\\frac{\\theta - \\theta_w}{2},\\qquad \\int_{-\\pi}^{\\pi} D\\,d\\theta = 1,

θ_w the direction the waves travel (downwind). The wavenumber spectrum by deep-water dispersion
:math:`\\omega^2 = g k`: :math:`F(k) = S(\\omega)\\,d\\omega/dk`, and over the plane
:math:`\\Psi(k_x, k_y) = F(k) D(\\theta) / k` [m4], so that :math:`\\int \\Psi\\,d^2k` is the
elevation variance.

Synthesis
---------
On a periodic tile of side L with N × N samples (Δk = 2π/L), each wavevector k of the FFT grid
gets the amplitude :math:`c_k = \\sqrt{2\\Psi(\\mathbf k)}\\,\\Delta k\\,e^{i\\phi_k}`, its rms
value, with a random phase φ uniform in [0, 2π) (``numpy.random.default_rng(seed)``): the
surface is Gaussian by the number of components, and every draw holds the spectrum's variances
(up to the interference of the pairs k, −k, small where little energy travels upwind), and

.. math:: h(\\mathbf x, t) = \\mathrm{Re} \\sum_{\\mathbf k} c_{\\mathbf k}\\,
          e^{i(\\mathbf k\\cdot\\mathbf x - \\omega_k t)},\\qquad \\omega_k = \\sqrt{g |\\mathbf k|},

one inverse FFT per instant: every component travels along its own k at its phase speed ω/k,
and :math:`\\overline{h^2} = \\sum \\Psi \\Delta k^2`. The mesh's facets have the slopes of forward
differences of the samples, whose variance is
:math:`\\sum \\Psi\\Delta k^2\\,[(2\\sin(k_x\\Delta x/2)/\\Delta x)^2 + (2\\sin(k_y\\Delta x/2)/\\Delta x)^2]`
(:meth:`SeaSurface.mesh_slope_variance`): the waves between the tile and the sampling's
Nyquist wavenumber π/Δx. Shorter waves are not in the geometry.

References
----------
W. J. Pierson, L. Moskowitz, "A proposed spectral form for fully developed wind seas based on
the similarity theory of S. A. Kitaigorodskii", J. Geophys. Res. 69(24), 5181–5190 (1964),
doi:10.1029/JZ069i024p05181.
K. Hasselmann et al., "Measurements of wind-wave growth and swell decay during the Joint North
Sea Wave Project (JONSWAP)", Dtsch. Hydrogr. Z. Suppl. A 8(12), 1–95 (1973).
M. S. Longuet-Higgins, D. E. Cartwright, N. D. Smith, "Observations of the directional
spectrum of sea waves using the motions of a floating buoy", in Ocean Wave Spectra,
Prentice-Hall, 111–136 (1963).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.constants import g as GRAVITY  # standard acceleration of gravity [m s-2]
from scipy.special import gammaln

from radscene.errors import ConfigError, did_you_mean
from radscene.geometry.mesh import Mesh
from radscene.geometry.terrain import Heightfield

__all__ = ["SPECTRA", "SeaSurface", "TiledSea", "jonswap", "pierson_moskowitz", "spreading", "wind_at_height"]

#: Phillips' constant of the Pierson–Moskowitz spectrum [-].
PM_ALPHA = 8.1e-3
#: β of the Pierson–Moskowitz spectrum [-].
PM_BETA = 0.74
#: Roughness length of the open sea in the neutral wind profile [m].
SEA_ROUGHNESS_LENGTH = 2e-4


def wind_at_height(wind_speed, height):
    """Wind speed at ``height`` from U₁₀ by the neutral logarithmic profile [m s-1].

    Parameters
    ----------
    wind_speed : array_like
        U₁₀, 10 m above the sea [m s-1].
    height : array_like
        [m], > 0.

    Returns
    -------
    numpy.ndarray
        U₁₀ ln(z/z₀) / ln(10/z₀), z₀ = 2e-4 m [m s-1].

    Examples
    --------
    >>> round(float(wind_at_height(10.0, 19.5)), 3)
    10.617
    """
    z = np.asarray(height, dtype=float)
    return np.asarray(wind_speed, dtype=float) * np.log(z / SEA_ROUGHNESS_LENGTH) / math.log(
        10.0 / SEA_ROUGHNESS_LENGTH)


def pierson_moskowitz(omega, wind_speed):
    """Pierson–Moskowitz (1964) frequency spectrum of a fully developed sea [m2 s rad-1].

    Parameters
    ----------
    omega : array_like
        Angular frequency [rad s-1]; 0 gives 0.
    wind_speed : float
        U₁₀ [m s-1], ≥ 0 (0: a calm sea, S = 0); converted to U₁₉.₅ (:func:`wind_at_height`).

    Returns
    -------
    numpy.ndarray
        S(ω), shape of ``omega``.

    Examples
    --------
    >>> w_peak = 0.877 * GRAVITY / float(wind_at_height(10.0, 19.5))   # the peak, (4β/5)^(1/4) ω0
    >>> bool(pierson_moskowitz(w_peak, 10.0) > pierson_moskowitz(1.1 * w_peak, 10.0))
    True
    """
    w = np.asarray(omega, dtype=float)
    if wind_speed <= 0.0:
        return np.zeros_like(w)
    w0 = GRAVITY / float(wind_at_height(wind_speed, 19.5))
    out = np.zeros_like(w)
    pos = w > 0
    out[pos] = PM_ALPHA * GRAVITY**2 * w[pos] ** -5 * np.exp(-PM_BETA * (w0 / w[pos]) ** 4)
    return out


def jonswap(omega, wind_speed, fetch, gamma=3.3):
    """JONSWAP (Hasselmann et al. 1973) frequency spectrum of a fetch-limited sea [m2 s rad-1].

    Parameters
    ----------
    omega : array_like
        Angular frequency [rad s-1]; 0 gives 0.
    wind_speed : float
        U₁₀ [m s-1], ≥ 0 (0: calm, S = 0).
    fetch : float
        Distance over which the wind has blown [m], > 0.
    gamma : float
        Peak enhancement factor [-], ≥ 1 (1: the Pierson–Moskowitz shape at that peak).

    Returns
    -------
    numpy.ndarray
        S(ω), shape of ``omega``.

    Examples
    --------
    >>> float(jonswap(0.0, 10.0, 100e3))
    0.0
    """
    w = np.asarray(omega, dtype=float)
    if wind_speed <= 0.0:
        return np.zeros_like(w)
    if not fetch > 0:
        raise ConfigError(f"must be > 0 m, got {fetch!r}", key="fetch")
    x = GRAVITY * fetch / wind_speed**2
    alpha = 0.076 * x**-0.22
    wp = 22.0 * (GRAVITY / wind_speed) * x**-0.33
    out = np.zeros_like(w)
    pos = w > 0
    wq = w[pos]
    sigma = np.where(wq <= wp, 0.07, 0.09)
    peak = gamma ** np.exp(-((wq - wp) ** 2) / (2.0 * sigma**2 * wp**2))
    out[pos] = alpha * GRAVITY**2 * wq**-5 * np.exp(-1.25 * (wp / wq) ** 4) * peak
    return out


def spreading(theta, direction, s):
    """The cos-2s directional spreading function D(θ) [rad-1], normalised over the circle.

    Parameters
    ----------
    theta : array_like
        Direction of travel of a wave component [rad].
    direction : float
        Mean direction of travel (downwind) [rad].
    s : float
        Spreading exponent [-], ≥ 0 (0: isotropic); larger is narrower.

    Returns
    -------
    numpy.ndarray
        Γ(s+1) / (2√π Γ(s+1/2)) cos^{2s}((θ − θ_w)/2).

    Examples
    --------
    >>> t = np.linspace(-np.pi, np.pi, 20001)
    >>> round(float(np.trapezoid(spreading(t, 0.3, 8.0), t)), 6)
    1.0
    """
    norm = math.exp(gammaln(s + 1.0) - gammaln(s + 0.5)) / (2.0 * math.sqrt(math.pi))
    return norm * np.abs(np.cos(0.5 * (np.asarray(theta, dtype=float) - direction))) ** (2.0 * s)


#: The frequency spectra by name (``terrain.spectrum`` of a sea).
SPECTRA = {"pierson_moskowitz": pierson_moskowitz, "jonswap": jonswap}


class SeaSurface:
    """A periodic tile of sea surface that moves with time (module docstring).

    Parameters
    ----------
    amplitudes : array_like
        Complex amplitudes c_k [m], shape (N, N), indexed ``[ky, kx]`` in numpy's FFT order.
    tile : float
        Side of the square tile [m].

    Examples
    --------
    >>> sea = SeaSurface.from_spectrum("pierson_moskowitz", 8.0, 0.0, tile=32.0, resolution=0.5)
    >>> sea.height(0.0).shape
    (64, 64)
    """

    def __init__(self, amplitudes, tile: float):
        c = np.asarray(amplitudes, dtype=complex)
        if c.ndim != 2 or c.shape[0] != c.shape[1] or c.shape[0] < 2:
            raise ConfigError(f"must be a square array of at least 2 x 2, got {c.shape}",
                              key="amplitudes")
        if not tile > 0:
            raise ConfigError(f"must be > 0 m, got {tile!r}", key="tile")
        self.amplitudes = c
        self.tile = float(tile)
        n = c.shape[0]
        self.spacing = self.tile / n
        k = 2.0 * math.pi * np.fft.fftfreq(n, d=self.spacing)
        self.kx, self.ky = k[None, :], k[:, None]
        self.omega = np.sqrt(GRAVITY * np.hypot(self.kx, self.ky))  # deep water [rad s-1]

    @classmethod
    def from_spectrum(cls, spectrum: str, wind_speed: float, wind_direction: float, *,
                      tile: float, resolution: float, fetch: float | None = None,
                      gamma: float = 3.3, spreading_exponent: float = 10.0,
                      seed: int = 0) -> SeaSurface:
        """A tile drawn from a named spectrum; the same seed gives the same sea.

        Parameters
        ----------
        spectrum : {"pierson_moskowitz", "jonswap"}
        wind_speed : float
            U₁₀ [m s-1], ≥ 0.
        wind_direction : float
            Where the wind comes from, clockwise from north [deg]; the waves travel downwind.
        tile : float
            Side of the periodic tile [m].
        resolution : float
            Sample spacing [m]; ``tile / resolution`` must be a whole number (≥ 2).
        fetch : float, optional
            [m]; JONSWAP only, and required there.
        gamma : float
            JONSWAP's peak enhancement [-].
        spreading_exponent : float
            s of the cos-2s spreading [-].
        seed : int
            Of ``numpy.random.default_rng``.

        Returns
        -------
        SeaSurface
        """
        name = str(spectrum).lower()
        if name not in SPECTRA:
            raise ConfigError(f"unknown spectrum {spectrum!r}; known: {', '.join(SPECTRA)}"
                              f"{did_you_mean(spectrum, SPECTRA)}",
                              key="spectrum")
        if not (np.isfinite(wind_speed) and wind_speed >= 0):
            raise ConfigError(f"must be a finite speed >= 0, got {wind_speed!r}", key="wind_speed")
        n = _samples(tile, resolution)
        if name == "jonswap":
            if fetch is None:
                raise ConfigError("the JONSWAP spectrum needs a fetch [m]", key="fetch")
            frequency = lambda w: jonswap(w, wind_speed, fetch, gamma)  # noqa: E731
        else:
            if fetch is not None:
                raise ConfigError("the Pierson-Moskowitz sea is fully developed: it takes no "
                                  "fetch (use jonswap)", key="fetch")
            frequency = lambda w: pierson_moskowitz(w, wind_speed)  # noqa: E731
        dx = tile / n
        kv = 2.0 * math.pi * np.fft.fftfreq(n, d=dx)
        kx, ky = np.meshgrid(kv, kv)
        k = np.hypot(kx, ky)
        psi = np.zeros_like(k)
        pos = k > 0
        w = np.sqrt(GRAVITY * k[pos])
        # F(k) = S(ω) dω/dk, dω/dk = g / (2ω); Ψ = F D / k
        travel = math.radians(90.0 - (wind_direction + 180.0))  # downwind, from the +x (east) axis
        theta = np.arctan2(ky[pos], kx[pos])
        psi[pos] = frequency(w) * GRAVITY / (2.0 * w) * spreading(theta, travel,
                                                                   spreading_exponent) / k[pos]
        dk = 2.0 * math.pi / tile
        phase = np.random.default_rng(seed).uniform(0.0, 2.0 * math.pi, (n, n))
        sea = cls(np.sqrt(2.0 * psi) * dk * np.exp(1j * phase), tile)
        sea.spectral_density = psi
        return sea

    # -- the surface ------------------------------------------------------------------------

    def _field(self, factor, t: float) -> np.ndarray:
        n = self.amplitudes.shape[0]
        phase = np.exp(-1j * self.omega * float(t))
        return np.real(np.fft.ifft2(factor * self.amplitudes * phase)) * n * n

    def height(self, t: float = 0.0) -> np.ndarray:
        """Elevation on the tile's samples at time ``t`` [s]: shape (N, N) [m], row ``i`` at
        y = i Δx, column ``j`` at x = j Δx (south to north, west to east)."""
        return self._field(1.0, t)

    def slopes(self, t: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """∂h/∂x and ∂h/∂y of the continuous surface at the samples [-] (spectral derivatives)."""
        return self._field(1j * self.kx, t), self._field(1j * self.ky, t)

    def mesh_slope_variance(self) -> float:
        """Variance of the slopes (∂h/∂x, ∂h/∂y summed) of the mesh's facets [-]: forward
        differences over Δx of the samples (module docstring), from the amplitudes (the
        interference of k and −k left out)."""
        d = self.spacing
        weight = (2.0 * np.sin(0.5 * self.kx * d) / d) ** 2 + (2.0 * np.sin(0.5 * self.ky * d) / d) ** 2
        return float(np.sum(0.5 * np.abs(self.amplitudes) ** 2 * weight))

    def heightfield(self, t: float, size, origin=(0.0, 0.0)) -> Heightfield:
        """The surface at ``t`` [s] over ``size`` (sx, sy) [m] from the south-west corner
        ``origin`` [m], the tile repeated; samples every Δx (sizes rounded to whole samples)."""
        nx, ny = (int(round(s / self.spacing)) + 1 for s in size)
        h = self.height(t)
        n = h.shape[0]
        rows = np.arange(ny - 1, -1, -1) % n  # north-up: row 0 of the heightfield is north
        cols = np.arange(nx) % n
        return Heightfield(h[np.ix_(rows, cols)], origin=origin, spacing=self.spacing)

    def mesh(self, t: float, size, origin=(0.0, 0.0), name: str = "terrain") -> Mesh:
        """:meth:`heightfield` triangulated (:meth:`Heightfield.to_mesh`)."""
        return self.heightfield(t, size, origin).to_mesh(name=name)


def _samples(tile, resolution) -> int:
    if not (np.isfinite(tile) and tile > 0):
        raise ConfigError(f"must be > 0 m, got {tile!r}", key="tile")
    if not (np.isfinite(resolution) and resolution > 0):
        raise ConfigError(f"must be > 0 m, got {resolution!r}", key="resolution")
    n = int(round(tile / resolution))
    if n < 2 or abs(n * resolution - tile) > 1e-6 * tile:
        raise ConfigError(f"the tile ({tile:g} m) must hold a whole number (>= 2) of samples of "
                          f"{resolution:g} m", key="resolution")
    return n


class TiledSea:
    """A :class:`SeaSurface` laid over an extent: the mesh the ray tracer holds, at any time.

    Parameters
    ----------
    surface : SeaSurface or None
        The waves; None for a flat sea (calm, or the far field), which does not move.
    size : array_like
        (sx, sy) extent east and north [m].
    origin : array_like
        South-west corner (x0, y0) [m].
    """

    def __init__(self, surface: SeaSurface | None, size, origin=(0.0, 0.0)):
        self.surface = surface
        self.size = tuple(float(s) for s in size)
        self.origin = tuple(float(o) for o in origin)

    @property
    def moves(self) -> bool:
        """Whether the geometry changes with time (waves in the mesh)."""
        return self.surface is not None and bool(np.any(self.surface.amplitudes))

    def heightfield(self, t: float = 0.0) -> Heightfield:
        """The surface at ``t`` [s] since the start (flat: two samples a side, z = 0)."""
        if self.surface is None:
            return Heightfield(np.zeros((2, 2)), origin=self.origin,
                               spacing=(self.size[0], self.size[1]))
        return self.surface.heightfield(t, self.size, self.origin)

    def mesh(self, t: float = 0.0, name: str = "terrain") -> Mesh:
        """:meth:`heightfield` triangulated."""
        return self.heightfield(t).to_mesh(name=name)

    def mean_level(self) -> Heightfield:
        """The mean sea level, z = 0 over the extent (what objects ``on_ground`` stand on)."""
        return Heightfield(np.zeros((2, 2)), origin=self.origin,
                           spacing=(self.size[0], self.size[1]))
