"""``radscene atmosphere``: build a database, look along one line of sight, look at the sky,
compile LOWTRAN7 (``build-lowtran``, :mod:`radscene.cli.lowtran`).

Registered by :mod:`radscene.cli` as ``radscene atmosphere`` (``add_subcommands(app,
"atmosphere", ...)``); bad input raises :class:`radscene.errors.ConfigError` naming the option
(``--water: must lie in [0, 10] g cm-2; got '25'``), which the main CLI prints as one line with
exit code 2, before anything is written. Quantities take units: ``10km``, ``"550 nm"``,
``"25 degC"`` (bare numbers: m, um, deg, K).

``los`` and ``sky`` say what 6S and LOWTRAN users say: the aerosol as ``--visibility`` or
``--aot550``, the gas columns ``--water`` [g cm-2] and ``--ozone`` [cm-atm], the ``--date``
(Earth–Sun distance), the ``--solar-spectrum`` (``radscene``: ASTM G173-03 / Gueymard 2004;
``tsis1``: TSIS-1 HSRS v2, Coddington et al. 2021; ``6s``: 6S's own; ``lowtran``: LOWTRAN7's
own; see :mod:`radscene.atmosphere.options`), and bands as rectangles
(``--band 0.63,0.69``), a library sensor's responses (``--sensor landsat8_oli --band B4``) or
a response file (``--srf my_band.csv``: two numeric columns, wavelength and response). Band
values are response-weighted (:mod:`radscene.atmosphere.bands`), with brightness temperatures
for bands centred beyond 3 um. ``los`` reports the apparent radiance of a uniform Lambertian
ground of ``--ground-albedo`` with the engine's ground-atmosphere coupling.
"""

from __future__ import annotations

import json
import re
import time
from pathlib import Path

import numpy as np
import typer
from rich.console import Console
from rich.table import Table

from radscene.cli.lowtran import build_lowtran
from radscene.errors import ConfigError

app = typer.Typer(name="atmosphere", help="Atmospheric databases, lines of sight and skies; "
                  "the LOWTRAN7 build.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False)
console = Console()
err_console = Console(stderr=True)

_ENGINE = typer.Option("database", "--engine", "-e", help="database, sixs or lowtran.")
_PROFILE = typer.Option("us_standard", help="Gas profile: tropical, midlatitude_summer, "
                        "midlatitude_winter, subarctic_summer, subarctic_winter, us_standard.")
_AEROSOL = typer.Option("rural", help="Aerosol model: rural, maritime, urban, desert, none, ...")
_VIS = typer.Option(None, help="Visibility (> 0), e.g. 23km, 5000 (m); default 23km unless "
                    "--aot550 is given.")
_AOT = typer.Option(None, "--aot550", help="Aerosol optical thickness at 550 nm (>= 0), instead "
                    "of --visibility (engine sixs; database if it has the tables).")
_WATER = typer.Option(None, "--water", help="Water vapour column [g cm-2], 0-10 (engine sixs: "
                      "with --ozone and profile us_standard).")
_OZONE = typer.Option(None, "--ozone", help="Ozone column [cm-atm], 0-1 (0.3 cm-atm = 300 DU).")
_DATE = typer.Option(None, "--date", help="Date YYYY-MM-DD: the Earth-Sun distance (NREL SPA, "
                     "12:00 UTC; LOWTRAN: its day of year); default 1 AU.")
_SPECTRUM = typer.Option(None, "--solar-spectrum", help="Top-of-atmosphere solar spectrum: "
                         "radscene (ASTM G173-03 extraterrestrial, Gueymard 2004; engines "
                         "sixs, database), tsis1 (TSIS-1 HSRS v2, Coddington et al. 2021, "
                         "to 2.73 µm, radscene's beyond; sixs, database), 6s (6S's own; sixs), "
                         "lowtran (LOWTRAN7's own; lowtran). Default: the engine's first.")
_MS = typer.Option(True, "--multiple-scattering/--single-scattering",
                   help="Multiple scattering (LOWTRAN only may switch it off).")
_SUN_Z = typer.Option("30", help="Sun zenith [deg]; >= 90: night.")
_SUN_A = typer.Option("180", help="Sun azimuth [deg, clockwise from north].")
_ALBEDO = typer.Option(0.0, help="Albedo of the surroundings the engine's sky sees [0-1] "
                       "(6S/database sky and diffuse light; LOWTRAN's SALB).")
_GROUND = typer.Option(None, "--ground-albedo", help="Albedo of the uniform Lambertian ground "
                       "whose apparent radiance is reported, with the ground-atmosphere "
                       "coupling of sixs/database [0-1]; default --surface-albedo.")
_WMIN = typer.Option(None, "--wavelength-min", help="Shortest wavelength, e.g. 0.4 or 400nm.")
_WMAX = typer.Option(None, "--wavelength-max", help="Longest wavelength, e.g. 2.5 or 12um.")
_STEP = typer.Option(None, help="Wavelength step [µm] (default 0.005 below 4 µm, 0.05 above).")
_BAND = typer.Option(None, "--band", help="Band 'min,max' in µm, or with --sensor a band name "
                     "(B4); repeatable. Default: the whole range, or all the sensor's bands.")
_SENSOR = typer.Option(None, "--sensor", help="Library sensor whose spectral responses are the "
                       "bands, e.g. landsat8_oli, goes16_abi (or a multi-band SRF table).")
_SRF = typer.Option(None, "--srf", help="Spectral response file: two numeric columns, "
                    "wavelength and response >= 0, wavelengths increasing (repeatable).")
_SRF_UNIT = typer.Option("um", "--srf-unit", help="Wavelength unit of --srf files (um, nm).")
_DB = typer.Option(None, "--database", help="Database file or shipped name (engine database).")
_JSON = typer.Option(False, "--json", help="Print JSON instead of a table.")
_OUT = typer.Option(None, "-o", "--output", help="Write the Dataset to this NetCDF file.")
_PLOT = typer.Option(None, "--plot", help="Write a PNG plot to this file.")
_DB_OUT = typer.Option(..., "-o", "--output", help="NetCDF database to write.")
_QUIET = typer.Option(False, "--quiet", "-q", help="Print only errors: no table, no JSON; the "
                      "-o and --plot files are still written (without either, the exit code "
                      "alone says whether the inputs hold and the engine ran). Not with --json.")
_VERBOSE = typer.Option(False, "--verbose", "-v", help="Also print each stage on standard "
                        "error: what it does and its time.")
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


#: Option of each key that an error may name (the last part of a dotted key).
_OPTION_OF = {"visibility": "--visibility", "aot550": "--aot550", "water": "--water",
              "ozone": "--ozone", "date": "--date", "earth_sun_distance": "--date",
              "solar_spectrum": "--solar-spectrum", "surface_albedo": "--surface-albedo",
              "ground_albedo": "--ground-albedo", "profile": "--profile", "aerosol": "--aerosol",
              "engine": "--engine", "multiple_scattering": "--single-scattering",
              "sun_zenith": "--sun-zenith", "sun_azimuth": "--sun-azimuth",
              "view_azimuth": "--view-azimuth", "surface_temperature": "--surface-temperature",
              "file": "--database", "step": "--step", "sensor": "--sensor"}


def _named(err: ConfigError, origins) -> ConfigError:
    """The error with its key turned into the command-line option it came from."""
    key = err.key or ""
    band = re.fullmatch(r"bands\[(\d+)\].*", key)
    if band and int(band.group(1)) < len(origins):
        return ConfigError(err.message, key=origins[int(band.group(1))])
    if key.startswith("sensor ") and key.endswith(".band"):
        return ConfigError(f"{err.message} (of {key[7:-5]})", key="--band")
    option = _OPTION_OF.get(key.split(".")[-1])
    return ConfigError(err.message, key=option) if option else err


def _srf_file(path, unit, key):
    """A response from a two-column (wavelength, response) file; strict: one optional header
    line, then two numbers per line."""
    from radscene.radiometry.srf import TabulatedResponse

    scale = _q(f"1 {unit}", "wavelength", "--srf-unit")
    try:
        text = Path(path).read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"cannot read it: {getattr(exc, 'strerror', None) or exc}",
                          key=key) from None
    rows, header = [], False
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        fields = [f for f in re.split(r"[,;\s]+", stripped) if f]
        try:
            values = [float(f) for f in fields]
        except ValueError:
            values = None
        if values is None and not rows and not header:
            header = True  # a header line such as "wavelength,response"
            continue
        if values is None or len(values) != 2 or not np.all(np.isfinite(values)):
            raise ConfigError(f"line {lineno}: not two numeric columns (wavelength, "
                              f"response): {stripped[:60]!r}", key=key)
        rows.append(values)
    if len(rows) < 2:
        raise ConfigError("needs at least two rows of wavelength, response", key=key)
    data = np.array(rows)
    wl = data[:, 0] * scale
    if wl.max() > 100.0:
        raise ConfigError(f"wavelengths up to {wl.max():g} µm: are they in nm? give "
                          "--srf-unit nm", key=key)
    if not np.all(np.diff(wl) > 0):
        i = int(np.flatnonzero(np.diff(wl) <= 0)[0])
        raise ConfigError(f"wavelengths must increase; {data[i + 1, 0]:g} follows "
                          f"{data[i, 0]:g}", key=key)
    if np.any(data[:, 1] < 0):
        i = int(np.argmin(data[:, 1]))
        raise ConfigError(f"responses must be >= 0; got {data[i, 1]:g} at {data[i, 0]:g}",
                          key=key)
    try:
        return TabulatedResponse(wl, data[:, 1], name=Path(path).stem)
    except ConfigError as err:
        raise ConfigError(err.message, key=key) from None


def _band_options(band, sensor, srf, srf_unit):
    """(bands for the API or None, the option each band came from)."""
    bands, origins = [], []
    if sensor is not None:
        from radscene.sensor.srf_library import get_sensor_bands

        try:
            chosen = get_sensor_bands(sensor, list(band) if band else None)
        except ConfigError as err:
            raise _named(err, []) from None
        for name, response in chosen:
            bands.append(response)
            origins.append(f"--sensor {sensor} --band {name}")
    else:
        for i, b in enumerate(band or []):
            parts = [p for p in str(b).replace(";", ",").split(",") if p.strip()]
            if len(parts) != 2:
                raise ConfigError(f"'min,max' in µm (a band name needs --sensor); got {b!r}",
                                  key="--band")
            bands.append((_q(parts[0].strip(), "wavelength", f"band[{i}]"),
                          _q(parts[1].strip(), "wavelength", f"band[{i}]")))
            origins.append(f"--band {b}")
    for path in srf or []:
        key = f"--srf {path}"
        bands.append(_srf_file(path, srf_unit, key))
        origins.append(key)
    return (bands or None), origins


def _run(function, origins, *args, **kwargs):
    """Call an API function; its ConfigError names the command-line option."""
    try:
        return function(*args, **kwargs)
    except ConfigError as err:
        raise _named(err, origins) from None


def _sun_line(ds) -> str:
    date = ds.attrs.get("date")
    when = f"{date}, " if date else ""
    return (f"{when}Earth-Sun {ds.attrs['earth_sun_distance_au']:.5f} AU, solar spectrum "
            f"{ds.attrs['solar_spectrum']}")


def _band_label(ds, b) -> str:
    name = str(ds["band_name"].values[b])
    lo, hi = float(ds["band_min"][b]), float(ds["band_max"][b])
    rect = name == f"{lo:g}-{hi:g} um"  # the name radscene.atmosphere.bands gives
    return (f"{lo:.3g}–{hi:.3g}" if rect else
            f"{name.rsplit(' ', 1)[-1]} ({float(ds['band_center'][b]):.4g})")


def _report(quiet, verbose, as_json):
    """The :class:`radscene.cli.Report` of ``los`` and ``sky``: --quiet prints nothing, so it
    refuses --json, whose JSON is all the command prints."""
    from radscene.cli import Report

    report = Report(quiet, verbose)
    if quiet and as_json:
        raise ConfigError("give --quiet or --json, not both: with --quiet nothing is printed "
                          "(write the Dataset with -o)", key="--quiet")
    return report


def _write(ds, output, plot, plotter, report):
    """The -o file and the --plot PNG, each named on standard error unless quiet."""
    def wrote(path, started):
        if report.verbose:
            report.wrote(path, started)
        elif not report.quiet:
            err_console.print(f"wrote {path}")

    if output is not None:
        from radscene.io import write_netcdf

        t = time.perf_counter()
        wrote(write_netcdf(ds, output, compress=False), t)
    if plot is not None:
        t = time.perf_counter()
        wrote(plotter(ds, Path(plot)), t)


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
    quiet: bool = typer.Option(False, "--quiet", "-q", help="Print only errors: no progress, "
                               "no summary table."),
    verbose: bool = typer.Option(False, "--verbose", "-v", help="Also print each stage on "
                                 "standard error as it finishes: its runs and its time."),
):
    """Sample the geometry space with 6S (and LOWTRAN for the thermal range) into a database.
    Shows a progress bar per stage on a terminal (elsewhere, a line per finished stage), then
    a summary table; --quiet prints only errors; --verbose adds each stage and its time."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    from radscene.atmosphere.build import build_database, load_config
    from radscene.cli import Report
    from radscene.cli import err_console as stages
    from radscene.io import write_netcdf

    report = Report(quiet, verbose)
    t = time.perf_counter()
    cfg = load_config(None if config == "default" else config)
    report.stage(f"configuration {config} read", time.perf_counter() - t)
    user = {k: v for k, v in cfg.items() if not k.startswith("_")}
    if workers is not None:
        if workers < 1:
            raise ConfigError(f"a positive integer; got {workers}", key="workers")
        user["workers"] = workers
    if cache is not None:
        user["cache"] = str(cache)
    started = time.perf_counter()
    # on a terminal a live bar; elsewhere (a log file, CI) one line per finished stage
    live = stages.is_terminal and not quiet
    with Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                  TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                  console=stages, disable=not live) as bar:
        tasks, begun = {}, {}

        def progress(stage, done, total):
            if stage not in tasks:
                tasks[stage] = bar.add_task(stage, total=total)
                begun[stage] = time.perf_counter()
            bar.update(tasks[stage], completed=done, total=total)
            if done == total:
                took = time.perf_counter() - begun[stage]
                if verbose:
                    report.stage(f"{stage}: {total} runs", took)
                elif not live and not quiet:
                    stages.print(f"{stage}: {total} runs in {took:.0f} s")

        ds = build_database(user, progress=progress)
    t = time.perf_counter()
    path = report.wrote(write_netcdf(ds, output, compress=True), t)
    if quiet:
        return
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
    a2.set_ylabel("radiance [W m-2 sr-1 µm-1]")
    a2.set_xlabel("wavelength [µm]")
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
    visibility: str = _VIS, aot550: str = _AOT, water: str = _WATER, ozone: str = _OZONE,
    multiple_scattering: bool = _MS, sun_zenith: str = _SUN_Z, sun_azimuth: str = _SUN_A,
    date: str = _DATE, solar_spectrum: str = _SPECTRUM, surface_albedo: float = _ALBEDO,
    ground_albedo: float = _GROUND,
    surface_temperature: str = typer.Option(None, help="Ground temperature, e.g. 300 or "
                                            "'25 degC': its emission in the apparent radiance."),
    wavelength_min: str = _WMIN, wavelength_max: str = _WMAX, step: float = _STEP,
    band: list[str] = _BAND, sensor: str = _SENSOR, srf: list[Path] = _SRF,
    srf_unit: str = _SRF_UNIT, database: str = _DB, as_json: bool = _JSON,
    output: Path = _OUT, plot: Path = _PLOT, quiet: bool = _QUIET, verbose: bool = _VERBOSE,
):
    """One line of sight: transmittance, path radiance (thermal and solar) and the apparent
    radiance of a Lambertian ground, per wavelength and per band (brightness temperatures
    beyond 3 µm). Prints them as tables (or JSON), and writes the Dataset (-o) and a plot
    (--plot) if asked; --quiet writes those files and prints only errors."""
    from radscene.atmosphere.api import line_of_sight

    report = _report(quiet, verbose, as_json)
    bands, origins = _band_options(band, sensor, srf, srf_unit)
    t = time.perf_counter()
    ds = _run(
        line_of_sight, origins,
        _q(observer_altitude, "length", "observer_altitude"),
        _q(target_altitude, "length", "target_altitude"), _q(zenith, "angle", "zenith"),
        engine=engine, profile=profile, aerosol=aerosol, visibility=visibility, aot550=aot550,
        water=water, ozone=ozone, multiple_scattering=multiple_scattering,
        sun_zenith=_q(sun_zenith, "angle", "sun_zenith"),
        sun_azimuth=_q(sun_azimuth, "angle", "sun_azimuth"),
        view_azimuth=None if view_azimuth is None else _q(view_azimuth, "angle", "view_azimuth"),
        date=date, solar_spectrum=solar_spectrum, surface_albedo=surface_albedo,
        ground_albedo=ground_albedo,
        surface_temperature=None if surface_temperature is None else _q(
            surface_temperature, "temperature", "surface_temperature"),
        wavelength_range=_range(wavelength_min, wavelength_max), step=step,
        bands=bands, database=database)
    report.stage(f"line of sight ({ds.attrs['engine']}): {ds.sizes['wavelength']} "
                 f"wavelength(s), {ds.sizes.get('band', 0)} band(s)", time.perf_counter() - t)
    _write(ds, output, plot, _los_plot, report)
    if quiet:
        return
    if as_json:
        console.print_json(_json_dump(ds))
        return
    table = Table(title=f"line of sight ({ds.attrs['engine']}): "
                        f"{ds.attrs['observer_altitude_m']:g} m → "
                        f"{ds.attrs['target_altitude_m']:g} m, zenith "
                        f"{ds.attrs['view_zenith_deg']:g}°, sun {ds.attrs['sun_zenith_deg']:g}°; "
                        f"{_sun_line(ds)}; ground albedo {ds.attrs['ground_albedo']:g}",
                  caption="L: band integrals ∫S L dλ [W m-2 sr-1] of the path (thermal, "
                          "scattered) and the apparent (app) radiance; L̄: band means "
                          "[W m-2 sr-1 µm-1]; BT: band brightness temperatures [K]")
    thermal = "band_apparent_brightness_temperature" in ds and bool(
        np.isfinite(ds["band_apparent_brightness_temperature"].values).any())
    columns = ["band [µm]", "τ mean", "L path", "thermal", "scattered", "L app",
               "L̄ app"] + (["BT app", "BT path"] if thermal else [])
    for col in columns:
        table.add_column(col, justify="right")
    for b in range(ds.sizes.get("band", 0)):
        row = [_band_label(ds, b), f"{float(ds['band_transmittance'][b]):.4f}",
               f"{float(ds['band_path_radiance'][b]):.4g}",
               f"{float(ds['band_path_thermal_radiance'][b]):.4g}",
               f"{float(ds['band_path_scattered_radiance'][b]):.4g}",
               f"{float(ds['band_apparent_radiance'][b]):.4g}",
               f"{float(ds['band_mean_apparent_radiance'][b]):.4g}"]
        if thermal:
            row += [_kelvin(ds["band_apparent_brightness_temperature"][b]),
                    _kelvin(ds["band_path_brightness_temperature"][b])]
        table.add_row(*row)
    console.print(table)
    spec = Table(title="spectral samples")
    for col in ("λ [µm]", "τ", "τ sun", "L path [W m-2 sr-1 µm-1]", "L apparent"):
        spec.add_column(col, justify="right")
    wl = ds["wavelength"].values
    for i in np.unique(np.linspace(0, wl.size - 1, min(12, wl.size)).astype(int)):
        spec.add_row(f"{wl[i]:.4g}", f"{float(ds['transmittance'][i]):.4f}",
                     f"{float(ds['sun_transmittance'][i]):.4f}",
                     f"{float(ds['path_radiance'][i]):.4g}",
                     f"{float(ds['apparent_radiance'][i]):.4g}")
    console.print(spec)


def _kelvin(value) -> str:
    v = float(value)
    return f"{v:.2f}" if np.isfinite(v) else "—"


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
    ax2.set_xlabel("wavelength [µm]")
    ax2.set_ylabel("irradiance on a horizontal surface [W m-2 µm-1]")
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
    visibility: str = _VIS, aot550: str = _AOT, water: str = _WATER, ozone: str = _OZONE,
    multiple_scattering: bool = _MS, sun_zenith: str = _SUN_Z, sun_azimuth: str = _SUN_A,
    date: str = _DATE, solar_spectrum: str = _SPECTRUM, surface_albedo: float = _ALBEDO,
    wavelength_min: str = _WMIN, wavelength_max: str = _WMAX, step: float = _STEP,
    band: list[str] = _BAND, sensor: str = _SENSOR, srf: list[Path] = _SRF,
    srf_unit: str = _SRF_UNIT, database: str = _DB, as_json: bool = _JSON,
    output: Path = _OUT, plot: Path = _PLOT, quiet: bool = _QUIET, verbose: bool = _VERBOSE,
):
    """Sky radiance map from the surface and the downwelling irradiance, per wavelength and
    per band (brightness temperatures beyond 3 µm). Prints a table per band (or JSON), and
    writes the Dataset (-o) and a plot (--plot) if asked; --quiet writes those files and
    prints only errors."""
    from radscene.atmosphere.api import sky_radiance

    report = _report(quiet, verbose, as_json)
    bands, origins = _band_options(band, sensor, srf, srf_unit)
    t = time.perf_counter()
    ds = _run(
        sky_radiance, origins, _angles(zenith, "zenith"), _angles(azimuth, "azimuth"),
        target_altitude=_q(target_altitude, "length", "target_altitude"), engine=engine,
        profile=profile, aerosol=aerosol, visibility=visibility, aot550=aot550, water=water,
        ozone=ozone, multiple_scattering=multiple_scattering,
        sun_zenith=_q(sun_zenith, "angle", "sun_zenith"),
        sun_azimuth=_q(sun_azimuth, "angle", "sun_azimuth"), date=date,
        solar_spectrum=solar_spectrum, surface_albedo=surface_albedo,
        wavelength_range=_range(wavelength_min, wavelength_max), step=step,
        bands=bands, database=database)
    report.stage(f"sky ({ds.attrs['engine']}): {ds.sizes['zenith']}×{ds.sizes['azimuth']} "
                 f"directions, {ds.sizes['wavelength']} wavelength(s), "
                 f"{ds.sizes.get('band', 0)} band(s)", time.perf_counter() - t)
    _write(ds, output, plot, _sky_plot, report)
    if quiet:
        return
    if as_json:
        console.print_json(_json_dump(ds))
        return
    bt = ds.get("band_sky_brightness_temperature")
    for b in range(ds.sizes.get("band", 0)):
        thermal = bt is not None and bool(np.isfinite(bt.values[..., b]).any())
        values, unit = ((bt.values[..., b], "brightness temperature [K]") if thermal else
                        (ds["band_sky_radiance"].values[..., b], "[W m-2 sr-1]"))
        table = Table(title=f"sky ({ds.attrs['engine']}), band {_band_label(ds, b)} µm "
                            f"{unit}; rows zenith, columns azimuth [deg]; diffuse "
                            f"irradiance {float(ds['band_downwelling_irradiance'][b]):.4g} "
                            f"W m-2; {_sun_line(ds)}")
        table.add_column("zenith", justify="right")
        for a in ds["azimuth"].values:
            table.add_column(f"{a:g}", justify="right")
        for i, z in enumerate(ds["zenith"].values):
            table.add_row(f"{z:g}", *((f"{v:.2f}" if thermal else f"{v:.4g}")
                                      for v in values[i]))
        console.print(table)


# -- LOWTRAN ----------------------------------------------------------------------------------
app.command(name="build-lowtran")(build_lowtran)
