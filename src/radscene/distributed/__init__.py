"""Sweeps of a scene on a dask cluster: the same scene rendered under many settings at once.

A trade study, a day cycle or a training set is one scene file rendered again and again with a
few keys changed: the sun, the time, the visibility, a camera's altitude or field of view, a
material. :func:`render_sweep` expands the settings into variants (every combination of the
values given, or an explicit list), checks every variant before any render starts (a bad key
or value is refused naming the variant and the key), then renders them as tasks of a dask
``distributed`` cluster — a local one of ``workers`` processes by default, or the user's own
``Client`` (a cluster of many machines; the workers need radscene and the scene's files at the
same paths). Each variant writes its observers' NetCDF files into its own folder, with its
settings in the files' attributes (``sweep_variant``, ``sweep_settings``) beside the usual
provenance, and ``sweep.json`` indexes them all.

Needs the ``dask`` extra (``pip install '.[dask]'``: dask and distributed).

Example::

    from radscene.distributed import render_sweep
    files = render_sweep("scene.yaml", {"environment.sun.zenith": [20, 40, 60],
                                        "environment.atmosphere.visibility": ["5 km", "23 km"]},
                         "out/", workers=2)

or ``radscene sweep scene.yaml -o out --set environment.sun.zenith=20,40,60 --workers 2``.

Keys are dotted paths into the scene file, with ``[i]`` for list items
(``observers[0].altitude``) or a list item's ``name`` (``observers[map].altitude``).
"""

from __future__ import annotations

import copy
import itertools
import json
import re
from pathlib import Path

from radscene.errors import ConfigError

__all__ = ["variants", "apply_setting", "render_sweep"]

_PART = re.compile(r"([^.\[\]]+)|\[([^\]]+)\]")


def _parts(key: str) -> list[str | int]:
    if not isinstance(key, str) or not key or key.startswith(".") or key.endswith("."):
        raise ConfigError(f"a setting's key is a dotted path such as environment.sun.zenith; "
                          f"got {key!r}", key="settings")
    out: list[str | int] = []
    for name, index in _PART.findall(key):
        if name:
            out.append(name)
        else:
            out.append(int(index) if index.lstrip("-").isdigit() else f"[{index}]")
    return out


def apply_setting(document: dict, key: str, value) -> dict:
    """A copy of the scene ``document`` with ``key`` (a dotted path, ``[i]`` for a list item or
    ``[name]`` for the item of that ``name``) set to ``value``; missing mappings on the way are
    created.

    Raises
    ------
    ConfigError
        A path through something that is not a mapping or list, an index out of range or an
        unknown item name (naming ``key``).

    Examples
    --------
    >>> apply_setting({"observers": [{"name": "map", "gsd": 1.0}]}, "observers[map].gsd", 2.0)
    {'observers': [{'name': 'map', 'gsd': 2.0}]}
    """
    out = copy.deepcopy(document)
    node = out
    parts = _parts(key)
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = key if last else ".".join(str(p) for p in parts[: i + 1])
        if isinstance(part, int) or (isinstance(part, str) and part.startswith("[")):
            if not isinstance(node, list):
                raise ConfigError(f"{where}: not a list in the scene", key=key)
            if isinstance(part, int):
                if not -len(node) <= part < len(node):
                    raise ConfigError(f"index {part} out of range (the list has {len(node)} "
                                      "items)", key=key)
                index = part
            else:
                name = part[1:-1]
                names = [item.get("name") if isinstance(item, dict) else None for item in node]
                if name not in names:
                    known = ", ".join(str(n) for n in names if n is not None) or "none"
                    raise ConfigError(f"no item named {name!r}; named: {known}", key=key)
                index = names.index(name)
            if last:
                node[index] = value
            else:
                node = node[index]
            continue
        if not isinstance(node, dict):
            raise ConfigError(f"{where}: not a mapping in the scene", key=key)
        if last:
            node[part] = value
        else:
            node = node.setdefault(part, {})
    return out


def variants(settings) -> list[dict]:
    """The variants of a sweep: each a dict of key → value.

    Parameters
    ----------
    settings : dict of str to list, or list of dict
        Every combination of the values of each key (the first key varying slowest), or the
        variants themselves.

    Returns
    -------
    list of dict

    Examples
    --------
    >>> variants({"a": [1, 2], "b": ["x", "y"]})
    [{'a': 1, 'b': 'x'}, {'a': 1, 'b': 'y'}, {'a': 2, 'b': 'x'}, {'a': 2, 'b': 'y'}]
    """
    if isinstance(settings, dict):
        keys = list(settings)
        values = []
        for key in keys:
            v = settings[key]
            v = list(v) if isinstance(v, (list, tuple)) else [v]
            if not v:
                raise ConfigError("no values to sweep", key=key)
            values.append(v)
        out = [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*values)]
    elif isinstance(settings, (list, tuple)) and all(isinstance(s, dict) for s in settings):
        out = [dict(s) for s in settings]
    else:
        raise ConfigError("settings are a mapping of key to values, or a list of mappings",
                          key="settings")
    if not out:
        raise ConfigError("a sweep needs at least one variant", key="settings")
    return out


def _document(scene) -> tuple[dict, Path]:
    import yaml

    if isinstance(scene, dict):
        return copy.deepcopy(scene), Path.cwd()
    path = Path(scene)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise ConfigError(f"cannot read {path}: {err.strerror}", key="scene") from None
    document = yaml.safe_load(text)
    if not isinstance(document, dict):
        raise ConfigError(f"{path}: not a scene file (a YAML mapping)", key="scene")
    return document, path.resolve().parent


def _render_variant(document: dict, base_dir: str, folder: str, name: str,
                    setting: dict) -> list[str]:
    """One variant on a worker: load, render every observer, write ``folder/<observer>.nc``."""
    from radscene.io.netcdf import write_netcdf
    from radscene.pipeline import render_all
    from radscene.scene import load_scene

    scene = load_scene(document, base_dir)
    images = render_all(scene, progress=False)
    out = Path(folder)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for observer, ds in images.items():
        ds.attrs["sweep_variant"] = name
        ds.attrs["sweep_settings"] = json.dumps(setting, default=str)
        written.append(str(write_netcdf(ds, out / f"{observer}.nc")))
    return written


def render_sweep(scene, settings, output, *, client=None, workers: int | None = None,
                 overwrite: bool = False, progress=None) -> dict[str, list[Path]]:
    """Render a scene under every variant of ``settings`` on a dask cluster.

    Parameters
    ----------
    scene : str, pathlib.Path or dict
        A scene file (its relative file names are resolved against its folder, on the
        workers too) or its content.
    settings : dict of str to list, or list of dict
        As for :func:`variants`: keys are dotted paths into the scene file.
    output : str or pathlib.Path
        Folder of the results: ``variant_NNN/<observer>.nc`` and ``sweep.json``.
    client : distributed.Client, optional
        The cluster to run on; by default a local cluster of ``workers`` processes, closed
        at the end.
    workers : int, optional
        Processes of the local cluster (default 1; each renders one variant at a time).
    overwrite : bool
        Replace the results of an earlier sweep in ``output``.
    progress : callable(done, total), optional
        Called as each variant finishes.

    Returns
    -------
    dict of str to list of pathlib.Path
        Per variant name, the files it wrote.

    Raises
    ------
    ConfigError
        A bad key or value in any variant (naming the variant and the key), before any
        render; results of an earlier sweep in ``output`` without ``overwrite``; the ``dask``
        extra missing.
    """
    from radscene.io.files import atomic_output, check_output_folder
    from radscene.scene import load_scene

    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise ConfigError("a sweep runs on dask: install the dask extra (pip install "
                          "'.[dask]': dask and distributed)", key="sweep") from None
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ConfigError(f"must be a whole number >= 1; got {workers!r}", key="workers")
    document, base_dir = _document(scene)
    todo = variants(settings)
    output = Path(output)
    names = [f"variant_{i:03d}" for i in range(len(todo))]
    check_output_folder(output, ["sweep.json", *names], overwrite=overwrite)
    documents = []
    for name, setting in zip(names, todo, strict=True):
        doc = document
        for key, value in setting.items():
            doc = apply_setting(doc, key, value)
        try:  # every variant checked before the first render
            load_scene(doc, base_dir)
        except ConfigError as err:
            raise ConfigError(f"{name} ({_describe(setting)}): {err.message}",
                              key=err.key) from None
        documents.append(doc)
    own = client is None
    cluster = LocalCluster(n_workers=workers or 1, threads_per_worker=1, processes=True,
                           dashboard_address=None) if own else None
    client = Client(cluster) if own else client
    try:
        futures = {client.submit(_render_variant, doc, str(base_dir), str(output / name), name,
                                 setting, pure=False): name
                   for name, doc, setting in zip(names, documents, todo, strict=True)}
        written = {}
        for done, future in enumerate(as_completed(futures), start=1):
            written[futures[future]] = [Path(p) for p in future.result()]
            if progress is not None:
                progress(done, len(futures))
    finally:
        if own:
            client.close()
            cluster.close()
    index = {"scene": str(scene) if not isinstance(scene, dict) else None,
             "variants": [{"name": name, "settings": setting,
                           "files": [str(p.relative_to(output)) for p in written[name]]}
                          for name, setting in zip(names, todo, strict=True)]}
    with atomic_output(output / "sweep.json", suffix=".json") as tmp:
        Path(tmp).write_text(json.dumps(index, indent=1, default=str), encoding="utf-8")
    return {name: written[name] for name in names}


def _describe(setting: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in setting.items())
