"""Reflected background: the radiance of the scene's own surfaces reflected by each hit.

The hemisphere above a surface hit x is split between the sky and the scene. Directions that
leave the scene upwards see the sky: their share is the ``sky_reflected`` term (the visible-sky
fractions of :mod:`radscene.render.illumination`). Directions that meet another surface y bring
y's radiance towards x; reflected by x, that is the ``background_reflected`` term — seed 000's
"adjacent object reflected radiance", OSSIM's "reflected background":

.. math::
    L_{bg}(x, \\omega_o) = \\Delta\\rho_x\\,\\tau_a \\int_{\\Omega_{scene}}
        f_x(\\omega_i, \\omega_o)\\,L(y, -\\omega_i)\\,\\cos\\theta_i\\,d\\omega_i ,

    L(y, \\omega) = \\Delta\\varepsilon_y L_e(y) + \\Delta\\rho_y\\,f_y(\\omega_s, \\omega)
        E_{sun}\\cos\\theta_s\\,\\mathrm{lit}(y) + \\Delta\\rho_y \\int_{\\Omega_{sky}}
        f_y L_{sky} \\cos\\theta\\,d\\omega + \\Delta\\rho_y \\int_{\\Omega_{scene}}
        f_y L(y', \\cdot) \\cos\\theta\\,d\\omega ,

with y = y(x, ω_i) the first surface along ω_i. The last integral is the next bounce: with
``bounces`` = N the estimator follows paths of up to N surface vertices beyond x (a path
tracer, Kajiya 1986), so N = 1 counts each neighbour's own emission, sun and sky, and N → ∞
the whole exchange between the surfaces (the geometric series of two facing plates).

Estimator
---------
Each hit draws ``samples`` paths. At every vertex beyond x the incident direction is drawn
from the vertex's BRDF through the registry's ``sample`` (:mod:`radscene.materials.brdf`),
weighted by f cos θ / pdf. At x itself a plain material's BRDF is split into its Lambertian
part and its Phong lobe, each drawn with its own density
(:mod:`radscene.render.background_first`): the diffuse directions of the first ``sky_samples``
paths are the render's own sky fan — the stratified, per-hit rotated cosine-weighted
directions whose visible sky ``sky_reflected`` counts —, those of further paths are drawn;
the lobe is drawn with probability ρ_s / (ρ_d + ρ_s). A material with a BRDF model draws
every first direction through its model. The sun at a vertex is a shadow ray (next-event
estimation); its sky is the sampled direction itself: the ray that continues the path, or at
the last vertex an occlusion ray, sees the sky where it leaves the scene upwards. From x
itself only the scene counts (sky directions are ``sky_reflected``'s). The other random
numbers are independent uniforms, counter-based (SplitMix64 of the path, vertex and dimension
under a key from the scene's ``seed`` and the tile; Steele, Lea & Flood 2014): a render is
repeatable, and a path's numbers are drawn only while it lives. The noise falls as
1/√samples or faster: the fan's directions are stratified.

Cost: most first directions leave the scene (93.5 % of the 16.8 M of the background
benchmark, ``benchmarks/bench_background.py``). The sky pass has already traced the fan's
directions, and flagged those that do not see the sky: only those are intersected here, for
their hit. Directions drawn beyond the fan (and the lobes') are drawn and traced as occlusion
queries in one compiled pass where Embree's packets are available
(:func:`radscene.render.background_kernels.first_blocked`, eight rays of a point to a packet),
then only those that meet the scene are intersected. The numbers are those of drawing every
direction and intersecting it (:func:`reflected_reference`).

Assumptions
-----------
* Reflections inside the pass use **band-mean** BRDFs: a plain material's ρ_d and ρ_s averaged
  over each band with the response times the light that reaches it — the solar irradiance at
  the ground in solar bands, a 300 K blackbody in bands centred at or beyond 2.5 µm; a BRDF
  model is evaluated at the band's centre wavelength. The vertices' own emission,
  ∫ S ε B(λ, T) dλ, is exact. Exact for materials that are grey within a band.
* The air between surfaces is transparent (τ = 1, no path radiance over the short path); the
  path from x to the sensor has the render's τ_a.
* The sun and sky at the vertices are those of the render's reference sun node.
* The emissivity of a vertex of a BRDF material is its material's 1 − ρ_d − ρ_s − τ.

References
----------
J. T. Kajiya, "The rendering equation", SIGGRAPH '86, 143-150 (1986),
doi:10.1145/15886.15902.
R. Cranley, T. N. L. Patterson, "Randomization of number theoretic methods for multiple
integration", SIAM J. Numer. Anal. 13(6), 904-914 (1976), doi:10.1137/0713071.
G. L. Steele, D. Lea, C. H. Flood, "Fast splittable pseudorandom number generators",
OOPSLA 2014, 453-472, doi:10.1145/2660193.2660195.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from radscene.atmosphere import sky_node_weights
from radscene.render import background_first as first
from radscene.render import background_kernels as kernels
from radscene.render.background_first import Fan
from radscene.render.background_tables import (
    WEIGHTING_TEMPERATURE,
    BackgroundTables,
    band_tables,
    brdf,
    brdf_reference,
    brdf_weight,
    brdf_weight_reference,
    directions,
    emission,
)

__all__ = ["BackgroundTables", "band_tables", "draws", "reflected", "reflected_reference",
           "reflected_parts", "reflected_reference_parts", "sky_radiance", "air_emission", "brdf", "brdf_reference", "brdf_weight", "brdf_weight_reference",
           "directions", "Draws", "Fan", "Pass", "for_render", "render_tables",
           "WEIGHTING_TEMPERATURE", "CHUNK_SAMPLES"]

#: Paths (hits × samples) handled at once; the results do not depend on it.
CHUNK_SAMPLES = 1 << 18


@dataclass(frozen=True)
class Draws:
    """The uniforms of a tile's paths: ``points`` × ``samples`` paths of ``bounces`` + 1
    vertices (the point itself and the vertices beyond it), two numbers per vertex.

    Counter-based (SplitMix64 of the path, vertex and dimension under the tile's ``key``):
    any path's numbers are drawn alone and in any order, so the vectorised pass draws them
    only for the paths still alive, and the reference pass path by path, the same numbers.
    """

    key: int
    points: int
    samples: int
    bounces: int

    def at(self, paths, bounce: int) -> np.ndarray:
        """(len(paths), 2) uniforms in [0, 1) of ``paths`` (point · samples + sample) at
        vertex ``bounce``."""
        from radscene.render import background_kernels

        paths = np.ascontiguousarray(paths, dtype=np.int64)
        out = np.empty((len(paths), 2))
        background_kernels.counter_uniforms(np.uint64(self.key), paths, int(bounce),
                                            self.bounces + 1, out)
        return out


def draws(seed: int, first_sample: int, n_points: int, samples: int, bounces: int) -> Draws:
    """The uniforms of the tile whose first ray sample is ``first_sample``: they depend on the
    scene's ``seed`` and the tile, not on the order tiles are rendered in."""
    key = np.random.SeedSequence([int(seed) % (1 << 64), 0x62676E64, int(first_sample)])
    return Draws(int(key.generate_state(1, np.uint64)[0]), int(n_points), int(samples),
                 int(bounces))


def sky_radiance(tables, directions, zenith=None, thermal=False) -> np.ndarray:
    """Band sky radiance along unit ``directions`` (N, 3): (N, n_b) [W m-2 sr-1]; 0 at and
    below the horizon. With ``zenith`` [deg], the sky at that zenith angle in the directions'
    azimuths instead (the horizon's: :func:`horizon_radiance`). With ``thermal``, only the
    sky's emission (``tables.sky_thermal``)."""
    d = np.asarray(directions, dtype=float)
    sky = tables.sky_thermal if thermal else tables.sky
    if len(d) == 0:
        return np.zeros((0, tables.bands))
    azimuth = np.degrees(np.arctan2(d[:, 0], d[:, 1]))
    if zenith is not None:
        return sky_node_weights(np.full(len(d), float(zenith)), azimuth,
                                *tables.sky_nodes) @ sky.T
    zenith = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
    hats = sky_node_weights(zenith, azimuth, *tables.sky_nodes)
    return (hats @ sky.T) * (d[:, 2] > 0.0)[:, None]


def _sky_pair(tables, directions):
    """(the sky, its emission or None where the sky emits nothing) along ``directions``."""
    emits = bool(np.any(tables.sky_thermal != 0.0))
    return (sky_radiance(tables, directions),
            sky_radiance(tables, directions, thermal=True) if emits else None)


@dataclass
class _Vertices:
    """Surface points met by a batch of rays, their normals turned to face the ray."""

    material: np.ndarray
    normal: np.ndarray
    origin: np.ndarray  # offset along the normal, for the rays that leave them
    to_previous: np.ndarray
    reflectance: np.ndarray  # texture multipliers Δρ, Δε
    emissivity: np.ndarray
    temperature: np.ndarray


def _vertices(tables, hits, directions, epsilon, texture) -> _Vertices:
    face = tables.face_offset[hits.object] + hits.primitive
    normal = hits.normal.astype(float)
    facing = np.einsum("nc,nc->n", normal, directions) > 0.0
    normal[facing] *= -1.0
    n = len(face)
    if texture is None:
        refl, emis = np.ones(n), np.ones(n)
    else:
        tex = texture(hits.object, hits.position)
        refl, emis = tex["reflectance"], tex["emissivity"]
    return _Vertices(tables.face_material[face], normal, hits.position + epsilon * normal,
                     -np.asarray(directions, dtype=float), refl, emis,
                     tables.face_temperature[face])


def _own(tracer, tables, v, sun, shadows, f=None, media=None, occluded=None, record=None):
    """Emission and reflected sun of vertices towards the previous vertex, and the emission
    alone: (N, n_b) each; the sun through the ``media``'s volumes where given; ``f`` and
    ``occluded`` default to :func:`brdf` and :func:`_occluded`. ``record``, where given, is
    called once as ``record(rows, origins, directions, lit)``: the vertices facing the sun
    (rows), their shadow rays and every vertex's sun flag."""
    emitted = emission(tables, v.material, v.temperature) * v.emissivity[:, None]
    out = emitted.copy()
    if not np.any(tables.sun_irradiance > 0.0) or len(out) == 0:
        if record is not None:
            record(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3)),
                   np.zeros(len(out), dtype=bool))
        return out, emitted
    sun = np.broadcast_to(sun, v.normal.shape)
    cos_s = np.einsum("nc,nc->n", v.normal, sun)
    lit = cos_s > 0.0
    facing = np.flatnonzero(lit)
    if shadows and len(facing):
        lit[facing] = ~(occluded or partial(_occluded, tracer))(v.origin[facing], sun[facing])
    if record is not None:
        record(facing, v.origin[facing], sun[facing], lit)
    if np.any(lit):
        values = (f or brdf)(tables, v.material[lit], sun[lit], v.to_previous[lit],
                             v.normal[lit])
        values = (values * (cos_s[lit] * v.reflectance[lit])[:, None]
                  * tables.sun_irradiance[None, :])
        if media is not None and media.volumes:
            values *= media.sun_transmittance(v.origin[lit], sun[lit])
        out[lit] += values
    return out, emitted


#: Zenith angle [deg] at which the sky is read for the radiance of the air along a
#: horizontal path (:func:`horizon_radiance`): just above the horizon.
HORIZON_ZENITH = 89.5


def horizon_radiance(tables, directions, thermal=False) -> np.ndarray:
    """The sky's band radiance at the horizon in the azimuths of ``directions`` (N, 3):
    (N, n_b) [W m-2 sr-1], the radiance of a long horizontal path of the ground's air; with
    ``thermal``, its emission alone."""
    return sky_radiance(tables, directions,
                        zenith=min(HORIZON_ZENITH, float(tables.sky_nodes[0][-1])),
                        thermal=thermal)


def air_path(tables, direction, distance):
    """τ (N, n_b) and L (N, n_b) of the air along segments of ``distance`` (N,) [m] between
    surfaces: e^{−k d} and (1 − e^{−k d}) L_horizon (:func:`~radscene.render.
    background_tables.air_extinction`, :func:`horizon_radiance`)."""
    k = tables.air_extinction
    trans = np.exp(-np.asarray(distance, dtype=float)[:, None] * k[None, :])
    if not np.any(k > 0.0):
        return trans, np.zeros_like(trans)
    return trans, (1.0 - trans) * horizon_radiance(tables, direction)


def air_emission(tables, direction, transmittance):
    """The emission's part (N, n_b) [W m-2 sr-1] of the light of :func:`air_path` whose
    transmittance is ``transmittance`` (N, n_b): (1 − τ) L_horizon,thermal."""
    return (1.0 - transmittance) * horizon_radiance(tables, direction, thermal=True)


def _segment(media, origin, direction, distance, beta, out, rows, sky=None, tables=None):
    """A path segment through the ``media`` and, between surfaces (``distance`` given), the
    ground's air (:func:`air_path`, with ``tables``): adds β L (and β T L_sky where ``sky``
    is the sky at its end, :func:`_sky_pair`) to ``out``, the (total, thermal) sums, at
    ``rows``; returns β T, the weight beyond it. The volumes' radiance counts in the total,
    their emission also in the thermal sums (:mod:`radscene.render.sky_split`)."""
    total, heat = out
    if distance is not None and tables is not None:
        trans, light = air_path(tables, direction, distance)
        _add(total, rows, beta * light)
        if np.any(tables.sky_thermal != 0.0) and np.any(light != 0.0):
            _add(heat, rows, beta * air_emission(tables, direction, trans))
        beta = beta * trans
    if media is None:
        if sky is not None:
            _add(total, rows, beta * sky[0])
            if sky[1] is not None:
                _add(heat, rows, beta * sky[1])
        return beta
    trans, light, emission = media.along(origin, direction, distance, sheets=False, parts=True)
    beta_t = beta * trans
    _add(total, rows, beta * light if sky is None else beta * light + beta_t * sky[0])
    if sky is not None and sky[1] is not None:
        _add(heat, rows, beta * emission + beta_t * sky[1])
    elif np.any(emission != 0.0):
        _add(heat, rows, beta * emission)
    return beta_t


def reflected(tracer, tables, origin, normal, wo, material, sun, u, *, epsilon, shadows=True,
              texture: Callable | None = None, media=None, fan: Fan | None = None,
              kept=None) -> np.ndarray:
    """Background radiance reflected by surface points, at the surface: (N, n_b); the first
    of :func:`reflected_parts`, whose parameters it takes."""
    return reflected_parts(tracer, tables, origin, normal, wo, material, sun, u,
                           epsilon=epsilon, shadows=shadows, texture=texture, media=media,
                           fan=fan, kept=kept)[0]


def reflected_parts(tracer, tables, origin, normal, wo, material, sun, u, *, epsilon,
                    shadows=True, texture: Callable | None = None, media=None,
                    fan: Fan | None = None, kept=None, record=None, active=None
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Background radiance reflected by surface points, at the surface, and its
    self-emitted part: (N, n_b) each.

    Vectorised over the paths; the same estimator and random numbers as
    :func:`reflected_reference_parts`. The self-emitted part is what the paths bring of the
    vertices' emission, the sky's emission (``tables.sky_thermal``) and the air's
    (:func:`air_emission`); the rest is sunlight (seed 001 eq. 1's H and G).

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    tables : BackgroundTables
    origin : (N, 3) points offset along their normals [m]
    normal : (N, 3) unit normals facing the sensor
    wo : (N, 3) unit vectors towards the sensor
    material : (N,) int
    sun : (3,), (1, 3) or (N, 3) unit vectors towards the sun
    u : Draws — the paths' uniforms (:func:`draws`), N points
    epsilon : float — offset of ray origins along the normal [m]
    shadows : bool — trace the vertices' shadow rays (else every vertex facing the sun is lit)
    texture : callable, optional — ``texture(object, position)`` → {"reflectance": Δρ,
        "emissivity": Δε} (N,) each, at vertices
    media : radscene.render.media.Media, optional — the volumes every segment crosses (its
        transmittance and their own radiance) and that dim the vertices' sun
    fan : Fan, optional — the points' sky fans (from ``origin`` about ``normal``): the first
        diffuse directions of their first paths (:mod:`radscene.render.background_first`);
        without it every direction is drawn
    kept : optional — a sequence's last frame (:meth:`radscene.render.frame_cache.FrameCache.
        background`): whether each drawn first direction met the scene, taken where nothing
        moved through it; the fan's blocked directions come kept or traced with the fan
    record : optional — a key frame's record of the paths' rays beyond the fan and of their
        vertices' sun flags (:meth:`radscene.render.background_record.PathRecord.bind`);
        one-bounce paths
    active : (N,) bool, optional — the points whose paths are followed; the others' first
        directions are drawn (and, with ``kept``, answered) but not followed, and their rows
        stay zero. The random numbers are those of every point's paths

    Returns
    -------
    total, thermal : numpy.ndarray
        (N, n_b) band radiance [W m-2 sr-1], without the target-to-sensor τ_a and x's Δρ.
    """
    n, samples, bounces = u.points, u.samples, u.bounces
    out, heat = np.zeros((n, tables.bands)), np.zeros((n, tables.bands))
    if n == 0 or samples == 0 or bounces == 0:
        return out, heat
    sun = np.reshape(np.asarray(sun, dtype=float), (-1, 3))
    step = max(1, CHUNK_SAMPLES // samples)
    sky_on = bool(np.any(tables.sky > 0.0)) or (media is not None and bool(media.volumes))
    origin, normal, wo = (np.ascontiguousarray(a, dtype=np.float64) for a in (origin, normal, wo))
    material = np.ascontiguousarray(material, dtype=np.int64)
    for start in range(0, n, step):
        # the first directions that meet the scene, with their weights
        paths, point, d, hits, beta = first.first_vertices(
            tracer, tables, origin, normal, wo, material, u, fan, start, min(start + step, n),
            kept, None if record is None else (
                lambda p, directions: record.rays(p, origin[p], directions)), active)
        alive = np.arange(len(paths))  # rows of paths
        beta = _segment(media, origin[point], d, hits.distance, beta, (out, heat), point,
                        tables=tables)
        for bounce in range(1, bounces + 1):
            if len(alive) == 0:
                break
            v = _vertices(tables, hits, d, epsilon, texture)
            p_sun = sun if len(sun) == 1 else sun[point[alive]]
            seen = None if record is None else partial(
                _record_vertices, record, point[alive],
                paths[alive] % samples + samples * (paths[alive] >= n * samples))
            own, emitted = _own(tracer, tables, v, p_sun, shadows, media=media, record=seen)
            _add(out, point[alive], beta * own)
            _add(heat, point[alive], beta * emitted)
            wi_v, w_v = brdf_weight(tables, v.material, v.to_previous, v.normal,
                                    u.at(paths[alive], bounce))
            beta = beta * w_v * v.reflectance[:, None]
            go = np.flatnonzero(np.any(beta > 0.0, axis=1))
            alive, beta, o, d = alive[go], beta[go], v.origin[go], wi_v[go]
            if len(alive) == 0:
                break
            if bounce == bounces:  # the last vertex's sky: an occlusion ray
                if sky_on:
                    sky = np.flatnonzero(d[:, 2] > 0.0)
                    if record is not None:
                        record.rays(point[alive[sky]], o[sky], d[sky])
                    sky = sky[~_occluded(tracer, o[sky], d[sky])]
                    _segment(media, o[sky], d[sky], None, beta[sky], (out, heat),
                             point[alive[sky]], _sky_pair(tables, d[sky]))
                break
            hits = tracer.intersect(o, d)  # the vertex's sky, or the next vertex
            sky = ~hits.hit & (d[:, 2] > 0.0)
            if np.any(sky):
                _segment(media, o[sky], d[sky], None, beta[sky], (out, heat),
                         point[alive[sky]], _sky_pair(tables, d[sky]))
            keep = hits.hit
            alive, beta, d, hits = alive[keep], beta[keep], d[keep], first.take(hits, keep)
            beta = _segment(media, o[keep], d, hits.distance, beta, (out, heat), point[alive],
                            tables=tables)
    out /= samples
    heat /= samples
    return out, heat


def _record_vertices(record, point, key, rows, origins, directions, lit):
    """Record the vertices' shadow rays and sun flags (the ``record`` of :func:`_own`): the
    vertices of ``point``, ``key`` their path within the point (sample, and which part)."""
    record.rays(point[rows], origins, directions)
    record.lit(point, key, lit)


def _add(out, rows, values):
    """out[rows] += values, rows repeating (in their order)."""
    if len(rows) == 0:
        return
    kernels.add_rows(out, np.ascontiguousarray(rows, dtype=np.int64),
                     np.ascontiguousarray(values, dtype=np.float64))


def _occluded(tracer, origins, directions) -> np.ndarray:
    """``tracer.occluded(origins, directions)``, as Embree packets where the tracer has them
    and the origins lie in its box (then clipping the rays to the box changes nothing)."""
    local = None if tracer.packets is None or len(origins) == 0 else tracer.to_local(origins)
    if local is None:
        return tracer.occluded(origins, directions)
    d = np.asarray(directions, dtype=np.float64)
    d = d / np.linalg.norm(d, axis=1)[:, None]  # as RayTracer.occluded normalises
    return tracer.occluded_local(local, np.ascontiguousarray(d, dtype=np.float32))


def reflected_reference(tracer, tables, origin, normal, wo, material, sun, u, *, epsilon,
                        shadows=True, texture: Callable | None = None, media=None,
                        fan: Fan | None = None) -> np.ndarray:
    """:func:`reflected`, one path at a time: the first of :func:`reflected_reference_parts`,
    whose parameters it takes."""
    return reflected_reference_parts(tracer, tables, origin, normal, wo, material, sun, u,
                                     epsilon=epsilon, shadows=shadows, texture=texture,
                                     media=media, fan=fan)[0]


def reflected_reference_parts(tracer, tables, origin, normal, wo, material, sun, u, *,
                              epsilon, shadows=True, texture: Callable | None = None,
                              media=None, fan: Fan | None = None
                              ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`reflected_parts`, one path at a time: the slow, obvious version (the tests'
    oracle). Every first direction is intersected (the fan's ``blocked`` flags are not
    used)."""
    n, samples = u.points, u.samples
    sun = np.reshape(np.asarray(sun, dtype=float), (-1, 3))
    out = np.zeros((2, n, tables.bands))
    for i in range(n):
        s_dir = sun[0] if len(sun) == 1 else sun[i]
        for s in range(samples):
            # the first directions, from x: only the scene counts
            for path, wi, beta in first.first_reference(tables, material, wo, normal, u, fan,
                                                        i, s):
                if np.any(beta > 0.0):
                    out[:, i] += _path_reference(tracer, tables, origin[i:i + 1], wi, beta,
                                                 u, path, s_dir, epsilon, shadows, texture,
                                                 media)
        out[:, i] /= max(samples, 1)
    return out[0], out[1]


def _path_reference(tracer, tables, o, d, beta, u, path, sun, epsilon, shadows, texture,
                    media) -> np.ndarray:
    """The radiance (n_b,) that one path brings back along its first direction ``d`` (1, 3)
    from ``o``, with its first weight ``beta`` (1, n_b), and its self-emitted part: (2, n_b)."""
    out = np.zeros((2, tables.bands))
    depth = u.bounces + 1
    for bounce in range(1, depth):
        hits = tracer.intersect(o, d)
        if not hits.hit[0]:
            if bounce > 1 and d[0, 2] > 0.0:
                out += _sky_reference(tables, media, o, d, beta[0])
            break
        air, glow = air_path(tables, d, hits.distance)
        out += beta[0] * np.stack([glow[0], air_emission(tables, d, air)[0]])
        beta = beta * air
        trans, light, emission = _along_reference(media, o, d, hits.distance)
        out += beta[0] * np.stack([light, emission])
        beta = beta * trans
        v = _vertices(tables, hits, d, epsilon, texture)
        out += beta[0] * np.concatenate(_own(tracer, tables, v, sun[None], shadows,
                                             brdf_reference, media, tracer.occluded))
        d, w = brdf_weight_reference(tables, v.material, v.to_previous, v.normal,
                                     u.at([path], bounce))
        beta = beta * w * v.reflectance[0]
        if not np.any(beta > 0.0):
            break
        o = v.origin
        if bounce == depth - 1 and d[0, 2] > 0.0 and not tracer.occluded(o, d)[0]:
            out += _sky_reference(tables, media, o, d, beta[0])
    return out


def _sky_reference(tables, media, o, d, beta):
    """The sky that one path sees along ``d`` (1, 3) from ``o`` through the media, times
    ``beta`` (n_b,), and its emission: (2, n_b)."""
    trans, light, emission = _along_reference(media, o, d, None)
    return beta * np.stack([trans * sky_radiance(tables, d)[0] + light,
                            trans * sky_radiance(tables, d, thermal=True)[0] + emission])


def _along_reference(media, origin, direction, distance):
    """T (n_b,), L_v (n_b,) and the emission in L_v (n_b,) of one segment (T = 1, L = 0
    without media)."""
    if media is None:
        return 1.0, 0.0, 0.0
    trans, light, emission = media.along(origin, direction, distance, sheets=False, parts=True)
    return trans[0], light[0], emission[0]


class Pass:
    """The background pass of one render, called once per tile of ray samples.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    tables : BackgroundTables
    samples, bounces : int — paths per hit, vertices per path (≥ 1)
    seed : int — the scene's seed; each tile's uniforms come from :func:`draws`
    epsilon : float — offset of ray origins along the normal [m]
    shadows : bool — trace the vertices' shadow rays
    texture, media : optional — as for :func:`reflected`
    """

    def __init__(self, tracer, tables, *, samples, bounces, seed, epsilon, shadows=True,
                 texture=None, media=None):
        if int(samples) < 1 or int(bounces) < 1:
            raise ValueError(f"samples and bounces must be >= 1; got {samples}, {bounces}")
        self.tracer, self.tables = tracer, tables
        self.samples, self.bounces, self.seed = int(samples), int(bounces), int(seed)
        self.epsilon, self.shadows, self.texture = float(epsilon), bool(shadows), texture
        self.media = media if media is not None and media.volumes else None

    def __call__(self, origin, normal, wo, material, sun, first_sample, fan=None,
                 kept=None, record=None, active=None) -> tuple[np.ndarray, np.ndarray]:
        """(N, n_b) background radiance at the surface of a tile's hits and its self-emitted
        part (:func:`reflected_parts`); ``first_sample`` is the index of the tile's first ray
        sample, ``fan`` the hits' sky fans (:class:`Fan`) or None, ``kept`` as for
        :func:`reflected`, ``record`` and ``active`` as :func:`reflected_parts` takes
        them."""
        u = draws(self.seed, first_sample, len(material), self.samples, self.bounces)
        return reflected_parts(self.tracer, self.tables, origin, normal, wo, material, sun, u,
                               epsilon=self.epsilon, shadows=self.shadows,
                               texture=self.texture, media=self.media, fan=fan, kept=kept,
                               record=record, active=active)


def for_render(scene, tables, bset, bands, per_pixel, thermal, texture=None,
               media=None) -> Pass | None:
    """The pass of one render, or None where the scene's ``background_bounces`` is 0.

    ``tables`` are the integrator's scene tables (tracer, per-face material and temperature,
    epsilon), ``bset`` its band setup (quadrature, the reference sun's spectrum, the sky
    table); the ``background_samples`` of a pixel are shared among its ``per_pixel`` ray
    samples (at least one path each); ``thermal`` flags the bands whose reflectances are
    weighted by a 300 K blackbody; ``texture`` and ``media`` as for :func:`reflected`.
    """
    settings = scene.settings
    if settings.background_bounces == 0:
        return None
    pass_tables = render_tables(scene, tables, bset, thermal)
    pass_tables.air_extinction = bset.air_extinction  # the paths between surfaces only
    return Pass(tables.tracer, pass_tables, samples=-(-settings.background_samples // per_pixel),
                bounces=settings.background_bounces, seed=settings.seed,
                epsilon=tables.epsilon, shadows=settings.shadows, texture=texture,
                media=media)


def render_tables(scene, tables, bset, thermal) -> BackgroundTables:
    """The band tables (:func:`band_tables`) of one render: ``tables``, ``bset`` and
    ``thermal`` as for :func:`for_render`; also those that reflect the volumes' own radiance
    where the render has no background pass."""
    out = band_tables(scene.materials, scene.brdfs, bset.quadrature, bset.sun_spectra,
                      bset.coefficients.sky_view, bset.sky_nodes, thermal, tables.face_offset,
                      tables.face_material, tables.face_temperature)
    out.sky_thermal = bset.sky_split.view  # the sky's emission (sky_split.py)
    return out
