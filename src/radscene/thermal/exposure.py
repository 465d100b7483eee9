"""What each element sees, from the ray engine: the sun (shadows) and its hemisphere (sky view
factor and view factors to the other elements).

Both are asked of the same Embree scene the renderer traces, so a shadow in the heat balance is
the shadow in the image.

**Shadows.** For every sun position, occlusion rays towards the sun from points on each face
(raised off the surface by ``epsilon`` along its normal: one at the centroid of a terrain face,
about one per m² of an object face, :func:`shadow_points`); an element's sunlit fraction is
the area-weighted share of those points that see the sun. Faces turned away from the sun are not
traced (the absorbed beam is zero there whatever the shadow).

**Hemisphere.** ``n_samples`` cosine-weighted directions per element, each from a random point
of one of its faces (chosen in proportion to the faces' areas, stratified), over that face's
outer hemisphere (so elements are averaged over their area): with cosine weighting the
share of rays that escape is the face's sky view factor V_sky, and the share that hits face
``g`` of element ``j`` is the view factor F_fj (Modest 2013, *Radiative Heat Transfer*, 3rd
ed., §4.2: F = (1/π) ∫ cos θ dω over the directions that reach the other surface). Element
view factors are the area-weighted means over their faces, F_ij = Σ_f (A_f / A_i) F_fj.
Rays that hit a face without an element (an object of fixed temperature) go into ``fixed``:
the view factor to each such face, so its fixed temperature can be counted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from radscene.errors import ConfigError

__all__ = ["Hemisphere", "hemisphere_exposure", "shadow_points", "sunlit_fraction"]


def _points(elements, faces, r1, r2, epsilon):
    """Points uniform over the given faces for unit-square samples (r1, r2), raised by
    ``epsilon`` along the face normal (Shirley & Chiu's warp: Pharr et al. 2023, *Physically
    Based Rendering*, 4th ed., §6.5.1)."""
    v = elements.face_vertices[faces]
    s = np.sqrt(r1)[:, None]
    p = (1.0 - s) * v[:, 0] + s * (1.0 - r2[:, None]) * v[:, 1] + s * r2[:, None] * v[:, 2]
    return p + epsilon * elements.face_normal[faces]


def shadow_points(elements, spacing=1.0):
    """Where each solved face is tested for shadow: stratified points, about one per
    ``spacing``² of its area (at least one, at most 64), terrain faces one at the centroid.

    Returns
    -------
    face : ndarray of int, (n_points,)
        The face of each point.
    weight : ndarray, (n_points,)
        Each point's share of its face [-].
    r1, r2 : ndarray, (n_points,)
        Unit-square coordinates of each point on its face.
    """
    solved = np.flatnonzero(elements.face_element >= 0)
    terrain = elements.cell[elements.face_element[solved]] >= 0
    count = np.where(terrain, 1, np.clip(np.ceil(elements.face_area[solved] / spacing**2), 1, 64)).astype(np.int64)
    face = np.repeat(solved, count)
    k = np.arange(face.size) - np.repeat(np.cumsum(count) - count, count)
    n = np.repeat(count, count)
    r1 = np.where(n == 1, 1.0 / 3.0, (k + 0.5) / n)
    r2 = np.where(n == 1, 0.5, (k * 0.6180339887498949 + 0.5) % 1.0)
    return face, 1.0 / n, r1, r2


def sunlit_fraction(tracer, elements, sun_direction, epsilon=1e-3, spacing=1.0, progress=None,
                    transmittance=None):
    """Sunlit share of every element for each sun direction.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
        The scene's ray engine (its meshes in the order of ``elements``' faces).
    elements : SurfaceElements
    sun_direction : array_like, (n_times, 3) or (3,)
        Unit vectors towards the sun (east, north, up) [-].
    epsilon : float, optional
        Distance the ray origins are raised off the faces [m].
    spacing : float, optional
        About one shadow ray per ``spacing``² of an object face's area [m]
        (:func:`shadow_points`).
    progress : callable(done, total), optional
        Called after each sun direction.
    transmittance : callable(points, sun), optional
        The share [-] (N,) of the direct sun that passes the semi-transparent media (volumes)
        between points (N, 3) [m] and the sun (unit vector (3,)): a point that sees the sun
        counts that share of it (partial shadows).

    Returns
    -------
    ndarray, (n_times, n_elements)
        Sunlit fraction [-]: area share of faces that face the sun and see it, times the
        media's transmittance where given.
    """
    sun = np.atleast_2d(np.asarray(sun_direction, float))
    if sun.shape[1] != 3 or not np.all(np.isfinite(sun)):
        raise ConfigError(f"must be finite unit vectors of shape (n, 3); got shape {sun.shape}", key="sun_direction")
    face, weight, r1, r2 = shadow_points(elements, spacing)
    origin = _points(elements, face, r1, r2, epsilon)
    normal = elements.face_normal[face]
    local = tracer.to_local(origin)
    if local is not None:
        local = np.ascontiguousarray(local, np.float32)
    element = elements.face_element[face]
    share = weight * elements.face_weight[face]  # each point's share of its element's area
    out = np.zeros((len(sun), elements.size))
    for k, s in enumerate(sun):
        s = s / np.linalg.norm(s)
        facing = np.flatnonzero(normal @ s > 0.0)
        if s[2] > 0.0 and facing.size:
            if local is None:
                seen = ~tracer.occluded(origin[facing], np.broadcast_to(s, (facing.size, 3)))
            else:
                d = np.ascontiguousarray(np.broadcast_to(s.astype(np.float32), (facing.size, 3)))
                seen = ~tracer.occluded_local(local[facing], d)
            if transmittance is not None:
                seen = seen * transmittance(origin[facing], s)
            out[k] = np.bincount(element[facing], weights=share[facing] * seen, minlength=elements.size)
        if progress is not None:
            progress(k + 1, len(sun))
    # the faces' area shares sum to one only to rounding
    return np.minimum(out, 1.0, out=out)


@dataclass(frozen=True)
class Hemisphere:
    """What each element's hemisphere holds.

    Attributes
    ----------
    sky_view : ndarray, (n_elements,)
        Sky view factor V_sky [-], semi-transparent sheets passing their long-wave share.
    exchange : scipy.sparse.csr_array, (n_elements, n_elements)
        View factor F_ij from element i to element j [-].
    fixed : scipy.sparse.csr_array, (n_elements, n_faces)
        View factor from element i to face f of a surface that is not solved [-].
    samples : int
        Rays per face.
    sky_view_shortwave : ndarray, (n_elements,), optional
        The sky view through sheets' short-wave share [-] (the diffuse sky's light); default
        ``sky_view``.
    """

    sky_view: np.ndarray
    exchange: sparse.csr_array
    fixed: sparse.csr_array
    samples: int
    sky_view_shortwave: np.ndarray | None = None


def _stratified(n_elements, n_samples, rng):
    """(n_elements, n_samples, 2) points of a stratified unit-square pattern, shifted at random
    (modulo 1) per element."""
    side = int(np.ceil(np.sqrt(n_samples)))
    rows = int(np.ceil(n_samples / side))
    i, j = np.divmod(np.arange(n_samples), side)
    base = np.stack([(i + 0.5) / rows, (j + 0.5) / side], axis=1)
    return (base[None, :, :] + rng.random((n_elements, 1, 2))) % 1.0


def _cosine_directions(normal, u):
    """Cosine-weighted unit directions about unit normals (N, 3) for unit-square points (N, 2)."""
    r = np.sqrt(u[:, 0])
    phi = 2.0 * np.pi * u[:, 1]
    x, y, z = r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u[:, 0]))
    # an orthonormal frame (t, b, n) per normal (Duff et al. 2017, JCGT 6(1))
    n = normal
    sign = np.where(n[:, 2] >= 0.0, 1.0, -1.0)
    a = -1.0 / (sign + n[:, 2])
    b = n[:, 0] * n[:, 1] * a
    t = np.stack([1.0 + sign * n[:, 0] ** 2 * a, sign * b, -sign * n[:, 0]], axis=1)
    bb = np.stack([b, sign + n[:, 1] ** 2 * a, -n[:, 1]], axis=1)
    return x[:, None] * t + y[:, None] * bb + z[:, None] * n


def hemisphere_exposure(tracer, elements, n_samples=64, seed=0, epsilon=1e-3, batch=65536,
                        see_through=None, max_crossings=8):
    """Sky view factor and view factors between elements, by cosine-weighted hemisphere rays.

    A ray that meets a semi-transparent sheet (a net, a foliage layer, a pane) gives the sheet
    the share 1 − τ of its weight and goes on through it with the share τ, to the sky or to
    what lies behind (up to ``max_crossings`` sheets; a ray still inside a sheet after those
    gives its remaining weight to the last sheet). The view factors between surfaces and the
    sky view take the long-wave τ; a second sky view takes the short-wave τ (glass passes the
    diffuse sky's light and hides the sky's long-wave).

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    elements : SurfaceElements
    n_samples : int, optional
        Rays per element, each from a point of one of its faces chosen in proportion to the
        faces' areas; the standard error of a view factor F is about sqrt(F (1 − F) / n).
    seed : int, optional
        Seeds the shifts of the pattern and the points (same seed, same answer).
    epsilon : float, optional
        Distance the ray origins are raised off the faces [m].
    batch : int, optional
        Rays traced per call.
    see_through : callable, optional
        ``see_through(object, primitive, position) -> τ`` (N,) or (N, 2) [-]: the share of the
        hemisphere a face passes, per hit (object and primitive indices of ``tracer``, hit
        points (N, 3)), long-wave (and short-wave, the second column; else the same); 0 for
        opaque faces. Default: every face opaque.
    max_crossings : int, optional
        Sheets a ray may pass.

    Returns
    -------
    Hemisphere
    """
    n_samples = int(n_samples)
    if n_samples < 1:
        raise ConfigError(f"must be >= 1; got {n_samples}", key="thermal.hemisphere_samples")
    rng = np.random.default_rng(seed)
    n_faces = len(elements.face_element)
    n_el = elements.size
    face_offset = np.concatenate([[0], np.cumsum([len(m.faces) for m in tracer.meshes])[:-1]]).astype(np.int64)
    # the solved faces in element order; their area shares run from e to e + 1 in element e
    solved = np.flatnonzero(elements.face_element >= 0)
    by_element = solved[np.argsort(elements.face_element[solved], kind="stable")]
    cumulative = np.cumsum(elements.face_weight[by_element])
    first = np.searchsorted(elements.face_element[by_element], np.arange(n_el))
    last = np.append(first[1:], by_element.size) - 1
    sky = np.zeros(n_el)
    sky_shortwave = np.zeros(n_el)
    rows, cols, vals, frows, fcols, fvals = [], [], [], [], [], []
    per = max(1, batch // n_samples)
    for start in range(0, n_el, per):
        els = np.arange(start, min(start + per, n_el))
        # stratified area sampling of each element's faces
        u = (np.arange(n_samples)[None, :] + rng.random((els.size, n_samples))) / n_samples
        pick = np.searchsorted(cumulative, els[:, None] + u, side="right")
        pick = np.clip(pick, first[els, None], last[els, None])
        source = by_element[pick.ravel()]
        d = _cosine_directions(elements.face_normal[source], _stratified(els.size, n_samples, rng).reshape(-1, 2))
        r = rng.random((2, source.size))
        origin = _points(elements, source, r[0], r[1], epsilon)
        element_i = np.repeat(els, n_samples)
        weight = np.full((element_i.size, 2), 1.0 / n_samples)  # long-wave, short-wave
        for crossing in range(max_crossings + 1):
            hits = tracer.intersect(origin, d)
            miss = ~hits.hit
            sky[els] += np.bincount(element_i[miss] - start, weights=weight[miss, 0],
                                    minlength=els.size)
            sky_shortwave[els] += np.bincount(element_i[miss] - start, weights=weight[miss, 1],
                                              minlength=els.size)
            hit = hits.hit
            target = face_offset[hits.object[hit]] + hits.primitive[hit]
            tau = np.zeros((target.size, 2))
            if see_through is not None and crossing < max_crossings and target.size:
                given = np.asarray(see_through(hits.object[hit], hits.primitive[hit],
                                               hits.position[hit]), float)
                tau[:] = np.clip(given.reshape(target.size, -1), 0.0, 1.0)
            element_j = elements.face_element[target]
            to_element = element_j >= 0
            stays = weight[hit, 0] * (1.0 - tau[:, 0])
            rows.append(element_i[hit][to_element])
            cols.append(element_j[to_element])
            vals.append(stays[to_element])
            frows.append(element_i[hit][~to_element])
            fcols.append(target[~to_element])
            fvals.append(stays[~to_element])
            on = (tau > 0.0).any(axis=1)
            if not on.any():
                break
            # through the sheet: on from just past the hit, with the shares τ
            d = d[hit][on]
            origin = hits.position[hit][on] + epsilon * d
            element_i = element_i[hit][on]
            weight = weight[hit][on] * tau[on]

    def matrix(r, c, v, shape):
        if not r:
            return sparse.csr_array(shape)
        return sparse.coo_array((np.concatenate(v), (np.concatenate(r), np.concatenate(c))), shape=shape).tocsr()

    return Hemisphere(
        sky_view=sky,
        sky_view_shortwave=sky_shortwave,
        exchange=matrix(rows, cols, vals, (n_el, n_el)),
        fixed=matrix(frows, fcols, fvals, (n_el, n_faces)),
        samples=n_samples,
    )
