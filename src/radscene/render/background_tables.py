"""Band tables and BRDF sampling of the reflected-background pass.

:func:`band_tables` integrates, once per render, what the pass needs per material and band:
the band-mean reflectances that its reflections use, the vertices' emission
∫ S ε B(λ, T) dλ on the scene's temperatures, the sun's band irradiance and the sky table.
The BRDF functions draw directions from each material's registry model (``*_reference``:
through its ``sample``, ``pdf`` and ``f``) or, for plain materials, from the compiled
kernels of :mod:`radscene.render.background_kernels`, which give the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["BackgroundTables", "band_tables", "sampling_wavelengths", "brdf", "brdf_reference",
           "brdf_weight",
           "brdf_weight_reference", "directions", "emission", "WEIGHTING_TEMPERATURE",
           "MAX_TEMPERATURE_NODES"]

#: Blackbody temperature that weights the band-mean reflectance in thermal bands [K].
WEIGHTING_TEMPERATURE = 300.0


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
    air_extinction : (n_b,) the air's extinction coefficient at the ground [m-1], which
        dims the paths between surfaces (:func:`air_extinction`; zeros: clear air)
    sky_thermal : (n_b, n_k) the emission's part of ``sky`` [W m-2 sr-1] (zeros: none;
        :mod:`radscene.render.sky_split`)
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
    air_extinction: np.ndarray | None = None
    sky_thermal: np.ndarray | None = None

    def __post_init__(self):
        if self.air_extinction is None:
            self.air_extinction = np.zeros(len(self.centre))
        if self.sky_thermal is None:
            self.sky_thermal = np.zeros_like(self.sky)

    @property
    def bands(self) -> int:
        return len(self.centre)


#: Largest number of temperature nodes of the emission table; beyond it the scene's
#: temperatures are spanned by this many evenly spaced nodes, linearly interpolated (over
#: 100 K, 0.2 K apart: a relative error below 1e-5 of the 3-14 um band emission).
MAX_TEMPERATURE_NODES = 512


#: Wavelengths over which a material's diffuse and specular reflectances are averaged for its
#: sampler's lobe weight [um].
SAMPLING_WAVELENGTHS = np.geomspace(0.4, 14.0, 64)


def sampling_wavelengths(material) -> np.ndarray:
    """The wavelengths of :data:`SAMPLING_WAVELENGTHS` where ``material`` is defined [um]; a
    material tabulated over a narrower range than any two of them (a visible-only table) is
    averaged at its range's ends and middle. Neither depends on the bands rendered."""
    lo, hi = material.wavelength_range
    inside = SAMPLING_WAVELENGTHS[(SAMPLING_WAVELENGTHS >= lo) & (SAMPLING_WAVELENGTHS <= hi)]
    return inside if inside.size >= 2 else np.array([lo, 0.5 * (lo + hi), hi])


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
    # the samplers' lobe weights from each material's mean over a fixed grid, not over the
    # pass's bands: a spectral cube rendered a few channels at a time then draws the same
    # directions in every pass (the weights f cos / pdf carry the bands' own reflectances)
    fixed = [m.components(sampling_wavelengths(m)) for m in materials]
    for m in range(n_m):
        d_mean = float(np.mean(fixed[m]["diffuse_reflectance"]))
        s_mean = float(np.mean(fixed[m]["specular_reflectance"]))
        scale = max(1.0, d_mean + s_mean)  # rounding guard
        rd, rs = d_mean / scale, s_mean / scale
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


#: Height of the vertical path whose optical depth gives the air's extinction at the ground
#: (:func:`air_extinction`) [m].
AIR_LAYER = 100.0


def air_extinction(atmosphere, altitude, quadrature) -> np.ndarray:
    """The air's band extinction coefficient at the ground, (n_b,) [m-1]: the optical depth
    −ln τ of the vertical path from ``altitude`` [m] up :data:`AIR_LAYER` over its height,
    averaged over each band's ``quadrature`` (nodes [um], weights). It dims a path of length
    d between two surfaces by e^{−k d}; the path's own radiance is (1 − e^{−k d}) times the
    sky's at the horizon in its direction, the radiance of a long horizontal path of the
    same air. Zeros for an engine whose spectra do not depend on the path
    (``geometry_dependent`` False: vacuum, or the user's own ``uniform`` spectra)."""
    out = np.zeros(len(quadrature))
    if not getattr(atmosphere, "geometry_dependent", False):
        return out
    for b, (nodes, weights) in enumerate(quadrature):
        tau = np.asarray(atmosphere.path(altitude + AIR_LAYER, altitude, 0.0,
                                         nodes).transmittance, dtype=float).ravel()
        with np.errstate(divide="ignore"):
            k = -np.log(np.clip(tau, 1e-300, 1.0)) / AIR_LAYER
        out[b] = float(weights @ k / weights.sum())
    return out


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


def emission(tables, material, temperature) -> np.ndarray:
    """∫ S ε B(T) dλ of points: (N, n_b), linear in T between the table's nodes."""
    t = tables.temperature_nodes
    if t.size == 1:
        return tables.emission[material, 0]
    hi = np.clip(np.searchsorted(t, temperature), 1, t.size - 1)
    frac = np.clip((temperature - t[hi - 1]) / (t[hi] - t[hi - 1]), 0.0, 1.0)[:, None]
    return (1.0 - frac) * tables.emission[material, hi - 1] + frac * tables.emission[material, hi]
