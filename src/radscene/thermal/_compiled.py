"""Compiled (numba) step of the heat balance: elimination of every stack, Newton on its surface
node and back-substitution, fused in one pass per element.

The numpy path of :class:`radscene.thermal.HeatBalance` (``compiled=False``:
:meth:`ImplicitConduction.eliminate`, :func:`solve_surface_temperature`,
:meth:`ImplicitConduction.substitute`) does the same arithmetic in the same order over arrays of
elements and is the oracle of the tests; the two differ only in when Newton stops (here per
element, there when the largest update of all is below the tolerance), by less than the
tolerance.

The coefficients of the eliminated tridiagonal systems depend only on an element's stack and
Δt, so they are passed per stack (node-major tables, (n_nodes, n_stacks)) with each element's
stack index, and the back-substitution offsets overwrite the old temperatures in place: a step
streams the node-major state once, and the tables stay in cache. Compiled on first use and
cached on disk (``cache=True``) next to this file.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["balance_step", "substitute"]


#: Elements per block: each sweep runs over a block's elements (independent, so the processor
#: overlaps them) rather than down one element's nodes (a chain of dependent divisions).
BLOCK = 256


def _balance_step(state, stack, a, g, e, inverse_e, alpha, fixed, deep, inside, constant, slope, es, tolerance, max_iterations, solve, surface, offset):
    """Advance the node-major ``state`` (n_nodes, n_elements) [K] by one backward-Euler step.

    Per element j of stack s: eliminate from the bottom up (offsets stored in state[1:]), B in
    ``offset[j]``; with ``solve``, find T of c + B − es T⁴ − (m + A) T = 0 (c = constant[j],
    m = slope[j], A = e[0, s]) by Newton from the old surface temperature, store it in
    ``surface[j]`` and back-substitute. ``inverse_e`` is 1/e (a product instead of a
    division in the sweeps). Blocks of ``BLOCK`` elements run in parallel; Newton
    stops when the largest update in a block is below ``tolerance``. Returns the number of
    blocks where it did not within ``max_iterations``.
    """
    n_nodes, n_el = state.shape
    last = n_nodes - 1
    n_blocks = (n_el + BLOCK - 1) // BLOCK
    failures = 0
    for block in numba.prange(n_blocks):
        j0 = block * BLOCK
        j1 = min(n_el, j0 + BLOCK)
        for j in range(j0, j1):
            s = stack[j]
            if fixed[s]:
                state[last, j] = deep[s]
            else:
                state[last, j] = (a[last, s] * state[last, j] + inside[s]) * inverse_e[last, s]
        for i in range(last - 1, 0, -1):
            for j in range(j0, j1):
                s = stack[j]
                state[i, j] = (a[i, s] * state[i, j] + g[i, s] * state[i + 1, j]) * inverse_e[i, s]
        for j in range(j0, j1):
            s = stack[j]
            offset[j] = a[0, s] * state[0, j] + g[0, s] * state[1, j]
            surface[j] = state[0, j]
        if solve:
            converged = False
            for _ in range(max_iterations):
                largest = 0.0
                for j in range(j0, j1):
                    t = surface[j]
                    k = es[j]
                    m = slope[j] + e[0, stack[j]]
                    t3 = t * t * t
                    step = (constant[j] + offset[j] - k * t3 * t - m * t) / (4.0 * k * t3 + m)
                    surface[j] = t + step
                    largest = max(largest, abs(step))
                if largest < tolerance:
                    converged = True
                    break
            if not converged:
                failures += 1
            for j in range(j0, j1):
                state[0, j] = surface[j]
            for i in range(1, n_nodes):
                for j in range(j0, j1):
                    state[i, j] = alpha[i, stack[j]] * state[i - 1, j] + state[i, j]
    return failures


def _substitute(state, stack, alpha, surface):
    """Back-substitution after :func:`balance_step` with ``solve=False``: the new surface
    temperatures ``surface`` [K] into state[0], the profile below from the stored offsets."""
    n_nodes, n_el = state.shape
    n_blocks = (n_el + BLOCK - 1) // BLOCK
    for block in numba.prange(n_blocks):
        j0 = block * BLOCK
        j1 = min(n_el, j0 + BLOCK)
        for j in range(j0, j1):
            state[0, j] = surface[j]
        for i in range(1, n_nodes):
            for j in range(j0, j1):
                state[i, j] = alpha[i, stack[j]] * state[i - 1, j] + state[i, j]


#: Below this many elements the serial kernels run: a parallel launch costs more than it saves,
#: and much more on a machine whose cores are busy.
PARALLEL_THRESHOLD = 20_000

_parallel_step = numba.njit(parallel=True, cache=True)(_balance_step)
_serial_step = numba.njit(cache=True)(_balance_step)
_parallel_substitute = numba.njit(parallel=True, cache=True)(_substitute)
_serial_substitute = numba.njit(cache=True)(_substitute)


def balance_step(state, *args):
    """:func:`_balance_step`, in parallel from ``PARALLEL_THRESHOLD`` elements on."""
    kernel = _parallel_step if state.shape[1] >= PARALLEL_THRESHOLD else _serial_step
    return kernel(state, *args)


def substitute(state, *args):
    """:func:`_substitute`, in parallel from ``PARALLEL_THRESHOLD`` elements on."""
    kernel = _parallel_substitute if state.shape[1] >= PARALLEL_THRESHOLD else _serial_substitute
    return kernel(state, *args)


def warm_up():
    """Compile (or load from the disk cache) both kernels on a one-element problem."""
    state = np.full((2, 1), 300.0)
    stack = np.zeros(1, np.int64)
    ones = np.ones((2, 1))
    balance_step(state, stack, ones, ones[:1], ones, ones, ones, np.zeros(1, np.bool_), np.zeros(1), np.zeros(1), np.ones(1),
                 np.ones(1), np.zeros(1), 1e-9, 50, True, np.zeros(1), np.zeros(1))
    substitute(state, stack, ones, np.full(1, 300.0))
