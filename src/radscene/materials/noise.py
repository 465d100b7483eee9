"""Procedural noise for texture and terrain detail: 2-D gradient (Perlin) noise and its fractal sum.

:func:`gradient_noise` is Perlin's improved noise in two dimensions (quintic fade, gradients on
a lattice hashed by a seeded permutation), scaled so that its values lie in [−1, 1] (the
extreme of 2-D gradient noise with unit gradients is √2/2). :func:`fractal_noise` sums
``octaves`` of it at frequencies ``lacunarity**i / scale`` with amplitudes ``persistence**i`` and
divides by the sum of the amplitudes, so it too lies in [−1, 1]. Both are continuous,
deterministic for a seed, and vectorised over any shape of points.

:class:`NoiseTexture` turns fractal noise into a multiplier field ``1 + amplitude * noise``
(Δρ, Δε or Δτ over the ground) with the :class:`~radscene.materials.Texture` interface
(``sample(x, y)``); :func:`noise_elevation` gives terrain detail in metres.

===========  =====  =======  ====================================================
parameter    unit   default  meaning
===========  =====  =======  ====================================================
scale        [m]    —        wavelength of the first octave (feature size)
amplitude    [-]    —        multiplier swing (texture) or [m] (elevation)
octaves      [-]    4        number of octaves, 1-16
persistence  [-]    0.5      amplitude ratio of successive octaves, (0, 1]
lacunarity   [-]    2.0      frequency ratio of successive octaves, > 1
seed         [-]    0        integer seed of the lattice
===========  =====  =======  ====================================================

Config snippet: ``{type: noise, amplitude: 0.2, scale: 25 m, octaves: 5, seed: 7}``.

Reference
---------
K. Perlin, "Improving noise", ACM Trans. Graph. 21(3), 681-682 (SIGGRAPH 2002),
doi:10.1145/566654.566636.
"""

from __future__ import annotations

import functools
import math
import numbers

import numpy as np

from radscene.errors import ConfigError

__all__ = ["gradient_noise", "fractal_noise", "noise_elevation", "NoiseTexture"]

#: Gradient directions (unit vectors at 45° steps).
_GRADIENTS = np.array(
    [[math.cos(a), math.sin(a)] for a in np.arange(8) * math.pi / 4.0], dtype=float
)
_NORMALISE = math.sqrt(2.0)  # 1 / max|n| of 2-D gradient noise with unit gradients


@functools.lru_cache(maxsize=64)
def _permutation(seed: int) -> np.ndarray:
    perm = np.random.default_rng(seed).permutation(256)
    table = np.concatenate([perm, perm]).astype(np.int64)
    table.setflags(write=False)
    return table


def _fade(t):
    return t * t * t * (t * (t * 6.0 - 15.0) + 10.0)


def _int(value, key, low, high=None):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ConfigError(f"must be an integer; got {value!r}", key=key)
    if value < low or (high is not None and value > high):
        raise ConfigError(f"must be in [{low}, {high}]; got {value}", key=key)
    return int(value)


def _real(value, key, low=None, high=None, low_open=False):
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ConfigError(f"must be a finite number; got {value!r}", key=key)
    value = float(value)
    if low is not None and (value < low or (low_open and value == low)):
        raise ConfigError(f"must be {'>' if low_open else '>='} {low:g}; got {value:g}", key=key)
    if high is not None and value > high:
        raise ConfigError(f"must be <= {high:g}; got {value:g}", key=key)
    return value


def gradient_noise(x, y, seed: int = 0) -> np.ndarray:
    """2-D gradient noise on the unit lattice, in [−1, 1].

    Parameters
    ----------
    x, y : array_like
        Coordinates in lattice units, broadcastable. NaN gives NaN.
    seed : int
        Lattice seed (≥ 0).

    Returns
    -------
    numpy.ndarray
        Values in [−1, 1], 0 at every lattice point.
    """
    seed = _int(seed, "seed", 0)
    perm = _permutation(seed)
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    finite = np.isfinite(x) & np.isfinite(y)
    xs, ys = np.where(finite, x, 0.0), np.where(finite, y, 0.0)
    x0, y0 = np.floor(xs), np.floor(ys)
    fx, fy = xs - x0, ys - y0
    xi = x0.astype(np.int64) & 255
    yi = y0.astype(np.int64) & 255

    def corner(dx, dy):
        h = perm[perm[(xi + dx) & 255] + ((yi + dy) & 255)] & 7
        g = _GRADIENTS[h]
        return g[..., 0] * (fx - dx) + g[..., 1] * (fy - dy)

    u, v = _fade(fx), _fade(fy)
    n00, n10, n01, n11 = corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)
    nx0 = n00 + u * (n10 - n00)
    nx1 = n01 + u * (n11 - n01)
    out = (nx0 + v * (nx1 - nx0)) * _NORMALISE
    return np.where(finite, np.clip(out, -1.0, 1.0), np.nan)


def fractal_noise(
    x,
    y,
    *,
    scale: float,
    octaves: int = 4,
    persistence: float = 0.5,
    lacunarity: float = 2.0,
    seed: int = 0,
) -> np.ndarray:
    """Fractal (fBm) sum of gradient noise over ground coordinates, in [−1, 1].

    Parameters
    ----------
    x, y : array_like
        East and north [m], broadcastable.
    scale : float
        Feature size of the first octave [m], > 0.
    octaves : int
        1-16.
    persistence : float
        Amplitude ratio between octaves, in (0, 1].
    lacunarity : float
        Frequency ratio between octaves, > 1.
    seed : int
        Octave i uses seed ``seed + i``.

    Returns
    -------
    numpy.ndarray

    Examples
    --------
    >>> v = fractal_noise(np.linspace(0, 100, 5), 0.0, scale=20.0, seed=1)
    >>> bool(np.all(np.abs(v) <= 1.0))
    True
    """
    scale = _real(scale, "scale", 0.0, low_open=True)
    octaves = _int(octaves, "octaves", 1, 16)
    persistence = _real(persistence, "persistence", 0.0, 1.0, low_open=True)
    lacunarity = _real(lacunarity, "lacunarity", 1.0, low_open=True)
    seed = _int(seed, "seed", 0)
    x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    total = np.zeros(x.shape)
    norm = 0.0
    for i in range(octaves):
        f = lacunarity**i / scale
        a = persistence**i
        total = total + a * gradient_noise(x * f, y * f, seed=seed + i)
        norm += a
    return total / norm


def noise_elevation(x, y, *, amplitude: float, scale: float, **kwargs) -> np.ndarray:
    """Terrain detail: ``amplitude * fractal_noise(x, y, scale=scale, ...)`` [m].

    Parameters
    ----------
    x, y : array_like
        [m].
    amplitude : float
        Largest elevation offset [m], ≥ 0.
    scale : float
        Feature size [m].
    **kwargs
        ``octaves``, ``persistence``, ``lacunarity``, ``seed`` of :func:`fractal_noise`.

    Returns
    -------
    numpy.ndarray
        Elevation offsets in [−amplitude, amplitude] [m].
    """
    amplitude = _real(amplitude, "amplitude", 0.0)
    return amplitude * fractal_noise(x, y, scale=scale, **kwargs)


class NoiseTexture:
    """A procedural multiplier field ``1 + amplitude * fractal_noise`` over the ground plane.

    Same interface as :class:`~radscene.materials.Texture` (:meth:`sample`); it covers the
    whole plane.

    Parameters
    ----------
    amplitude : float
        Multiplier swing [-], in [0, 1] so the multiplier stays in [1 − a, 1 + a] ⊂ [0, 2].
    scale : float
        Feature size [m].
    octaves, persistence, lacunarity, seed
        See :func:`fractal_noise`.
    name : str, optional

    Examples
    --------
    >>> t = NoiseTexture(amplitude=0.2, scale=10.0)
    >>> m = t.sample(np.arange(50.0), 3.0)
    >>> bool(m.min() >= 0.8 and m.max() <= 1.2)
    True
    """

    def __init__(self, amplitude: float, scale: float, octaves: int = 4, persistence: float = 0.5,
                 lacunarity: float = 2.0, seed: int = 0, name: str = ""):
        key = name or "noise"
        self.amplitude = _real(amplitude, f"{key}.amplitude", 0.0, 1.0)
        self._kwargs = {
            "scale": _real(scale, f"{key}.scale", 0.0, low_open=True),
            "octaves": _int(octaves, f"{key}.octaves", 1, 16),
            "persistence": _real(persistence, f"{key}.persistence", 0.0, 1.0, low_open=True),
            "lacunarity": _real(lacunarity, f"{key}.lacunarity", 1.0, low_open=True),
            "seed": _int(seed, f"{key}.seed", 0),
        }
        self.name = str(name)

    @property
    def parameters(self) -> dict:
        """scale [m], octaves, persistence, lacunarity, seed."""
        return dict(self._kwargs)

    def sample(self, x, y) -> np.ndarray:
        """Multiplier at ground points [-]; NaN gives NaN.

        Parameters
        ----------
        x, y : array_like
            [m], broadcastable.
        """
        return 1.0 + self.amplitude * fractal_noise(x, y, **self._kwargs)

    def rasterize(self, size, shape, origin=(0.0, 0.0), wrap: bool = False):
        """A :class:`~radscene.materials.Texture` image of this field.

        Parameters
        ----------
        size : (float, float)
            (width, height) [m].
        shape : (int, int)
            (rows, cols) [px].
        origin : (float, float)
            South-west corner [m].
        wrap : bool
            Passed to the Texture.

        Returns
        -------
        Texture
            Pixel centres sampled (row 0 north).
        """
        from radscene.materials.texture import Texture

        rows, cols = (_int(v, "shape", 1) for v in shape)
        w, h = float(size[0]), float(size[1])
        x = origin[0] + (np.arange(cols) + 0.5) * w / cols
        y = origin[1] + h - (np.arange(rows) + 0.5) * h / rows
        values = self.sample(x[None, :], y[:, None])
        return Texture(values, size=(w, h), origin=origin, wrap=wrap, name=self.name or "noise")

    def __repr__(self) -> str:
        return f"NoiseTexture(amplitude={self.amplitude:g}, {self._kwargs})"
