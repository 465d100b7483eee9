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


def thermal(
    scene_file: Path = typer.Argument(..., help="Scene YAML file."),
    output: Path = typer.Option(..., "-o", "--output", help="NetCDF file to write."),
    start: str = typer.Option(None, "--start", help="ISO 8601 time with offset; default thermal.start or a "
                              "day before the scene's time."),
    end: str = typer.Option(None, "--end", help="ISO 8601 time with offset; default thermal.end or the "
                            "scene's time."),
    step: str = typer.Option(None, "--step", help="Time step, e.g. 60s or 10 min; default thermal.step."),
    plots: bool = typer.Option(True, help="Write the diurnal curves and temperature maps beside the file."),
    overwrite: bool = typer.Option(False, "--overwrite", help="Replace an existing OUTPUT."),
):
    """Solve the heat balance of SCENE_FILE and write the temperatures and flux terms per element
    and time (CF NetCDF), with PNGs of the diurnal curves and of the terrain's temperature."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from radscene.cli import err_console
    from radscene.io import write_netcdf
    from radscene.pipeline import solve_thermal
    from radscene.radiometry.units import parse_quantity
    from radscene.scene import load_scene

    t0, t1 = _when(start, "--start"), _when(end, "--end")
    dt = None if step is None else parse_quantity(step, "time", key="--step")
    if dt is not None and dt <= 0:
        raise ConfigError(f"must be > 0; got {step!r}", key="--step")
    if output.suffix.lower() != ".nc":
        raise ConfigError(f"give a .nc file; got {output}", key="--output")
    from radscene.io.files import check_output_file

    check_output_file(output, overwrite)
    scene = load_scene(scene_file)
    with Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                  TimeElapsedColumn(), console=err_console, transient=True) as bar:
        tasks = {}

        def progress(stage, done, total):
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
            bar.update(tasks[stage], completed=done, total=total)

        ds = solve_thermal(scene, start=t0, end=t1, step=dt, progress=progress)
    written = [write_netcdf(ds, output)]
    if plots:
        from radscene.io.thermal_plots import diurnal_figure, temperature_maps

        written.append(diurnal_figure(ds, output.with_name(output.stem + "_diurnal.png")))
        written.extend(temperature_maps(ds, output.parent / (output.stem + "_maps")))
    for path in written:
        typer.echo(str(path))
