"""Compiled (numba) step of the heat balance: elimination of every stack, Newton on its surface
node and back-substitution, fused in one pass per block of elements.

The numpy path of :class:`radscene.thermal.HeatBalance` (``compiled=False``:
:meth:`ImplicitConduction.eliminate`, :func:`solve_surface_temperature`,
:meth:`ImplicitConduction.substitute`) does the same arithmetic over arrays of elements and is
the oracle of the tests; the two differ by rounding (here 1/e is multiplied, there e divides)
and by when Newton stops (here when the largest update in a block, there in all elements, is
below the tolerance), together by far less than the tolerance.

The coefficients of the eliminated tridiagonal systems depend only on an element's stack and
Δt. The compiled path therefore keeps the elements sorted by stack (``HeatBalance`` permutes
them in and out) and cuts them into blocks of at most ``BLOCK`` elements of one stack: within a
block the coefficients of a node are scalars, and each sweep runs over the block's contiguous
elements (independent of each other, so the processor overlaps them and can vectorise) rather
than down one element's nodes (a chain of dependent operations). The back-substitution offsets
overwrite the old temperatures in place. Blocks may run in parallel from
``PARALLEL_THRESHOLD`` elements on (:class:`Stepper`). Compiled on first use and cached on
disk (``cache=True``) next to this file.
"""

from __future__ import annotations

import time

import numba
import numpy as np

__all__ = ["BLOCK", "PARALLEL_THRESHOLD", "Stepper", "blocks_of"]

#: Most elements in a block.
BLOCK = 256
#: Below this many elements the serial kernels run: a parallel launch costs more than it saves,
#: and much more on a machine whose cores are busy.
PARALLEL_THRESHOLD = 20_000


def blocks_of(sorted_stack):
    """Blocks (first, stop, stack) [int64, (n_blocks, 3)] of at most ``BLOCK`` consecutive
    elements of one stack, for elements sorted by stack index ``sorted_stack``."""
    sorted_stack = np.asarray(sorted_stack)
    n = sorted_stack.size
    bounds = np.flatnonzero(np.diff(sorted_stack)) + 1
    rows = []
    for first, stop in zip(np.concatenate([[0], bounds]), np.concatenate([bounds, [n]]), strict=True):
        for j in range(int(first), int(stop), BLOCK):
            rows.append((j, min(int(stop), j + BLOCK), int(sorted_stack[first])))
    return np.array(rows, dtype=np.int64).reshape(-1, 3)


@numba.njit(cache=True)
def _step_blocks(first, stop, state, blocks, a, g, e, inverse_e, alpha, fixed, deep, inside, constant, slope, es, tolerance, max_iterations, solve, surface, offset):
    """Advance blocks ``first`` to ``stop`` (excluded) of the node-major ``state``
    (n_nodes, n_elements) [K] by one backward-Euler step.

    ``blocks`` from :func:`blocks_of`; the tables (n_nodes, n_stacks) from
    :class:`radscene.thermal.ImplicitConduction` of the stacks, ``inverse_e`` = 1/e. Per element
    j: eliminate from the bottom up (offsets stored in state[1:]), B in ``offset[j]``; with
    ``solve``, find T of c + B − es T⁴ − (m + A) T = 0 (c = constant[j], m = slope[j],
    A = e[0, s]) by Newton from the old surface temperature, store it in ``surface[j]`` and
    back-substitute. Newton stops when the largest update in a block is below ``tolerance``.
    Returns the number of blocks where it did not within ``max_iterations``.
    """
    n_nodes = state.shape[0]
    last = n_nodes - 1
    failures = 0
    for block in range(first, stop):
        j0, j1, s = blocks[block, 0], blocks[block, 1], blocks[block, 2]
        if fixed[s]:
            held = deep[s]
            for j in range(j0, j1):
                state[last, j] = held
        else:
            own, room = a[last, s] * inverse_e[last, s], inside[s] * inverse_e[last, s]
            for j in range(j0, j1):
                state[last, j] = own * state[last, j] + room
        for i in range(last - 1, 0, -1):
            own, below = a[i, s] * inverse_e[i, s], g[i, s] * inverse_e[i, s]
            for j in range(j0, j1):
                state[i, j] = own * state[i, j] + below * state[i + 1, j]
        a0, g0, e0 = a[0, s], g[0, s], e[0, s]
        for j in range(j0, j1):
            offset[j] = a0 * state[0, j] + g0 * state[1, j]
            surface[j] = state[0, j]
        if solve:
            converged = False
            for _ in range(max_iterations):
                largest = 0.0
                for j in range(j0, j1):
                    t = surface[j]
                    k = es[j]
                    m = slope[j] + e0
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
                down = alpha[i, s]
                for j in range(j0, j1):
                    state[i, j] = down * state[i - 1, j] + state[i, j]
    return failures


@numba.njit(cache=True)
def _substitute_blocks(first, stop, state, blocks, alpha, surface):
    """Blocks ``first`` to ``stop`` of :func:`substitute`."""
    n_nodes = state.shape[0]
    for block in range(first, stop):
        j0, j1, s = blocks[block, 0], blocks[block, 1], blocks[block, 2]
        for j in range(j0, j1):
            state[0, j] = surface[j]
        for i in range(1, n_nodes):
            down = alpha[i, s]
            for j in range(j0, j1):
                state[i, j] = down * state[i - 1, j] + state[i, j]


# The parallel kernels hand each thread a contiguous range of blocks. (They are functions of
# their own: numba's disk cache would mix up two dispatchers of one function.)
@numba.njit(parallel=True, cache=True)
def _parallel_step(n_threads, state, blocks, *args):
    per_thread = (blocks.shape[0] + n_threads - 1) // n_threads
    failures = 0
    for thread in numba.prange(n_threads):
        first = min(thread * per_thread, blocks.shape[0])
        failures += _step_blocks(first, min(first + per_thread, blocks.shape[0]), state, blocks, *args)
    return failures


@numba.njit(parallel=True, cache=True)
def _parallel_substitute(n_threads, state, blocks, alpha, surface):
    per_thread = (blocks.shape[0] + n_threads - 1) // n_threads
    for thread in numba.prange(n_threads):
        first = min(thread * per_thread, blocks.shape[0])
        _substitute_blocks(first, min(first + per_thread, blocks.shape[0]), state, blocks, alpha, surface)


class Stepper:
    """Runs :func:`_step_blocks` and :func:`_substitute_blocks` over all blocks, serially or
    in parallel.

    Below ``PARALLEL_THRESHOLD`` elements always serially. Above, the first four of every
    ``TRIAL_PERIOD`` steps alternate between the two and the faster one runs the rest of the
    period: on a machine whose cores are busy with other work the parallel kernels can be
    several times slower than the serial ones, and the load changes. The results are the same
    either way (the blocks do not interact).
    """

    #: Steps between two trials of both kernels.
    TRIAL_PERIOD = 100

    def __init__(self):
        self._count = 0
        self._times = {True: [], False: []}
        self.parallel = None

    def _choose(self, n_elements):
        if n_elements < PARALLEL_THRESHOLD or numba.get_num_threads() < 2:
            return False
        phase = self._count % self.TRIAL_PERIOD
        if phase < 4:
            return phase % 2 == 0  # parallel, serial, parallel, serial
        if phase == 4 and all(self._times.values()):
            self.parallel = min(self._times[True]) < min(self._times[False])
            self._times = {True: [], False: []}
        return bool(self.parallel)

    def step(self, state, blocks, *args):
        """Advance ``state``; arguments and return value of :func:`_step_blocks` after
        ``first, stop``."""
        parallel = self._choose(state.shape[1])
        trial = state.shape[1] >= PARALLEL_THRESHOLD and self._count % self.TRIAL_PERIOD < 4
        self._count += 1
        start = time.perf_counter()
        if parallel:
            failures = _parallel_step(numba.get_num_threads(), state, blocks, *args)
        else:
            failures = _step_blocks(0, blocks.shape[0], state, blocks, *args)
        if trial:
            self._times[parallel].append(time.perf_counter() - start)
        return failures

    def substitute(self, state, blocks, alpha, surface):
        """Back-substitution after :meth:`step` with ``solve=False``: the new surface
        temperatures ``surface`` [K] into state[0], the profile below from the stored offsets."""
        if state.shape[1] >= PARALLEL_THRESHOLD and self.parallel:
            _parallel_substitute(numba.get_num_threads(), state, blocks, alpha, surface)
        else:
            _substitute_blocks(0, blocks.shape[0], state, blocks, alpha, surface)
