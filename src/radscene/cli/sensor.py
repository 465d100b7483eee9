"""``radscene sensor ...``: apply a sensor to rendered radiance, report a sensor's performance.

:mod:`radscene.cli` registers this sub-app with
``add_subcommands(app, "sensor", "Sensor models: ...")``; a
:class:`~radscene.errors.ConfigError` raised here becomes one line and exit code 2 there.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from radscene.errors import ConfigError

app = typer.Typer(help="Sensor models: optics, detector, noise, electronics, processing.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False)


def _temperature(text: str) -> float:
    from radscene.radiometry.units import parse_quantity

    return parse_quantity(text, "temperature", key="--temperature")


@app.command("apply")
def apply_command(
    radiance: Annotated[Path, typer.Argument(help="Rendered radiance NetCDF (radscene render).")],
    sensor: Annotated[str, typer.Option("--sensor", "-s",
                                        help="Sensor YAML file or a bundled example.")],
    output: Annotated[Path, typer.Option("--output", "-o", help="Signal NetCDF to write.")],
    frames: Annotated[int, typer.Option(help="Frames to record.")] = 1,
    seed: Annotated[int | None, typer.Option(help="Temporal noise seed (default: random).")] = None,
    oversample: Annotated[int | None, typer.Option(
        help="Rendered samples per detector pitch (default: the sensor's).")] = None,
    quiet: Annotated[bool, typer.Option(
        "--quiet", "-q", help="Print only errors: no summary line.")] = False,
    verbose: Annotated[bool, typer.Option(
        "--verbose", "-v", help="Also print each stage on standard error: what it does and "
                                "its time.")] = False,
):
    """Turn a rendered radiance file into digital numbers, with the truth carried along.
    Prints one line: the file written, its frames, bands, detectors and range of DN; --quiet
    prints only errors; --verbose adds each stage and its time."""
    import time

    import xarray as xr

    from radscene.cli import Report
    from radscene.io import write_netcdf
    from radscene.sensor.config import load_sensor

    report = Report(quiet, verbose)
    if not radiance.is_file():
        raise ConfigError("no such file", key=str(radiance))
    t = time.perf_counter()
    model = load_sensor(sensor)
    report.stage(f"loaded sensor {model.name}", time.perf_counter() - t)
    t = time.perf_counter()
    try:
        ds = xr.load_dataset(radiance, engine="h5netcdf")
    except (OSError, ValueError):
        raise ConfigError("not a readable NetCDF file", key=str(radiance)) from None
    report.stage(f"read {radiance}: {ds.sizes.get('band', 1)} band(s), "
                 f"{ds.sizes.get('x')}×{ds.sizes.get('y')} px", time.perf_counter() - t)
    if frames < 1:
        raise ConfigError(f"must be >= 1; got {frames}", key="--frames")
    t = time.perf_counter()
    signal = model.apply(ds, frames=frames, seed=seed, oversample=oversample)
    report.stage(f"sensor applied: {frames} frame(s)", time.perf_counter() - t)
    t = time.perf_counter()
    path = report.wrote(write_netcdf(signal, output), t)
    dn = signal["dn"]
    if not quiet:
        typer.echo(f"{path}: {dn.sizes['frame']} frame(s), bands "
                   f"{', '.join(map(str, signal.band.values))}, {dn.sizes['y']} x "
                   f"{dn.sizes['x']} detectors, DN {float(dn.min()):.0f} to {float(dn.max()):.0f}")


@app.command("info")
def info_command(
    sensor: Annotated[str, typer.Argument(help="Sensor YAML file or a bundled example.")],
    temperature: Annotated[str, typer.Option(help="Blackbody scene for NETD and SNR.")] = "300 K",
    frames: Annotated[int, typer.Option(help="Frames in a sequence (1/f noise).")] = 1,
):
    """Print a sensor's geometry and, per configured band, its SNR and NETD."""
    from radscene.sensor.analysis import netd, noise_budget
    from radscene.sensor.config import load_sensor

    model = load_sensor(sensor)
    t = _temperature(temperature)
    opt, det = model.base.optics, model.base.detector
    typer.echo(f"{model.name}: {det.kind} detector, pitch {det.pitch * 1e6:g} µm, "
               f"f = {opt.focal_length * 1e3:g} mm, F/{opt.f_number:g}, "
               f"IFOV {model.ifov * 3.141592653589793 / 180 * 1e6:.1f} urad, "
               f"oversample {model.oversample}")
    bands = [b for b in (model.config.get("bands") or {}) if model.channel(b).response is not None]
    if not bands:
        typer.echo("no band with a spectral response configured: add bands.<name>.response")
    for band in bands:
        budget = noise_budget(model, band, temperature=t, frames=frames)
        value = float(netd(model, band, t, frames=frames))
        typer.echo(f"  {band}: signal {float(budget.signal):.4g} {budget.unit}, temporal noise "
                   f"{float(budget.temporal_rms):.4g} {budget.unit}, SNR {float(budget.snr):.4g}, "
                   f"NETD {value * 1e3:.1f} mK at {t:g} K")


@app.command("list")
def list_command():
    """List the bundled example sensors."""
    from radscene.sensor.config import example_sensor_path, example_sensors

    for name in example_sensors():
        first = example_sensor_path(name).read_text(encoding="utf-8").splitlines()[0]
        typer.echo(f"{name}: {first.lstrip('# ').strip()}")
