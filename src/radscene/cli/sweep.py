"""``radscene sweep``: one scene rendered under many settings on a dask cluster
(:mod:`radscene.distributed`)."""

from __future__ import annotations

from pathlib import Path

import typer

from radscene.errors import ConfigError


def _setting(text: str) -> tuple[str, list]:
    """``KEY=V1,V2,...`` → (KEY, [V1, V2, ...]), each value read as YAML (numbers, strings)."""
    import yaml

    key, sep, values = text.partition("=")
    if not sep or not key.strip() or not values.strip():
        raise ConfigError(f"give KEY=VALUE[,VALUE...], e.g. environment.sun.zenith=20,40; "
                          f"got {text!r}", key="--set")
    return key.strip(), [yaml.safe_load(v.strip()) for v in values.split(",")]


def sweep(
    scene_file: Path = typer.Argument(..., help="Scene YAML file."),
    output: Path = typer.Option(Path("sweep"), "-o", "--output",
                                help="Output folder: variant_NNN/OBSERVER.nc and sweep.json."),
    setting: list[str] = typer.Option(..., "--set",
                                      help="KEY=V1,V2,... (a dotted key of the scene file, "
                                           "[i] or [name] for list items); several --set "
                                           "give every combination."),
    workers: int = typer.Option(1, "--workers", help="Processes of the local dask cluster."),
    scheduler: str = typer.Option(None, "--scheduler",
                                  help="Address of a running dask scheduler, e.g. "
                                       "tcp://host:8786, instead of a local cluster."),
    overwrite: bool = typer.Option(False, "--overwrite",
                                   help="Replace the results of an earlier sweep in OUTPUT."),
    quiet: bool = typer.Option(False, "--quiet", "-q",
                               help="Print only errors: no progress lines, no list of files."),
    verbose: bool = typer.Option(False, "--verbose", "-v",
                                 help="Also print each stage on standard error: the variants, "
                                      "the cluster, each variant finished and the time taken."),
) -> None:
    """Render SCENE_FILE once per combination of the --set values, in parallel on dask.
    Prints a line as each variant finishes, then the files written; --quiet prints only
    errors; --verbose adds each stage and its time."""
    import time

    from radscene.cli import Report
    from radscene.distributed import render_sweep, variants

    report = Report(quiet, verbose)
    settings = dict(_setting(s) for s in setting)
    report.stage(f"{len(variants(settings))} variant(s) of {len(settings)} setting(s): "
                 + "; ".join(f"{key}={','.join(map(str, values))}"
                             for key, values in settings.items()))
    client = None
    if scheduler is not None:
        try:
            from distributed import Client
        except ImportError:
            raise ConfigError("a sweep runs on dask: install the dask extra (pip install "
                              "'.[dask]')", key="--scheduler") from None
        try:
            client = Client(scheduler, timeout="10s")
        except OSError as err:
            raise ConfigError(f"no dask scheduler at {scheduler}: {err}", key="--scheduler") from None
    report.stage(f"rendering on the dask scheduler {scheduler}" if client is not None else
                 f"rendering on a local dask cluster of {workers} process(es)")
    started = time.perf_counter()

    def progress(done, total):
        report.say(f"variant {done}/{total}")
        report.stage(f"variant {done}/{total} finished", time.perf_counter() - started)

    try:
        files = render_sweep(scene_file, settings, output, client=client, workers=workers,
                             overwrite=overwrite, progress=progress)
    finally:
        if client is not None:
            client.close()
    report.stage(f"{len(files)} variant(s) rendered and written, indexed in "
                 f"{output / 'sweep.json'}", time.perf_counter() - started)
    for name, paths in files.items():
        for path in paths:
            report.say(f"{name}: {path}", markup=False)
    report.say(f"wrote {output / 'sweep.json'}", markup=False)
