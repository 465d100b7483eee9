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
