"""The render benchmark's parts (``benchmarks/bench_render.py`` runs them).

* :mod:`.scene` — the benchmark scene: terrain, land cover, bands, sun and atmospheres;
* :mod:`.timing` — instruments of one render: peak memory, rays counted at the ray engine,
  the integrator's helpers timed, the atmospheric look-ups timed;
* :mod:`.bare` — the same rays traced bare through embreex (the floor of the render);
* :mod:`.mitsuba` — the same scene rendered by Mitsuba 3 at equal noise;
* :mod:`.report` — the machine and the commit measured, and the figures as a table.
"""

from pathlib import Path

#: The repository and the benchmarks' output folder.
ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "out" / "bench"
