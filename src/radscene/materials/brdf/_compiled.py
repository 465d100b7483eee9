"""Compiled (numba) fast paths of BRDF kernels, built on first use and cached on disk.

Each fast path is a parallel numba ufunc made from a scalar Python function of float64
arguments; numpy broadcasting comes with the ufunc. They are compiled the first time a model
evaluates (not at import, so importing radscene stays quick) and cached (``cache=True``) next to
the sources. Every compiled kernel has a numpy reference implementation beside it, which the
tests use as its oracle.
"""

from __future__ import annotations

from collections.abc import Callable

__all__ = ["parallel_ufunc"]

_UFUNCS: dict[str, Callable] = {}


def parallel_ufunc(scalar: Callable, n_args: int) -> Callable:
    """The parallel float64 ufunc of ``scalar`` (a function of ``n_args`` floats), compiled once.

    Parameters
    ----------
    scalar : callable
        A module-level function of ``n_args`` float64 scalars returning a float64, in the subset
        of Python numba compiles.
    n_args : int
        Its number of arguments.

    Returns
    -------
    callable
        A numpy ufunc (``target="parallel"``).
    """
    key = f"{scalar.__module__}.{scalar.__qualname__}"
    ufunc = _UFUNCS.get(key)
    if ufunc is None:
        import numba

        signature = f"float64({', '.join(['float64'] * n_args)})"
        ufunc = numba.vectorize([signature], nopython=True, target="parallel",
                                cache=True)(scalar)
        _UFUNCS[key] = ufunc
    return ufunc
