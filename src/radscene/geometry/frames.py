"""Frames and angle conventions.

radscene's local frame is east-north-up (x east, y north, z up), lengths in metres. A direction
is given by its zenith angle (from the local vertical, +z) and its azimuth (clockwise from north,
+y, towards east, +x), both in degrees at every public interface.

A direction *to* a source (the sun, a sky patch) and a direction *of travel* of a ray differ by a
sign; functions here speak of unit vectors and say which they mean.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "direction_from_angles",
    "angles_from_direction",
    "orthonormal_basis",
    "to_world",
    "normalize",
]


def direction_from_angles(zenith, azimuth) -> np.ndarray:
    """Unit vector in the east-north-up frame from zenith and azimuth angles.

    Parameters
    ----------
    zenith : array_like
        Angle from the local vertical [deg].
    azimuth : array_like
        Angle clockwise from north [deg].

    Returns
    -------
    numpy.ndarray
        Unit vectors, shape ``broadcast(zenith, azimuth).shape + (3,)`` [-].

    Notes
    -----
    .. math:: \\mathbf{d} = (\\sin\\theta\\sin\\phi,\\ \\sin\\theta\\cos\\phi,\\ \\cos\\theta)

    Examples
    --------
    >>> direction_from_angles(90.0, 90.0).round(12)  # horizontal, towards east
    array([1., 0., 0.])
    """
    zen = np.radians(np.asarray(zenith, dtype=float))
    azi = np.radians(np.asarray(azimuth, dtype=float))
    zen, azi = np.broadcast_arrays(zen, azi)
    sin_z = np.sin(zen)
    return np.stack([sin_z * np.sin(azi), sin_z * np.cos(azi), np.cos(zen)], axis=-1)


def angles_from_direction(direction) -> tuple[np.ndarray, np.ndarray]:
    """Zenith and azimuth [deg] of unit vectors in the east-north-up frame.

    Parameters
    ----------
    direction : array_like
        Vectors, shape ``(..., 3)``; they need not be normalised.

    Returns
    -------
    zenith, azimuth : numpy.ndarray
        Zenith angle in [0, 180] [deg] and azimuth in [0, 360) clockwise from north [deg].

    Examples
    --------
    >>> [round(float(a), 9) for a in angles_from_direction([0.0, -1.0, 1.0])]
    [45.0, 180.0]
    """
    d = np.asarray(direction, dtype=float)
    norm = np.linalg.norm(d, axis=-1)
    zenith = np.degrees(np.arccos(np.clip(d[..., 2] / norm, -1.0, 1.0)))
    azimuth = np.degrees(np.arctan2(d[..., 0], d[..., 1])) % 360.0
    return zenith, azimuth


def normalize(vectors) -> np.ndarray:
    """Vectors scaled to unit length along the last axis [-]."""
    v = np.asarray(vectors, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def orthonormal_basis(axis) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors that complete ``axis`` to a right-handed orthonormal frame.

    Uses the branchless construction of Duff et al. (2017), "Building an Orthonormal Basis,
    Revisited", JCGT 6(1), https://jcgt.org/published/0006/01/01/.

    Parameters
    ----------
    axis : array_like
        Unit vectors, shape ``(..., 3)``.

    Returns
    -------
    tangent, bitangent : numpy.ndarray
        Shape ``(..., 3)`` each, with ``tangent × bitangent = axis``.
    """
    n = np.asarray(axis, dtype=float)
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    sign = np.where(z >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    tangent = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    bitangent = np.stack([b, sign + y * y * a, -y], axis=-1)
    return tangent, bitangent


def to_world(local, axis) -> np.ndarray:
    """Rotate directions given in a frame whose +z is ``axis`` into the world frame.

    Parameters
    ----------
    local : array_like
        Directions in the local frame, shape ``(..., 3)``.
    axis : array_like
        The local frame's +z in world coordinates, unit vectors broadcastable to ``local``.

    Returns
    -------
    numpy.ndarray
        World directions, shape of the broadcast of ``local`` and ``axis``.
    """
    local = np.asarray(local, dtype=float)
    axis = np.asarray(axis, dtype=float)
    t, b = orthonormal_basis(axis)
    return local[..., 0:1] * t + local[..., 1:2] * b + local[..., 2:3] * axis
