"""Progress bars for the Python API: ``radscene.render(scene, progress=True)``.

The public functions of :mod:`radscene.pipeline` take ``progress`` as

- a callable — called as before (``progress(done, total)``; the heat balance's
  ``progress(stage, done, total)``), no bar;
- ``True`` — a bar on standard error;
- ``False`` — nothing;
- ``None`` (the default) — a bar when Python runs interactively (IPython, a Jupyter kernel,
  the ``python`` prompt or ``python -i``), nothing in a script or a test.

The bar is tqdm's (``tqdm.auto``: a widget in Jupyter with ipywidgets, a text bar that redraws
in place elsewhere, Jupyter included) when tqdm is installed, else rich's
(:class:`rich.progress.Progress`; in Jupyter rich needs ipywidgets to redraw, and without it
prints the finished bar once).
"""

from __future__ import annotations

import contextlib
import importlib.util
import sys
import time
import warnings
from collections.abc import Callable, Iterator

__all__ = ["interactive", "progress_callback"]


def interactive() -> bool:
    """Whether Python runs interactively: IPython or a Jupyter kernel, the ``python`` prompt
    (``sys.ps1``), or ``python -i``."""
    if hasattr(sys, "ps1") or sys.flags.interactive:
        return True
    ipython = sys.modules.get("IPython")
    return ipython is not None and getattr(ipython, "get_ipython", lambda: None)() is not None


def _backend() -> str:
    return "tqdm" if importlib.util.find_spec("tqdm") is not None else "rich"


class _TqdmBar:
    def __init__(self, description: str, total: int):
        with warnings.catch_warnings():
            # without ipywidgets tqdm.auto falls back to its text bar, with a warning
            warnings.simplefilter("ignore")
            from tqdm.auto import tqdm
        self._bar = tqdm(total=total, desc=description, unit="", leave=True,
                         file=sys.stderr)

    def update(self, done: int, total: int, stage: str | None) -> None:
        if self._bar.total != total:
            self._bar.reset(total=total)
        if stage is not None:
            self._bar.set_description_str(stage, refresh=False)
        self._bar.n = done
        self._bar.refresh()

    def close(self) -> None:
        self._bar.close()


class _RichBar:
    def __init__(self, description: str, total: int):
        from rich.console import Console
        from rich.progress import Progress

        self._progress = Progress(console=Console(stderr=True))
        self._task = self._progress.add_task(description, total=total)
        self._progress.start()

    def update(self, done: int, total: int, stage: str | None) -> None:
        changes = {} if stage is None else {"description": stage}
        self._progress.update(self._task, completed=done, total=total, **changes)

    def close(self) -> None:
        self._progress.stop()


_BARS = {"tqdm": _TqdmBar, "rich": _RichBar}


@contextlib.contextmanager
def progress_callback(progress, description: str, *, stages: bool = False, when_interactive: bool = True,
                      backend: str | None = None) -> Iterator[Callable | None]:
    """The callable to hand to the renderer or the heat balance for a ``progress`` argument.

    Parameters
    ----------
    progress : callable, bool or None
        As the module docstring says.
    description : str
        The bar's label.
    stages : bool
        The callable is called as ``(stage, done, total)`` (the heat balance) rather than
        ``(done, total)``; the stage names the bar.
    when_interactive : bool
        Whether ``None`` shows a bar when Python runs interactively (False for the step API of
        a closed loop, where a bar per frame would be noise).
    backend : {"tqdm", "rich"}, optional
        Default tqdm when installed, else rich.

    Yields
    ------
    callable or None
        ``progress`` itself when it is callable; None when no bar is wanted; else a callable
        that moves a bar — drawn at its first call, so that work found done (a cached heat
        balance) draws none — closed when the block ends.
    """
    if callable(progress):
        yield progress
        return
    if progress is not None and not isinstance(progress, bool):
        raise TypeError(f"progress: True, False, None or a callable, not {type(progress).__name__}")
    if not (progress or (progress is None and when_interactive and interactive())):
        yield None
        return
    name = backend or _backend()
    if name not in _BARS:
        raise ValueError(f"progress backend {name!r}; known: {', '.join(_BARS)}")
    bar, last = None, 0.0

    def move(done, total, stage=None):
        nonlocal bar, last
        if bar is None:
            bar = _BARS[name](description if stage is None else stage, int(total))
        now = time.monotonic()
        if done >= total or now - last >= 0.1:  # redraw at most ten times a second
            last = now
            bar.update(int(done), int(total), stage)

    try:
        if stages:
            yield lambda stage, done, total: move(done, total, f"{description}: {stage}")
        else:
            yield move
    finally:
        if bar is not None:
            bar.close()
