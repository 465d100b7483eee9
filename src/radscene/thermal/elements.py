"""Surface elements of the heat balance, built from the faces of a scene's meshes.

An element is a piece of surface with one material stack, one orientation and one temperature:
a terrain cell of the thermal grid (the terrain's faces grouped by cell of ``resolution`` and by
material), or one facet of an object (the faces of one material and one orientation, grouped,
so a box has six elements of two faces each, and a curved mesh one element per face).
Every face of the scene knows its element (``face_element``), so the renderer reads the solved
temperature of the face a ray hits, and the ray engine's answers per face (shadow, hits of
hemisphere rays) fold into per-element ones by the faces' area weights.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radscene.errors import ConfigError

__all__ = ["SurfaceElements", "build_elements"]

@dataclass(frozen=True)
class SurfaceElements:
    """The elements of a scene and the faces they are made of.

    Attributes
    ----------
    position : ndarray, (n, 3)
        Area-weighted centroid of each element [m].
    normal : ndarray, (n, 3)
        Unit area-weighted mean normal [-].
    area : ndarray, (n,)
        [m2].
    material : ndarray of int, (n,)
        Index of the element's material (the scene's material list).
    object : ndarray of int, (n,)
        Index of the object (mesh) the element belongs to.
    face_element : ndarray of int, (n_faces,)
        Element of every face of the meshes, in the order of the meshes concatenated; -1 for a
        face that is not solved (an object that keeps a fixed temperature).
    face_weight : ndarray, (n_faces,)
        Share of its element's area each face has (0 for faces without an element) [-].
    face_centroid, face_normal : ndarray, (n_faces, 3)
        Of every face [m], [-].
    face_vertices : ndarray, (n_faces, 3, 3)
        The corners of every face [m].
    face_area : ndarray, (n_faces,)
        [m2].
    cell : ndarray of int, (n,)
        Thermal-grid cell of terrain elements (row-major over ``grid_shape``); -1 for facets.
    grid_shape : tuple of int or None
        (rows, columns) of the terrain's thermal grid, rows from north to south.
    """

    position: np.ndarray
    normal: np.ndarray
    area: np.ndarray
    material: np.ndarray
    object: np.ndarray
    face_element: np.ndarray
    face_weight: np.ndarray
    face_centroid: np.ndarray
    face_normal: np.ndarray
    face_vertices: np.ndarray
    face_area: np.ndarray
    cell: np.ndarray
    grid_shape: tuple | None = None

    @property
    def size(self) -> int:
        """Number of elements."""
        return int(self.area.size)

    def per_element(self, face_values):
        """Area-weighted mean over each element's faces of per-face values (leading axis faces).

        Parameters
        ----------
        face_values : array_like, (n_faces, ...)

        Returns
        -------
        ndarray, (n_elements, ...)
        """
        values = np.asarray(face_values, float)
        solved = self.face_element >= 0
        flat = values[solved].reshape(int(solved.sum()), -1) * self.face_weight[solved, None]
        out = np.stack([np.bincount(self.face_element[solved], weights=flat[:, j], minlength=self.size)
                        for j in range(flat.shape[1])], axis=1)
        return out.reshape((self.size,) + values.shape[1:])

    def face_values(self, element_values, fixed):
        """Per-face values from per-element ones; faces without an element take ``fixed``.

        Parameters
        ----------
        element_values : array_like, (n_elements,)
        fixed : array_like, (n_faces,)

        Returns
        -------
        ndarray, (n_faces,)
        """
        out = np.array(fixed, float, copy=True)
        solved = self.face_element >= 0
        out[solved] = np.asarray(element_values, float)[self.face_element[solved]]
        return out


def _group(keys):
    """Group index of each row of an integer key array, groups in order of first appearance."""
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    return rank[inverse.ravel()]


def _orientation_classes(normals):
    """Class of each unit normal: coplanar facets (normals equal to 1e-5) share a class."""
    return _group(np.rint(np.asarray(normals) * 1e5).astype(np.int64))


def build_elements(meshes, face_material, solved, *, terrain=None, heightfield=None, resolution=None):
    """The surface elements of a scene's meshes.

    Parameters
    ----------
    meshes : sequence of radscene.geometry.Mesh
        Every mesh of the scene, in the ray tracer's order.
    face_material : sequence of ndarray of int
        Material index of each face, one array per mesh.
    solved : sequence of bool or of bool arrays
        Whether each mesh's faces are solved (False: the face keeps a fixed temperature), one
        flag or one array of flags per face for each mesh.
    terrain : int, optional
        Index of the terrain mesh; its faces are grouped on the thermal grid.
    heightfield : radscene.geometry.Heightfield, optional
        The terrain's heightfield (needed with ``terrain``).
    resolution : float, optional
        Cell size of the terrain's thermal grid [m]; default the heightfield's spacing (one
        element per cell and material).

    Returns
    -------
    SurfaceElements

    Raises
    ------
    ConfigError
        A resolution ≤ 0, or finer than the terrain's own spacing.
    """
    meshes = list(meshes)
    centroids, normals, areas, mats, objs, cells, keys, corners = [], [], [], [], [], [], [], []
    grid_shape = None
    if terrain is not None:
        spacing = float(min(heightfield.spacing))
        step = spacing if resolution is None else float(resolution)
        if not np.isfinite(step) or step <= 0:
            raise ConfigError(f"must be > 0 m; got {resolution!r}", key="thermal.resolution")
        if step < spacing * (1.0 - 1e-9):
            raise ConfigError(f"{step:g} m is finer than the terrain's spacing {spacing:g} m; give at least that",
                              key="thermal.resolution")
        x0, x1, y0, y1 = heightfield.extent
        grid_shape = (max(1, int(np.ceil((y1 - y0) / step - 1e-9))), max(1, int(np.ceil((x1 - x0) / step - 1e-9))))
    for k, mesh in enumerate(meshes):
        v = mesh.vertices[mesh.faces]
        c = v.mean(axis=1)
        n = mesh.face_normals
        a = mesh.area
        m = np.asarray(face_material[k], dtype=np.int64)
        centroids.append(c)
        corners.append(v)
        normals.append(n)
        areas.append(a)
        mats.append(m)
        objs.append(np.full(len(a), k, dtype=np.int64))
        if k == terrain:
            col = np.clip(((c[:, 0] - x0) / step).astype(np.int64), 0, grid_shape[1] - 1)
            row = grid_shape[0] - 1 - np.clip(((c[:, 1] - y0) / step).astype(np.int64), 0, grid_shape[0] - 1)
            cell = row * grid_shape[1] + col
            key = np.column_stack([np.full(len(a), k), m, cell])
        else:
            cell = np.full(len(a), -1, dtype=np.int64)
            key = np.column_stack([np.full(len(a), k), m, _orientation_classes(n)])
        fixed = ~np.broadcast_to(np.asarray(solved[k], dtype=bool), (len(a),))
        key[fixed] = -1
        cell = np.where(fixed, -1, cell)
        cells.append(cell)
        keys.append(key)
    centroid = np.concatenate(centroids) if centroids else np.zeros((0, 3))
    normal = np.concatenate(normals) if normals else np.zeros((0, 3))
    area = np.concatenate(areas) if areas else np.zeros(0)
    material = np.concatenate(mats) if mats else np.zeros(0, np.int64)
    obj = np.concatenate(objs) if objs else np.zeros(0, np.int64)
    cell = np.concatenate(cells) if cells else np.zeros(0, np.int64)
    key = np.concatenate(keys) if keys else np.zeros((0, 3), np.int64)

    solved_face = (key[:, 0] >= 0) & (area > 0)
    face_element = np.full(len(area), -1, dtype=np.int64)
    if solved_face.any():
        face_element[solved_face] = _group(key[solved_face])
    n_el = int(face_element.max()) + 1 if solved_face.any() else 0
    el_area = np.bincount(face_element[solved_face], weights=area[solved_face], minlength=n_el)
    face_weight = np.zeros(len(area))
    face_weight[solved_face] = area[solved_face] / el_area[face_element[solved_face]]

    def mean(values):
        out = np.zeros((n_el, values.shape[1]))
        np.add.at(out, face_element[solved_face], face_weight[solved_face, None] * values[solved_face])
        return out

    position = mean(centroid)
    el_normal = mean(normal * 1.0)
    length = np.linalg.norm(el_normal, axis=1, keepdims=True)
    el_normal = np.divide(el_normal, length, out=np.tile([0.0, 0.0, 1.0], (n_el, 1)), where=length > 1e-12)
    first = np.zeros(n_el, dtype=np.int64)
    idx = np.flatnonzero(solved_face)
    first[face_element[idx[::-1]]] = idx[::-1]
    return SurfaceElements(
        position=position,
        normal=el_normal,
        area=el_area,
        material=material[first],
        object=obj[first],
        face_element=face_element,
        face_weight=face_weight,
        face_centroid=centroid,
        face_normal=normal,
        face_vertices=np.concatenate(corners) if corners else np.zeros((0, 3, 3)),
        face_area=area,
        cell=cell[first] if n_el else np.zeros(0, np.int64),
        grid_shape=grid_shape,
    )
