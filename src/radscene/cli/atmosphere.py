"""``radscene atmosphere``: build a database, look along one line of sight, look at the sky.

Registered by :mod:`radscene.cli` as ``radscene atmosphere`` (``add_subcommands(app,
"atmosphere", ...)``); bad input raises :class:`radscene.errors.ConfigError`, which the main CLI
prints as one line with exit code 2. Quantities take units: ``10km``, ``"550 nm"``, ``"25 degC"``
(bare numbers: m, um, deg, K).
"""

from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from radscene.errors import ConfigError

app = typer.Typer(name="atmosphere", help="Atmospheric databases, lines of sight and skies.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False)
console = Console()
err_console = Console(stderr=True)

_ENGINE = typer.Option("database", "--engine", "-e", help="database, sixs or lowtran.")
_PROFILE = typer.Option("us_standard", help="Gas profile: tropical, midlatitude_summer, "
                        "midlatitude_winter, subarctic_summer, subarctic_winter, us_standard.")
_AEROSOL = typer.Option("rural", help="Aerosol model: rural, maritime, urban, desert, none, ...")
_VIS = typer.Option("23km", help="Visibility (> 0), e.g. 23km, 5000 (m).")
_MS = typer.Option(True, "--multiple-scattering/--single-scattering",
                   help="Multiple scattering (LOWTRAN only may switch it off).")
_SUN_Z = typer.Option("30", help="Sun zenith [deg]; >= 90: night.")
_SUN_A = typer.Option("180", help="Sun azimuth [deg, clockwise from north].")
_ALBEDO = typer.Option(0.0, help="Surface albedo [0-1].")
_WMIN = typer.Option(None, "--wavelength-min", help="Shortest wavelength, e.g. 0.4 or 400nm.")
_WMAX = typer.Option(None, "--wavelength-max", help="Longest wavelength, e.g. 2.5 or 12um.")
_STEP = typer.Option(None, help="Wavelength step [um] (default 0.005 below 4 um, 0.05 above).")
_BAND = typer.Option(None, "--band", help="Band 'min,max' in um for band-integrated values "
                     "(repeatable); default: the whole range.")
_DB = typer.Option(None, "--database", help="Database file or shipped name (engine database).")
_JSON = typer.Option(False, "--json", help="Print JSON instead of a table.")
_OUT = typer.Option(None, "-o", "--output", help="Write the Dataset to this NetCDF file.")
_PLOT = typer.Option(None, "--plot", help="Write a PNG plot to this file.")
_DB_OUT = typer.Option(..., "-o", "--output", help="NetCDF database to write.")
_WORKERS = typer.Option(None, help="Parallel 6S processes (default: CPUs).")
_CACHE = typer.Option(None, help="Cache folder of 6S results (default: none).")


def _q(value, kind, key):
    from radscene.radiometry.units import parse_quantity

    return parse_quantity(value, kind, key=key)


def _range(wmin, wmax):
    if wmin is None and wmax is None:
        return None
    if wmin is None or wmax is None:
        raise ConfigError("give both --wavelength-min and --wavelength-max",
                          key="wavelength_range")
    return (_q(wmin, "wavelength", "wavelength_min"), _q(wmax, "wavelength", "wavelength_max"))


def _parse_bands(bands):
    if not bands:
        return None
    out = []
    for i, b in enumerate(bands):
        parts = [p for p in str(b).replace(";", ",").split(",") if p.strip()]
        if len(parts) != 2:
            raise ConfigError(f"'min,max' in um; got {b!r}", key=f"band[{i}]")
        out.append((_q(parts[0].strip(), "wavelength", f"band[{i}]"),
                    _q(parts[1].strip(), "wavelength", f"band[{i}]")))
    return out


def _write(ds, output, plot, plotter):
    if output is not None:
        from radscene.io import write_netcdf

        path = write_netcdf(ds, output, compress=False)
        err_console.print(f"wrote {path}")
    if plot is not None:
        path = plotter(ds, Path(plot))
        err_console.print(f"wrote {path}")


def _json_dump(ds) -> str:
    out = {"attrs": {k: (v.item() if hasattr(v, "item") else v) for k, v in ds.attrs.items()},
           "coords": {}, "data": {}}
    for name, c in ds.coords.items():
        out["coords"][name] = np.asarray(c.values).tolist()
    for name, v in ds.data_vars.items():
        out["data"][name] = {"dims": list(v.dims), "units": v.attrs.get("units", ""),
                             "values": np.asarray(v.values).tolist()}
    return json.dumps(out, default=str)


# -- build ------------------------------------------------------------------------------------
@app.command()
def build(
    config: str = typer.Argument("default", help="Build configuration (YAML), or 'default'."),
    output: Path = _DB_OUT, workers: int = _WORKERS, cache: Path = _CACHE,
):
    """Sample the geometry space with 6S (and LOWTRAN for the thermal range) into a database."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from radscene.atmosphere.build import build_database, load_config
    from radscene.io import write_netcdf

    cfg = load_config(None if config == "default" else config)
    user = {k: v for k, v in cfg.items() if not k.startswith("_")}
    if workers is not None:
        if workers < 1:
            raise ConfigError(f"a positive integer; got {workers}", key="workers")
        user["workers"] = workers
    if cache is not None:
        user["cache"] = str(cache)
    started = time.perf_counter()
    live = err_console.is_terminal  # elsewhere (a log file, CI) one line per finished stage
    with Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                  TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                  console=err_console, disable=not live) as bar:
        tasks, begun = {}, {}

        def progress(stage, done, total):
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
                begun[stage] = time.perf_counter()
            bar.update(tasks[stage], completed=done, total=total)
            if not live and done == total:
                err_console.print(f"{stage}: {total} runs in "
                                  f"{time.perf_counter() - begun[stage]:.0f} s")

        ds = build_database(user, progress=progress)
    path = write_netcdf(ds, output, compress=True)
    table = Table(title=f"atmosphere database {path}")
    table.add_column("item")
    table.add_column("value", justify="right")
    table.add_row("size", f"{path.stat().st_size / 1e6:.2f} MB")
    table.add_row("profiles", ", ".join(map(str, ds["profile"].values)))
    table.add_row("aerosols", ", ".join(map(str, ds["aerosol"].values)))
    table.add_row("wavelengths (gas / scattering)",
                  f"{ds.sizes['wavelength']} / {ds.sizes['scattering_wavelength']}")
    if "thermal_wavelength" in ds.sizes:
        table.add_row("thermal wavelengths", str(ds.sizes["thermal_wavelength"]))
    table.add_row("6S runs", str(ds.attrs["sixs_runs"]))
    table.add_row("6S runs per second (one worker)", str(ds.attrs["sixs_runs_per_second"]))
    table.add_row("6S CPU time", f"{ds.attrs['sixs_cpu_seconds']:.0f} s")
    table.add_row("wall time", f"{time.perf_counter() - started:.0f} s")
    console.print(table)


# -- line of sight --------------------------------------------------------------------------------
def _los_plot(ds, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    wl = ds["wavelength"].values
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    a1.plot(wl, ds["transmittance"].values, label="target to observer")
    if "sun_transmittance" in ds:
        a1.plot(wl, ds["sun_transmittance"].values, label="sun to target")
    a1.set_ylabel("transmittance")
    a1.legend()
    for name in ("path_scattered_radiance", "path_thermal_radiance", "apparent_radiance"):
        if name in ds:
            a2.plot(wl, ds[name].values, label=name.replace("_", " "))
    a2.set_ylabel("radiance [W m-2 sr-1 um-1]")
    a2.set_xlabel("wavelength [um]")
    a2.set_yscale("symlog", linthresh=1e-2)
    a2.legend()
    fig.suptitle(f"{ds.attrs['engine']}: {ds.attrs['observer_altitude_m']:g} m → "
                 f"{ds.attrs['target_altitude_m']:g} m at {ds.attrs['view_zenith_deg']:g}°")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


@app.command()
def los(
    observer_altitude: str = typer.Option("100km", "--observer-altitude",
                                          help="Observer altitude; >= 100km: space."),
    target_altitude: str = typer.Option("0", "--target-altitude", help="Target altitude."),
    zenith: str = typer.Option("0", "--zenith", help="Zenith of the target→observer "
                               "direction [deg]."),
    view_azimuth: str = typer.Option(None, "--view-azimuth", help="Its azimuth [deg]."),
    engine: str = _ENGINE, profile: str = _PROFILE, aerosol: str = _AEROSOL,
    visibility: str = _VIS, multiple_scattering: bool = _MS, sun_zenith: str = _SUN_Z,
    sun_azimuth: str = _SUN_A, surface_albedo: float = _ALBEDO,
    surface_temperature: str = typer.Option(None, help="Surface temperature, e.g. 300 or "
                                            "'25 degC'."),
    wavelength_min: str = _WMIN, wavelength_max: str = _WMAX, step: float = _STEP,
    band: list[str] = _BAND, database: str = _DB, as_json: bool = _JSON,
    output: Path = _OUT, plot: Path = _PLOT,
):
    """One line of sight: transmittance and path radiance, thermal and solar."""
    from radscene.atmosphere.api import line_of_sight

    ds = line_of_sight(
        _q(observer_altitude, "length", "observer_altitude"),
        _q(target_altitude, "length", "target_altitude"), _q(zenith, "angle", "zenith"),
        engine=engine, profile=profile, aerosol=aerosol, visibility=visibility,
        multiple_scattering=multiple_scattering, sun_zenith=_q(sun_zenith, "angle", "sun_zenith"),
        sun_azimuth=_q(sun_azimuth, "angle", "sun_azimuth"),
        view_azimuth=None if view_azimuth is None else _q(view_azimuth, "angle", "view_azimuth"),
        surface_albedo=surface_albedo,
        surface_temperature=None if surface_temperature is None else _q(
            surface_temperature, "temperature", "surface_temperature"),
        wavelength_range=_range(wavelength_min, wavelength_max), step=step,
        bands=_parse_bands(band), database=database)
    _write(ds, output, plot, _los_plot)
    if as_json:
        console.print_json(_json_dump(ds))
        return
    table = Table(title=f"line of sight ({ds.attrs['engine']}): "
                        f"{ds.attrs['observer_altitude_m']:g} m → "
                        f"{ds.attrs['target_altitude_m']:g} m, zenith "
                        f"{ds.attrs['view_zenith_deg']:g}°, sun {ds.attrs['sun_zenith_deg']:g}°")
    for col in ("band [um]", "τ mean", "L path [W m-2 sr-1]", "thermal", "scattered",
                "L apparent"):
        table.add_column(col, justify="right")
    for b in range(ds.sizes["band"]):
        table.add_row(f"{float(ds['band_min'][b]):.3g}–{float(ds['band_max'][b]):.3g}",
                      f"{float(ds['band_transmittance'][b]):.4f}",
                      f"{float(ds['band_path_radiance'][b]):.4g}",
                      f"{float(ds['band_path_thermal_radiance'][b]):.4g}",
                      f"{float(ds['band_path_scattered_radiance'][b]):.4g}",
                      f"{float(ds['band_apparent_radiance'][b]):.4g}")
    console.print(table)
    spec = Table(title="spectral samples")
    for col in ("λ [um]", "τ", "τ sun", "L path [W m-2 sr-1 um-1]", "L apparent"):
        spec.add_column(col, justify="right")
    wl = ds["wavelength"].values
    for i in np.unique(np.linspace(0, wl.size - 1, min(12, wl.size)).astype(int)):
        spec.add_row(f"{wl[i]:.4g}", f"{float(ds['transmittance'][i]):.4f}",
                     f"{float(ds['sun_transmittance'][i]):.4f}",
                     f"{float(ds['path_radiance'][i]):.4g}",
                     f"{float(ds['apparent_radiance'][i]):.4g}")
    console.print(spec)


# -- sky -----------------------------------------------------------------------------------------
def _sky_plot(ds, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    band = ds["band_sky_radiance"].isel(band=0).values  # (zenith, azimuth)
    zen, azi = ds["zenith"].values, ds["azimuth"].values
    order = np.argsort(azi % 360.0)
    az = np.radians(np.append(azi[order] % 360.0, azi[order][0] % 360.0 + 360.0))
    vals = np.concatenate([band[:, order], band[:, order][:, :1]], axis=1)
    fig = plt.figure(figsize=(10, 4.5))
    ax = fig.add_subplot(121, projection="polar")
    ax.set_theta_zero_location("N")
    ax.set_theta_direction(-1)
    mesh = ax.pcolormesh(az, zen, vals, shading="gouraud")
    fig.colorbar(mesh, ax=ax, label="band sky radiance [W m-2 sr-1]")
    ax.set_title("sky (zenith radial, azimuth clockwise from N)")
    ax2 = fig.add_subplot(122)
    ax2.plot(ds["wavelength"].values, ds["downwelling_irradiance"].values, label="diffuse sky")
    ax2.plot(ds["wavelength"].values, ds["direct_irradiance"].values, label="direct sun")
    ax2.set_xlabel("wavelength [um]")
    ax2.set_ylabel("irradiance on a horizontal surface [W m-2 um-1]")
    ax2.legend()
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _angles(text, key):
    if text is None:
        return None
    try:
        return [float(x) for x in str(text).replace(";", ",").split(",") if x.strip()]
    except ValueError:
        raise ConfigError(f"comma-separated angles [deg]; got {text!r}", key=key) from None


@app.command()
def sky(
    target_altitude: str = typer.Option("0", "--target-altitude", help="Where the sky is "
                                        "seen from."),
    zenith: str = typer.Option(None, "--zenith", help="Zenith grid, e.g. '0,30,60,85' [deg]."),
    azimuth: str = typer.Option(None, "--azimuth", help="Azimuth grid [deg, clockwise from N]."),
    engine: str = _ENGINE, profile: str = _PROFILE, aerosol: str = _AEROSOL,
    visibility: str = _VIS, multiple_scattering: bool = _MS, sun_zenith: str = _SUN_Z,
    sun_azimuth: str = _SUN_A, surface_albedo: float = _ALBEDO,
    wavelength_min: str = _WMIN, wavelength_max: str = _WMAX, step: float = _STEP,
    band: list[str] = _BAND, database: str = _DB, as_json: bool = _JSON,
    output: Path = _OUT, plot: Path = _PLOT,
):
    """Sky radiance map from the surface and the downwelling irradiance."""
    from radscene.atmosphere.api import sky_radiance

    ds = sky_radiance(
        _angles(zenith, "zenith"), _angles(azimuth, "azimuth"),
        target_altitude=_q(target_altitude, "length", "target_altitude"), engine=engine,
        profile=profile, aerosol=aerosol, visibility=visibility,
        multiple_scattering=multiple_scattering, sun_zenith=_q(sun_zenith, "angle", "sun_zenith"),
        sun_azimuth=_q(sun_azimuth, "angle", "sun_azimuth"), surface_albedo=surface_albedo,
        wavelength_range=_range(wavelength_min, wavelength_max), step=step,
        bands=_parse_bands(band), database=database)
    _write(ds, output, plot, _sky_plot)
    if as_json:
        console.print_json(_json_dump(ds))
        return
    for b in range(ds.sizes["band"]):
        lo, hi = float(ds["band_min"][b]), float(ds["band_max"][b])
        table = Table(title=f"sky ({ds.attrs['engine']}), band {lo:.3g}–{hi:.3g} um "
                            "[W m-2 sr-1]; rows zenith, columns azimuth [deg]; diffuse "
                            f"irradiance {float(ds['band_downwelling_irradiance'][b]):.4g} "
                            "W m-2")
        table.add_column("zenith", justify="right")
        for a in ds["azimuth"].values:
            table.add_column(f"{a:g}", justify="right")
        for i, z in enumerate(ds["zenith"].values):
            table.add_row(f"{z:g}", *(f"{v:.4g}" for v in ds["band_sky_radiance"].values[i, :, b]))
        console.print(table)
