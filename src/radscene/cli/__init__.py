"""The ``radscene`` command line: ``render``, ``check``, ``examples`` here, ``thermal``
(:mod:`radscene.cli.thermal`), and the sub-apps
``atmosphere``, ``materials`` and ``sensor`` (:mod:`radscene.cli.atmosphere`,
:mod:`radscene.cli.materials`, :mod:`radscene.cli.sensor`), registered with
:func:`add_subcommands`. The domain packages hold no command-line code."""

from __future__ import annotations

import shutil
import sys
import time
from importlib import resources
from pathlib import Path

import typer
from rich.console import Console
from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from radscene import __version__
from radscene.errors import ConfigError, EngineError

# rich_markup_mode=None: help texts are plain text, so units in brackets ("[deg]", "[g cm-2]")
# are shown instead of being taken for Rich markup and dropped
app = typer.Typer(
    rich_markup_mode=None,
    name="radscene",
    help="Render what an EO/IR sensor records of a scene, 0.4–20 µm.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
console = Console()
err_console = Console(stderr=True)


def _fail(err: Exception) -> None:
    """One line on stderr; exit code 2 for bad input, 1 for an engine that failed."""
    err_console.print(f"[bold red]error:[/] {err}", highlight=False, soft_wrap=True)
    raise typer.Exit(code=2 if isinstance(err, ConfigError) else 1)


def _guarded(function):
    """Wrap a command so that a ConfigError becomes one line on stderr and exit code 2, an
    EngineError one line and exit code 1."""
    import functools

    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except (ConfigError, EngineError) as err:
            _fail(err)

    return wrapper


def add_subcommands(sub_app: typer.Typer, name: str, help_text: str) -> None:
    """Register a package's typer sub-app under ``radscene NAME``, with radscene's error rule."""
    import copy

    guarded = typer.Typer(name=name, help=help_text, no_args_is_help=True, rich_markup_mode=None)
    for info in sub_app.registered_commands:
        entry = copy.copy(info)
        entry.callback = _guarded(info.callback)
        guarded.registered_commands.append(entry)
    app.add_typer(guarded, name=name, help=help_text)


def _version(value: bool):
    if value:
        console.print(f"radscene {__version__}")
        raise typer.Exit()


@app.callback()
def main(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True,
                                 help="Print the version and exit."),
):
    """radscene: radiometric EO/IR scene and sensor simulation."""


def _instant(value, key):
    """A timezone-aware datetime from an ISO 8601 string (None stays None)."""
    import datetime as _dt

    if value is None:
        return None
    try:
        when = _dt.datetime.fromisoformat(value)
    except ValueError:
        raise ConfigError(f"an ISO 8601 time such as 2026-06-21T10:00:00Z, not {value!r}", key=key) from None
    if when.tzinfo is None:
        raise ConfigError(f"a time with a UTC offset, e.g. '2026-06-21T10:30:00+02:00' or '...Z', not {value!r}",
                          key=key)
    return when


def _render_sequence(scene, names, output, start, end, step, quicklooks, video):
    """``radscene render`` of a sequence: every frame rendered, then one file per observer (and
    with quicklooks a GIF and/or an MP4 per band, as ``render.video`` or --video says)."""
    from radscene.io import band_animations, band_videos, write_netcdf
    from radscene.io.animation import video_formats
    from radscene.pipeline.simulation import render_sequence

    started = time.perf_counter()
    given = {"time.start": start, "time.end": end, "time.step": step}
    try:
        formats = video_formats(video or scene.spec.render.video,
                                "--video" if video else "render.video") if quicklooks else ()
        span = scene.spec.time
        start = _instant(start, "--start") or (span.start if span else None)
        end = _instant(end, "--end") or (span.end if span else None)
        step = step if step is not None else (span.step if span else None)
        with Progress(TextColumn("[bold]{task.description}"), BarColumn(), TextColumn("{task.completed}/{task.total}"),
                      TimeElapsedColumn(), TimeRemainingColumn(), console=err_console, transient=False) as bar:
            task = bar.add_task("frames", total=None)

            def progress(done, total):
                bar.update(task, completed=done, total=total)

            sequences = render_sequence(scene, start=start, end=end, step=step, observers=names,
                                        progress=progress)
    except (ConfigError, EngineError) as err:
        if isinstance(err, ConfigError) and given.get(err.key) is not None:  # the command line's
            err = ConfigError(err.message, key=err.key.replace("time.", "--"))
        _fail(err)
    for name, ds in sequences.radiance.items():
        path = write_netcdf(ds, output / f"{name}_sequence.nc")
        console.print(f"{name}: {ds.sizes['time']} frames -> {path}")
        if name in sequences.signal:
            console.print(f"{name}: {write_netcdf(sequences.signal[name], output / f'{name}_signal_sequence.nc')}")
        if "band" in ds.dims:
            written = band_animations(ds, output / f"{name}_sequence") if "gif" in formats else []
            written += band_videos(ds, output / f"{name}_sequence") if "mp4" in formats else []
            for animation in written:
                console.print(f"{name}: {animation}")
    console.print(f"{scene.name}: {len(sequences.radiance)} observer(s) in {time.perf_counter() - started:.1f} s")


@app.command()
def render(
    scene_file: Path = typer.Argument(None, help="Scene YAML file (or --from)."),
    output: Path = typer.Option(Path("out"), "-o", "--output", help="Output folder."),
    observer: list[str] = typer.Option(None, "--observer", help="Render only these observers."),
    quicklooks: bool = typer.Option(True, help="Write PNG quicklooks beside the NetCDF files."),
    overwrite: bool = typer.Option(False, "--overwrite",
                                   help="Replace results of an earlier run in OUTPUT."),
    max_memory: str = typer.Option(None, "--max-memory",
                                   help="Refuse a scene whose render needs more, e.g. 8GB "
                                        "(default: render.max_memory, else the machine's "
                                        "memory)."),
    confine: bool = typer.Option(False, "--confine",
                                 help="Read no file outside the scene file's folder."),
    resume: bool = typer.Option(False, "--resume",
                                help="Finish a run that stopped midway in OUTPUT: render only "
                                     "the observers it had not written."),
    start: str = typer.Option(None, "--start", help="A sequence's first frame, e.g. 2026-06-21T10:00:00Z."),
    end: str = typer.Option(None, "--end", help="A sequence's last instant."),
    step: str = typer.Option(None, "--step", help="A sequence's step, e.g. '40 ms' or '10 min'."),
    video: str = typer.Option(None, "--video",
                              help="A sequence's animations per band: auto, gif, mp4, both or none "
                                   "(default render.video, auto: GIF, and MP4 with imageio-ffmpeg)."),
    from_file: Path = typer.Option(None, "--from",
                                   help="Render again what an output NetCDF file of radscene "
                                        "holds, from its provenance (the scene, its files "
                                        "checked by SHA-256), instead of SCENE_FILE."),
):
    """Render every observer of a scene to NetCDF (and PNG quicklooks) in OUTPUT; an observer
    with a spectral grid to NAME_spectral.nc and the ENVI NAME_spectral.img/.hdr. OUTPUT is
    checked before any work: a file, a folder under a file or one that cannot be written is
    refused, and so are earlier results in it unless --overwrite. While the run lasts OUTPUT
    holds a marker (.radscene-incomplete.json) listing the observers finished; a complete run
    replaces it with manifest.json (every file, its size and SHA-256). With a sequence
    (--start/--end/--step, or ``time`` in the scene file) one NAME_sequence.nc per observer
    with a time axis (NAME_signal_sequence.nc for a sensor's), and with quicklooks
    NAME_sequence/BAND.gif and/or BAND.mp4 (--video), written after the last frame. With
    --from out/NAME.nc, the scene that file was rendered from is rendered again (its observer,
    unless --observer), to the same numbers."""
    from radscene.io import run_record
    from radscene.io.files import check_output_folder
    from radscene.pipeline import apply_thermal, solve_thermal, thermal_active
    from radscene.scene import load_scene

    try:
        if (scene_file is None) == (from_file is None):
            raise ConfigError("give a scene file or --from FILE.nc (one of the two)",
                              key="scene" if scene_file is None else "--from")
        if from_file is not None:
            from radscene.pipeline.provenance import scene_from_output

            recorded = scene_from_output(from_file)
            scene = load_scene(recorded.document, base_dir=recorded.base_dir,
                               max_memory=max_memory, confine=confine)
            scene.source = recorded.scene_file
            scene_file = from_file
            observer = observer or ([recorded.observer] if recorded.observer else None)
        else:
            scene = load_scene(scene_file, max_memory=max_memory, confine=confine)
        names = observer or [o.name for o in scene.observers]
        for name in names:
            scene.observer(name)
        if scene.spec.time is not None or any(v is not None for v in (start, end, step)):
            check_output_folder(output, _sequence_files(scene, names), overwrite)
            sequence = True
        else:
            sequence = False
            done = run_record.finished(output, scene_file) if resume else []
            todo = [n for n in names if n not in done]
            check_output_folder(output, _result_files(scene, todo), overwrite or resume)
    except (ConfigError, EngineError) as err:
        _fail(err)
    if sequence:
        return _render_sequence(scene, names, output, start, end, step, quicklooks, video)
    started = time.perf_counter()
    results, spectral, written = {}, {}, []
    with run_record.RunRecord(output, scene_file, names, done) as record:
        try:
            with Progress(TextColumn("[bold]{task.description}"), BarColumn(),
                          TextColumn("{task.percentage:>3.0f}%"), TimeElapsedColumn(),
                          TimeRemainingColumn(), console=err_console, transient=False) as bar:
                if todo and thermal_active(scene):  # the heat balance first, its own progress
                    stages = {}

                    def thermal_progress(stage, done, total):
                        if stage not in stages:
                            stages[stage] = bar.add_task(f"heat balance: {stage}", total=total)
                        bar.update(stages[stage], completed=done, total=total)

                    apply_thermal(scene, solve_thermal(scene, progress=thermal_progress))
                for name in todo:
                    task = bar.add_task(f"render {name}", total=1)

                    def progress(done, total, task=task):
                        bar.update(task, completed=done, total=total)

                    if scene.observer(name).spectral is not None:  # written pass by pass
                        spectral[name], files = _write_spectral(scene, name, output, progress)
                    else:
                        results[name], files = _render_and_write(scene, name, output,
                                                                 quicklooks, progress)
                    written.extend(files)
                    record.finish(name, files)
        except (ConfigError, EngineError) as err:
            _fail(err)
    if done:
        console.print(f"resumed: {', '.join(done)} already written")
    _summary(scene, results, spectral, written, output, started)


def _render_and_write(scene, name, output, quicklooks, progress):
    """Render one observer (and its sensor) and write its files; returns (Dataset, files)."""
    from radscene.io import (
        band_quicklooks,
        signal_quicklooks,
        terms_figure,
        truth_figure,
        write_netcdf,
    )
    from radscene.pipeline import simulate

    ds, signal = simulate(scene, name, progress=progress)
    written = [write_netcdf(ds, output / f"{name}.nc")]
    if ds["x"].attrs.get("units") == "m":  # a map product: also a GeoTIFF
        from radscene.io.geotiff import write_geotiff
        from radscene.platform.geolocation import LocalFrame

        loc = scene.location
        written.append(write_geotiff(ds["radiance"], output / f"{name}_radiance.tif",
                                     crs=LocalFrame(loc.latitude, loc.longitude, loc.altitude)))
    if signal is not None:
        written.append(write_netcdf(signal, output / f"{name}_signal.nc"))
        if quicklooks:
            written.extend(signal_quicklooks(signal, output / f"{name}_signal"))
    if quicklooks:
        written.extend(band_quicklooks(ds, output / name))
        written.append(terms_figure(ds, output / f"{name}_terms.png"))
        written.append(truth_figure(ds, output / f"{name}_truth.png"))
    return ds, written


def _summary(scene, results, spectral, written, output, started):
    table = Table(title=f"{scene.name}: {len(results)} observer(s) in "
                        f"{time.perf_counter() - started:.1f} s")
    for col in ("observer", "band", "λ [um]", "mean L [W m-2 sr-1]", "min", "max", "mean BT [K]"):
        table.add_column(col, justify="right" if col != "observer" and col != "band" else "left")
    for name, ds in results.items():
        for band in ds["band"].values:
            sel = ds.sel(band=band)
            rad = sel["radiance"].values
            bt = sel["brightness_temperature"].values
            table.add_row(name, str(band), f"{float(sel['wavelength_center']):.3g}",
                          f"{rad.mean():.4g}", f"{rad.min():.4g}", f"{rad.max():.4g}",
                          f"{float(bt[bt == bt].mean()):.2f}" if (bt == bt).any() else "—")
    if results:
        console.print(table)
    for name, text in spectral.items():
        console.print(f"{name}: {text}")
    console.print(f"wrote {len(written)} files under {output}/")


def _coverage(scene, obs) -> None:
    """Print what an observer sees: field of view or GSD, the share of its pixels that meet the
    scene, their ground footprint and range; warn when it sees nothing."""
    import numpy as np

    from radscene.geometry import RayTracer

    camera = obs.camera
    optics = []
    if getattr(camera, "gsd", None) is not None:
        optics.append(f"GSD {camera.gsd:.4g} m")
    if getattr(camera, "fov", None) is not None:
        optics.append(f"field of view {camera.fov:.4g}°")
    try:
        rays = camera.rays(supersample=1)
    except Exception:  # scanners need their own time axis; the render checks them
        return
    tracer = scene.render_cache.get("check_tracer")
    if tracer is None:
        tracer = RayTracer([o.mesh for o in scene.objects])
        scene.render_cache["check_tracer"] = tracer
    hits = tracer.intersect(rays.origins, rays.directions)
    share = float(np.mean(hits.hit)) if hits.hit.size else 0.0
    if share == 0.0:
        err_console.print(f"warning: observer {obs.name} looks at nothing: none of its pixels' "
                          "rays meets the scene (check its position, attitude or look-at)",
                          highlight=False)
        return
    pos = hits.position[hits.hit]
    span = np.ptp(pos[:, :2], axis=0)
    dist = hits.distance[hits.hit]

    def metres(value):
        return f"{value:,.0f}" if value >= 100 else f"{value:.3g}"

    optics.append(f"{100 * share:.0f} % of pixels on the scene, their centres spanning "
                  f"{metres(span[0])} × {metres(span[1])} m on the ground, range "
                  f"{metres(dist.min())}–{metres(dist.max())} m")
    console.print("    " + "; ".join(optics))


def _sequence_files(scene, names) -> list[str]:
    """The data files ``radscene render`` writes for a sequence of these observers."""
    return [f for name in names for f in (f"{name}_sequence.nc", f"{name}_signal_sequence.nc")]


def _result_files(scene, names) -> list[str]:
    """The data files ``radscene render`` writes for these observers (not the quicklooks)."""
    files = []
    for name in names:
        if scene.observer(name).spectral is not None:
            files += [f"{name}_spectral.nc", f"{name}_spectral.img", f"{name}_spectral.hdr"]
        else:
            files += [f"{name}.nc", f"{name}_signal.nc", f"{name}_radiance.tif"]
    return files


def _write_spectral(scene, name, output, progress):
    """Render a spectral observer pass by pass into ``NAME_spectral.nc`` and the ENVI
    ``NAME_spectral.img``/``.hdr``; returns a summary line and the files."""
    import numpy as np

    from radscene.io import write_spectral
    from radscene.pipeline import spectral_passes

    grid = scene.observer(name).spectral
    stats = []

    def summarised(passes):
        for part in passes:
            values = part["radiance"].values
            stats.append((float(values.sum()), values.size, float(values.min()),
                          float(values.max())))
            yield part

    files = write_spectral(summarised(spectral_passes(scene, name, progress=progress)),
                           output / f"{name}_spectral.nc", grid,
                           envi=output / f"{name}_spectral.img")
    total, count, low, high = (sum(s[0] for s in stats), sum(s[1] for s in stats),
                               min(s[2] for s in stats), max(s[3] for s in stats))
    wl = np.asarray(grid.wavelength)
    text = (f"{len(wl)} channels {wl[0]:.4g}–{wl[-1]:.4g} um every {grid.step:.4g} um; spectral "
            f"radiance mean {total / count:.4g}, min {low:.4g}, max {high:.4g} W m-2 sr-1 um-1")
    return text, files


@app.command()
def check(scene_file: Path = typer.Argument(..., help="Scene YAML file."),
          max_memory: str = typer.Option(None, "--max-memory",
                                         help="Refuse a scene whose render needs more, e.g. "
                                              "8GB (default: render.max_memory, else the "
                                              "machine's memory)."),
          confine: bool = typer.Option(False, "--confine",
                                       help="Read no file outside the scene file's folder.")):
    """Validate a scene file and summarise what it holds, without rendering."""
    from radscene.pipeline import check_thermal_inputs
    from radscene.render import sun_geometry
    from radscene.scene import load_scene

    try:
        scene = load_scene(scene_file, max_memory=max_memory, confine=confine)
        sun = sun_geometry(scene)
        check_thermal_inputs(scene)
    except (ConfigError, EngineError) as err:
        _fail(err)
    n_tri = sum(len(o.mesh.faces) for o in scene.objects)
    console.print(f"[bold]{scene.name}[/]: valid")
    console.print(f"  objects: {len(scene.objects)} ({n_tri:,} triangles)")
    console.print(f"  materials: {', '.join(scene.material_names)}")
    console.print(f"  bands: {', '.join(b.name for b in scene.bands)}")
    for obs in scene.observers:
        grid = "" if obs.spectral is None else (
            f", spectral: {len(obs.spectral)} channels {obs.spectral.wavelength[0]:.4g}–"
            f"{obs.spectral.wavelength[-1]:.4g} um every {obs.spectral.step:.4g} um")
        console.print(f"  observer {obs.name}: {obs.kind} {obs.camera.shape[1]}×{obs.camera.shape[0]}"
                      f" px, supersample {obs.supersample}{grid}")
        _coverage(scene, obs)
    from radscene.scene.memory import estimate

    need = max((b for b, _, _ in estimate(scene.spec)["observers"]), default=0.0)
    if need:
        console.print(f"  memory: about {need / 1e9:.1f} GB for the largest render (estimate)")
    console.print(f"  atmosphere: {scene.atmosphere.name}")
    console.print(f"  sun: zenith {sun.zenith:.2f}°, azimuth {sun.azimuth:.2f}°, "
                  f"{sun.distance:.5f} AU")


def _examples() -> dict[str, Path]:
    folder = resources.files("radscene") / "examples"
    return {p.name.removesuffix(".yaml"): Path(str(p)) for p in folder.iterdir()
            if p.name.endswith(".yaml")}


@app.command()
def examples(
    name: str = typer.Argument(None, help="Example to copy."),
    copy_to: Path = typer.Option(None, "--copy", help="Folder to copy the example into."),
):
    """List the bundled example scenes, or copy one (with its data files) to a folder."""
    found = _examples()
    if name is None:
        table = Table(title="bundled example scenes")
        table.add_column("name")
        table.add_column("description")
        for key, path in sorted(found.items()):
            import yaml

            desc = (yaml.safe_load(path.read_text()) or {}).get("description", "")
            table.add_row(key, desc.strip().splitlines()[0] if desc else "")
        console.print(table)
        console.print("copy one with: radscene examples NAME --copy DIR")
        return
    if name not in found:
        _fail(ConfigError(f"unknown example {name!r}; known: {', '.join(sorted(found))}",
                          key="name"))
    dest = copy_to or Path.cwd()
    dest.mkdir(parents=True, exist_ok=True)
    src = found[name]
    shutil.copy(src, dest / src.name)
    data = src.parent / name
    if data.is_dir():
        shutil.copytree(data, dest / name, dirs_exist_ok=True)
    console.print(f"copied {name} to {dest / src.name}")


@app.command()
def schema(
    output: Path = typer.Option(None, "-o", "--output",
                                help="File to write (default: standard output)."),
):
    """Print the JSON schema of a scene file, for completion and checking in editors.

    VS Code (YAML extension): put `# yaml-language-server: $schema=scene.schema.json` on the
    first line of a scene file.
    """
    import json

    from radscene.scene.reference import scene_json_schema

    text = json.dumps(scene_json_schema(), indent=2, ensure_ascii=False) + "\n"
    if output is None:
        sys.stdout.write(text)
        return
    if output.is_dir():
        _fail(ConfigError(f"{output} is a folder; give a file name, e.g. scene.schema.json",
                          key="output"))
    try:
        output.write_text(text, encoding="utf-8")
    except OSError as err:
        _fail(ConfigError(f"cannot write {output}: {err.strerror}", key="output"))
    console.print(f"wrote {output}")


def _register_subcommands() -> None:
    from radscene.cli.atmosphere import app as atmosphere_app
    from radscene.cli.materials import app as materials_app
    from radscene.cli.sensor import app as sensor_app
    from radscene.cli.thermal import thermal

    app.command(name="thermal")(_guarded(thermal))

    add_subcommands(atmosphere_app, "atmosphere",
                    "Atmospheric databases, lines of sight and skies.")
    add_subcommands(materials_app, "materials", "Built-in materials and spectral libraries.")
    add_subcommands(sensor_app, "sensor",
                    "Sensor models: optics, detector, noise, electronics, processing.")


_register_subcommands()


def run() -> None:  # pragma: no cover - console entry
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)
