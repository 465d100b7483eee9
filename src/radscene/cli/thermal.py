"""``radscene thermal``: the heat balance of a scene to NetCDF, with diurnal curves and maps.

Registered by :mod:`radscene.cli` as the top-level command ``radscene thermal``.
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import typer

from radscene.errors import ConfigError


def _when(text, key):
    if text is None:
        return None
    try:
        value = _dt.datetime.fromisoformat(text)
    except ValueError:
        raise ConfigError(f"not an ISO 8601 time: {text!r}", key=key) from None
    if value.tzinfo is None:
        raise ConfigError(f"give a UTC offset, e.g. {text}+02:00 or {text}Z", key=key)
    return value


def _check_map_times(map_times, start, end):
    """Refuse a map time (aware datetime) outside the heat balance's [``start``, ``end``]."""
    for when in map_times:
        if not start <= when <= end:
            raise ConfigError(f"{when.isoformat()} lies outside the heat balance's span "
                              f"{start.isoformat()} – {end.isoformat()}", key="--map-time")


def _map_steps(map_times, times):
    """Indices into the solved ``times`` (datetime64, UTC) of the steps nearest to each of
    ``map_times`` (aware datetimes)."""
    import numpy as np

    utc = np.array([when.astimezone(_dt.UTC).replace(tzinfo=None) for when in map_times],
                   "datetime64[ns]")
    return [int(i) for i in np.argmin(np.abs(times[None, :] - utc[:, None]), axis=1)]


def _spin_up_line(ds, spec) -> str:
    """The spin-up's report: the days it repeated and the last day-to-day change."""
    import math

    days, change = int(ds.attrs["spin_up_days"]), float(ds.attrs["spin_up_change_K"])
    if math.isnan(change):
        return ("spin-up: none (started from thermal.initial_temperature)" if spec.initial_temperature is not None
                else "spin-up: none (thermal.spin_up: false)")
    return f"spin-up: {days} day{'' if days == 1 else 's'}, last day-to-day change {change:.2g} K"


def thermal(
    scene_file: Path = typer.Argument(..., help="Scene YAML file."),
    output: Path = typer.Option(..., "-o", "--output", help="NetCDF file to write."),
    start: str = typer.Option(None, "--start", help="ISO 8601 time with offset; default thermal.start or a "
                              "day before the scene's time."),
    end: str = typer.Option(None, "--end", help="ISO 8601 time with offset; default thermal.end or the "
                            "scene's time."),
    step: str = typer.Option(None, "--step", help="Time step, e.g. 60s or 10 min; default thermal.step."),
    plots: bool = typer.Option(True, help="Write the diurnal curves and temperature maps beside the file."),
    map_time: list[str] = typer.Option(
        None, "--map-time", help="ISO 8601 time with offset of a temperature map (repeatable); the "
        "map shows the solved step nearest to it. Default: four times spread over the run."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing OUTPUT."),
    max_memory: str = typer.Option(None, "--max-memory",
                                   help="Refuse a heat balance (or a scene) that needs more, e.g. "
                                        "8GB (default: render.max_memory, else the machine's "
                                        "memory)."),
    confine: bool = typer.Option(False, "--confine",
                                 help="Read no file outside the scene file's folder."),
    quiet: bool = typer.Option(False, "--quiet", "-q",
                               help="Print only errors: no progress bars, no list of files."),
    verbose: bool = typer.Option(False, "--verbose", "-v",
                                 help="Also print each stage on standard error: what it does "
                                      "and its time."),
):
    """Solve the heat balance of SCENE_FILE and write the temperatures and flux terms per element
    and time (CF NetCDF), with PNGs of the diurnal curves and of the terrain's temperature. Its
    size (elements × time steps) is checked against the memory limit before the first step.
    The plots are written first and OUTPUT last, each whole or not at all: a run stopped midway
    leaves no OUTPUT. A --map-time outside the heat balance's span is refused before the
    balance runs. Prints the files written and the spin-up's days and last day-to-day change."""
    import time

    from rich.progress import BarColumn, TextColumn, TimeElapsedColumn

    from radscene.cli import Report
    from radscene.io import write_netcdf
    from radscene.pipeline import _span, check_thermal_size, solve_thermal
    from radscene.radiometry.units import parse_quantity
    from radscene.scene import load_scene

    report = Report(quiet, verbose)
    t0, t1 = _when(start, "--start"), _when(end, "--end")
    dt = None if step is None else parse_quantity(step, "time", key="--step")
    if dt is not None and dt <= 0:
        raise ConfigError(f"must be > 0; got {step!r}", key="--step")
    if output.suffix.lower() != ".nc":
        raise ConfigError(f"give a .nc file; got {output}", key="--output")
    map_times = [_when(text, "--map-time") for text in map_time or ()]
    if map_times and not plots:
        raise ConfigError("no maps are drawn with --no-plots", key="--map-time")
    from radscene.io.files import check_output_file, remove_stale_temporaries

    check_output_file(output, overwrite)
    remove_stale_temporaries(output.parent, [output.name, output.stem + "_diurnal.png"])
    remove_stale_temporaries(output.parent / (output.stem + "_maps"))
    t = time.perf_counter()
    scene = load_scene(scene_file, max_memory=max_memory, confine=confine)
    report.stage(f"loaded {scene_file}: {len(scene.objects)} object(s)", time.perf_counter() - t)
    given = {"thermal.start": start, "thermal.end": end, "thermal.step": step}
    try:
        check_thermal_size(scene, t0, t1, dt)
    except ConfigError as err:
        if given.get(err.key) is None:
            raise
        raise ConfigError(err.message, key=err.key.replace("thermal.", "--")) from None
    _check_map_times(map_times, *_span(scene, t0, t1))
    if map_times and not any(o.is_terrain and o.face_fixed is not None and not o.face_fixed.all()
                             for o in scene.objects):
        raise ConfigError("the maps are of the terrain's solved temperatures, and this scene has no terrain "
                          "without a fixed temperature", key="--map-time")
    t = time.perf_counter()
    with report.progress(TextColumn("[bold]{task.description}"), BarColumn(),
                         TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                         transient=True) as bar:
        tasks = {}

        def progress(stage, done, total):
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
                report.stage(f"heat balance: {stage}")
            bar.update(tasks[stage], completed=done, total=total)

        ds = solve_thermal(scene, start=t0, end=t1, step=dt, progress=progress)
    report.stage(f"heat balance solved: {ds.sizes.get('time', 1)} time step(s)",
                 time.perf_counter() - t)
    written = []
    if plots:  # before OUTPUT, whose presence says the run finished
        from radscene.io.thermal_plots import diurnal_figure, temperature_maps

        t = time.perf_counter()
        written.append(diurnal_figure(ds, output.with_name(output.stem + "_diurnal.png")))
        steps = _map_steps(map_times, ds.time.values) if map_times else None
        written.extend(temperature_maps(ds, output.parent / (output.stem + "_maps"), times=steps))
        report.stage(f"{len(written)} plot(s)", time.perf_counter() - t)
    t = time.perf_counter()
    written.insert(0, report.wrote(write_netcdf(ds, output), t))
    if not quiet:
        for path in written:
            typer.echo(str(path))
        typer.echo(_spin_up_line(ds, scene.spec.thermal))
