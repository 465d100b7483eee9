"""Compiled per-sample mixing of the atmosphere's band tables between path nodes (numba).

The renderer integrates every spectral factor over each band once per *path node* (a
line-of-sight geometry of the atmosphere, :meth:`radscene.atmosphere.Atmosphere.path_nodes`);
each ray sample then mixes a few nodes with its weights (and the path radiance also the
relative-azimuth nodes around its line of sight). Done with numpy fancy indexing this
builds (samples × bands × sky nodes) temporaries per node; these kernels write the mixed band
values directly, skipping zero weights (the sky sum is a dense dot product over the sky nodes
per band, which vectorises better than skipping zero fractions). :func:`mix_terms` does the
same mixing for every signature term of a tile of hits at once and multiplies in the terms'
geometry (:mod:`radscene.render.terms`), writing each term into the render's (term, band,
pixel) outputs: no per-term (samples × bands) arrays and no transposed copies. The numpy
expressions they replace are their oracle (tests/unit/test_node_mixing.py).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["mix_rows", "mix_sky", "mix_terms", "gather_band", "sky_sum", "TERM_SLOTS"]


@numba.njit(inline="always")
def _row_sample(table, r, index, weight, h, b):
    """Σ_s w_s table[r, idx[h, s], b] (zero weights skipped)."""
    acc = 0.0
    for s in range(index.shape[1]):
        w = weight[h, s]
        if w == 0.0:
            continue
        acc += w * table[r, index[h, s], b]
    return acc


@numba.njit(fastmath=True)  # not inlined: its callers' flags would replace fastmath
def _sky_sample(table, r, index, weight, h, fractions, i, b):
    """Σ_s w_s Σ_k table[r, idx[h, s], b, k] F[i, k] (zero weights skipped)."""
    acc = 0.0
    for s in range(index.shape[1]):
        w = weight[h, s]
        if w == 0.0:
            continue
        j = index[h, s]
        dot = 0.0
        for k in range(table.shape[3]):
            dot += fractions[i, k] * table[r, j, b, k]
        acc += w * dot
    return acc


@numba.njit(parallel=True, cache=True)
def _mix_rows(table, row, index, weight, out):
    for i in numba.prange(index.shape[0]):
        for b in range(table.shape[2]):
            out[i, b] = _row_sample(table, row[i], index, weight, i, b)


@numba.njit(parallel=True, cache=True, fastmath=True)
def _mix_sky(table, row, index, weight, fractions, out):
    for i in numba.prange(index.shape[0]):
        for b in range(table.shape[2]):
            out[i, b] = _sky_sample(table, row[i], index, weight, i, fractions, i, b)


#: Slots of :func:`mix_terms`'s output: the signature terms, in the renderer's order.
TERM_SLOTS = ("sun_diffuse", "sun_specular", "thermal_emission", "sky_reflected",
              "path_radiance")


#: Hits per parallel work item of :func:`mix_terms`. Its outputs are rows a whole image apart,
#: which share cache sets: writing them hit by hit would evict a line per value, so each
#: item writes run after run of one band's values.
_TERM_CHUNK = 256


@numba.njit(parallel=True, cache=True)
def _mix_terms(rank, material, pair, index, weight, cos_i, lit, tex_r, tex_e, lobe, specular,
               sky_f, lobe_f, sun_d, sun_s, emission, sky_d, sky_s, path, tau, pixel,
               pixel_weight, presummed, sky_sums, path_index, path_weight, out, tau_out):
    n = rank.shape[0]
    for c in numba.prange((n + _TERM_CHUNK - 1) // _TERM_CHUNK):
        lo, hi = c * _TERM_CHUNK, min(n, (c + 1) * _TERM_CHUNK)
        geometry = np.empty(hi - lo)
        glint = np.empty(hi - lo)
        for i in range(lo, hi):
            geometry[i - lo] = max(cos_i[i], 0.0) * lit[i] * tex_r[i]
            glint[i - lo] = lobe[i] * lit[i] * tex_r[i]
        for b in range(sun_d.shape[2]):
            for i in range(lo, hi):
                h = rank[i]
                m = material[i]
                p = pixel[i]
                pw = pixel_weight[i]
                sun_specular = 0.0
                if presummed:
                    sky = sky_sums[i, b]
                else:
                    sky = _sky_sample(sky_d, m, index, weight, h, sky_f, i, b)
                if specular[i]:
                    sun_specular = _row_sample(sun_s, m, index, weight, h, b) * glint[i - lo]
                    sky += _sky_sample(sky_s, m, index, weight, h, lobe_f, i, b)
                out[0, b, p] = _row_sample(sun_d, m, index, weight, h, b) * geometry[i - lo] * pw
                out[1, b, p] = sun_specular * pw
                out[2, b, p] = (_row_sample(emission, pair[h], index, weight, h, b) * tex_e[i]
                                * pw)
                out[3, b, p] = sky * tex_r[i] * pw
                radiance = 0.0  # the path radiance: its azimuth nodes' rows, mixed
                for a in range(path_index.shape[1]):
                    wa = path_weight[h, a]
                    if wa != 0.0:
                        radiance += wa * _row_sample(path, path_index[h, a], index, weight, h, b)
                out[4, b, p] = radiance * pw
                tau_out[b, p] = _row_sample(tau, 0, index, weight, h, b) * pw


def _run(kernel, table, row, index, weight, *extra) -> np.ndarray:
    """Call ``kernel`` on contiguous float64/int64 copies; (N, n_b) out, n_b = table.shape[2]."""
    table = np.ascontiguousarray(table, dtype=np.float64)
    row = np.ascontiguousarray(row, dtype=np.int64)
    out = np.empty((row.size, table.shape[2]))
    if row.size:
        kernel(table, row, np.ascontiguousarray(index, dtype=np.int64),
               np.ascontiguousarray(weight, dtype=np.float64),
               *(np.ascontiguousarray(a, dtype=np.float64) for a in extra), out)
    return out


def mix_rows(table, row, index, weight) -> np.ndarray:
    """Σ_s w_s table[row, idx_s, :] for each sample.

    Parameters
    ----------
    table : (n_rows, n_nodes, n_b) band values per row (material, emission pair…) and node
    row : (N,) int — each sample's row
    index, weight : (N, S) — the nodes each sample mixes and their weights

    Returns
    -------
    numpy.ndarray
        (N, n_b) float64.
    """
    return _run(_mix_rows, table, row, index, weight)


def mix_sky(table, row, index, weight, fractions) -> np.ndarray:
    """Σ_s w_s Σ_k table[row, idx_s, :, k] F_k for each sample.

    Parameters
    ----------
    table : (n_rows, n_nodes, n_b, n_k) band values per row, path node, band and sky node
    row : (N,) int
    index, weight : (N, S) — path nodes and weights, as in :func:`mix_rows`
    fractions : (N, n_k) — each sample's sky fractions F_k

    Returns
    -------
    numpy.ndarray
        (N, n_b) float64.
    """
    return _run(_mix_sky, table, row, index, weight, fractions)


def gather_band(table, nodes) -> np.ndarray:
    """Σ_j w_j table[:, idx_j] for each sample: (N, n_b); ``table`` is (n_b, n_j) and
    ``nodes`` the samples' path nodes (``index``, ``weight``)."""
    return mix_rows(table.T[None], np.zeros(len(nodes.index), dtype=np.int64), nodes.index,
                    nodes.weight)


def sky_sum(table, row, nodes, fractions) -> np.ndarray:
    """Σ_j w_j Σ_k table[row, :, idx_j, k] F_k for each sample: (N, n_b).

    ``table`` is (n_rows, n_b, n_j, n_k) (rows: materials, or view cosines of a BRDF table),
    ``row`` and ``fractions`` (N,) and (N, n_k): terms.sky_reflected's sum without forming
    the (N, n_b, n_k) table of each sample.
    """
    return mix_sky(table.transpose(0, 2, 1, 3), row, nodes.index, nodes.weight, fractions)


def _f64(a):
    return np.ascontiguousarray(a, dtype=np.float64)


def _i64(a):
    return np.ascontiguousarray(a, dtype=np.int64)


def mix_terms(out, transmittance_out, pixel, pixel_weight, rank, material, pair, index, weight,
              *, cos_incidence, lit, reflectance, emissivity, lobe, specular, sky_fractions,
              lobe_fractions, sun_diffuse, sun_specular, emission, sky_diffuse, sky_specular, path,
              transmittance, sky_sums=None, path_index=None, path_weight=None) -> None:
    """The signature terms of a tile of hits, written straight into ``out``.

    For hit ``i`` of the tile, ``out[t, b, pixel[i]] = term_t[b] * pixel_weight[i]``, ``t``
    running over :data:`TERM_SLOTS`, and ``transmittance_out[b, pixel[i]]`` the same for the
    path transmittance; the terms are those of :mod:`radscene.render.terms`
    with their band coefficients mixed between path nodes as :func:`mix_rows` and
    :func:`mix_sky` do (the same sums in the same order):

    * sun_diffuse: mix(sun_diffuse[m]) · max(cos θ_i, 0) · lit · Δρ
    * sun_specular: mix(sun_specular[m]) · lobe · lit · Δρ where ``specular``, else 0
    * thermal_emission: mix(emission[pair]) · Δε
    * sky_reflected: (mix_sky(sky_diffuse[m], F) + mix_sky(sky_specular[m], G) where
      ``specular``) · Δρ
    * path_radiance: Σ_a u_a mix(path[a]), over the hit's relative-azimuth nodes ``a`` of
      weights ``u_a`` (``path_index``, ``path_weight``); the transmittance: mix(transmittance)

    Parameters
    ----------
    out : (5, n_b, P) float64 — written at the tile's pixels only
    transmittance_out : (n_b, P) float64 — the same
    pixel : (N,) int — each hit's column of ``out``; distinct (hits run in parallel)
    pixel_weight : (N,) float — each hit's weight in its pixel
    rank : (N,) int — each hit's row of ``pair``, ``index`` and ``weight``
    material : (N,) int — each hit's material
    pair : (H,) int — each hit's row of ``emission`` (its material and temperature)
    index, weight : (H, S) — path nodes and weights of every hit, as in :func:`mix_rows`
    cos_incidence, lit, reflectance, emissivity, lobe : (N,) float — cos θ_i, 1 where sunlit,
        Δρ, Δε, the Phong lobe (n+1)/(2π) cosⁿ θ_r
    specular : (N,) bool — the hit's material has a specular part
    sky_fractions, lobe_fractions : (N, n_k) float — F_k and G_k (G is read only where
        ``specular``; F not at all where ``sky_sums`` is given)
    sun_diffuse, sun_specular : (n_m, n_j, n_b); emission : (n_pairs, n_j, n_b)
    sky_diffuse, sky_specular : (n_m, n_j, n_b, n_k)
    path : (n_a, n_j, n_b) — per relative-azimuth node (one: no azimuth axis)
    transmittance : (1, n_j, n_b)
    sky_sums : (N, n_b) float, optional — mix_sky(sky_diffuse[m], F) already summed, as
        :func:`radscene.render.illumination.sky_sums` returns it
    path_index, path_weight : (H, A), optional — each hit's azimuth nodes (rows of ``path``)
        and their weights (:meth:`radscene.atmosphere.PathNodes.azimuth_mixing`); default:
        row 0 with weight 1
    """
    for name, a, shape in (("out", out, (len(TERM_SLOTS),) + transmittance_out.shape),
                           ("transmittance_out", transmittance_out, out.shape[1:])):
        if a.shape != shape or a.dtype != np.float64 or not a.flags.writeable:
            raise ValueError(f"{name} must be a writable float64 array of shape {shape}; got "
                             f"{a.dtype} {a.shape}")
    if len(rank) == 0:
        return
    presummed = sky_sums is not None
    if presummed:
        sky_sums = _f64(sky_sums)
        if sky_sums.shape != (len(rank), transmittance_out.shape[0]):
            raise ValueError(f"sky_sums must have shape {(len(rank), transmittance_out.shape[0])};"
                             f" got {sky_sums.shape}")
        sky_fractions = np.zeros((0, np.shape(sky_diffuse)[-1]))
    else:
        sky_sums = np.zeros((0, transmittance_out.shape[0]))
    if path_index is None:
        path_index, path_weight = np.zeros((len(pair), 1)), np.ones((len(pair), 1))
    if np.shape(path_index) != np.shape(path_weight) or len(path_index) != len(pair):
        raise ValueError(f"path_index and path_weight must both have shape ({len(pair)}, A); "
                         f"got {np.shape(path_index)} and {np.shape(path_weight)}")
    _mix_terms(_i64(rank), _i64(material), _i64(pair), _i64(index), _f64(weight),
               _f64(cos_incidence), _f64(lit), _f64(reflectance), _f64(emissivity), _f64(lobe),
               np.ascontiguousarray(specular, dtype=np.bool_), _f64(sky_fractions),
               _f64(lobe_fractions), _f64(sun_diffuse), _f64(sun_specular), _f64(emission),
               _f64(sky_diffuse), _f64(sky_specular), _f64(path), _f64(transmittance), _i64(pixel),
               _f64(pixel_weight), presummed, sky_sums, _i64(path_index), _f64(path_weight),
               out, transmittance_out)
