"""Triangle meshes: the container, rigid transforms and loading from files.

A :class:`Mesh` is a plain pair of arrays, vertices in metres in the east-north-up frame and
triangles as vertex indices. Winding is counter-clockwise seen from the outside, so the
right-hand-rule normal ``(v1 - v0) × (v2 - v0)`` points outward.

Attitude convention (:func:`rotation_matrix`, :meth:`Mesh.transformed`, cameras)
-------------------------------------------------------------------------------
A body is described in its own frame with *right* = +x, *forward* = +y, *up* = +z; with no
rotation the body frame is the world frame (forward points north). The attitude
``(yaw, pitch, roll)`` [deg] is applied as intrinsic rotations in this order:

1. **yaw** about the body's up axis (+z), *clockwise seen from above*: yaw is the heading of the
   forward axis as an azimuth (0 north, 90 east);
2. **pitch** about the (yawed) right axis, positive raises the forward axis above the horizontal
   (nose up);
3. **roll** about the (yawed and pitched) forward axis, positive lowers the right side (right
   wing down).

The rotation matrix is :math:`R = R_z(-\\psi)\\,R_x(\\theta)\\,R_y(\\phi)` with right-handed
elementary rotations, and a body vector :math:`\\mathbf{b}` goes to
:math:`\\mathbf{w} = R\\,\\mathbf{b}`.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from radscene.errors import ConfigError, unreadable

__all__ = [
    "Mesh",
    "concatenate",
    "load_mesh",
    "rotation_matrix",
    "GLTF_TO_ENU",
    "MESH_FORMATS",
]

#: File suffixes :func:`load_mesh` reads, mapped to whether the format is Y-up (glTF).
MESH_FORMATS = {".obj": False, ".ply": False, ".stl": False, ".gltf": True, ".glb": True}

#: glTF (+Y up, +Z front, -X right) to east-north-up: ``(x, y, z) = (-X, Z, Y)``. The model's
#: front (+Z) faces north (+y), so the ``yaw`` of :meth:`Mesh.transformed` is its heading.
GLTF_TO_ENU = np.array([[-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])


def rotation_matrix(yaw=0.0, pitch=0.0, roll=0.0) -> np.ndarray:
    """Body-to-world rotation matrix for an attitude (yaw, pitch, roll).

    See the module docstring for the convention (yaw clockwise from north about +z, then pitch
    about the right axis nose-up positive, then roll about the forward axis right-down positive).

    Parameters
    ----------
    yaw : array_like
        Heading of the body's forward (+y) axis, clockwise from north [deg].
    pitch : array_like
        Elevation of the forward axis above the horizontal [deg].
    roll : array_like
        Rotation about the forward axis, positive lowers the right (+x) side [deg].

    Returns
    -------
    numpy.ndarray
        Rotation matrices, shape ``broadcast(yaw, pitch, roll).shape + (3, 3)`` [-]; the columns
        are the body's right, forward and up axes in world coordinates.

    Examples
    --------
    >>> (rotation_matrix(90.0) @ [0.0, 1.0, 0.0]).round(12)  # north, yawed 90 deg, is east
    array([1., 0., 0.])
    """
    psi, theta, phi = np.broadcast_arrays(
        *(np.radians(np.asarray(a, dtype=float)) for a in (yaw, pitch, roll))
    )
    cy, sy = np.cos(psi), np.sin(psi)
    cp, sp = np.cos(theta), np.sin(theta)
    cr, sr = np.cos(phi), np.sin(phi)
    one, zero = np.ones_like(psi), np.zeros_like(psi)
    # R_z(-yaw): clockwise seen from above.
    rz = np.stack([cy, sy, zero, -sy, cy, zero, zero, zero, one], axis=-1)
    rx = np.stack([one, zero, zero, zero, cp, -sp, zero, sp, cp], axis=-1)
    ry = np.stack([cr, zero, sr, zero, one, zero, -sr, zero, cr], axis=-1)
    shape = psi.shape + (3, 3)
    return rz.reshape(shape) @ rx.reshape(shape) @ ry.reshape(shape)


@dataclass
class Mesh:
    """A triangle mesh in the east-north-up frame.

    Parameters
    ----------
    vertices : array_like
        Vertex positions, shape ``(N, 3)`` [m]; stored as float64. Must be finite.
    faces : array_like
        Vertex indices of each triangle, shape ``(M, 3)``; stored as int64. Counter-clockwise
        seen from the outside (right-hand-rule normal points outward).
    name : str
        A label, e.g. the file stem or the scene object's name.

    Examples
    --------
    >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    >>> m.face_normals, m.area
    (array([[0., 0., 1.]]), array([0.5]))
    """

    vertices: np.ndarray
    faces: np.ndarray
    name: str = field(default="")

    def __post_init__(self):
        label = f"mesh {self.name!r}" if self.name else "mesh"
        v = np.array(self.vertices, dtype=np.float64)
        if v.size == 0:
            v = v.reshape(0, 3)
        if v.ndim != 2 or v.shape[1] != 3:
            raise ConfigError(f"{label}: vertices must have shape (N, 3), got {v.shape}",
                              key="vertices")
        bad = ~np.isfinite(v).all(axis=1)
        if bad.any():
            raise ConfigError(f"{label}: {int(bad.sum())} vertices are not finite, first is "
                              f"vertex {int(np.argmax(bad))}", key="vertices")
        f = np.asarray(self.faces)
        if f.size == 0:
            f = f.reshape(0, 3)
        if f.ndim != 2 or f.shape[1] != 3:
            raise ConfigError(f"{label}: faces must have shape (M, 3), got {f.shape}",
                              key="faces")
        if not (np.issubdtype(f.dtype, np.integer) or f.size == 0):
            raise ConfigError(f"{label}: faces must be integer vertex indices, got {f.dtype}",
                              key="faces")
        f = f.astype(np.int64)
        if f.size and (f.min() < 0 or f.max() >= len(v)):
            raise ConfigError(f"{label}: face indices must lie in [0, {len(v) - 1}], got "
                              f"[{f.min()}, {f.max()}]", key="faces")
        self.vertices, self.faces = v, f

    def __repr__(self) -> str:
        return f"Mesh(name={self.name!r}, vertices={len(self.vertices)}, faces={len(self.faces)})"

    def with_vertices(self, vertices) -> Mesh:
        """The same mesh with its vertices moved: the faces shared, not checked again.

        For meshes moved frame after frame (:meth:`radscene.geometry.RayTracer.move` checks
        that the new vertices are finite).

        Parameters
        ----------
        vertices : array_like
            ``(N, 3)`` [m], as many as the mesh has.

        Raises
        ------
        ConfigError
            Another shape.

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
        >>> m.with_vertices(m.vertices + 1.0).faces is m.faces
        True
        """
        v = np.asarray(vertices, dtype=np.float64)
        if v.shape != self.vertices.shape:
            raise ConfigError(f"mesh {self.name!r}: {self.vertices.shape[0]} vertices (N, 3) to "
                              f"move, got an array of shape {v.shape}", key="vertices")
        moved = object.__new__(Mesh)
        moved.vertices, moved.faces, moved.name = v, self.faces, self.name
        return moved

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Axis-aligned bounding box ``(min (3,), max (3,))`` of the vertices [m].

        An empty mesh gives NaN bounds.
        """
        if len(self.vertices) == 0:
            return np.full(3, np.nan), np.full(3, np.nan)
        return self.vertices.min(axis=0), self.vertices.max(axis=0)

    def _cross(self) -> np.ndarray:
        v0, v1, v2 = (self.vertices[self.faces[:, k]] for k in range(3))
        return np.cross(v1 - v0, v2 - v0)

    @property
    def face_normals(self) -> np.ndarray:
        """Unit right-hand-rule normal of each face, shape ``(M, 3)`` [-].

        Degenerate (zero-area) faces get a zero vector.
        """
        n = self._cross()
        length = np.linalg.norm(n, axis=1, keepdims=True)
        return np.divide(n, length, out=np.zeros_like(n), where=length > 0)

    @property
    def area(self) -> np.ndarray:
        """Area of each face, shape ``(M,)`` [m2]."""
        return 0.5 * np.linalg.norm(self._cross(), axis=1)

    def transformed(self, translation=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0),
                    scale=1.0) -> Mesh:
        """A copy scaled, then rotated, then translated.

        .. math:: \\mathbf{w} = \\mathbf{t} + R(\\psi, \\theta, \\phi)\\,(s \\odot \\mathbf{v})

        Parameters
        ----------
        translation : array_like
            Offset (east, north, up) added last, shape ``(3,)`` [m].
        rotation : array_like
            Attitude ``(yaw, pitch, roll)`` [deg], see :func:`rotation_matrix`: yaw is the
            heading of the model's +y axis clockwise from north.
        scale : float or array_like
            Positive factor, one for all axes or ``(sx, sy, sz)`` along the model's own axes [-].

        Returns
        -------
        Mesh
            The transformed mesh (same faces, same name).

        Examples
        --------
        >>> m = Mesh([[0, 0, 0], [0, 1, 0], [0, 0, 1]], [[0, 1, 2]])
        >>> m.transformed(rotation=(90, 0, 0)).vertices[1].round(12)
        array([1., 0., 0.])
        """
        t = np.asarray(translation, dtype=float)
        r = np.asarray(rotation, dtype=float)
        s = np.asarray(scale, dtype=float)
        if t.shape != (3,) or not np.isfinite(t).all():
            raise ConfigError(f"translation must be 3 finite numbers [m], got {translation!r}",
                              key="translation")
        if r.shape != (3,) or not np.isfinite(r).all():
            raise ConfigError("rotation must be 3 finite angles (yaw, pitch, roll) [deg], got "
                              f"{rotation!r}", key="rotation")
        if s.shape not in ((), (3,)) or not np.isfinite(s).all() or (s <= 0).any():
            raise ConfigError(f"scale must be a positive number or 3 positive numbers, got "
                              f"{scale!r}", key="scale")
        rot = rotation_matrix(*r)
        vertices = (self.vertices * s) @ rot.T + t
        return Mesh(vertices, self.faces.copy(), self.name)


def concatenate(meshes: Sequence[Mesh], name: str = "") -> Mesh:
    """Join meshes into one; faces keep their order, mesh after mesh.

    Parameters
    ----------
    meshes : sequence of Mesh
        The parts; may be empty (gives an empty mesh).
    name : str
        Name of the result.

    Returns
    -------
    Mesh
        Vertices stacked, face indices offset to point at their own mesh's vertices.
    """
    meshes = list(meshes)
    if not meshes:
        return Mesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64), name)
    offsets = np.cumsum([0] + [len(m.vertices) for m in meshes[:-1]])
    vertices = np.concatenate([m.vertices for m in meshes])
    faces = np.concatenate([m.faces + o for m, o in zip(meshes, offsets, strict=True)])
    return Mesh(vertices, faces, name)


def load_mesh(path, name: str | None = None) -> Mesh:
    """Read a triangle mesh with trimesh and bring it into the east-north-up frame.

    Formats: OBJ, PLY, STL (taken as Z-up, coordinates kept as they are) and glTF / GLB
    (Y-up by the glTF 2.0 specification; converted with :data:`GLTF_TO_ENU`, so glTF +Y
    becomes up, +Z (the model's front) north and +X west). Multi-part files (scenes) are
    flattened into one mesh with every node's transform applied. Units are taken as metres.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    name : str, optional
        Name of the mesh; the file stem if not given.

    Returns
    -------
    Mesh

    Raises
    ------
    ConfigError
        The file does not exist, its format is not one of the above, or it holds no triangles.
    """
    import trimesh

    path = os.fspath(path)
    if not os.path.isfile(path):
        raise ConfigError(f"mesh file not found: {path!r}", key="path")
    suffix = os.path.splitext(path)[1].lower()
    if suffix not in MESH_FORMATS:
        raise ConfigError(f"cannot read {path!r}: unknown mesh format {suffix!r}; accepted: "
                          f"{', '.join(sorted(MESH_FORMATS))}", key="path")
    try:
        loaded = trimesh.load(path, file_type=suffix[1:])
    except Exception as exc:  # trimesh raises many types for a bad file
        raise ConfigError(f"cannot read mesh {path!r}: {unreadable(exc)}", key="path") from None
    if isinstance(loaded, trimesh.Scene):
        loaded = loaded.to_mesh() if loaded.geometry else None
    if not isinstance(loaded, trimesh.Trimesh) or len(loaded.faces) == 0:
        raise ConfigError(f"mesh file {path!r} holds no triangles", key="path")
    vertices = np.asarray(loaded.vertices, dtype=float)
    if MESH_FORMATS[suffix]:
        vertices = vertices @ GLTF_TO_ENU.T
    if name is None:
        name = os.path.splitext(os.path.basename(path))[0]
    return Mesh(vertices, np.asarray(loaded.faces, dtype=np.int64), name)
