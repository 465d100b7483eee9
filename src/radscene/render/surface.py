"""The surfaces a render hits: per-face tables, the state at a tile's hits, their secondary rays.

:func:`scene_tables` builds once per scene the ray tracer and the per-face material and
temperature; :func:`surface_state` gathers for a tile of ray samples the hits' normals,
view and sun cosines; :func:`shadows` traces every hit's sun ray (Embree packets) and
:func:`secondary_rays` a tile's sky and specular-lobe fans
(:mod:`radscene.render.illumination`).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from radscene.render import illumination, sheets
from radscene.render.sun_track import sun_geometry

__all__ = ["SceneTables", "scene_tables", "surface_state", "hit_temperature", "textures",
           "shadows", "secondary_rays", "fan_shifts"]


class SceneTables:
    """Per-scene data shared by all observers: the ray tracer and per-face lookups (``tracer``:
    one already built of the objects' meshes, kept)."""

    def __init__(self, scene, tracer=None):
        from radscene.geometry import RayTracer

        self.scene = scene
        self.tracer = RayTracer([obj.mesh for obj in scene.objects]) if tracer is None else tracer
        sizes = [len(obj.face_material) for obj in scene.objects]
        self.face_offset = np.concatenate([[0], np.cumsum(sizes)[:-1]]).astype(np.int64)
        self.face_material = np.concatenate([obj.face_material for obj in scene.objects])
        self.face_temperature = np.concatenate([obj.face_temperature for obj in scene.objects])
        corners = [getattr(obj, "face_corner_temperature", None) for obj in scene.objects]
        self.face_corner_temperature = None if all(c is None for c in corners) else np.concatenate(
            [np.repeat(np.asarray(obj.face_temperature, float)[:, None], 3, axis=1) if c is None else np.asarray(c, float)
             for obj, c in zip(scene.objects, corners, strict=True)])
        # semi-transparent sheets: shadow rays pass them (render/sheets.py)
        self.sheet_object, self.shadow_tracer, self.sheet_tracer = sheets.tracers(
            scene.objects, self.tracer)
        lo, hi = self.tracer.bounds
        self.epsilon = 1e-4 + 2e-6 * float(np.linalg.norm(np.asarray(hi) - np.asarray(lo)))
        self.sun = sun_geometry(scene)
        self.exponent = np.array([m.specular_exponent for m in scene.materials], dtype=float)


def scene_tables(scene, tracer=None) -> SceneTables:
    """The ray tracer and per-face tables of a scene, built once and kept with the scene;
    given a ``tracer`` (of the objects' meshes as they are), built anew around it."""
    cached = scene.render_cache.get("tables")
    if cached is None or tracer is not None:
        cached = scene.render_cache["tables"] = SceneTables(scene, tracer)
    return cached


def textures(scene, obj, pos) -> dict[str, np.ndarray]:
    """The texture multipliers Δρ, Δε and Δτ [-] of hits on objects ``obj`` at positions
    ``pos`` (N, 3) [m]: ``{"reflectance", "emissivity", "transmittance"}``, (N,) each."""
    out = {k: np.ones(len(obj)) for k in ("reflectance", "emissivity", "transmittance")}
    for o, sobj in enumerate(scene.objects):
        if not sobj.textures:
            continue
        sel = obj == o
        if not np.any(sel):
            continue
        for kind, texture in sobj.textures.items():
            out[kind][sel] = texture.sample(pos[sel, 0], pos[sel, 1])
    return out


def hit_temperature(tables, hits, hit, hit_face):
    """The surface temperature at each hit [K]: its face's, or interpolated barycentrically
    between the face's corner temperatures where the scene gives them."""
    if tables.face_corner_temperature is None:
        return tables.face_temperature[hit_face]
    corner = tables.face_corner_temperature[hit_face]
    u = hits.u[hit].astype(float)
    v = hits.v[hit].astype(float)
    return (1.0 - u - v) * corner[:, 0] + u * corner[:, 1] + v * corner[:, 2]


def surface_state(tables, rays, hits, hit, hit_rank, sl, sun_dir, material, temperature):
    """The state at the hits of one tile of samples, or None where the tile has none.

    ``sun_dir`` is the unit vector towards the sun of every hit (in hit order), or one row
    for all; the state's ``sun`` is that of the tile's hits (or the one row). ``material``
    and ``temperature`` [K] are every hit's (in hit order); ``hit_rank`` each ray sample's
    index among the hits.
    """
    from radscene.render import kernels

    h = hit[sl]
    if not np.any(h):
        return None
    hidx = np.nonzero(h)[0] + sl.start
    rank = hit_rank[hidx]
    sun = sun_dir if len(sun_dir) == 1 else sun_dir[rank]
    nrm, wo, cos_v, cos_i, origin = kernels.surface_state(
        hits.normal, rays.directions, hits.position, hidx, tables.epsilon, sun)
    return SimpleNamespace(
        hidx=hidx, rank=rank, obj=hits.object[hidx], mat=material[rank],
        temp=temperature[rank], pos=hits.position[hidx], nrm=nrm, wo=wo, cos_v=cos_v,
        cos_i=cos_i, origin=origin, sun=sun)


def fan_shifts(seed, sl, hidx, specular):
    """The rotations of the sky and lobe fans of a tile's hits (Cranley–Patterson).

    Two uniforms per ray sample of the tile ``sl`` and fan, from a generator keyed by the
    scene's ``seed`` and the tile's first sample: a hit's rotations depend on its sample
    alone, not on what the tile's other samples hit, so a sequence's frames can keep the fans
    of the samples that nothing moved into (:mod:`radscene.render.frame_cache`).

    Parameters
    ----------
    seed : int — the scene's ``render.seed``
    sl : slice — the tile's ray samples
    hidx : (N,) int — the samples of its hits
    specular : (N,) bool — the hits that trace a lobe

    Returns
    -------
    sky : (N, 2) [-]
    lobe : (count of specular, 2) [-], or None where no hit is specular
    """
    key = np.random.SeedSequence([int(seed) % (1 << 64), 0x66616E73, int(sl.start)])
    draws = np.random.default_rng(key).random((2, sl.stop - sl.start, 2))
    at = np.asarray(hidx) - sl.start
    lobe = at[np.asarray(specular, dtype=bool)]
    return draws[0, at], (draws[1, lobe] if len(lobe) else None)


def shadows(tables, hits, hit, directions, sun_dir, trace, sun_up=True) -> np.ndarray:
    """1.0 for each hit (in hit order) where the sun is above its face (the normal turned to
    face the viewer) and, with ``trace``, seen from it; else 0.0. ``sun_dir`` is the unit
    vector towards the sun of each hit, or one row for all; ``sun_up`` False: it is below
    the horizon for every hit."""
    from radscene.render import kernels

    sel = slice(None) if hit.all() else hit
    pos, nrm, view = hits.position[sel], hits.normal[sel], directions[sel]
    sun_dir = np.reshape(sun_dir, (-1, 3))
    lit = np.zeros(len(pos))
    if not sun_up or len(pos) == 0:
        return lit
    tracer = tables.shadow_tracer
    todo = slice(None)  # the hits left to the checked query below: all of them, or
    if tracer.packets is not None:  # one pass, packets of eight neighbouring hits
        _traced, outside = kernels.packet_shadows(tracer.packets, np.ascontiguousarray(pos),
                                                  np.ascontiguousarray(nrm),
                                                  np.ascontiguousarray(view),
                                                  tracer.center, tracer.half_size,
                                                  tables.epsilon, sun_dir, trace, lit)
        if not outside:
            return lit
        todo = np.flatnonzero(lit < 0.0)  # those whose origin lies outside the scene's box
    pos, nrm, view = pos[todo], nrm[todo], view[todo]
    sun = np.broadcast_to(sun_dir if len(sun_dir) == 1 else sun_dir[todo], pos.shape)
    nrm = np.where((np.einsum("nc,nc->n", nrm, view) > 0.0)[:, None], -nrm, nrm)
    facing = np.einsum("nc,nc->n", nrm, sun) > 0.0
    out = np.zeros(len(pos))
    if trace:
        out[facing] = illumination.cast_shadow(tracer, pos[facing] + tables.epsilon
                                               * nrm[facing], sun[facing])
    else:
        out[facing] = 1.0
    lit[todo] = out
    return lit


def secondary_rays(tables, st, settings, sky_nodes, shifts, scratch, sky, shadow_pass,
                   cache=None):
    """Lit flags, sky and lobe rays of one tile's hits: (lit, sky, lobe fractions).

    ``shifts`` are the sky and lobe fans' rotations, drawn by the caller; ``scratch`` holds
    the fans' ray buffers between tiles. ``sky`` is None, or (table, index, weight): then the
    sky fan is folded straight into the reflected-sky band sums and the second item is
    (sums (N, n_b), sky view (N,)) instead of the fractions (N, K). The lobe fractions have
    no rows where the tile has no specular hit. ``shadow_pass`` is the future of
    :func:`shadows` for every hit of the render (run earlier on the same thread). Where the
    state has a ``fan`` (:class:`radscene.render.background.Fan`), its ``blocked`` flags are
    filled with the sky fan's directions that are not sky. ``cache``, where given, keeps the
    fans of the observer's last frame (:class:`radscene.render.frame_cache.FrameCache`): the
    same answers, traced again only where something moved through them (the ``blocked``
    flags of a kept fan are its kept answers).
    """
    lit = shadow_pass.result()[st.rank]
    fan = getattr(st, "fan", None)
    blocked = None if fan is None else fan.blocked
    if cache is not None:
        sky_out = cache.sky(tables.tracer, st, settings.sky_samples, sky_nodes, shifts[0], sky,
                            blocked=blocked)
    elif sky is None:
        sky_out = illumination.sky_fractions(tables.tracer, st.origin, st.nrm,
                                             settings.sky_samples, sky_nodes, None,
                                             shift=shifts[0], scratch=scratch, blocked=blocked)
    else:
        table, index, weight = sky
        sky_out = illumination.sky_sums(tables.tracer, st.origin, st.nrm, settings.sky_samples,
                                        sky_nodes, None, rank=st.rank, material=st.mat,
                                        index=index, weight=weight, table=table,
                                        shift=shifts[0], scratch=scratch, blocked=blocked)
    n_k = len(sky_nodes[0]) * len(sky_nodes[1])
    if shifts[1] is None:
        return lit, sky_out, np.zeros((0, n_k))
    lobe_f = np.zeros((len(st.mat), n_k))
    sel = st.specular
    axis = 2.0 * st.cos_v[sel, None] * st.nrm[sel] - st.wo[sel]
    if cache is not None:
        lobe_f[sel] = cache.lobe(tables.tracer, st, sel, axis, tables.exponent[st.mat[sel]],
                                 settings.specular_samples, sky_nodes, shifts[1])
        return lit, sky_out, lobe_f
    lobe_f[sel] = illumination.lobe_sky_fractions(
        tables.tracer, st.origin[sel], st.nrm[sel], axis, tables.exponent[st.mat[sel]],
        settings.specular_samples, sky_nodes, None, shift=shifts[1], scratch=scratch)
    return lit, sky_out, lobe_f
