"""Heat-balance benchmark: seconds per time step of radscene.thermal for many elements.

100 000 elements (``--elements``) drawn at random from eight built-in material stacks (roads,
paint, painted metal sheet, snow on ground, soil, shingles, a leaf, concrete), 30 nodes each
(``--nodes``), sunlit forcing at 10-minute steps. Timed apart: building the grid and the
balance (``setup``), and, per step, the conduction sweeps alone (bottom-up elimination and
back-substitution, :class:`radscene.thermal.ImplicitConduction`) and the whole balance step
(flux terms, elimination, Newton on the surface node, back-substitution) through
:meth:`radscene.thermal.HeatBalance.run`, compiled (the default) and on the numpy reference
path (``compiled=False``). Best of ``--repeat`` runs of ``--steps`` steps. With ``--day``, also
a whole day at one-minute steps (1440 steps) through ``run`` with the default balance, the
figure the solver's target is stated for (10 s for 100 000 elements × 10 nodes on 2 cores),
in wall-clock and in CPU time of the process (on a machine shared with other work the two
differ), with the load average.

Run ``python benchmarks/bench_thermal.py`` (the step figures at 30 nodes) and ``python
benchmarks/bench_thermal.py --day --nodes 10`` (the target case); ``make bench`` runs both.
Figures go to ``out/bench/bench_thermal_<elements>x<nodes>[_day].json`` (one file per case) and
a Markdown table to stdout.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import json
import os
import platform
import time
from pathlib import Path

import numpy as np

from radscene.materials import get_thermal_properties
from radscene.thermal import DAY, HeatBalance, ImplicitConduction, ThermalForcing

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "out" / "bench"
MATERIALS = ["asphalt", "white_paint", "painted_metal", "snow", "bare_soil", "asphalt_shingle", "green_leaf", "concrete"]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--elements", type=int, default=100_000)
    parser.add_argument("--nodes", type=int, default=30)
    parser.add_argument("--steps", type=int, default=20)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--day", action="store_true", help="also time a day at one-minute steps")
    args = parser.parse_args(argv)

    stacks = [get_thermal_properties(name) for name in MATERIALS]
    index = np.random.default_rng(0).integers(0, len(stacks), args.elements)
    start = time.perf_counter()
    balance = HeatBalance(stacks, index, n_nodes=args.nodes)
    setup = time.perf_counter() - start

    times = DAY / 2 + 600.0 * np.arange(args.steps + 1)
    forcing = ThermalForcing(times, 800.0, 0.7, 100.0, 300.0, 290.0, 2.0)
    balance.run(ThermalForcing(times[:2], 800.0, 0.7, 100.0, 300.0, 290.0, 2.0), initial_temperature=290.0)
    whole = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        balance.run(forcing, initial_temperature=290.0)
        whole.append((time.perf_counter() - start) / args.steps)
    reference = HeatBalance(stacks, index, n_nodes=args.nodes, compiled=False)
    numpy_path = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        reference.run(forcing, initial_temperature=290.0)
        numpy_path.append((time.perf_counter() - start) / args.steps)
    day = day_cpu = float("nan")
    if args.day:
        minutes = np.arange(0.0, DAY + 1, 60.0)
        sun = np.maximum(0.0, -np.cos(2 * np.pi * minutes / DAY))[:, None]
        start, start_cpu = time.perf_counter(), time.process_time()
        balance.run(ThermalForcing(minutes, 800.0 * sun, 0.7 * sun, 100.0 * sun, 300.0, 290.0, 2.0), initial_temperature=290.0)
        day, day_cpu = time.perf_counter() - start, time.process_time() - start_cpu

    solver = ImplicitConduction(balance.grid, 600.0)
    state = np.full((args.nodes, args.elements), 290.0)
    sweeps = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        for _ in range(args.steps):
            beta, b = solver.eliminate(state)
            solver.substitute((b + 300.0) / (solver.surface_conductance + 20.0), beta, out=state)
        sweeps.append((time.perf_counter() - start) / args.steps)

    figures = {
        "date": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "machine": platform.platform(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "elements": args.elements,
        "nodes": args.nodes,
        "setup_s": setup,
        "conduction_step_s": min(sweeps),
        "balance_step_s": min(whole),
        "balance_step_numpy_s": min(numpy_path),
        "day_at_60s_s": day,
        "day_at_60s_cpu_s": day_cpu,
        "parallel": balance._stepper.parallel,
        "load_average": os.getloadavg()[0],
    }
    OUT.mkdir(parents=True, exist_ok=True)
    case = f"{args.elements}x{args.nodes}" + ("_day" if args.day else "")
    (OUT / f"bench_thermal_{case}.json").write_text(json.dumps(figures, indent=2))
    print("| elements x nodes | setup [s] | conduction step (numpy) [s] | balance step [s] | balance step, numpy [s] "
          "| day at 60 s, wall (CPU) [s] |\n|---|---|---|---|---|---|\n"
          f"| {args.elements} x {args.nodes} | {setup:.3f} | {min(sweeps):.4f} | {min(whole):.4f} | {min(numpy_path):.4f} "
          f"| {day:.2f} ({day_cpu:.2f}) |")


if __name__ == "__main__":
    main()
