"""Simple closed and flat shapes as meshes: box, cylinder, plate.

Each stands on (or lies in) the plane z = 0, centred on the z axis, with faces wound
counter-clockwise seen from outside so that their right-hand-rule normals point outward.
Place them with :meth:`radscene.geometry.Mesh.transformed`.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.mesh import Mesh

__all__ = ["box", "cylinder", "plate"]


def _positive(value, key: str) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ConfigError(f"must be a positive number [m], got {value!r}", key=key) from None
    if not np.isfinite(v) or v <= 0.0:
        raise ConfigError(f"must be a positive finite number [m], got {value!r}", key=key)
    return v


def box(size=(1.0, 1.0, 1.0), name: str = "box") -> Mesh:
    """A rectangular box, base on z = 0, centred on x = y = 0, 12 outward-facing triangles.

    Parameters
    ----------
    size : array_like
        Edge lengths ``(sx, sy, sz)`` along east, north, up [m]; each > 0.
    name : str
        Mesh name.

    Returns
    -------
    Mesh
        8 vertices, 12 faces; faces ``2k, 2k+1`` form side ``k`` in the order
        bottom (-z), top (+z), south (-y), north (+y), west (-x), east (+x).

    Examples
    --------
    >>> float(box((2.0, 4.0, 1.0)).area.sum())
    28.0
    """
    try:
        sx, sy, sz = (_positive(s, f"size[{k}]") for k, s in enumerate(size))
    except (TypeError, ValueError) as exc:
        if isinstance(exc, ConfigError):
            raise
        raise ConfigError(f"must be three edge lengths (sx, sy, sz) [m], got {size!r}",
                          key="size") from None
    x, y = 0.5 * sx, 0.5 * sy
    vertices = np.array([
        [-x, -y, 0.0], [x, -y, 0.0], [x, y, 0.0], [-x, y, 0.0],   # 0-3 bottom, CCW from above
        [-x, -y, sz], [x, -y, sz], [x, y, sz], [-x, y, sz],       # 4-7 top
    ])
    faces = np.array([
        [0, 2, 1], [0, 3, 2],  # bottom, normal -z
        [4, 5, 6], [4, 6, 7],  # top, +z
        [0, 1, 5], [0, 5, 4],  # south, -y
        [2, 3, 7], [2, 7, 6],  # north, +y
        [3, 0, 4], [3, 4, 7],  # west, -x
        [1, 2, 6], [1, 6, 5],  # east, +x
    ])
    return Mesh(vertices, faces, name)


def cylinder(radius: float, height: float, sections: int = 32, name: str = "cylinder") -> Mesh:
    """A capped right circular cylinder, base on z = 0, axis along +z through x = y = 0.

    The circle is approximated by a regular polygon with ``sections`` vertices on the radius
    (so the polygon lies inside the true circle).

    Parameters
    ----------
    radius : float
        Radius of the vertices' circle [m], > 0.
    height : float
        Height [m], > 0.
    sections : int
        Number of polygon sides, >= 3.
    name : str
        Mesh name.

    Returns
    -------
    Mesh
        ``2 * sections + 2`` vertices and ``4 * sections`` faces: the side (``2 * sections``),
        then the bottom cap, then the top cap (``sections`` each).
    """
    r = _positive(radius, "radius")
    h = _positive(height, "height")
    if isinstance(sections, bool) or not isinstance(sections, int | np.integer) or sections < 3:
        raise ConfigError(f"must be an integer >= 3, got {sections!r}", key="sections")
    n = int(sections)
    phi = 2.0 * np.pi * np.arange(n) / n
    ring = np.column_stack([r * np.cos(phi), r * np.sin(phi)])  # counter-clockwise from above
    vertices = np.vstack([
        np.column_stack([ring, np.zeros(n)]),  # 0 .. n-1 bottom ring
        np.column_stack([ring, np.full(n, h)]),  # n .. 2n-1 top ring
        [[0.0, 0.0, 0.0], [0.0, 0.0, h]],  # 2n bottom centre, 2n+1 top centre
    ])
    i = np.arange(n)
    j = (i + 1) % n
    side = np.concatenate([np.column_stack([i, j, n + j]), np.column_stack([i, n + j, n + i])])
    bottom = np.column_stack([np.full(n, 2 * n), j, i])
    top = np.column_stack([np.full(n, 2 * n + 1), n + i, n + j])
    return Mesh(vertices, np.concatenate([side, bottom, top]), name)


def plate(width: float, length: float, name: str = "plate") -> Mesh:
    """A flat rectangle in the plane z = 0, centred on the origin, normal +z (two triangles).

    Parameters
    ----------
    width : float
        Extent along x (east) [m], > 0.
    length : float
        Extent along y (north) [m], > 0.
    name : str
        Mesh name.

    Returns
    -------
    Mesh
        4 vertices, 2 faces with normal +z.
    """
    x = 0.5 * _positive(width, "width")
    y = 0.5 * _positive(length, "length")
    vertices = np.array([[-x, -y, 0.0], [x, -y, 0.0], [x, y, 0.0], [-x, y, 0.0]])
    return Mesh(vertices, np.array([[0, 1, 2], [0, 2, 3]]), name)
