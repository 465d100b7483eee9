"""``radscene render``: every observer of a scene to data files, GeoTIFFs, ENVI and quicklooks.

Registered by :mod:`radscene.cli` as the top-level command ``radscene render``.

The data format follows the output folder's name: ``-o OUT`` writes NetCDF-4
(``OUT/NAME.nc``), ``-o OUT.zarr`` one Zarr store per observer (``OUT.zarr/NAME.zarr``).
"""

from __future__ import annotations

import time
from pathlib import Path

import typer
from rich.progress import BarColumn, TextColumn, TimeElapsedColumn, TimeRemainingColumn
from rich.table import Table

from radscene.cli import Report, _fail, _instant
from radscene.errors import ConfigError, EngineError, did_you_mean

GEOTIFF_HELP = ("Cloud-Optimised GeoTIFFs of a map product (a nadir orthographic observer), "
                "NAME_LAYER.tif in the scene frame's CRS: none; radiance (radiance of every "
                "band, brightness_temperature of the thermal bands); maps (those and the truth "
                "maps surface_temperature, object_id, material_id, range, shadow_fraction, "
                "sky_view_fraction, cos_incidence); all (those and every per-term layer).")


class Formats:
    """The files ``radscene render`` writes per observer, from its options."""

    def __init__(self, output: Path, geotiff: str, envi: bool, quicklooks: bool):
        from radscene.io.cog import LEVELS

        if geotiff not in LEVELS:
            raise ConfigError(f"unknown GeoTIFF choice {geotiff!r}; known: {', '.join(LEVELS)}"
                              f"{did_you_mean(geotiff, LEVELS)}",
                              key="--geotiff")
        self.output = output
        self.ext = ".zarr" if output.suffix.lower() == ".zarr" else ".nc"
        self.geotiff, self.envi, self.quicklooks = geotiff, envi, quicklooks

    def data(self, stem: str) -> Path:
        """The data file (or store) ``stem`` in the run's format."""
        return self.output / f"{stem}{self.ext}"

    def write(self, ds, stem: str) -> Path:
        from radscene.io import write_netcdf, write_zarr

        return (write_zarr if self.ext == ".zarr" else write_netcdf)(ds, self.data(stem))

    def result_files(self, scene, names) -> list[str]:
        """The names of the data files of these observers (not the quicklooks), for the check
        of the output folder before any work."""
        from radscene.io.cog import layer_names

        files = []
        for name in names:
            if scene.observer(name).spectral is not None:
                files += [f"{name}_spectral{self.ext}", f"{name}_spectral.img",
                          f"{name}_spectral.hdr"]
                continue
            files += [f"{name}{self.ext}", f"{name}_signal{self.ext}"]
            files += [f"{name}_{layer}.tif" for layer in layer_names(self.geotiff)]
            files += [f"{name}.img", f"{name}.hdr"] if self.envi else []
        return files

    def sequence_files(self, names) -> list[str]:
        """The data files of a sequence of these observers."""
        return [f"{name}{part}{self.ext}" for name in names
                for part in ("_sequence", "_signal_sequence")]

    def describe(self, sequence: bool = False) -> str:
        """The formats in words (a sequence: its data files and animations only)."""
        kinds = ["Zarr" if self.ext == ".zarr" else "NetCDF"]
        if sequence:
            return ", ".join(kinds + (["animations"] if self.quicklooks else []))
        kinds += [f"COG ({self.geotiff})"] if self.geotiff != "none" else []
        kinds += ["ENVI"] if self.envi else []
        kinds += ["PNG quicklooks"] if self.quicklooks else []
        return ", ".join(kinds)


def _sequence_span(scene, names, start, end, step, video, formats):
    """A sequence's span from the options or the scene's ``time``, checked with its frames'
    memory (:func:`radscene.pipeline.simulation.check_sequence`) and its animation formats,
    before the output folder is touched: ((start, end, step), frames, animation kinds). A
    ConfigError of an option the command line gave names the option (--step, not time.step)."""
    from radscene.io.animation import video_formats
    from radscene.pipeline.simulation import check_sequence

    given = {"time.start": start, "time.end": end, "time.step": step}
    try:
        kinds = video_formats(video or scene.spec.render.video,
                              "--video" if video else "render.video") if formats.quicklooks else ()
        span = scene.spec.time
        start = _instant(start, "--start") or (span.start if span else None)
        end = _instant(end, "--end") or (span.end if span else None)
        step = step if step is not None else (span.step if span else None)
        frames = check_sequence(scene, start=start, end=end, step=step, observers=names,
                                output=formats.output)
    except ConfigError as err:
        if given.get(err.key) is not None:
            raise ConfigError(err.message, key=err.key.replace("time.", "--")) from None
        if err.key == "output":
            raise ConfigError(err.message, key="--output") from None
        raise
    return (start, end, step), frames, kinds


def _render_sequence(scene, names, formats, span, frames, kinds, record, report):
    """``radscene render`` of a sequence: every frame written to its observer's data file as it
    is rendered (the files take their places after the last frame), then per observer its
    animations (with quicklooks a GIF and/or an MP4 per band, read back from the file),
    recorded as they land."""
    from radscene.io import band_animations, band_videos
    from radscene.pipeline.simulation import render_sequence

    output = formats.output
    started = time.perf_counter()
    start, end, step = span
    report.stage(f"sequence from {start} to {end} every {step}: render {frames} frame(s) of "
                 f"{', '.join(names)}, each written to {output}/ as it comes")
    with report.progress(TextColumn("[bold]{task.description}"), BarColumn(),
                         TextColumn("{task.completed}/{task.total}"), TimeElapsedColumn(),
                         TimeRemainingColumn(), transient=False) as bar:
        task = bar.add_task("frames", total=frames)

        def progress(done, total):
            bar.update(task, completed=done, total=total)

        # the CLI checked the folder (--overwrite, --resume) already
        sequences = render_sequence(scene, start=start, end=end, step=step, observers=names,
                                    progress=progress, output=output, overwrite=True)
    report.stage("frames rendered and written", time.perf_counter() - started)
    try:
        for name, ds in sequences.radiance.items():
            path = report.wrote(formats.data(f"{name}_sequence"), started)
            files = [path]
            report.say(f"{name}: {ds.sizes['time']} frames -> {path}")
            if name in sequences.signal:
                path = report.wrote(formats.data(f"{name}_signal_sequence"), started)
                files.append(path)
                report.say(f"{name}: {path}")
            if "band" in ds.dims and kinds:
                t = time.perf_counter()
                written = band_animations(ds, output / f"{name}_sequence") if "gif" in kinds else []
                written += band_videos(ds, output / f"{name}_sequence") if "mp4" in kinds else []
                report.stage(f"{name}: {len(written)} animation(s)", time.perf_counter() - t)
                for animation in written:
                    report.say(f"{name}: {animation}")
                files += written
            record.finish(name, files)
    finally:
        for ds in (*sequences.radiance.values(), *sequences.signal.values()):
            ds.close()
    report.say(f"{scene.name}: {len(sequences.radiance)} observer(s) in "
               f"{time.perf_counter() - started:.1f} s")


def render(
    scene_file: Path = typer.Argument(None, help="Scene YAML file (or --from)."),
    output: Path = typer.Option(Path("out"), "-o", "--output",
                                help="Output folder; a name ending in .zarr writes Zarr stores "
                                     "(OUT.zarr/NAME.zarr) instead of NetCDF files."),
    observer: list[str] = typer.Option(None, "--observer", help="Render only these observers."),
    quicklooks: bool = typer.Option(True, help="Write PNG quicklooks beside the data files."),
    geotiff: str = typer.Option("maps", "--geotiff", help=GEOTIFF_HELP),
    envi: bool = typer.Option(False, "--envi",
                              help="Also write the band radiance as ENVI NAME.img/.hdr "
                                   "(wavelength = band centres, fwhm = equivalent widths [µm])."),
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
                                   help="Render again what an output NetCDF file or Zarr store "
                                        "of radscene holds, from its provenance (the scene, its "
                                        "files checked by SHA-256), instead of SCENE_FILE."),
    quiet: bool = typer.Option(False, "--quiet", "-q",
                               help="Print only errors: no progress bars, no summary table."),
    verbose: bool = typer.Option(False, "--verbose", "-v",
                                 help="Also print each stage on standard error: what it does "
                                      "and its time."),
):
    """Render every observer of a scene to NetCDF (or Zarr), GeoTIFFs and PNG quicklooks in
    OUTPUT: NAME.nc per observer (NAME_signal.nc with a sensor); with an OUTPUT named *.zarr,
    NAME.zarr stores instead (same variables and attributes). A map product (a nadir
    orthographic observer) also gets Cloud-Optimised GeoTIFFs NAME_LAYER.tif (--geotiff,
    default maps: radiance, brightness temperature and the truth maps); --envi adds the band
    radiance as ENVI NAME.img/.hdr. An observer with a spectral grid goes to NAME_spectral.nc
    (NAME_spectral.zarr) and the ENVI NAME_spectral.img/.hdr. OUTPUT is checked before any
    work: a file, a folder under a file or one that cannot be written is refused, and so are
    earlier results in it unless --overwrite. While the run lasts OUTPUT holds a marker (.radscene-incomplete.json)
    listing the observers finished; a complete run replaces it with manifest.json (every
    file, its size and SHA-256). With a sequence (--start/--end/--step, or ``time`` in the
    scene file) one NAME_sequence.nc (.zarr) per observer with a time axis
    (NAME_signal_sequence for a sensor's), each frame written to it as it is rendered (so
    one frame is held in memory, whatever their number) under a hidden temporary name that
    takes its place after the last frame, and with quicklooks NAME_sequence/BAND.gif and/or
    BAND.mp4 (--video), read back from it, under the same marker and manifest (--resume
    renders the observers a stopped sequence of the same span had not written); before any
    frame is rendered its memory is sized against the memory limit, and its files against
    the disk space free in OUTPUT. A run
    of another machine writing into OUTPUT (shared storage) counts as running until its
    heartbeat in the marker is 10 min old (radscene.io.run_record). With --from out/NAME.nc (or
    out.zarr/NAME.zarr), the scene that file was rendered from is rendered again (its
    observer, unless --observer), to the same numbers; a file the scene names that is gone
    or changed is taken from the output, which carries them up to 64 MiB in all, into
    OUTPUT/scene_files/. --quiet prints only errors; --verbose
    adds each stage and its time."""
    from radscene.atmosphere import check_engine
    from radscene.io import run_record
    from radscene.io.files import check_output_folder
    from radscene.pipeline import apply_thermal, check_thermal_inputs, solve_thermal, thermal_active
    from radscene.scene import load_scene

    try:
        report = Report(quiet, verbose)
        formats = Formats(output, geotiff, envi, quicklooks)
        t = time.perf_counter()
        if (scene_file is None) == (from_file is None):
            raise ConfigError("give a scene file or --from FILE.nc (one of the two)",
                              key="scene" if scene_file is None else "--from")
        if from_file is not None:
            from radscene.pipeline.provenance import scene_from_output

            recorded = scene_from_output(from_file, extract_to=Path(output) / "scene_files")
            for key, where in recorded.extracted.items():
                report.warn(f"{key}: taken from {from_file.name} into {where} (gone from, "
                            "or changed at, its recorded place)")
            scene = load_scene(recorded.document, base_dir=recorded.base_dir,
                               max_memory=max_memory, confine=confine)
            scene.source = recorded.scene_file
            scene_file = from_file
            observer = observer or ([recorded.observer] if recorded.observer else None)
        else:
            scene = load_scene(scene_file, max_memory=max_memory, confine=confine)
        names = observer or [o.name for o in scene.observers]
        for name in names:
            try:
                scene.observer(name)
            except ConfigError as err:
                raise ConfigError(err.message, key="--observer") from None
        report.stage(f"loaded {scene_file}: scene {scene.name!r}, {len(scene.objects)} "
                     f"object(s), bands {', '.join(b.name for b in scene.bands)}, observers "
                     f"{', '.join(names)}", time.perf_counter() - t)
        if scene.spec.time is not None or any(v is not None for v in (start, end, step)):
            sequence = True
            span, frames, kinds = _sequence_span(scene, names, start, end, step, video, formats)
            variant = f"sequence {span[0].isoformat()} to {span[1].isoformat()} every {span[2]}"
            done = run_record.finished(output, scene_file, variant) if resume else []
            todo = [n for n in names if n not in done]
            check_output_folder(output, formats.sequence_files(todo), overwrite or resume)
            if todo:  # the heat balance's description, weather and size, before the folder is touched
                check_thermal_inputs(scene)
        else:
            sequence = False
            done = run_record.finished(output, scene_file) if resume else []
            todo = [n for n in names if n not in done]
            check_output_folder(output, formats.result_files(scene, todo), overwrite or resume)
            if todo:  # the heat balance's weather file and size, before the folder is touched
                check_thermal_inputs(scene)
        check_engine(scene.atmosphere)
        report.stage(f"output {output}/ checked; writing {formats.describe(sequence)}")
    except (ConfigError, EngineError) as err:
        _fail(err)
    if sequence:
        with run_record.RunRecord(output, scene_file, names, done, variant) as record:
            try:
                if todo:
                    _render_sequence(scene, todo, formats, span, frames, kinds, record, report)
            except (ConfigError, EngineError) as err:
                _fail(err)
        if done:
            report.say(f"resumed: {', '.join(done)} already written")
        return None
    started = time.perf_counter()
    results, spectral, written = {}, {}, []
    with run_record.RunRecord(output, scene_file, names, done) as record:
        try:
            with report.progress(TextColumn("[bold]{task.description}"), BarColumn(),
                                 TextColumn("{task.percentage:>3.0f}%"), TimeElapsedColumn(),
                                 TimeRemainingColumn(), transient=False) as bar:
                if todo and thermal_active(scene):  # the heat balance first, its own progress
                    stages = {}
                    t = time.perf_counter()

                    def thermal_progress(stage, done, total):
                        if stage not in stages:
                            stages[stage] = bar.add_task(f"heat balance: {stage}", total=total)
                        bar.update(stages[stage], completed=done, total=total)

                    apply_thermal(scene, solve_thermal(scene, progress=thermal_progress))
                    report.stage("heat balance solved: surface temperatures set",
                                 time.perf_counter() - t)
                for name in todo:
                    task = bar.add_task(f"render {name}", total=1)

                    def progress(done, total, task=task):
                        bar.update(task, completed=done, total=total)

                    if scene.observer(name).spectral is not None:  # written pass by pass
                        spectral[name], files = _write_spectral(scene, name, formats, progress,
                                                                report)
                    else:
                        results[name], files = _render_and_write(scene, name, formats,
                                                                 progress, report)
                    written.extend(files)
                    record.finish(name, files)
        except (ConfigError, EngineError) as err:
            _fail(err)
    if done:
        report.say(f"resumed: {', '.join(done)} already written")
    if not report.quiet:
        _summary(scene, results, spectral, written, output, started)


def _render_and_write(scene, name, formats, progress, report):
    """Render one observer (and its sensor) and write its files; returns (Dataset, files)."""
    from radscene.io import (
        band_quicklooks,
        signal_quicklooks,
        terms_figure,
        truth_figure,
        write_envi,
        write_map_cogs,
    )
    from radscene.io.cog import is_map_product
    from radscene.pipeline import simulate

    output = formats.output
    t = time.perf_counter()
    ds, signal = simulate(scene, name, progress=progress)
    report.stage(f"{name}: rendered {ds.sizes.get('x')}×{ds.sizes.get('y')} px, "
                 f"{ds.sizes.get('band', 0)} band(s)"
                 + (" and the sensor chain" if signal is not None else ""),
                 time.perf_counter() - t)
    t = time.perf_counter()
    written = [report.wrote(formats.write(ds, name), t)]
    if formats.geotiff != "none" and is_map_product(ds):
        t = time.perf_counter()
        cogs = write_map_cogs(ds, output / name, formats.geotiff)
        report.stage(f"{name}: {len(cogs)} Cloud-Optimised GeoTIFF(s) "
                     f"({', '.join(p.stem.removeprefix(name + '_') for p in cogs)})",
                     time.perf_counter() - t)
        written.extend(cogs)
    if formats.envi:
        t = time.perf_counter()
        files = write_envi(ds["radiance"], output / f"{name}.img", attrs=ds.attrs)
        written.extend(report.wrote(f, t) for f in files)
    if signal is not None:
        t = time.perf_counter()
        written.append(report.wrote(formats.write(signal, f"{name}_signal"), t))
        if formats.quicklooks:
            written.extend(signal_quicklooks(signal, output / f"{name}_signal"))
    if formats.quicklooks:
        t = time.perf_counter()
        pictures = band_quicklooks(ds, output / name)
        pictures.append(terms_figure(ds, output / f"{name}_terms.png"))
        pictures.append(truth_figure(ds, output / f"{name}_truth.png"))
        report.stage(f"{name}: {len(pictures)} quicklook(s)", time.perf_counter() - t)
        written.extend(pictures)
    return ds, written


def _summary(scene, results, spectral, written, output, started):
    from radscene.cli import console

    table = Table(title=f"{scene.name}: {len(results)} observer(s) in "
                        f"{time.perf_counter() - started:.1f} s")
    for col in ("observer", "band", "λ [µm]", "mean L [W m-2 sr-1]", "min", "max", "mean BT [K]"):
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


def _write_spectral(scene, name, formats, progress, report):
    """Render a spectral observer pass by pass into ``NAME_spectral.nc`` (``.zarr`` with a
    Zarr output) and the ENVI ``NAME_spectral.img``/``.hdr``; returns a summary line and the
    files."""
    import numpy as np

    from radscene.io import write_spectral
    from radscene.pipeline import spectral_passes

    grid = scene.observer(name).spectral
    stats = []
    t = time.perf_counter()

    def summarised(passes):
        for part in passes:
            values = part["radiance"].values
            stats.append((float(values.sum()), values.size, float(values.min()),
                          float(values.max())))
            yield part

    files = write_spectral(summarised(spectral_passes(scene, name, progress=progress)),
                           formats.data(f"{name}_spectral"), grid,
                           envi=formats.output / f"{name}_spectral.img")
    report.stage(f"{name}: rendered and wrote {len(grid.wavelength)} channels pass by pass to "
                 f"{', '.join(str(f) for f in files)}", time.perf_counter() - t)
    total, count, low, high = (sum(s[0] for s in stats), sum(s[1] for s in stats),
                               min(s[2] for s in stats), max(s[3] for s in stats))
    wl = np.asarray(grid.wavelength)
    text = (f"{len(wl)} channels {wl[0]:.4g}–{wl[-1]:.4g} µm every {grid.step:.4g} µm; spectral "
            f"radiance mean {total / count:.4g}, min {low:.4g}, max {high:.4g} W m-2 sr-1 µm-1")
    return text, files
