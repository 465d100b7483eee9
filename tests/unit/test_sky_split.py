"""radscene.render.sky_split: which bands pay a second sky contraction, and the parts of a
layer from its thermal part."""

from __future__ import annotations

import numpy as np
import pytest

from radscene.render.sky_split import PART_LAYERS, PART_NAMES, SkySplit, part_layers


def _split():
    """Four bands: sunlight only, both, emission only, neither."""
    n_m, n_b, n_j, n_k = 2, 4, 3, 5
    split = SkySplit(n_m, n_b, n_j, n_k)
    rng = np.random.default_rng(1)
    weights = np.full(6, 0.1)
    rho = (rng.random((n_m, 6)), rng.random((n_m, 6)))
    tau = rng.random((n_j, 6))
    sky = rng.random((n_k, 6))
    zero = np.zeros((n_k, 6))
    for b, (solar, thermal) in enumerate([(sky, zero), (sky, 0.5 * sky), (zero, sky),
                                          (zero, zero)]):
        split.add(b, slice(0, n_j), (solar, thermal), rho, tau, weights)
    split.finish()
    return split, rho, tau, sky


def test_only_bands_with_both_parts_are_split():
    split, rho, tau, sky = _split()
    assert split.solar.tolist() == [True, True, False, False]
    assert split.thermal.tolist() == [False, True, True, False]
    assert split.split.tolist() == [1]
    assert split.diffuse.shape == (2, 3, 1, 5) and split.diffuse.flags.c_contiguous
    want = np.einsum("mq,jq,kq->mjk", rho[0], tau, 0.5 * sky)
    assert split.diffuse[:, :, 0] == pytest.approx(want, rel=1e-12)
    assert split.view[1] == pytest.approx(0.5 * sky @ np.full(6, 0.1), rel=1e-12)
    assert np.all(split.view[0] == 0.0)


def test_fused_table_appends_the_split_bands():
    split, *_ = _split()
    table = np.ones((2, 3, 4, 5))
    fused = split.fused_table(table)
    assert fused.shape == (2, 3, 5, 5)
    assert np.array_equal(fused[:, :, 4], split.diffuse[:, :, 0])
    sums, extra = split.columns(np.arange(10.0).reshape(2, 5), 4)
    assert sums.tolist() == [[0, 1, 2, 3], [5, 6, 7, 8]] and extra.tolist() == [[4], [9]]
    assert split.columns(np.zeros((2, 4)), 4)[1] is None


def test_part_layers():
    split, *_ = _split()
    layer = np.array([[1.0, 2.0], [3.0, 4.0], [5.0, 6.0], [0.0, 0.0]])
    solar, thermal = part_layers(layer, np.array([[1.0, 0.5]]), split.solar, split.thermal,
                                 split.split)
    assert thermal.tolist() == [[0.0, 0.0], [1.0, 0.5], [5.0, 6.0], [0.0, 0.0]]
    assert solar.tolist() == [[1.0, 2.0], [2.0, 3.5], [0.0, 0.0], [0.0, 0.0]]
    solar, thermal = part_layers(layer, 0.25 * layer, None, None, None)
    assert np.array_equal(solar + thermal, layer)


def test_part_names():
    assert PART_NAMES == ("sky_reflected_solar", "sky_reflected_thermal",
                          "background_reflected_solar", "background_reflected_thermal")
    assert list(PART_LAYERS) == ["sky_reflected", "background_reflected"]
