"""Parameters of BRDF models: declaration, bounds, the documentation table."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Parameter", "REQUIRED", "parameter_table"]

#: Marker of a parameter without default.
REQUIRED: Any = object()


@dataclass(frozen=True)
class Parameter:
    """One parameter of a BRDF model, as documented in the module's table.

    Parameters
    ----------
    unit : str
        Unit as the docs write it in brackets, e.g. ``"-"``, ``"m s-1"``, ``"deg"``.
    meaning : str
        One line.
    default : object, optional
        Default value; :data:`REQUIRED` if it must be given.
    kind : {"spectrum", "number", "choice", "bool", "path", "text"}
        ``spectrum``: anything :func:`~radscene.materials.make_spectrum` takes (a number, a table
        mapping, a file), checked against the bounds at every tabulated wavelength;
        ``number``: a finite real; ``choice``: one of ``choices`` (case-insensitive). A default
        of None marks an optional parameter whose absence the model handles.
    low, high : float, optional
        Bounds; ``low_open``/``high_open`` make them exclusive.
    """

    unit: str
    meaning: str
    default: Any = REQUIRED
    kind: str = "number"
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple[str, ...] = ()

    def bounds_text(self) -> str:
        lo = "" if self.low is None else f"{self.low:g} {'<' if self.low_open else '<='} "
        hi = "" if self.high is None else f" {'<' if self.high_open else '<='} {self.high:g}"
        return f"{lo}value{hi}" if (lo or hi) else "finite"

    def violates(self, values: np.ndarray) -> np.ndarray:
        v = np.asarray(values, dtype=float)
        bad = ~np.isfinite(v)
        if self.low is not None:
            bad |= (v <= self.low) if self.low_open else (v < self.low)
        if self.high is not None:
            bad |= (v >= self.high) if self.high_open else (v > self.high)
        return bad


def parameter_table(cls) -> str:
    """The name | unit | default | meaning table of a model, as reStructuredText text."""
    rows = [(n, f"[{p.unit}]", "required" if p.default is REQUIRED else repr(p.default), p.meaning)
            for n, p in cls.PARAMETERS.items()]
    widths = [max(len(r[i]) for r in rows + [("parameter", "unit", "default", "meaning")])
              for i in range(4)]
    rule = "  ".join("=" * w for w in widths)
    head = "  ".join(h.ljust(w) for h, w in zip(("parameter", "unit", "default", "meaning"),
                                               widths, strict=True))
    body = ["  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)) for r in rows]
    return "\n".join([rule, head, rule, *body, rule])

