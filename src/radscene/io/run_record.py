"""What a run has written into its output folder: a marker while it lasts, a manifest after.

An output folder never looks complete when it is not: ``radscene render`` writes
:data:`MARKER` before its first file and lists in it each observer as its files land; only a
run that finishes replaces the marker with :data:`MANIFEST` (every file, its size and SHA-256).
A run stopped by an error, Ctrl-C or SIGTERM leaves the marker (the files being written at that
moment are temporaries, removed on the way out: :func:`radscene.io.files.atomic_output`), and
``--resume`` renders only the observers the marker does not list.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import json
import os
import signal
from pathlib import Path

from radscene.errors import ConfigError
from radscene.io.files import atomic_output

__all__ = ["MARKER", "MANIFEST", "RunRecord", "finished"]

#: Present while a run writes into the folder, and after one that stopped midway.
MARKER = ".radscene-incomplete.json"
#: Written when a run has finished.
MANIFEST = "manifest.json"


def _sha256(path: Path) -> str:
    """SHA-256 of a file's bytes; of a folder (a Zarr store given to --from), of the list of
    its files' relative paths and SHA-256s."""
    path = Path(path)
    if path.is_dir():
        listing = "".join(f"{p.relative_to(path).as_posix()}\0{_sha256(p)}\n"
                          for p in _files_of(path))
        return hashlib.sha256(listing.encode()).hexdigest()
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def _files_of(path: Path) -> list[Path]:
    """``path`` itself, or for a folder (a Zarr store) every file under it, sorted."""
    if path.is_dir():
        return sorted(p for p in path.rglob("*") if p.is_file())
    return [path]


def _write_json(path: Path, data: dict) -> None:
    with atomic_output(path, suffix=".json") as tmp:
        Path(tmp).write_text(json.dumps(data, indent=1))


def finished(folder, scene_file) -> list[str]:
    """Observers an interrupted run of ``scene_file`` finished in ``folder`` (for --resume).

    Raises
    ------
    radscene.errors.ConfigError
        When the folder holds no interrupted run, or one of another scene file.
    """
    folder = Path(folder)
    marker = folder / MARKER
    if not marker.is_file():
        if (folder / MANIFEST).is_file():
            raise ConfigError(f"{folder} holds a complete run ({MANIFEST}); nothing to resume",
                              key="--resume")
        raise ConfigError(f"{folder} holds no interrupted run to resume (no {MARKER})",
                          key="--resume")
    try:
        record = json.loads(marker.read_text())
        digest, done = record["scene_sha256"], list(record["finished"])
    except (OSError, ValueError, KeyError, TypeError):
        raise ConfigError(f"{marker} is not a radscene run marker", key="--resume") from None
    if digest != _sha256(Path(scene_file)):
        raise ConfigError(f"the run in {folder} was of another scene file (or the file has "
                          "changed since); render into a new folder", key="--resume")
    return [name for name in done if all((folder / f).exists()
                                         for f in record.get("files", {}).get(name, []))]


class RunRecord:
    """Context manager of one run into ``folder``: the marker on entry, updated by
    :meth:`finish`, the manifest on a clean exit; SIGTERM ends the run as Ctrl-C does, so the
    temporaries of the files being written are removed."""

    def __init__(self, folder, scene_file, observers, done=()):
        self.folder = Path(folder)
        self.scene_file = Path(scene_file)
        self.record = {
            "scene": str(self.scene_file),
            "scene_sha256": _sha256(self.scene_file),
            "observers": list(observers),
            "finished": [],
            "files": {},
            "started": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        }
        self._previous = {}
        if done:  # a resumed run keeps what the marker lists
            old = json.loads((self.folder / MARKER).read_text())
            self.record["finished"] = list(done)
            self.record["files"] = {n: old["files"][n] for n in done if n in old.get("files", {})}
        self._handler = None

    def __enter__(self):
        self.folder.mkdir(parents=True, exist_ok=True)
        (self.folder / MANIFEST).unlink(missing_ok=True)  # no longer describes the folder
        _write_json(self.folder / MARKER, self.record)

        def terminate(signum, frame):
            raise KeyboardInterrupt(f"signal {signum}")

        try:
            self._handler = signal.signal(signal.SIGTERM, terminate)
        except ValueError:  # not the main thread: leave SIGTERM alone
            self._handler = None
        return self

    def finish(self, observer: str, files) -> None:
        """Record that ``observer``'s files are written."""
        names = [os.path.relpath(f, self.folder) for f in files]
        self.record["finished"].append(observer)
        self.record["files"][observer] = names
        _write_json(self.folder / MARKER, self.record)

    def __exit__(self, kind, value, traceback):
        if self._handler is not None:
            signal.signal(signal.SIGTERM, self._handler)
        if kind is not None:
            return False  # the marker stays: the folder is incomplete
        entries = []
        for observer in self.record["finished"]:
            for name in self.record["files"].get(observer, []):
                for path in _files_of(self.folder / name):  # a Zarr store: each of its files
                    entries.append({"file": os.path.relpath(path, self.folder),
                                    "observer": observer, "bytes": path.stat().st_size,
                                    "sha256": _sha256(path)})
        manifest = {key: self.record[key] for key in ("scene", "scene_sha256", "observers",
                                                      "started")}
        manifest["finished"] = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
        manifest["files"] = entries
        _write_json(self.folder / MANIFEST, manifest)
        (self.folder / MARKER).unlink(missing_ok=True)
        return False
