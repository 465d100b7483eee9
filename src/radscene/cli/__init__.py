"""The ``radscene`` command line: ``check``, ``examples``, ``schema`` here, ``render``
(:mod:`radscene.cli.render`), ``thermal`` (:mod:`radscene.cli.thermal`), and the sub-apps
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
from rich.markup import escape
from rich.progress import Progress
from rich.table import Table

from radscene import __version__
from radscene.errors import ConfigError, EngineError, did_you_mean

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
    """One line on stderr; exit code 2 for bad input, 1 for an engine that failed. The message
    is escaped: its brackets ("name [unit]", "[0, 1]") are text, not Rich markup."""
    err_console.print(f"[bold red]error:[/] {escape(str(err))}", highlight=False, soft_wrap=True)
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


class Report:
    """What a command prints, by ``--quiet`` / ``--verbose``: errors always (on stderr, by
    :func:`_fail`); results, warnings and progress bars unless quiet; with verbose also each
    stage, what it did and its time (on stderr, so that standard output keeps the results)."""

    def __init__(self, quiet: bool = False, verbose: bool = False):
        if quiet and verbose:
            raise ConfigError("give --quiet or --verbose, not both", key="--quiet")
        self.quiet, self.verbose = quiet, verbose

    def say(self, *args, **kwargs) -> None:
        """A result line (standard output), unless quiet."""
        if not self.quiet:
            console.print(*args, **kwargs)

    def warn(self, text: str) -> None:
        """A warning (standard error), unless quiet."""
        if not self.quiet:
            err_console.print(f"warning: {escape(text)}", highlight=False)

    def stage(self, text: str, seconds: float | None = None) -> None:
        """With --verbose: a stage, what it did and how long it took (standard error). The
        text is printed as it is: brackets ("observers[map].gsd") are not Rich markup."""
        if self.verbose:
            took = "" if seconds is None else f" ({seconds:.2f} s)"
            err_console.print(f"[dim]{time.strftime('%H:%M:%S')}[/] {escape(text)}{took}",
                              highlight=False, soft_wrap=True)

    def progress(self, *columns, **kwargs) -> Progress:
        """A rich progress display on standard error, disabled when quiet; each update raises
        a stop that a signal asked for (radscene.io.stop)."""
        return _StoppableProgress(*columns, console=err_console, disable=self.quiet, **kwargs)

    def wrote(self, path, started: float) -> Path:
        """With --verbose: the file (or store) just written, its size and the time taken."""
        if self.verbose:
            path = Path(path)
            size = (sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
                    if path.is_dir() else path.stat().st_size)
            self.stage(f"wrote {path} ({_size(size)})", time.perf_counter() - started)
        return Path(path)


class _StoppableProgress(Progress):
    """A progress display whose updates raise a stop whose exception was dropped."""

    def update(self, *args, **kwargs) -> None:
        from radscene.io import stop

        stop.check()
        super().update(*args, **kwargs)

    def advance(self, *args, **kwargs) -> None:
        from radscene.io import stop

        stop.check()
        super().advance(*args, **kwargs)


def _size(count: int) -> str:
    for unit in ("B", "kB", "MB", "GB"):
        if count < 1000 or unit == "GB":
            return f"{count:.0f} {unit}" if unit == "B" else f"{count:.1f} {unit}"
        count /= 1000
    return ""




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


def _metres(value) -> str:
    return f"{value:,.0f}" if abs(value) >= 100 else f"{value:.3g}"


def _boresight(camera):
    """What sets an observer's field of view and GSD: (field of view text, boresight origin
    and direction [m, unit], pixel pitch on a plane at unit distance [-], when the boresight
    is taken); origin None for an orthographic camera (parallel rays, its GSD given)."""
    import numpy as np

    from radscene.platform import OrthographicCamera, PerspectiveCamera
    from radscene.platform.scanners import PushbroomScanner, WhiskbroomScanner

    rows, cols = camera.shape
    if isinstance(camera, OrthographicCamera):
        return (f"field of view: parallel rays over {_metres(cols * camera.gsd)} × "
                f"{_metres(rows * camera.gsd)} m"), None, None, None, ""
    if isinstance(camera, PerspectiveCamera):
        return (f"field of view {camera.fov:.4g}° × {camera.fov_vertical:.4g}°",
                camera.position, camera.forward, camera.pixel_pitch, "")
    if isinstance(camera, PushbroomScanner):
        fov = 2.0 * np.degrees(np.arctan(0.5 * cols * camera.pitch))
        mid = camera.start + 0.5 * rows * camera.line_time
        text = f"field of view {fov:.4g}° across track (IFOV {camera.ifov:.3g}°)"
        when = " at mid-image"
    elif isinstance(camera, WhiskbroomScanner):
        fov = float(np.degrees(camera.mirror_angle(0.0) - camera.mirror_angle(float(cols))))
        mid = camera.start
        text = f"field of view {abs(fov):.4g}° across the scan (IFOV {camera.ifov:.3g}°)"
        when = " at the start"
    else:
        return None, None, None, None, ""
    pos, axes = camera.sensor_axes(mid)
    return text, pos, -axes[:, 2], camera.pitch, when


def _coverage(scene, obs, report) -> None:
    """Print what an observer sees: its field of view, its GSD (an orthographic camera's own,
    else at the boresight's ground point, said where), the share of its pixels that meet the
    scene, their ground footprint and range; warn when it sees nothing."""
    import numpy as np

    from radscene.geometry import RayTracer

    camera = obs.camera
    tracer = scene.render_cache.get("check_tracer")
    if tracer is None:
        tracer = RayTracer([o.mesh for o in scene.objects])
        scene.render_cache["check_tracer"] = tracer
    fov, origin, bore, pitch, when = _boresight(camera)
    optics = [fov] if fov else []
    if getattr(camera, "gsd", None) is not None:
        optics.append(f"GSD {camera.gsd:.4g} m")
    elif origin is not None:
        origin = np.asarray(origin, dtype=float)
        bore = np.asarray(bore, dtype=float) / np.linalg.norm(bore)
        hit = tracer.intersect(origin[None], bore[None])
        if hit.hit[0]:
            dist, where = float(hit.distance[0]), "the boresight's ground point"
            point = hit.position[0]
        elif bore[2] < 0 and origin[2] > 0:
            dist, where = float(-origin[2] / bore[2]), "where the boresight meets z = 0"
            point = origin + dist * bore
        else:
            dist = None
        if dist is None:
            optics.append(f"GSD: none, the boresight meets no ground{when}")
        else:
            x, y, z = (f"{v + 0.0:,.0f}" for v in np.round(point))
            optics.append(f"GSD {dist * pitch:.3g} m at {where} ({x}, {y}, {z}) m{when}, "
                          f"{_metres(dist)} m away, across the line of sight")
    try:
        rays = camera.rays(supersample=1)
    except Exception:  # scanners need their own time axis; the render checks them
        report.say("    " + "; ".join(optics))
        return
    hits = tracer.intersect(rays.origins, rays.directions)
    share = float(np.mean(hits.hit)) if hits.hit.size else 0.0
    if share == 0.0:
        report.say("    " + "; ".join(optics + ["ground footprint: none (no pixel on the scene)"]))
        report.warn(f"observer {obs.name} looks at nothing: none of its pixels' rays meets the "
                    "scene (check its position, attitude or look-at)")
        return
    pos = hits.position[hits.hit]
    span = np.ptp(pos[:, :2], axis=0)
    dist = hits.distance[hits.hit]
    optics.append(f"ground footprint {_metres(span[0])} × {_metres(span[1])} m (pixel centres;"
                  f" {100 * share:.0f} % of pixels on the scene), range "
                  f"{_metres(dist.min())}–{_metres(dist.max())} m")
    report.say("    " + "; ".join(optics))


@app.command()
def check(scene_file: Path = typer.Argument(..., help="Scene YAML file."),
          max_memory: str = typer.Option(None, "--max-memory",
                                         help="Refuse a scene whose render needs more, e.g. "
                                              "8GB (default: render.max_memory, else the "
                                              "machine's memory)."),
          confine: bool = typer.Option(False, "--confine",
                                       help="Read no file outside the scene file's folder."),
          quiet: bool = typer.Option(False, "--quiet", "-q",
                                     help="Print only errors (the exit code says whether the "
                                          "scene is valid)."),
          verbose: bool = typer.Option(False, "--verbose", "-v",
                                       help="Also print each stage on standard error: what it "
                                            "does and its time.")):
    """Validate a scene file and summarise what it holds, without rendering."""
    from radscene.atmosphere import check_engine
    from radscene.pipeline import check_thermal_inputs
    from radscene.render import sun_geometry
    from radscene.scene import load_scene

    try:
        report = Report(quiet, verbose)
        t = time.perf_counter()
        scene = load_scene(scene_file, max_memory=max_memory, confine=confine)
        report.stage(f"loaded and validated {scene_file}", time.perf_counter() - t)
        check_engine(scene.atmosphere)
        t = time.perf_counter()
        sun = sun_geometry(scene)
        report.stage("sun position", time.perf_counter() - t)
        t = time.perf_counter()
        check_thermal_inputs(scene)
        report.stage("heat-balance inputs checked", time.perf_counter() - t)
        frames = None
        if scene.spec.time is not None:
            from radscene.pipeline.simulation import check_sequence

            # as radscene render writes it: a frame at a time, into the default folder
            frames = check_sequence(scene, output=Path("out"))
    except (ConfigError, EngineError) as err:
        _fail(err)
    if quiet:
        return
    n_tri = sum(len(o.mesh.faces) for o in scene.objects)
    report.say(f"[bold]{scene.name}[/]: valid")
    report.say(f"  objects: {len(scene.objects)} ({n_tri:,} triangles)")
    report.say(f"  materials: {', '.join(scene.material_names)}")
    report.say(f"  bands: {', '.join(b.name for b in scene.bands)}")
    for obs in scene.observers:
        grid = "" if obs.spectral is None else (
            f", spectral: {len(obs.spectral)} channels {obs.spectral.wavelength[0]:.4g}–"
            f"{obs.spectral.wavelength[-1]:.4g} µm every {obs.spectral.step:.4g} µm")
        report.say(f"  observer {obs.name}: {obs.kind} {obs.camera.shape[1]}×{obs.camera.shape[0]}"
                   f" px, supersample {obs.supersample}{grid}")
        t = time.perf_counter()
        _coverage(scene, obs, report)
        report.stage(f"traced one ray per pixel of {obs.name}", time.perf_counter() - t)
    from radscene.scene.memory import estimate

    need = max((b for b, _, _ in estimate(scene.spec, scene.base_dir)["observers"]),
               default=0.0)
    if need:
        report.say(f"  memory: about {need / 1e9:.1f} GB for the largest render (estimate)")
    if frames is not None:
        report.say(f"  sequence: {frames:,} frames")
    report.say(f"  atmosphere: {scene.atmosphere.name}")
    report.say(f"  sun: zenith {sun.zenith:.2f}°, azimuth {sun.azimuth:.2f}°, "
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

            desc = (yaml.safe_load(path.read_text(encoding="utf-8")) or {}).get("description", "")
            table.add_row(key, desc.strip().splitlines()[0] if desc else "")
        console.print(table)
        console.print("copy one with: radscene examples NAME --copy DIR")
        return
    if name not in found:
        _fail(ConfigError(f"unknown example {name!r}; known: {', '.join(sorted(found))}"
                          f"{did_you_mean(name, sorted(found))}",
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
    from radscene.cli.render import render
    from radscene.cli.sensor import app as sensor_app
    from radscene.cli.sweep import sweep
    from radscene.cli.thermal import thermal

    app.command(name="render")(render)
    app.command(name="thermal")(_guarded(thermal))
    app.command(name="sweep")(_guarded(sweep))

    add_subcommands(atmosphere_app, "atmosphere",
                    "Atmospheric databases, lines of sight and skies; the LOWTRAN7 build.")
    add_subcommands(materials_app, "materials", "Built-in materials and spectral libraries.")
    add_subcommands(sensor_app, "sensor",
                    "Sensor models: optics, detector, noise, electronics, processing.")


_register_subcommands()


def run() -> None:  # pragma: no cover - console entry
    """The console entry. SIGTERM ends a command as Ctrl-C does: the files being written are
    temporaries, removed on the way out (radscene.io.files.atomic_output), so none is left half
    written; a stop whose exception was dropped (radscene.io.stop) is raised again at the next
    progress update, and a command that got to its end anyway exits 130 too."""
    from radscene.io import stop

    stop.install()
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)
    except SystemExit as end:
        if stop.requested() is not None and end.code in (0, None):
            sys.exit(130)
        raise
