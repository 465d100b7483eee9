"""A stop asked for by SIGTERM or Ctrl-C that is never lost.

Python runs a signal handler in the main thread between two of its bytecodes. When that moment
falls inside a callback called from C — the JIT compiler's object-cache callback while numba
compiles a kernel, a ``__del__``, a weakref callback — the exception the handler raises is
printed as "Exception ignored" and dropped, and the run would go on to the end as if no signal
had come. So the handler also records the signal, and :func:`check`, called where work passes
anyway (each progress update, each file recorded, the end of a run), raises the stop again
until it is taken.

The command line installs the handler for its whole run (:func:`install`); the Python API
leaves signals to its caller.
"""

from __future__ import annotations

import signal
import threading

__all__ = ["check", "install", "requested", "reset", "restore"]

_SIGNALS = (signal.SIGTERM, signal.SIGINT)
_requested: int | None = None


def _stop(signum, frame):
    global _requested
    _requested = signum
    raise KeyboardInterrupt(f"signal {signum}")


def install() -> dict:
    """Handle SIGTERM and SIGINT by a recorded stop; the handlers they had (to give to
    :func:`restore`). Outside the main thread, where Python cannot set handlers, nothing."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    previous = {}
    for number in _SIGNALS:
        handler = signal.getsignal(number)
        if handler is not _stop:
            previous[number] = signal.signal(number, _stop)
    return previous


def restore(previous: dict) -> None:
    """Put back the handlers :func:`install` replaced."""
    for number, handler in previous.items():
        signal.signal(number, handler)


def requested() -> int | None:
    """The signal that asked for a stop, or None."""
    return _requested


def check() -> None:
    """Raise the stop a signal asked for, if any (KeyboardInterrupt, as the handler does)."""
    if _requested is not None:
        raise KeyboardInterrupt(f"signal {_requested}")


def reset() -> None:
    """Forget a stop that has been taken (a process that goes on after it)."""
    global _requested
    _requested = None
