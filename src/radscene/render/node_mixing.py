"""Compiled per-sample mixing of the atmosphere's band tables between path nodes (numba).

The renderer integrates every spectral factor over each band once per *path node* (a
line-of-sight geometry of the atmosphere, :meth:`radscene.atmosphere.Atmosphere.path_nodes`);
each ray sample then mixes a few nodes with its weights. Done with numpy fancy indexing this
builds (samples × bands × sky nodes) temporaries per node; these kernels write the mixed band
values directly, skipping zero weights (the sky sum is a dense dot product over the sky nodes
per band, which vectorises better than skipping zero fractions). The numpy expressions they
replace are their oracle (tests/unit/test_node_mixing.py).
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["mix_rows", "mix_sky"]


@numba.njit(parallel=True, cache=True)
def _mix_rows(table, row, index, weight, out):
    n, n_s = index.shape
    n_b = table.shape[2]
    for i in numba.prange(n):
        r = row[i]
        for b in range(n_b):
            out[i, b] = 0.0
        for s in range(n_s):
            w = weight[i, s]
            if w == 0.0:
                continue
            j = index[i, s]
            for b in range(n_b):
                out[i, b] += w * table[r, j, b]


@numba.njit(parallel=True, cache=True, fastmath=True)
def _mix_sky(table, row, index, weight, fractions, out):
    n, n_s = index.shape
    n_b, n_k = table.shape[2], table.shape[3]
    for i in numba.prange(n):
        r = row[i]
        for b in range(n_b):
            acc = 0.0
            for s in range(n_s):
                w = weight[i, s]
                if w == 0.0:
                    continue
                j = index[i, s]
                dot = 0.0
                for k in range(n_k):
                    dot += fractions[i, k] * table[r, j, b, k]
                acc += w * dot
            out[i, b] = acc


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
