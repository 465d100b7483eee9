"""Temperatures across the terrain's thermal cells: a limited, mean-preserving linear
reconstruction from the solved cell temperatures, so that a rendered terrain varies smoothly
from cell to cell instead of showing the cells as blocks.

Each terrain element (the faces of one material in one cell of the thermal grid) gets a linear
field about its area centroid c,

.. math::

    T(x, y) = T_e + s_x (x - c_x) + s_y (y - c_y),

whose area mean over the element is T_e exactly (the mean of a linear function over triangles
is its value at their area centroid). The slopes come from the neighbouring elements of the
same material in the four grid directions, limited by the monotonized-central limiter (van Leer
1977), one axis at a time:

.. math::

    s = \\operatorname{minmod}\\left(2\\Delta_-, \\tfrac{1}{2}(\\Delta_- + \\Delta_+), 2\\Delta_+\\right),

Δ∓ the one-sided differences [K m-1] towards the lower and upper neighbour; with one neighbour
the slope is that one-sided difference, with none it is 0. The gradient is then scaled by the
largest φ ∈ [0, 1] that keeps the field at every corner of the element's faces within the
range of the element's and its neighbours' temperatures (Barth & Jespersen 1989), which the
axis-by-axis limiter alone does not ensure at corners. Beyond the grid's edge the range takes
the linear continuation of the element and its opposite neighbour (2 T_e − T_opposite), so
that a gradient runs on to the scene's edge; beyond an edge between materials it does not, so
there the field stays within the values of the element's own material. A field linear
across the cells of a flat terrain is reproduced exactly (φ = 1) and is continuous at the cell
edges; at an extremum (a cell cooler or warmer than its neighbours, such as a shadow one cell
wide) the slope is 0, so the reconstruction makes no new extrema and keeps the edge of a
shadow sharp. Faces of objects keep their element's temperature.

References
----------
Barth, T. J. and Jespersen, D. C. (1989), The design and application of upwind schemes on
unstructured meshes, AIAA paper 89-0366, doi:10.2514/6.1989-366.

van Leer, B. (1977), Towards the ultimate conservative difference scheme III. Upstream-centered
finite-difference schemes for ideal compressible flow, *J. Comput. Phys.* 23, 263-275,
doi:10.1016/0021-9991(77)90094-8.
"""

from __future__ import annotations

import numpy as np

__all__ = ["corner_temperature", "limited_slopes", "terrain_neighbours"]


def terrain_neighbours(elements):
    """The neighbour of each terrain element in the four grid directions, same material.

    Parameters
    ----------
    elements : radscene.thermal.elements.SurfaceElements

    Returns
    -------
    numpy.ndarray of int, (n_elements, 4)
        Element index of the west, east, north and south neighbour (columns - 1, + 1, rows
        - 1, + 1 of the grid) with the same material; -2 beyond the grid's edge, -1 where the
        neighbouring cell has no element of that material or the element is not a terrain cell.
    """
    n = elements.size
    out = np.full((n, 4), -1, dtype=np.int64)
    if elements.grid_shape is None or n == 0:
        return out
    rows, cols = elements.grid_shape
    terrain = np.flatnonzero(elements.cell >= 0)
    if terrain.size == 0:
        return out
    n_mat = int(elements.material.max()) + 1
    row, col = np.divmod(elements.cell[terrain], cols)
    mat = elements.material[terrain]
    key = elements.cell[terrain] * n_mat + mat
    order = np.argsort(key)
    sorted_key = key[order]
    for j, (dr, dc) in enumerate(((0, -1), (0, 1), (-1, 0), (1, 0))):
        r, c = row + dr, col + dc
        inside = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
        query = (r * cols + c) * n_mat + mat
        at = np.minimum(np.searchsorted(sorted_key, query), sorted_key.size - 1)
        found = inside & (sorted_key[at] == query)
        out[terrain[found], j] = terrain[order[at[found]]]
        out[terrain[~inside], j] = -2
    return out


def _minmod3(a, b, c):
    same = ((a > 0) & (b > 0) & (c > 0)) | ((a < 0) & (b < 0) & (c < 0))
    smallest = np.minimum(np.minimum(np.abs(a), np.abs(b)), np.abs(c))
    return np.where(same, np.sign(b) * smallest, 0.0)


def limited_slopes(values, positions, neighbours):
    """Monotonized-central limited slopes of element values along x (east) and y (north).

    Parameters
    ----------
    values : array_like, (n,)
        Element temperatures [K].
    positions : array_like, (n, 3)
        Element area centroids [m].
    neighbours : array_like of int, (n, 4)
        From :func:`terrain_neighbours`.

    Returns
    -------
    numpy.ndarray, (n, 2)
        (s_x, s_y) [K m-1]; 0 for elements without neighbours.
    """
    values = np.asarray(values, float)
    positions = np.asarray(positions, float)
    neighbours = np.asarray(neighbours)
    out = np.zeros((values.size, 2))
    for axis, (low, high, coord) in enumerate(((0, 1, 0), (3, 2, 1))):  # x: west/east; y: south/north
        lo, hi = neighbours[:, low], neighbours[:, high]
        has_lo, has_hi = lo >= 0, hi >= 0
        x = positions[:, coord]
        d_lo = np.zeros(values.size)
        d_hi = np.zeros(values.size)
        i = np.flatnonzero(has_lo)
        d_lo[i] = (values[i] - values[lo[i]]) / (x[i] - positions[lo[i], coord])
        i = np.flatnonzero(has_hi)
        d_hi[i] = (values[hi[i]] - values[i]) / (positions[hi[i], coord] - x[i])
        both = has_lo & has_hi
        slope = np.where(has_lo, d_lo, 0.0) + np.where(has_hi, d_hi, 0.0)  # the one side there is
        slope[both] = _minmod3(2.0 * d_lo[both], 0.5 * (d_lo[both] + d_hi[both]), 2.0 * d_hi[both])
        out[:, axis] = slope
    return out


def corner_temperature(elements, element_values, fixed, neighbours=None):
    """The temperature at the three corners of every face: the terrain's reconstructed linear
    field, each object facet's element temperature, and ``fixed`` for faces not solved.

    Parameters
    ----------
    elements : radscene.thermal.elements.SurfaceElements
    element_values : array_like, (n_elements,)
        Solved temperature of each element [K].
    fixed : array_like, (n_faces,)
        Temperature of the faces without an element [K].
    neighbours : array_like of int, (n_elements, 4), optional
        From :func:`terrain_neighbours` (computed when not given).

    Returns
    -------
    numpy.ndarray, (n_faces, 3)
        [K], corners in the order of the faces' vertices. The area mean over each element's
        faces is the element's temperature (to rounding).

    Examples
    --------
    A linear gradient across two cells is reproduced and meets at their shared edge:

    >>> import numpy as np
    >>> from radscene.geometry import Heightfield
    >>> from radscene.thermal.elements import build_elements
    >>> hf = Heightfield(np.zeros((2, 3)), spacing=(1.0, 1.0), origin=(0.0, 0.0))
    >>> mesh = hf.to_mesh()
    >>> el = build_elements([mesh], [np.zeros(len(mesh.faces), int)], [True], terrain=0, heightfield=hf)
    >>> t = 300.0 + el.position[:, 0]  # 1 K per metre eastwards
    >>> c = corner_temperature(el, t, np.zeros(len(mesh.faces)))
    >>> bool(np.allclose(c, 300.0 + el.face_vertices[:, :, 0]))
    True
    """
    values = np.asarray(element_values, float)
    if neighbours is None:
        neighbours = terrain_neighbours(elements)
    out = np.repeat(np.asarray(fixed, float)[:, None], 3, axis=1)
    solved = np.flatnonzero(elements.face_element >= 0)
    e = elements.face_element[solved]
    slope = limited_slopes(values, elements.position, neighbours)
    offset = elements.face_vertices[solved, :, :2] - elements.position[e][:, None, :2]
    delta = np.einsum("fkd,fd->fk", offset, slope[e])  # corner minus element value [K]
    around = np.where(neighbours >= 0, values[np.maximum(neighbours, 0)], values[:, None])
    for side, opposite in ((0, 1), (1, 0), (2, 3), (3, 2)):  # beyond the grid: the linear continuation
        ghost = (neighbours[:, side] == -2) & (neighbours[:, opposite] >= 0)
        around[ghost, side] = 2.0 * values[ghost] - values[neighbours[ghost, opposite]]
    up = np.maximum(around.max(axis=1), values) - values  # room above and below [K], >= 0
    down = np.minimum(around.min(axis=1), values) - values
    ratio = np.ones_like(delta)
    rise, fall = delta > 0, delta < 0
    ratio[rise] = (up[e][:, None] * np.ones_like(delta))[rise] / delta[rise]
    ratio[fall] = (down[e][:, None] * np.ones_like(delta))[fall] / delta[fall]
    phi = np.ones(values.size)
    np.minimum.at(phi, e, np.minimum(ratio.min(axis=1), 1.0))
    out[solved] = values[e][:, None] + phi[e][:, None] * delta
    return out
