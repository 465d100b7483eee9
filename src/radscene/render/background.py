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
Each hit draws ``samples`` paths. At every vertex the incident direction is drawn from the
vertex's BRDF through the registry's ``sample`` (:mod:`radscene.materials.brdf`), weighted by
f cos θ / pdf. The sun at a vertex is a shadow ray (next-event estimation); its sky is the
sampled direction itself: the ray that continues the path, or at the last vertex an occlusion
ray, sees the sky where it leaves the scene upwards. From x itself only the scene counts
(sky directions are ``sky_reflected``'s). The random numbers are independent uniforms from a
generator seeded by the scene's ``seed``: the noise falls as 1/√samples and a render is
repeatable.

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
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from radscene.atmosphere import sky_node_weights

__all__ = ["BackgroundTables", "band_tables", "draws", "reflected", "reflected_reference",
           "sky_radiance", "brdf", "brdf_reference", "brdf_weight", "brdf_weight_reference",
           "directions",
           "tile_generator", "Pass", "WEIGHTING_TEMPERATURE",
           "CHUNK_SAMPLES"]

#: Blackbody temperature that weights the band-mean reflectance in thermal bands [K].
WEIGHTING_TEMPERATURE = 300.0
#: Paths (hits × samples) handled at once; the results do not depend on it.
CHUNK_SAMPLES = 1 << 18


@dataclass
class BackgroundTables:
    """Band tables of the background pass (see :func:`band_tables`).

    Attributes
    ----------
    diffuse, specular : (n_m, n_b) band-mean ρ_d and ρ_s of each material [-]
    exponent : (n_m,) Phong exponent [-]
    brdfs : {material index: BRDF model}, evaluated at ``centre``
    samplers : per material, the registry model whose ``sample`` draws the directions
    p_lobe : (n_m,) a plain material's sampler's probability of drawing from its lobe
    lobes : per material, a Phong model of unit lobe albedo (f of the lobe per unit ρ_s)
    centre : (n_b,) band centre wavelengths [um]
    sun_irradiance : (n_b,) ∫ S E_sun τ_so dλ on a plane normal to the beam [W m-2]
    sky : (n_b, n_k) ∫ S L_sky,k dλ at the sky table's nodes [W m-2 sr-1]
    sky_nodes : (zenith nodes, azimuth nodes) [deg]
    emission : (n_m, n_t, n_b) ∫ S ε_m B(λ, T_t) dλ [W m-2 sr-1]
    temperature_nodes : (n_t,) [K]
    face_offset, face_material, face_temperature : the scene's per-face tables
    """

    diffuse: np.ndarray
    specular: np.ndarray
    exponent: np.ndarray
    brdfs: dict
    samplers: list
    p_lobe: np.ndarray
    lobes: list
    centre: np.ndarray
    sun_irradiance: np.ndarray
    sky: np.ndarray
    sky_nodes: tuple
    emission: np.ndarray
    temperature_nodes: np.ndarray
    face_offset: np.ndarray
    face_material: np.ndarray
    face_temperature: np.ndarray

    @property
    def bands(self) -> int:
        return len(self.centre)


#: Largest number of temperature nodes of the emission table; beyond it the scene's
#: temperatures are spanned by this many evenly spaced nodes, linearly interpolated (over
#: 100 K, 0.2 K apart: a relative error below 1e-5 of the 3-14 um band emission).
MAX_TEMPERATURE_NODES = 512


def band_tables(materials, brdfs, quadrature, sun_spectra, sky, sky_nodes, thermal,
                face_offset, face_material, face_temperature) -> BackgroundTables:
    """The band tables of the pass.

    Parameters
    ----------
    materials : sequence of radscene.materials.Material
    brdfs : {material index: BRDF}
    quadrature : per band, (nodes [um], weights [um]) with the response in the weights
    sun_spectra : per band, E_sun τ_so at the nodes on a plane normal to the beam
        [W m-2 um-1] (zeros with the sun down)
    sky : (n_b, n_k) band sky radiance at the sky nodes [W m-2 sr-1]
    sky_nodes : (zenith nodes, azimuth nodes) [deg]
    thermal : (n_b,) bool, bands whose reflectances are weighted by a 300 K blackbody
    face_offset, face_material, face_temperature : per object and per face of the scene
    """
    from radscene.materials.brdf import make_brdf
    from radscene.radiometry import spectral_radiance

    n_m, n_b = len(materials), len(quadrature)
    diffuse, specular = np.zeros((n_m, n_b)), np.zeros((n_m, n_b))
    t_nodes = np.unique(np.asarray(face_temperature, dtype=float))
    if t_nodes.size > MAX_TEMPERATURE_NODES:
        t_nodes = np.linspace(t_nodes[0], t_nodes[-1], MAX_TEMPERATURE_NODES)
    emission = np.zeros((n_m, t_nodes.size, n_b))
    centre = np.zeros(n_b)
    sun = np.zeros(n_b)
    for b, (nodes, weights) in enumerate(quadrature):
        comps = [m.components(nodes) for m in materials]
        if thermal[b] or not np.any(sun_spectra[b] > 0.0):
            light = weights * (spectral_radiance(nodes, WEIGHTING_TEMPERATURE) if thermal[b]
                               else 1.0)
        else:
            light = weights * sun_spectra[b]
        light = light / light.sum()
        diffuse[:, b] = [c["diffuse_reflectance"] @ light for c in comps]
        specular[:, b] = [c["specular_reflectance"] @ light for c in comps]
        planck = spectral_radiance(nodes[None, :], t_nodes[:, None])  # (t, q)
        eps = np.array([c["emissivity"] for c in comps])  # (m, q)
        emission[:, :, b] = np.einsum("q,mq,tq->mt", weights, eps, planck)
        centre[b] = float(np.sum(weights * nodes) / np.sum(weights))
        sun[b] = float(weights @ sun_spectra[b])
    exponent = np.array([m.specular_exponent for m in materials], dtype=float)
    samplers, lobes, p_lobe = [], [], np.full(n_m, 0.5)
    for m in range(n_m):
        scale = max(1.0, float(diffuse[m].mean() + specular[m].mean()))  # rounding guard
        rd, rs = float(diffuse[m].mean()) / scale, float(specular[m].mean()) / scale
        if rd + rs > 0.0:  # as the phong model's mixture weight
            p_lobe[m] = rs / (rs + rd)
        samplers.append(brdfs.get(m) or make_brdf(
            {"type": "phong", "diffuse_reflectance": rd, "specular_reflectance": rs,
             "specular_exponent": exponent[m]}, key=f"materials[{m}]"))
        lobes.append(make_brdf({"type": "phong", "specular_reflectance": 1.0,
                                "specular_exponent": exponent[m]}, key=f"materials[{m}]"))
    return BackgroundTables(diffuse, specular, exponent, dict(brdfs), samplers, p_lobe, lobes,
                            centre,
                            sun, np.asarray(sky, dtype=float), sky_nodes, emission, t_nodes,
                            np.asarray(face_offset), np.asarray(face_material),
                            np.asarray(face_temperature, dtype=float))


def tile_generator(seed: int, first_sample: int) -> np.random.Generator:
    """The generator of the tile whose first ray sample is ``first_sample``: its draws
    depend on the scene's ``seed`` and the tile, not on the order tiles are rendered in."""
    return np.random.default_rng([int(seed) % (1 << 64), 0x62676E64, int(first_sample)])


def draws(rng: np.random.Generator, n_points: int, samples: int, bounces: int) -> np.ndarray:
    """The uniforms of ``n_points`` × ``samples`` paths: (n_points, samples, bounces + 1, 2);
    the direction drawn at x and at each of the ``bounces`` vertices beyond it."""
    return rng.random((n_points, samples, bounces + 1, 2))


def brdf_reference(tables, material, wi, wo, normal) -> np.ndarray:
    """Band-mean f(ω_i, ω_o) of points of several materials, from the registry's models:
    (N, n_b) [sr-1]."""
    out = np.zeros((len(material), tables.bands))
    for m in np.unique(material):
        sel = material == m
        model = tables.brdfs.get(int(m))
        if model is not None:
            out[sel] = model.f(wi[sel, None, :], wo[sel, None, :], tables.centre,
                               normal[sel, None, :])
            continue
        lobe = tables.lobes[m].f(wi[sel], wo[sel], None, normal[sel]) if np.any(
            tables.specular[m] > 0.0) else 0.0
        cos_i = np.einsum("nc,nc->n", wi[sel], normal[sel])
        cos_o = np.einsum("nc,nc->n", wo[sel], normal[sel])
        above = ((cos_i > 0.0) & (cos_o > 0.0))[:, None]
        out[sel] = np.where(above, tables.diffuse[m] / np.pi
                            + tables.specular[m] * np.reshape(lobe, (-1, 1)), 0.0)
    return out


def brdf_weight_reference(tables, material, wo, normal, u) -> tuple[np.ndarray, np.ndarray]:
    """Directions drawn from each point's BRDF by its registry model's ``sample``, and their
    weights f cos θ / pdf.

    Parameters
    ----------
    material : (N,) int
    wo : (N, 3) unit vectors from the point along the path back towards the sensor
    normal : (N, 3) unit normals facing ``wo``
    u : (N, 2) uniforms in [0, 1)

    Returns
    -------
    wi : (N, 3) unit directions
    weight : (N, n_b) f cos θ_i / pdf [-]; 0 below the horizon or where the density is 0
    """
    wi = np.zeros((len(material), 3))
    pdf = np.zeros(len(material))
    for m in np.unique(material):
        sel = material == m
        wi[sel], pdf[sel] = tables.samplers[m].sample(wo[sel], u[sel, 0], u[sel, 1],
                                                      float(np.median(tables.centre)),
                                                      normal[sel])
    cos_i = np.einsum("nc,nc->n", wi, normal)
    good = (cos_i > 0.0) & (pdf > 0.0) & np.isfinite(pdf)
    weight = np.zeros((len(material), tables.bands))
    if np.any(good):
        f = brdf_reference(tables, material[good], wi[good], wo[good], normal[good])
        weight[good] = f * (cos_i[good] / pdf[good])[:, None]
    return wi, weight


def _models(tables, material):
    """(plain, [(model material, its points)]): the points of plain materials (bool) and
    those of each material with a BRDF model."""
    plain = np.ones(len(material), dtype=bool)
    groups = []
    for m in tables.brdfs:
        sel = material == m
        if np.any(sel):
            plain &= ~sel
            groups.append((m, np.flatnonzero(sel)))
    return plain, groups


def brdf(tables, material, wi, wo, normal) -> np.ndarray:
    """:func:`brdf_reference`, the plain materials' in one compiled pass: (N, n_b) [sr-1]."""
    plain, groups = _models(tables, material)
    out = np.empty((len(material), tables.bands))
    if groups:
        for m, idx in groups:
            out[idx] = tables.brdfs[m].f(wi[idx, None, :], wo[idx, None, :], tables.centre,
                                         normal[idx, None, :])
        if np.any(plain):
            sub = np.empty((int(plain.sum()), tables.bands))
            _kernels().phong_values(*_rows(plain, wi, wo, normal), _int(material[plain]),
                                    tables.exponent, tables.diffuse, tables.specular, sub)
            out[plain] = sub
        return out
    _kernels().phong_values(*_rows(None, wi, wo, normal), _int(material), tables.exponent,
                            tables.diffuse, tables.specular, out)
    return out


def brdf_weight(tables, material, wo, normal, u) -> tuple[np.ndarray, np.ndarray]:
    """:func:`brdf_weight_reference`, the plain materials' directions drawn and weighed in
    one compiled pass (the same numbers)."""
    plain, groups = _models(tables, material)
    n = len(material)
    wi, weight = np.empty((n, 3)), np.empty((n, tables.bands))
    args = (tables.p_lobe, tables.exponent, tables.diffuse, tables.specular)
    if not groups:
        _kernels().phong_weights(*_rows(None, wo, normal, u), _int(material), *args, wi,
                                 weight)
        return wi, weight
    for _, idx in groups:
        wi[idx], weight[idx] = brdf_weight_reference(tables, material[idx], wo[idx],
                                                     normal[idx], u[idx])
    if np.any(plain):
        k = int(plain.sum())
        sub_wi, sub_w = np.empty((k, 3)), np.empty((k, tables.bands))
        _kernels().phong_weights(*_rows(plain, wo, normal, u), _int(material[plain]), *args,
                                 sub_wi, sub_w)
        wi[plain], weight[plain] = sub_wi, sub_w
    return wi, weight


def _kernels():
    from radscene.render import background_kernels

    return background_kernels


def _rows(sel, *arrays):
    """C-contiguous float64 copies (or views) of the rows ``sel`` (None: all) of arrays."""
    return tuple(np.ascontiguousarray(a if sel is None else a[sel], dtype=np.float64)
                 for a in arrays)


def _int(a):
    return np.ascontiguousarray(a, dtype=np.int64)


def sky_radiance(tables, directions) -> np.ndarray:
    """Band sky radiance along unit ``directions`` (N, 3): (N, n_b) [W m-2 sr-1]; 0 at and
    below the horizon."""
    d = np.asarray(directions, dtype=float)
    if len(d) == 0:
        return np.zeros((0, tables.bands))
    zenith = np.degrees(np.arccos(np.clip(d[:, 2], -1.0, 1.0)))
    azimuth = np.degrees(np.arctan2(d[:, 0], d[:, 1]))
    hats = sky_node_weights(zenith, azimuth, *tables.sky_nodes)
    return (hats @ tables.sky.T) * (d[:, 2] > 0.0)[:, None]


def _emission(tables, material, temperature) -> np.ndarray:
    """∫ S ε B(T) dλ of points: (N, n_b), linear in T between the table's nodes."""
    t = tables.temperature_nodes
    if t.size == 1:
        return tables.emission[material, 0]
    hi = np.clip(np.searchsorted(t, temperature), 1, t.size - 1)
    frac = np.clip((temperature - t[hi - 1]) / (t[hi] - t[hi - 1]), 0.0, 1.0)[:, None]
    return (1.0 - frac) * tables.emission[material, hi - 1] + frac * tables.emission[material, hi]


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


def _own(tracer, tables, v, sun, shadows, f=None) -> np.ndarray:
    """Emission and reflected sun of vertices towards the previous vertex: (N, n_b)."""
    out = _emission(tables, v.material, v.temperature) * v.emissivity[:, None]
    if not np.any(tables.sun_irradiance > 0.0) or len(out) == 0:
        return out
    sun = np.broadcast_to(sun, v.normal.shape)
    cos_s = np.einsum("nc,nc->n", v.normal, sun)
    lit = cos_s > 0.0
    if shadows and np.any(lit):
        idx = np.flatnonzero(lit)
        lit[idx] = ~tracer.occluded(v.origin[idx], sun[idx])
    if np.any(lit):
        values = (f or brdf)(tables, v.material[lit], sun[lit], v.to_previous[lit],
                             v.normal[lit])
        out[lit] += (values * (cos_s[lit] * v.reflectance[lit])[:, None]
                     * tables.sun_irradiance[None, :])
    return out


def reflected(tracer, tables, origin, normal, wo, material, sun, u, *, epsilon, shadows=True,
              texture: Callable | None = None) -> np.ndarray:
    """Background radiance reflected by surface points, at the surface: (N, n_b).

    Vectorised over the paths; the same estimator and random numbers as
    :func:`reflected_reference`.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    tables : BackgroundTables
    origin : (N, 3) points offset along their normals [m]
    normal : (N, 3) unit normals facing the sensor
    wo : (N, 3) unit vectors towards the sensor
    material : (N,) int
    sun : (3,), (1, 3) or (N, 3) unit vectors towards the sun
    u : (N, samples, bounces + 1, 2) uniforms (:func:`draws`)
    epsilon : float — offset of ray origins along the normal [m]
    shadows : bool — trace the vertices' shadow rays (else every vertex facing the sun is lit)
    texture : callable, optional — ``texture(object, position)`` → {"reflectance": Δρ,
        "emissivity": Δε} (N,) each, at vertices

    Returns
    -------
    numpy.ndarray
        (N, n_b) band radiance [W m-2 sr-1], without the target-to-sensor τ_a and x's Δρ.
    """
    n, samples, depth, _ = np.shape(u)
    bounces = depth - 1
    out = np.zeros((n, tables.bands))
    if n == 0 or samples == 0 or bounces == 0:
        return out
    sun = np.reshape(np.asarray(sun, dtype=float), (-1, 3))
    step = max(1, CHUNK_SAMPLES // samples)
    sky_on = bool(np.any(tables.sky > 0.0))
    for start in range(0, n, step):
        sl = slice(start, min(start + step, n))
        k = sl.stop - sl.start
        uu = u[sl].reshape(k * samples, depth, 2)
        point = np.arange(sl.start, sl.stop).repeat(samples)  # each path's point
        # every path's first direction; the weights only of those that meet the scene
        wi, valid = directions(tables, material, wo, normal, point, uu[:, 0])
        alive = np.flatnonzero(valid)
        hits = tracer.intersect(origin[point[alive]], wi[alive])
        alive, d, hits = alive[hits.hit], wi[alive[hits.hit]], _take(hits, hits.hit)
        at = point[alive]
        _, beta = brdf_weight(tables, material[at], wo[at], normal[at], uu[alive, 0])
        for bounce in range(1, bounces + 1):
            if len(alive) == 0:
                break
            v = _vertices(tables, hits, d, epsilon, texture)
            p_sun = sun if len(sun) == 1 else sun[point[alive]]
            _add(out, point[alive], beta * _own(tracer, tables, v, p_sun, shadows))
            wi_v, w_v = brdf_weight(tables, v.material, v.to_previous, v.normal,
                                    uu[alive, bounce])
            beta = beta * w_v * v.reflectance[:, None]
            go = np.flatnonzero(np.any(beta > 0.0, axis=1))
            alive, beta, o, d = alive[go], beta[go], v.origin[go], wi_v[go]
            if len(alive) == 0:
                break
            if bounce == bounces:  # the last vertex's sky: an occlusion ray
                if sky_on:
                    sky = np.flatnonzero(d[:, 2] > 0.0)
                    sky = sky[~tracer.occluded(o[sky], d[sky])]
                    _add(out, point[alive[sky]], beta[sky] * sky_radiance(tables, d[sky]))
                break
            hits = tracer.intersect(o, d)  # the vertex's sky, or the next vertex
            sky = ~hits.hit & (d[:, 2] > 0.0)
            if np.any(sky):
                _add(out, point[alive[sky]], beta[sky] * sky_radiance(tables, d[sky]))
            keep = hits.hit
            alive, beta, d, hits = alive[keep], beta[keep], d[keep], _take(hits, keep)
    out /= samples
    return out


def _add(out, rows, values):
    """out[rows] += values, rows repeating."""
    if len(rows) == 0:
        return
    for b in range(out.shape[1]):
        out[:, b] += np.bincount(rows, values[:, b], minlength=len(out))


def directions(tables, material, wo, normal, point, u) -> tuple[np.ndarray, np.ndarray]:
    """The directions :func:`brdf_weight` draws for paths from points, without the weights.

    ``point`` (P,) is each path's row of ``material``, ``wo`` and ``normal``; ``u`` (P, 2) its
    uniforms. Returns ω_i (P, 3) and whether each weight may be non-zero (P,) bool.
    """
    plain, groups = _models(tables, material[point])
    p = len(point)
    wi, valid = np.empty((p, 3)), np.empty(p, dtype=bool)
    reflects = np.any((tables.diffuse > 0.0) | (tables.specular > 0.0), axis=1)
    _kernels().phong_directions(*_rows(None, wo, normal), _int(point),
                                np.ascontiguousarray(u, dtype=np.float64), _int(material),
                                tables.p_lobe, tables.exponent, reflects, wi, valid)
    for _, idx in groups:  # materials with a BRDF model: through the registry
        at = point[idx]
        wi[idx], weight = brdf_weight_reference(tables, material[at], wo[at], normal[at],
                                                u[idx])
        valid[idx] = np.any(weight > 0.0, axis=1)
    return wi, valid


def _take(hits, keep):
    """The rows ``keep`` of a Hits batch (object, primitive, normal, position, hit)."""
    from radscene.geometry.raytracer import Hits

    return Hits(hits.distance[keep], hits.object[keep], hits.primitive[keep], hits.u[keep],
                hits.v[keep], hits.normal[keep], hits.position[keep], hits.hit[keep])


def reflected_reference(tracer, tables, origin, normal, wo, material, sun, u, *, epsilon,
                        shadows=True, texture: Callable | None = None) -> np.ndarray:
    """:func:`reflected`, one path at a time: the slow, obvious version (the tests' oracle)."""
    n, samples, depth, _ = np.shape(u)
    sun = np.reshape(np.asarray(sun, dtype=float), (-1, 3))
    out = np.zeros((n, tables.bands))
    for i in range(n):
        s_dir = sun[0] if len(sun) == 1 else sun[i]
        for s in range(samples):
            # the first direction, from x: only the scene counts
            wi, beta = brdf_weight_reference(tables, material[i:i + 1], wo[i:i + 1],
                                             normal[i:i + 1], u[i, s, 0][None])
            if not np.any(beta > 0.0):
                continue
            o, d = origin[i:i + 1], wi
            for bounce in range(1, depth):
                hits = tracer.intersect(o, d)
                if not hits.hit[0]:
                    if bounce > 1 and d[0, 2] > 0.0:
                        out[i] += beta[0] * sky_radiance(tables, d)[0]
                    break
                v = _vertices(tables, hits, d, epsilon, texture)
                out[i] += beta[0] * _own(tracer, tables, v, s_dir[None], shadows,
                                         brdf_reference)[0]
                d, w = brdf_weight_reference(tables, v.material, v.to_previous, v.normal,
                                             u[i, s, bounce][None])
                beta = beta * w * v.reflectance[0]
                if not np.any(beta > 0.0):
                    break
                o = v.origin
                if bounce == depth - 1 and d[0, 2] > 0.0 and not tracer.occluded(o, d)[0]:
                    out[i] += beta[0] * sky_radiance(tables, d)[0]
        out[i] /= max(samples, 1)
    return out


class Pass:
    """The background pass of one render, called once per tile of ray samples.

    Parameters
    ----------
    tracer : radscene.geometry.RayTracer
    tables : BackgroundTables
    samples, bounces : int — paths per hit, vertices per path (≥ 1)
    seed : int — the scene's seed; each tile's draws come from :func:`tile_generator`
    epsilon : float — offset of ray origins along the normal [m]
    shadows : bool — trace the vertices' shadow rays
    texture : callable, optional — as for :func:`reflected`
    """

    def __init__(self, tracer, tables, *, samples, bounces, seed, epsilon, shadows=True,
                 texture=None):
        if int(samples) < 1 or int(bounces) < 1:
            raise ValueError(f"samples and bounces must be >= 1; got {samples}, {bounces}")
        self.tracer, self.tables = tracer, tables
        self.samples, self.bounces, self.seed = int(samples), int(bounces), int(seed)
        self.epsilon, self.shadows, self.texture = float(epsilon), bool(shadows), texture

    def __call__(self, origin, normal, wo, material, sun, first_sample) -> np.ndarray:
        """(N, n_b) background radiance at the surface of a tile's hits (:func:`reflected`);
        ``first_sample`` is the index of the tile's first ray sample."""
        u = draws(tile_generator(self.seed, first_sample), len(material), self.samples,
                  self.bounces)
        return reflected(self.tracer, self.tables, origin, normal, wo, material, sun, u,
                         epsilon=self.epsilon, shadows=self.shadows, texture=self.texture)
