"""The ray engine: ray-triangle queries on Embree, in batches, on threads.

Precision. Embree works in float32. The scene is therefore moved into a local frame centred on
the centre of its bounding box, and every ray is first clipped, in float64, to that box (grown
by a small margin): rays that miss it are never traced, and rays that start outside are
advanced to where they enter it, the advance being added back to the distance. What Embree sees
is then always within the scene's own size of the local origin, so an observer 700 km away
gets the same (sub-millimetre, for a km-size scene) accuracy as one standing in the scene.

Robust mode. Embree's robust flag makes its ray-triangle test watertight (no ray slips between
two triangles that share an edge, as a ray aimed exactly at a terrain grid vertex may). It is
on by default; measured on the development machine it cost 1-5 % for intersection and
about 10-18 % for occlusion queries, a fair price for no light leaks through terrain seams.

Cost. Where Embree's packet queries can be used (:mod:`radscene.geometry.embree`, the default),
rays are traced eight at a time from numba kernels on numba's threads; otherwise embreex traces
one ray at a time in C and releases the GIL, so batches are cut into chunks that a thread pool
runs in parallel. Both give the same answers (unit tests). A ray with NaN components or a
zero direction costs Embree milliseconds; such input is refused with :class:`ConfigError`.
:meth:`intersect` checks, normalises and clips its rays in one compiled pass (numba) and forms
the hits in another, so that a million primary rays cost little beyond Embree's own time.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numba
import numpy as np

from radscene.errors import ConfigError
from radscene.geometry.mesh import Mesh

__all__ = ["Hits", "RayTracer", "BOX_GROWTH", "clip_ray"]

#: When a moved mesh leaves the box that rays are clipped to, the box grows to hold it plus
#: this fraction of its new half-size on every axis, so that a mesh moving on grows it
#: seldom: each growth moves every ray's float32 start point (by rounding), so that hits traced
#: before and after it may differ at that level (real-time frames retrace every pixel then).
BOX_GROWTH = 0.25


@dataclass
class Hits:
    """First intersections of a batch of N rays.

    Attributes
    ----------
    distance : numpy.ndarray
        (N,) float64, distance from the ray origin along the unit direction [m]; inf on miss.
    object : numpy.ndarray
        (N,) int32, index of the mesh hit in the list given to :class:`RayTracer`; -1 on miss.
    primitive : numpy.ndarray
        (N,) int32, index of the face within that mesh; -1 on miss.
    u, v : numpy.ndarray
        (N,) float32 barycentric coordinates [-]: the point is
        ``(1 - u - v) v0 + u v1 + v v2`` of the face's vertices; 0 on miss.
    normal : numpy.ndarray
        (N, 3) float64 unit geometric normal of the face (right-hand rule, i.e. outward for
        outward-wound meshes, *not* flipped towards the ray) [-]; zeros on miss.
    position : numpy.ndarray
        (N, 3) float64 ``origin + distance * direction`` in the world frame [m]; NaN on miss.
    hit : numpy.ndarray
        (N,) bool, whether the ray hit anything.
    """

    distance: np.ndarray
    object: np.ndarray
    primitive: np.ndarray
    u: np.ndarray
    v: np.ndarray
    normal: np.ndarray
    position: np.ndarray
    hit: np.ndarray

    def __len__(self) -> int:
        return len(self.distance)


def _rays(origins, directions) -> tuple[np.ndarray, np.ndarray]:
    """Broadcast to (N, 3) float64, refuse non-finite input and zero directions, normalise."""
    try:
        o, d = np.broadcast_arrays(np.asarray(origins, dtype=np.float64),
                                   np.asarray(directions, dtype=np.float64))
    except ValueError:
        raise ConfigError(f"origins {np.shape(origins)} and directions {np.shape(directions)} "
                          "do not broadcast together", key="origins, directions") from None
    if o.ndim != 2 or o.shape[1] != 3:
        raise ConfigError(f"rays must have shape (N, 3), got {o.shape}", key="origins")
    for name, a in (("origins", o), ("directions", d)):
        bad = ~np.isfinite(a).all(axis=1)
        if bad.any():
            raise ConfigError(f"{int(bad.sum())} rays are not finite, first is ray "
                              f"{int(np.argmax(bad))}: {a[np.argmax(bad)]}", key=name)
    length = np.linalg.norm(d, axis=1)
    zero = length == 0
    if zero.any():
        raise ConfigError(f"{int(zero.sum())} directions have zero length, first is ray "
                          f"{int(np.argmax(zero))}", key="directions")
    return o, d / length[:, None]


def _broadcast(origins, directions) -> tuple[np.ndarray, np.ndarray]:
    """Origins and directions broadcast to (N, 3) float64 (copies only where broadcast)."""
    o = np.asarray(origins, dtype=np.float64)
    d = np.asarray(directions, dtype=np.float64)
    if o.shape != d.shape:
        try:
            o, d = (np.array(a) for a in np.broadcast_arrays(o, d))
        except ValueError:
            raise ConfigError(f"origins {np.shape(origins)} and directions "
                              f"{np.shape(directions)} do not broadcast together",
                              key="origins, directions") from None
    if o.ndim != 2 or o.shape[1] != 3:
        raise ConfigError(f"rays must have shape (N, 3), got {o.shape}", key="origins")
    return o, d


@numba.njit(inline="always")
def _fmin(a, b):
    """numpy's fmin: the smaller, NaN ignored unless both are NaN."""
    if a != a:
        return b
    if b != b:
        return a
    return a if a <= b else b


@numba.njit(inline="always")
def _fmax(a, b):
    if a != a:
        return b
    if b != b:
        return a
    return a if a >= b else b


@numba.njit(inline="always")
def clip_ray(ox, oy, oz, dx, dy, dz, center, half):
    """One ray (unit direction) clipped to the box ``center`` ± ``half``, as :meth:`RayTracer.
    intersect` clips it: (entry advance, exit distance [m], float32 local start x, y, z).
    The box is missed where entry > exit."""
    lx, ly, lz = ox - center[0], oy - center[1], oz - center[2]
    t1x, t2x = (-half[0] - lx) * (1.0 / dx), (half[0] - lx) * (1.0 / dx)
    t1y, t2y = (-half[1] - ly) * (1.0 / dy), (half[1] - ly) * (1.0 / dy)
    t1z, t2z = (-half[2] - lz) * (1.0 / dz), (half[2] - lz) * (1.0 / dz)
    enter = _fmax(_fmax(_fmax(_fmin(t1x, t2x), _fmin(t1y, t2y)), _fmin(t1z, t2z)), 0.0)
    leave = _fmin(_fmin(_fmax(t1x, t2x), _fmax(t1y, t2y)), _fmax(t1z, t2z))
    return (enter, leave, np.float32(lx + enter * dx), np.float32(ly + enter * dy),
            np.float32(lz + enter * dz))


@numba.njit(parallel=True, cache=True, error_model="numpy")
def _prepare(o, d, center, half, unit, start, direction, t_in, reach):
    """Checked, normalised and box-clipped rays in one pass (as :func:`_rays`, ``_starts``).

    Writes the unit directions ``unit`` (float64), the float32 box-entry points ``start`` and
    directions, the entry advance ``t_in`` and ``reach``; returns the number of rays with a
    non-finite component or a zero direction (0: all valid).
    """
    bad = 0
    for i in numba.prange(o.shape[0]):
        ox, oy, oz, dx, dy, dz = o[i, 0], o[i, 1], o[i, 2], d[i, 0], d[i, 1], d[i, 2]
        length = math.sqrt(dx * dx + dy * dy + dz * dz)
        finite = (math.isfinite(ox) and math.isfinite(oy) and math.isfinite(oz)
                  and math.isfinite(dx) and math.isfinite(dy) and math.isfinite(dz))
        if not finite or length == 0.0:
            bad += 1
            reach[i] = False
            continue
        dx, dy, dz = dx / length, dy / length, dz / length
        unit[i, 0], unit[i, 1], unit[i, 2] = dx, dy, dz
        enter, leave, start[i, 0], start[i, 1], start[i, 2] = clip_ray(ox, oy, oz, dx, dy, dz,
                                                                     center, half)
        t_in[i] = enter
        reach[i] = enter <= leave
        direction[i, 0], direction[i, 1], direction[i, 2] = (
            np.float32(dx), np.float32(dy), np.float32(dz))
    return bad


@numba.njit(parallel=True, cache=True)
def _finish(o, d, t_in, geom, prim, tfar, hit_u, hit_v, object_of_geom, face_offset, normals,
            distance, obj, primitive, u, v, normal, position):
    """Hits from Embree's per-ray results (geomID < 0: miss), as :meth:`RayTracer.intersect`."""
    for i in numba.prange(o.shape[0]):
        g = geom[i]
        if g < 0:
            distance[i] = np.inf
            obj[i] = -1
            primitive[i] = -1
            u[i] = 0.0
            v[i] = 0.0
            for c in range(3):
                normal[i, c] = 0.0
                position[i, c] = np.nan
            continue
        k = object_of_geom[g]
        t = t_in[i] + np.float64(tfar[i])
        distance[i] = t
        obj[i] = k
        primitive[i] = prim[i]
        u[i] = hit_u[i]
        v[i] = hit_v[i]
        face = face_offset[k] + prim[i]
        for c in range(3):
            normal[i, c] = normals[face, c]
            position[i, c] = o[i, c] + t * d[i, c]


class RayTracer:
    """One Embree scene of several meshes; mesh ``k`` is object ``k``.

    Parameters
    ----------
    meshes : sequence of Mesh
        The geometry, in the world (east-north-up) frame [m]. Meshes without faces are allowed
        and never hit.
    robust : bool
        Use Embree's watertight ray-triangle test (see the module notes); default True.
    chunk_size : int
        Rays per Embree call and per thread-pool task.
    threads : int, optional
        Worker threads; default ``os.cpu_count()``.
    packets : bool
        Trace intersections, occlusion queries and secondary-ray fans as Embree packets of
        eight where the library allows it (:mod:`radscene.geometry.embree`; same answers);
        default True.
    dynamic : bool
        Geometry that will move (:meth:`update`): where packets are available every query
        goes to one Embree scene built for motion, a BVH per mesh under a top-level one, so
        that moving a mesh refits that mesh's alone; default False.

    Examples
    --------
    >>> from radscene.geometry import plate
    >>> rt = RayTracer([plate(10.0, 10.0)])
    >>> round(float(rt.intersect([[0.0, 0.0, 5.0]], [[0.0, 0.0, -1.0]]).distance[0]), 6)
    5.0
    """

    def __init__(self, meshes: Sequence[Mesh], robust: bool = True, chunk_size: int = 65536,
                 threads: int | None = None, packets: bool = True, dynamic: bool = False):
        meshes = list(meshes)
        for k, m in enumerate(meshes):
            if not isinstance(m, Mesh):
                raise ConfigError(f"must be a radscene Mesh, got {type(m).__name__}",
                                  key=f"meshes[{k}]")
        if int(chunk_size) < 1:
            raise ConfigError(f"must be a positive integer, got {chunk_size!r}", key="chunk_size")
        self.meshes = tuple(meshes)
        self.chunk_size = int(chunk_size)
        self.threads = int(threads) if threads else (os.cpu_count() or 1)
        self.robust = bool(robust)
        self.use_packets = bool(packets)
        self.dynamic = bool(dynamic)

        filled = [k for k, m in enumerate(meshes) if len(m.faces)]
        #: How many times each mesh was moved (:meth:`move`): what moved since a count was kept.
        self.move_count = np.zeros(len(meshes), dtype=np.int64)
        # each mesh's box (rows of empty meshes unused), kept: move() is O(moved)
        self._mesh_lo = np.zeros((len(meshes), 3))
        self._mesh_hi = np.zeros((len(meshes), 3))
        for k in filled:
            self._mesh_lo[k], self._mesh_hi[k] = meshes[k].bounds
        if filled:
            lo = self._mesh_lo[filled].min(axis=0)
            hi = self._mesh_hi[filled].max(axis=0)
        else:
            lo = hi = np.zeros(3)
        self._bounds = (lo, hi)
        self._center = 0.5 * (lo + hi)
        # Margin around the box, so the clipped origin lies outside every surface even after
        # rounding to float32 (relative 6e-8): 1e-5 of the size plus 1 mm.
        margin = 1e-5 * float(np.linalg.norm(hi - lo)) + 1e-3
        self._half = 0.5 * (hi - lo) + margin

        # geomID -> object index, and object -> offset of its faces in the stacked normals.
        self._object_of_geom = np.array(filled, dtype=np.int32)
        face_counts = np.array([len(m.faces) for m in meshes], dtype=np.int64)
        self._face_offset = np.concatenate([[0], np.cumsum(face_counts)[:-1]]).astype(np.int64)
        normals = [m.face_normals for m in meshes]
        self._normals = np.concatenate(normals) if normals else np.zeros((0, 3))
        self._empty = not filled
        self._embreex = None
        if not (self.dynamic and self.packets is not None):
            self._embreex = self._build_embreex()

    def _build_embreex(self):
        """The embreex scene of the meshes as they are now, committed."""
        from embreex import mesh_construction, rtcore_scene

        scene = rtcore_scene.EmbreeScene(robust=self.robust)
        for m in self.meshes:
            if len(m.faces):
                local = (m.vertices - self._center).astype(np.float32)
                mesh_construction.TriangleMesh(scene, local, m.faces.astype(np.int32))
        if not self._empty:  # embreex commits the scene on its first query: do it here, once
            scene.run(np.zeros((1, 3), np.float32), np.array([[0, 0, 1]], np.float32))
        return scene

    @property
    def _scene(self):
        """The embreex scene (built on first use after :meth:`update` moved a mesh)."""
        if self._embreex is None:
            self._embreex = self._build_embreex()
        return self._embreex

    def update(self, index: int, mesh: Mesh) -> None:
        """Replace mesh ``index`` by a moved copy of it: the same faces, new vertices.

        The other meshes are not touched: in a ``dynamic`` tracer with packets, Embree refits
        the moved mesh's BVH and the top level only; otherwise the embreex scene is rebuilt
        on its next query. The box rays are clipped to grows (about the same centre) to hold
        the moved mesh. :meth:`move` moves several at once.

        Parameters
        ----------
        index : int
            The mesh, its place in the list given to the constructor.
        mesh : Mesh
            Its new geometry, world frame [m]; same number of vertices and the same faces.

        Raises
        ------
        ConfigError
            An unknown index, or a mesh whose vertices or faces differ in number or order.
        """
        self.move({index: mesh})

    def move(self, meshes: dict) -> None:
        """Replace several meshes by moved copies at once (as :meth:`update` does one).

        The moved meshes' normals and boxes are computed in one pass, and Embree's top level
        is rebuilt once, on the next query, whatever the number of meshes moved: moving 100
        meshes of 100 triangles costs about what moving one does plus the vertex copies.

        Parameters
        ----------
        meshes : dict of int to Mesh
            Mesh index (its place in the list given to the constructor) to its new geometry,
            world frame [m]; each with its old number of vertices and the same faces.

        Raises
        ------
        ConfigError
            As :meth:`update`, naming the first bad index.
        """
        moved = []
        for index, mesh in meshes.items():
            if not 0 <= int(index) < len(self.meshes):
                raise ConfigError(f"no mesh {index}; the tracer holds {len(self.meshes)}",
                                  key="index")
            index = int(index)
            old = self.meshes[index]
            if not isinstance(mesh, Mesh):
                raise ConfigError(f"must be a radscene Mesh, got {type(mesh).__name__}",
                                  key=f"meshes[{index}]")
            if mesh.vertices.shape != old.vertices.shape or (
                    mesh.faces is not old.faces and not np.array_equal(mesh.faces, old.faces)):
                raise ConfigError(f"mesh {index} must keep its {len(old.vertices)} vertices and "
                                  f"{len(old.faces)} faces to be moved; got "
                                  f"{len(mesh.vertices)} and {len(mesh.faces)}",
                                  key=f"meshes[{index}]")
            if len(mesh.faces):
                moved.append((index, mesh))
        if not moved:
            for index, mesh in meshes.items():  # meshes without faces: nothing to trace
                self._replace(int(index), mesh)
            return
        # one pass over every moved vertex and face: finiteness, normals, boxes
        vertices = np.concatenate([m.vertices for _, m in moved])
        if not np.isfinite(vertices).all():
            raise ConfigError("vertices must be finite", key="meshes")
        counts = np.array([len(m.vertices) for _, m in moved])
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        faces = np.concatenate([m.faces + s for (_, m), s in zip(moved, starts, strict=True)])
        cross = np.cross(vertices[faces[:, 1]] - vertices[faces[:, 0]],
                         vertices[faces[:, 2]] - vertices[faces[:, 0]])
        length = np.linalg.norm(cross, axis=1, keepdims=True)
        normals = np.divide(cross, length, out=np.zeros_like(cross), where=length > 0)
        lo = np.minimum.reduceat(vertices, starts, axis=0)
        hi = np.maximum.reduceat(vertices, starts, axis=0)
        packets = getattr(self, "_packet_scene", None)
        first = 0
        indices = np.array([index for index, _ in moved])
        geometries = np.searchsorted(self._object_of_geom, indices).tolist()
        self._mesh_lo[indices], self._mesh_hi[indices] = lo, hi
        self.move_count[indices] += 1
        local = vertices - self._center
        all_meshes = list(self.meshes)
        for row, (index, mesh) in enumerate(moved):
            n_faces = len(mesh.faces)
            at = self._face_offset[index]
            self._normals[at:at + n_faces] = normals[first:first + n_faces]
            first += n_faces
            all_meshes[index] = mesh
            if packets is not None:  # committed on the next query (see packets)
                packets.update(geometries[row], local[starts[row]:starts[row] + counts[row]],
                               commit=False)
        self.meshes = tuple(all_meshes)
        filled = self._object_of_geom
        self._bounds = (self._mesh_lo[filled].min(axis=0), self._mesh_hi[filled].max(axis=0))
        reach = np.maximum(np.abs(self._bounds[0] - self._center),
                           np.abs(self._bounds[1] - self._center))
        margin = 1e-5 * float(np.linalg.norm(2 * reach)) + 1e-3
        needed = reach + margin
        if np.any(needed > self._half):  # with room to spare: see BOX_GROWTH
            self._half = np.maximum(self._half, needed * (1.0 + BOX_GROWTH))
        self._embreex = None

    def _replace(self, index, mesh):
        meshes = list(self.meshes)
        meshes[index] = mesh
        self.meshes = tuple(meshes)

    @property
    def packets(self):
        """The same geometry as an Embree scene for the packet kernels
        (:class:`radscene.geometry.embree.PacketScene`, built on first use), or None where
        Embree's packet queries are not available or the scene is empty."""
        from radscene.geometry import embree

        if self._empty or not self.use_packets:
            return None
        filled = [m for m in self.meshes if len(m.faces)]
        scene = embree.packet_scene(
            self, lambda: [(m.vertices - self._center).astype(np.float32) for m in filled],
            lambda: [m.faces for m in filled], self.robust, self.dynamic)
        if scene is not None and scene.pending:  # meshes moved since the last query
            scene.commit()
        return scene

    def __repr__(self) -> str:
        return (f"RayTracer({len(self.meshes)} meshes, "
                f"{sum(len(m.faces) for m in self.meshes)} faces, robust={self.robust})")

    @property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(min (3,), max (3,))`` of the vertices of all meshes with faces, world frame [m]."""
        return self._bounds[0].copy(), self._bounds[1].copy()

    @property
    def mesh_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """``(min (M, 3), max (M, 3))``: each mesh's box, world frame [m] (rows of meshes
        without faces are zero)."""
        return self._mesh_lo.copy(), self._mesh_hi.copy()

    @property
    def center(self) -> np.ndarray:
        """Origin of the tracer's local float32 frame in world coordinates [m]."""
        return self._center.copy()

    @property
    def half_size(self) -> np.ndarray:
        """Half-size of the box rays are clipped to, about :attr:`center` [m] (the meshes' box
        grown by a small margin)."""
        return self._half.copy()

    def to_local(self, points) -> np.ndarray | None:
        """float32 local-frame copies of world points ``(N, 3)``, for :meth:`occluded_local`.

        None where a point is not finite or lies outside the box that rays are clipped to
        (from such a point :meth:`occluded` is the query to use).
        """
        local = np.asarray(points, dtype=np.float64) - self._center
        if local.ndim != 2 or local.shape[1] != 3 or not np.all(np.abs(local) <= self._half):
            return None
        return local.astype(np.float32)

    # -- clipping ---------------------------------------------------------------------------

    def _clip(self, o, d):
        """Local origins, box entry and exit distances [m] (entry > exit: the box is missed)."""
        local = o - self._center
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1.0 / d
            t1 = (-self._half - local) * inv
            t2 = (self._half - local) * inv
        # A ray parallel to a slab (d = 0) gets t = -inf, +inf inside it and the same
        # infinity twice outside; 0 * inf = NaN on its boundary is skipped by fmin / fmax.
        t_lo, t_hi = np.fmin(t1, t2), np.fmax(t1, t2)
        t_in = np.fmax(np.fmax(np.fmax(t_lo[:, 0], t_lo[:, 1]), t_lo[:, 2]), 0.0)
        t_out = np.fmin(np.fmin(t_hi[:, 0], t_hi[:, 1]), t_hi[:, 2])
        return local, t_in, t_out

    def _starts(self, o, d, t_end=None):
        """Rays of one chunk that reach the box, as float32 (start, direction) for Embree.

        Returns the indices of those rays within the chunk, their box-entry advance [m] and the
        float32 start points and directions.
        """
        local, t_in, t_out = self._clip(o, d)
        if t_end is not None:
            t_out = np.minimum(t_end, t_out)
        reach = t_in <= t_out
        if reach.all():
            traced = np.arange(len(o))
        else:
            traced = np.flatnonzero(reach)
            local, d, t_in, t_out = local[traced], d[traced], t_in[traced], t_out[traced]
        start = local + t_in[:, None] * d
        return traced, t_in, t_out, start.astype(np.float32), d.astype(np.float32)

    def _run_chunks(self, n: int, work) -> None:
        starts = range(0, n, self.chunk_size)
        if n <= self.chunk_size or self.threads == 1:
            for s in starts:
                work(slice(s, min(s + self.chunk_size, n)))
            return
        with ThreadPoolExecutor(max_workers=min(self.threads, len(starts))) as pool:
            for _ in pool.map(lambda s: work(slice(s, min(s + self.chunk_size, n))), starts):
                pass

    # -- queries ----------------------------------------------------------------------------

    def intersect(self, origins, directions) -> Hits:
        """First hit along each ray.

        Parameters
        ----------
        origins : array_like
            Ray origins, shape ``(N, 3)`` (or broadcastable with ``directions``) [m].
        directions : array_like
            Ray directions, shape ``(N, 3)``, any non-zero length (normalised here) [-].

        Returns
        -------
        Hits
            Distances are along the unit direction [m]; a surface at the origin itself is hit at
            distance 0 (offset secondary-ray origins yourself).

        Raises
        ------
        ConfigError
            A ray with a non-finite component or a zero direction.
        """
        o, d = _broadcast(origins, directions)
        n = len(o)
        unit = np.empty((n, 3))
        start = np.empty((n, 3), np.float32)
        direction = np.empty((n, 3), np.float32)
        t_in = np.empty(n)
        reach = np.empty(n, dtype=bool)
        if n and _prepare(o, d, self._center, self._half, unit, start, direction, t_in, reach):
            _rays(o, d)  # raises, naming the first bad ray
        geom = np.full(n, -1, dtype=np.int32)
        prim = np.full(n, -1, dtype=np.int32)
        tfar = np.zeros(n, np.float32)
        hit_u = np.zeros(n, np.float32)
        hit_v = np.zeros(n, np.float32)
        traced = None if reach.all() else np.flatnonzero(reach)
        if traced is not None:  # rays that miss the box are not traced
            start, direction = start[traced], direction[traced]

        def work(sl):
            res = self._scene.run(start[sl], direction[sl], output=1)
            at = sl if traced is None else traced[sl]
            geom[at], prim[at], tfar[at] = res["geomID"], res["primID"], res["tfar"]
            hit_u[at], hit_v[at] = res["u"], res["v"]

        packets = self.packets
        if packets is not None and len(start):  # Embree's packets of eight, numba's threads
            at = slice(None) if traced is None else traced
            geom[at], prim[at], tfar[at], hit_u[at], hit_v[at] = packets.intersect(start,
                                                                                   direction)
        elif not self._empty:
            self._run_chunks(len(start), work)
        distance = np.empty(n)
        obj = np.empty(n, dtype=np.int32)
        primitive = np.empty(n, dtype=np.int32)
        u = np.empty(n, dtype=np.float32)
        v = np.empty(n, dtype=np.float32)
        normal = np.empty((n, 3))
        position = np.empty((n, 3))
        if n:
            _finish(o, unit, t_in, geom, prim, tfar, hit_u, hit_v, self._object_of_geom,
                    self._face_offset, self._normals, distance, obj, primitive, u, v, normal,
                    position)
        return Hits(distance, obj, primitive, u, v, normal, position, obj >= 0)

    def occluded(self, origins, directions, t_max=None) -> np.ndarray:
        """Whether anything lies on each ray between its origin and ``t_max``.

        Parameters
        ----------
        origins : array_like
            Ray origins, shape ``(N, 3)`` [m].
        directions : array_like
            Ray directions, shape ``(N, 3)``, any non-zero length [-].
        t_max : float or array_like, optional
            Distance along the unit direction up to which to look, scalar or ``(N,)``, >= 0
            (inf allowed) [m]; default inf.

        Returns
        -------
        numpy.ndarray
            (N,) bool. A surface at the origin itself counts as occluding.
        """
        o, d = _rays(origins, directions)
        n = len(o)
        if t_max is None:
            t_max = np.full(n, np.inf)
        else:
            try:
                t_max = np.broadcast_to(np.asarray(t_max, dtype=np.float64), (n,))
            except ValueError:
                raise ConfigError(f"must be a scalar or shape ({n},), got shape "
                                  f"{np.shape(t_max)}", key="t_max") from None
            bad = np.isnan(t_max) | (t_max < 0)
            if bad.any():
                raise ConfigError(f"must be >= 0 (inf allowed) [m], {int(bad.sum())} are not, "
                                  f"first is ray {int(np.argmax(bad))}", key="t_max")
        out = np.zeros(n, dtype=bool)
        packets = self.packets if self._embreex is None else None
        if packets is not None:  # a dynamic scene: packets on numba's threads, no embreex copy
            traced, t_in, t_end, start, direction = self._starts(o, d, t_max)
            if len(traced):
                out[traced] = packets.occluded_within(start, direction, t_end - t_in)
            return out

        def work(sl):
            traced, t_in, t_end, start, direction = self._starts(o[sl], d[sl], t_max[sl])
            if self._empty or not len(traced):
                return
            dists = (t_end - t_in).astype(np.float32)
            res = self._scene.run(start, direction, dists=dists, query="OCCLUDED")
            out[sl.start + traced] = res >= 0

        self._run_chunks(n, work)
        return out

    def occluded_local(self, origins, directions) -> np.ndarray:
        """Occlusion of rays already in the local frame: the fast path for secondary rays.

        For rays the caller generates itself (shadow, sky and lobe fans from hit points):
        ``origins`` are world points minus :attr:`center`, and origins and directions are
        C-contiguous float32 ``(N, 3)``, finite, with unit directions and origins near the
        scene. Nothing is checked or clipped; rays look to infinity.

        Returns
        -------
        numpy.ndarray
            (N,) bool.
        """
        n = len(origins)
        out = np.zeros(n, dtype=bool)
        if self._empty or n == 0:
            return out

        packets = self.packets
        if packets is not None:  # Embree's packets of eight, on numba's threads
            return packets.occluded(origins, directions)

        def work(sl):
            out[sl] = self._scene.run(origins[sl], directions[sl], query="OCCLUDED") >= 0

        self._run_chunks(n, work)
        return out
