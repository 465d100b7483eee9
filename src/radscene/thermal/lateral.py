"""Lateral conduction between neighbouring surface elements: conductance builders and the
coupled solve of the surface nodes.

Two elements i and j that share a boundary of length L_ij exchange G_ij (T_i − T_j) [W] through
a conducting layer of conductivity k and thickness t, with

.. math:: G_{ij} = \\frac{k\\,t\\,L_{ij}}{d_{ij}}

d_ij the distance between their centres across the boundary. Where k t differs between the two
sides the two half-paths are in series (the harmonic mean of Patankar 1980, §4.2.3):
G_ij = L_ij / (d_i/(k t)_i + d_j/(k t)_j), d_i the distance from the centre of i to the
boundary.

In the heat balance (``HeatBalance(..., lateral=G, area=A)``) the lateral heat enters and
leaves an element at its surface node, and the element's stack carries it downwards: the
surface temperatures of all elements are solved together, backward Euler, with the stacks
eliminated (Newton on the coupled system, :func:`coupled_surface_temperature`) — no operator
splitting. This is exact for a conducting layer thinner than its penetration depth over a step
(sheets, plates, skins), and lumps the lateral flow at the surface for thicker layers.

References
----------
Patankar, S. V. (1980). *Numerical Heat Transfer and Fluid Flow*. Washington: Hemisphere,
§4.2.3 (interface conductivity: the harmonic mean).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from radscene.errors import ConfigError, RadsceneError

_DIRECT = 5000  # elements up to which the Newton updates are solved directly

__all__ = [
    "grid_conductance",
    "mesh_conductance",
    "check_conductance",
    "laplacian",
    "coupled_surface_temperature",
]


def _series(length, d_i, kt_i, d_j, kt_j):
    return length / (d_i / kt_i + d_j / kt_j)


def _positive_field(value, shape, key):
    try:
        value = np.broadcast_to(np.asarray(value, float), shape)
    except ValueError:
        raise ConfigError(f"shape {np.shape(value)} does not broadcast to {shape}", key=key) from None
    if not np.all(np.isfinite(value) & (value > 0)):
        raise ConfigError("must be finite and > 0", key=key)
    return value


def grid_conductance(shape, spacing, conductivity, thickness):
    """Lateral conductances of a grid of rectangular cells, 4-neighbours [W K-1].

    Parameters
    ----------
    shape : (int, int)
        (n_rows, n_columns); cells are numbered row by row (C order).
    spacing : float or (float, float)
        Cell size (along rows' axis, along columns' axis), (dy, dx) [m].
    conductivity : array_like
        k [W m-1 K-1], scalar or per cell (``shape``).
    thickness : array_like
        t of the conducting layer [m], scalar or per cell.

    Returns
    -------
    scipy.sparse.csr_array, (n, n)
        G, symmetric, zero diagonal, n = n_rows · n_columns.

    Examples
    --------
    >>> g = grid_conductance((1, 3), 0.5, 50.0, 0.01)
    >>> g.toarray().round(6).tolist()
    [[0.0, 0.5, 0.0], [0.5, 0.0, 0.5], [0.0, 0.5, 0.0]]
    """
    shape = tuple(int(s) for s in shape)
    if len(shape) != 2 or min(shape) < 1:
        raise ConfigError(f"expected (n_rows, n_columns) >= 1; got {shape!r}", key="shape")
    dy, dx = _positive_field(spacing, (2,), "spacing")
    kt = _positive_field(conductivity, shape, "conductivity") * _positive_field(thickness, shape, "thickness")
    index = np.arange(shape[0] * shape[1]).reshape(shape)
    rows, cols, values = [], [], []
    for axis, (length, distance) in enumerate(((dx, dy), (dy, dx))):
        a = index.take(np.arange(shape[axis] - 1), axis=axis).ravel()
        b = index.take(np.arange(1, shape[axis]), axis=axis).ravel()
        ka, kb = kt.ravel()[a], kt.ravel()[b]
        g = _series(length, distance / 2, ka, distance / 2, kb)
        rows += [a, b]
        cols += [b, a]
        values += [g, g]
    n = index.size
    return sp.csr_array((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))


def mesh_conductance(vertices, faces, face_element, conductivity, thickness, n_elements=None):
    """Lateral conductances of elements made of triangles that share edges [W K-1].

    Parameters
    ----------
    vertices : array_like, (n_vertices, 3)
        [m].
    faces : array_like of int, (n_faces, 3)
        Triangles; neighbours must share vertex indices along their common edge (merge
        duplicated vertices first).
    face_element : array_like of int, (n_faces,)
        The element each face belongs to.
    conductivity, thickness : array_like
        k [W m-1 K-1] and t [m] per element (n_elements,) or scalar.
    n_elements : int, optional
        Default ``face_element.max() + 1``.

    Returns
    -------
    scipy.sparse.csr_array, (n_elements, n_elements)
        G, symmetric, zero diagonal.

    Notes
    -----
    Each edge shared by faces of two different elements contributes
    L / (d_i/(k t)_i + d_j/(k t)_j), with L the edge's length and d_i the distance from the
    centroid of element i (area-weighted over its faces) to the edge's midpoint, so that the
    path folds over the edge of a box. Edges inside an element contribute nothing.

    Examples
    --------
    >>> v = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0], [2, 1, 0]]
    >>> f = [[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]]      # two unit squares
    >>> mesh_conductance(v, f, [0, 0, 1, 1], 50.0, 0.01).toarray().round(6).tolist()
    [[0.0, 0.5], [0.5, 0.0]]
    """
    import trimesh

    vertices = np.asarray(vertices, float)
    faces = np.asarray(faces)
    face_element = np.asarray(face_element)
    if face_element.shape != (faces.shape[0],) or not np.issubdtype(face_element.dtype, np.integer) or face_element.min() < 0:
        raise ConfigError(f"expected {faces.shape[0]} integer element indices >= 0, one per face", key="face_element")
    n = int(face_element.max()) + 1 if n_elements is None else int(n_elements)
    if face_element.max() >= n:
        raise ConfigError(f"indices must lie in [0, {n - 1}]", key="face_element")
    kt = _positive_field(conductivity, (n,), "conductivity") * _positive_field(thickness, (n,), "thickness")
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    area = mesh.area_faces
    element_area = np.bincount(face_element, weights=area, minlength=n)
    centroid = np.stack(
        [np.bincount(face_element, weights=area * mesh.triangles_center[:, c], minlength=n) for c in range(3)], axis=1
    ) / np.where(element_area > 0, element_area, 1.0)[:, None]
    pairs, edges = mesh.face_adjacency, mesh.face_adjacency_edges
    ei, ej = face_element[pairs[:, 0]], face_element[pairs[:, 1]]
    keep = ei != ej
    ei, ej, edges = ei[keep], ej[keep], edges[keep]
    p, q = vertices[edges[:, 0]], vertices[edges[:, 1]]
    middle = 0.5 * (p + q)
    length = np.linalg.norm(q - p, axis=1)
    di = np.linalg.norm(centroid[ei] - middle, axis=1)
    dj = np.linalg.norm(centroid[ej] - middle, axis=1)
    g = _series(length, di, kt[ei], dj, kt[ej])
    out = sp.csr_array((np.concatenate([g, g]), (np.concatenate([ei, ej]), np.concatenate([ej, ei]))), shape=(n, n))
    out.sum_duplicates()
    return out


def check_conductance(conductance, n_elements, key="lateral"):
    """Validate a lateral conductance matrix: (n × n), finite, ≥ 0, symmetric. Returns CSR
    with its diagonal removed."""
    try:
        g = sp.csr_array(conductance, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ConfigError(f"expected a sparse (n_elements x n_elements) conductance matrix [W K-1]: {exc}", key=key) from None
    if g.shape != (n_elements, n_elements):
        raise ConfigError(f"shape {g.shape} is not (n_elements, n_elements) = {(n_elements, n_elements)}", key=key)
    g.setdiag(0.0)
    g.eliminate_zeros()
    if not np.all(np.isfinite(g.data)) or np.any(g.data < 0):
        raise ConfigError("conductances must be finite and >= 0 W K-1", key=key)
    scale = float(np.max(g.data, initial=0.0))
    if abs(g - g.T).max() > 1e-12 * scale:
        raise ConfigError("the conductance matrix must be symmetric (G_ij = G_ji)", key=key)
    return g


def laplacian(conductance):
    """L = diag(Σ_j G_ij) − G [W K-1], so that (L T)_i = Σ_j G_ij (T_i − T_j) leaves element i."""
    g = sp.csr_array(conductance)
    return (sp.diags_array(np.asarray(g.sum(axis=1)).ravel()) - g).tocsr()


def coupled_surface_temperature(constant, slope, emissivity, laplacian_matrix, area, start, tolerance=1e-9, max_iterations=50):
    """Surface temperatures of elements coupled by lateral conduction, by Newton's method.

    Solves, for every element i,

    .. math:: a_i\\,(c_i - \\varepsilon_i\\sigma T_i^4 - m_i T_i) - (L T)_i = 0

    Parameters
    ----------
    constant, slope, emissivity : ndarray, (n,)
        c [W m-2], m > 0 [W m-2 K-1], ε [-] of each element's surface equation
        (:func:`radscene.thermal.balance.solve_surface_temperature`).
    laplacian_matrix : scipy.sparse matrix, (n, n)
        L of :func:`laplacian` [W K-1].
    area : ndarray, (n,)
        a [m2].
    start : ndarray, (n,)
        First guess [K] (e.g. each element's uncoupled root).
    tolerance : float, optional
        [K] on the largest update.
    max_iterations : int, optional

    Returns
    -------
    ndarray, (n,)
        T [K].

    Notes
    -----
    The Jacobian diag(a (4εσT³ + m)) + L is symmetric positive definite (an M-matrix); each
    Newton update is solved directly (SuperLU) up to 5000 elements, above by conjugate
    gradients preconditioned by its diagonal. The residual
    is concave in T, so the iterates converge monotonically after the first.
    """
    from radscene.thermal.radiation import SIGMA

    es = np.asarray(emissivity, float) * SIGMA
    lap = sp.csr_array(laplacian_matrix)
    t = np.array(start, float)
    for _ in range(max_iterations):
        t3 = t**3
        residual = area * (constant - es * t3 * t - slope * t) - lap @ t
        diagonal = area * (4.0 * es * t3 + slope)
        jacobian = lap + sp.diags_array(diagonal)
        inverse = sp.diags_array(1.0 / (diagonal + lap.diagonal())) if t.size > _DIRECT else None
        if t.size <= _DIRECT:
            dt = spla.spsolve(jacobian.tocsc(), residual)
        else:
            dt, info = spla.cg(jacobian, residual, rtol=1e-12, atol=0.0, M=inverse, maxiter=10 * t.size + 100)
            if info != 0:
                raise RadsceneError(f"lateral conduction: the linear solve did not converge (cg info {info})")
        t += dt
        if np.max(np.abs(dt), initial=0.0) < tolerance:
            return t
    raise RadsceneError(f"lateral conduction: Newton did not converge in {max_iterations} iterations")
