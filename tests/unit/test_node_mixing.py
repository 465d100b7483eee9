"""The compiled node-mixing kernels against the numpy expressions they replace."""

import numpy as np
import pytest

from radscene.render.node_mixing import mix_rows, mix_sky


@pytest.fixture
def mixing():
    rng = np.random.default_rng(11)
    n, n_rows, n_nodes, n_b, n_k, s = 300, 5, 7, 4, 9, 4
    row = rng.integers(0, n_rows, n)
    index = rng.integers(0, n_nodes, (n, s))
    weight = rng.random((n, s))
    weight[rng.random((n, s)) < 0.3] = 0.0  # zero weights are skipped, not assumed
    weight[:, 0] += 0.1
    weight /= weight.sum(axis=1, keepdims=True)
    fractions = rng.random((n, n_k)) * (rng.random((n, n_k)) < 0.5)
    return row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k)


def test_mix_rows_matches_fancy_indexing(mixing):
    row, index, weight, _, rng, (n_rows, n_nodes, n_b, _k) = mixing
    table = rng.random((n_rows, n_nodes, n_b))
    expected = sum(weight[:, s, None] * table[row, index[:, s]] for s in range(index.shape[1]))
    assert mix_rows(table, row, index, weight) == pytest.approx(expected, rel=1e-12)


def test_mix_sky_matches_the_dense_contraction(mixing):
    row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k) = mixing
    table = rng.random((n_rows, n_nodes, n_b, n_k))
    dense = sum(weight[:, s, None, None] * table[row, index[:, s]] for s in range(index.shape[1]))
    expected = np.einsum("nbk,nk->nb", dense, fractions)
    assert mix_sky(table, row, index, weight, fractions) == pytest.approx(expected, rel=1e-12)


def test_empty_and_non_contiguous_inputs(mixing):
    row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k) = mixing
    table = rng.random((n_rows, n_b, n_nodes)).transpose(0, 2, 1)  # a view, as the renderer passes
    assert mix_rows(table, row[:0], index[:0], weight[:0]).shape == (0, n_b)
    out = mix_rows(table, row.astype(np.int32), index, weight)
    expected = sum(weight[:, s, None] * table[row, index[:, s]] for s in range(index.shape[1]))
    assert out == pytest.approx(expected, rel=1e-12)
    sky = rng.random((n_rows, n_nodes, n_b, n_k))
    assert mix_sky(sky, row[:0], index[:0], weight[:0], fractions[:0]).shape == (0, n_b)


def test_mix_terms_matches_the_term_functions(mixing):
    from radscene.render import terms
    from radscene.render.node_mixing import TERM_SLOTS, mix_terms

    row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k) = mixing
    n_hits = len(row)
    rank = rng.permutation(n_hits)[:120]  # a tile: some of the hits, in any order
    n = len(rank)
    material = row[rank]
    n_pairs = 6
    pair = rng.integers(0, n_pairs, n_hits)
    t = {"sun_diffuse": rng.random((n_rows, n_nodes, n_b)),
         "sun_specular": rng.random((n_rows, n_nodes, n_b)),
         "emission": rng.random((n_pairs, n_nodes, n_b)),
         "sky_diffuse": rng.random((n_rows, n_nodes, n_b, n_k)),
         "sky_specular": rng.random((n_rows, n_nodes, n_b, n_k)),
         "path": rng.random((1, n_nodes, n_b)), "transmittance": rng.random((1, n_nodes, n_b))}
    cos_i = rng.uniform(-0.5, 1.0, n)
    lit = (rng.random(n) < 0.8).astype(float)
    refl, emis = rng.uniform(0.5, 1.5, n), rng.uniform(0.5, 1.5, n)
    lobe = rng.random(n) * 3.0
    specular = rng.random(n) < 0.4
    sky_f, lobe_f = fractions[rank], rng.random((n, n_k))
    pixel = rng.permutation(500)[:n]
    pixel_weight = rng.uniform(0.2, 1.0, n)
    from radscene.render import TERMS

    assert TERM_SLOTS == TERMS  # the renderer's outputs, in its order
    out = np.full((len(TERM_SLOTS), n_b, 500), -7.0)
    tau = np.full((n_b, 500), -7.0)
    mix_terms(out, tau, pixel, pixel_weight, rank, material, pair, index, weight,
              cos_incidence=cos_i, lit=lit, reflectance=refl, emissivity=emis, lobe=lobe,
              specular=specular, sky_fractions=sky_f, lobe_fractions=lobe_f, **t)

    idx, wgt = index[rank], weight[rank]
    mix = lambda table, r: mix_rows(table, r, idx, wgt)  # noqa: E731
    spec_sun = np.where(specular[:, None], mix(t["sun_specular"], material), 0.0)
    spec_sky = np.where(specular[:, None],
                        mix_sky(t["sky_specular"], material, idx, wgt, lobe_f), 0.0)
    expected = {
        "sun_diffuse": terms.sun_diffuse(mix(t["sun_diffuse"], material), cos_i, lit, refl),
        "sun_specular": terms.sun_specular(spec_sun, lobe, lit, refl),
        "thermal_emission": terms.thermal_emission(mix(t["emission"], pair[rank]), emis),
        "sky_reflected": (mix_sky(t["sky_diffuse"], material, idx, wgt, sky_f) + spec_sky)
        * refl[:, None],
        "path_radiance": mix(t["path"], np.zeros(n, int)),
    }
    for slot, name in enumerate(TERM_SLOTS):
        got = out[slot][:, pixel].T
        assert got == pytest.approx(expected[name] * pixel_weight[:, None], rel=1e-12), name
    expected_tau = mix(t["transmittance"], np.zeros(n, int)) * pixel_weight[:, None]
    assert tau[:, pixel].T == pytest.approx(expected_tau, rel=1e-12)
    untouched = np.setdiff1d(np.arange(500), pixel)
    assert np.all(out[:, :, untouched] == -7.0) and np.all(tau[:, untouched] == -7.0)
    with pytest.raises(ValueError, match="out must be"):
        mix_terms(out[:4], tau, pixel, pixel_weight, rank, material, pair, index, weight,
                  cos_incidence=cos_i, lit=lit, reflectance=refl, emissivity=emis, lobe=lobe,
                  specular=specular, sky_fractions=sky_f, lobe_fractions=lobe_f, **t)


def test_mix_terms_takes_presummed_sky_sums(mixing):
    """With ``sky_sums`` (the diffuse sky already mixed, as illumination.sky_sums gives it)
    the terms are those of the fractions' path, and the fractions are not needed."""
    from radscene.render.node_mixing import mix_terms

    row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k) = mixing
    rank = rng.permutation(len(row))[:80]
    n = len(rank)
    material = row[rank]
    t = {"sun_diffuse": rng.random((n_rows, n_nodes, n_b)),
         "sun_specular": rng.random((n_rows, n_nodes, n_b)),
         "emission": rng.random((3, n_nodes, n_b)),
         "sky_diffuse": rng.random((n_rows, n_nodes, n_b, n_k)),
         "sky_specular": rng.random((n_rows, n_nodes, n_b, n_k)),
         "path": rng.random((1, n_nodes, n_b)), "transmittance": rng.random((1, n_nodes, n_b))}
    kw = dict(cos_incidence=rng.uniform(-0.5, 1.0, n), lit=np.ones(n),
              reflectance=rng.uniform(0.5, 1.5, n), emissivity=np.ones(n),
              lobe=rng.random(n), specular=rng.random(n) < 0.5,
              lobe_fractions=rng.random((n, n_k)), **t)
    pair = rng.integers(0, 3, len(row))
    pixel, pixel_weight = np.arange(n), np.ones(n)
    want, tau = np.zeros((5, n_b, n)), np.zeros((n_b, n))
    mix_terms(want, tau, pixel, pixel_weight, rank, material, pair, index, weight,
              sky_fractions=fractions[rank], **kw)
    sums = mix_sky(t["sky_diffuse"], material, index[rank], weight[rank], fractions[rank])
    got = np.zeros_like(want)
    mix_terms(got, tau, pixel, pixel_weight, rank, material, pair, index, weight,
              sky_fractions=None, sky_sums=sums, **kw)
    assert got == pytest.approx(want, rel=1e-12)
    with pytest.raises(ValueError, match="sky_sums must have shape"):
        mix_terms(got, tau, pixel, pixel_weight, rank, material, pair, index, weight,
                  sky_fractions=None, sky_sums=sums[:, :-1], **kw)


def test_mix_terms_mixes_the_path_radiance_over_its_azimuth_nodes(mixing):
    """The path radiance's table has a row per relative-azimuth node; each hit mixes two rows
    with its azimuth weights, then the path nodes as every term does; the other terms and
    the transmittance do not depend on the azimuth."""
    from radscene.render.node_mixing import mix_terms

    row, index, weight, fractions, rng, (n_rows, n_nodes, n_b, n_k) = mixing
    n_hits, n_a = len(row), 5
    rank = rng.permutation(n_hits)[:90]
    n = len(rank)
    t = {"sun_diffuse": rng.random((n_rows, n_nodes, n_b)),
         "sun_specular": rng.random((n_rows, n_nodes, n_b)),
         "emission": rng.random((3, n_nodes, n_b)),
         "sky_diffuse": rng.random((n_rows, n_nodes, n_b, n_k)),
         "sky_specular": rng.random((n_rows, n_nodes, n_b, n_k)),
         "path": rng.random((n_a, n_nodes, n_b)), "transmittance": rng.random((1, n_nodes, n_b))}
    path_index = rng.integers(0, n_a, (n_hits, 2))
    path_weight = rng.random((n_hits, 2))
    path_weight[rng.random(n_hits) < 0.2, 1] = 0.0  # on a node
    path_weight /= path_weight.sum(axis=1, keepdims=True)
    kw = dict(cos_incidence=rng.uniform(-0.5, 1.0, n), lit=np.ones(n),
              reflectance=rng.uniform(0.5, 1.5, n), emissivity=np.ones(n), lobe=rng.random(n),
              specular=rng.random(n) < 0.5, sky_fractions=fractions[row[rank]],
              lobe_fractions=rng.random((n, n_k)))
    pair = rng.integers(0, 3, n_hits)
    pixel, pixel_weight = np.arange(n), rng.uniform(0.5, 1.0, n)
    got, tau = np.zeros((5, n_b, n)), np.zeros((n_b, n))
    mix_terms(got, tau, pixel, pixel_weight, rank, row[rank], pair, index, weight,
              path_index=path_index, path_weight=path_weight, **kw, **t)
    idx, wgt = index[rank], weight[rank]
    expected = sum(path_weight[rank, a, None] * mix_rows(t["path"], path_index[rank, a], idx, wgt)
                   for a in range(2))
    assert got[4].T == pytest.approx(expected * pixel_weight[:, None], rel=1e-12)
    # the rest as without an azimuth axis (row 0 of a one-row path table)
    want = np.zeros_like(got)
    mix_terms(want, np.zeros_like(tau), pixel, pixel_weight, rank, row[rank], pair, index,
              weight, **kw, **{**t, "path": t["path"][:1]})
    assert got[:4] == pytest.approx(want[:4], rel=1e-12)
    with pytest.raises(ValueError, match="path_index and path_weight"):
        mix_terms(got, tau, pixel, pixel_weight, rank, row[rank], pair, index, weight,
                  path_index=path_index[:, :1], path_weight=path_weight, **kw, **t)
