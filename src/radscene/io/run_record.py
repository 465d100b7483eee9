"""What runs have written into an output folder: a marker while any lasts, a manifest after.

An output folder never looks complete when it is not: ``radscene render`` writes
:data:`MARKER` before its first file and lists in it each observer as its files land; when the
last run writing into the folder finishes, the marker is replaced by :data:`MANIFEST` (every
file, its size and SHA-256, of every observer any run finished there). A run stopped by an
error, Ctrl-C or SIGTERM leaves its part of the marker (the files being written at that moment
are temporaries, removed on the way out: :func:`radscene.io.files.atomic_output`), and
``--resume`` renders only the observers the stopped runs of the same scene had not finished.

Several runs may write into one folder at once (say one per observer, on two machines of a
cluster sharing the folder): each has its own entry under ``runs`` in the marker, and every
read-modify-write of the marker and the manifest holds an exclusive lock on the folder
(``flock``), so no run overwrites another's record, the folder stays marked incomplete until
the last one ends, and the manifest lists the observers of all of them. The marker's top level
(``finished``, ``files``, ``scene``, ``scene_sha256``) summarises its runs.

Whether a run in the marker still lasts is decided by where it runs. Each run records its host
name, its process id and that process's start time, and a heartbeat, rewritten every
:data:`HEARTBEAT` seconds while it lasts. A run of this host lasts while a process of its id
and start time does (a process id reused by another program does not count). A run of
another host (shared storage) cannot be asked: it counts as lasting until its heartbeat is
:data:`STALE_AFTER` seconds old, so a run that crashed on another machine is taken over by
``--resume`` that long after it stopped, and one that still runs is never. To clear a marker
sooner, remove the folder's :data:`MARKER` and render into the folder again (or into a new
one): what the stopped run had finished is then rendered again.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import fcntl
import hashlib
import json
import os
import socket
import threading
from pathlib import Path

from radscene.errors import ConfigError
from radscene.io import stop
from radscene.io.files import atomic_output, process_running, remove_stale_temporaries

__all__ = ["MARKER", "MANIFEST", "RunRecord", "finished"]

#: Present while a run writes into the folder, and after one that stopped midway.
MARKER = ".radscene-incomplete.json"
#: Written when a run has finished.
MANIFEST = "manifest.json"
#: How often a lasting run rewrites its heartbeat in the marker [s].
HEARTBEAT = 60.0
#: How old the heartbeat of another host's run may grow before the run counts as stopped [s].
STALE_AFTER = 600.0


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


@contextlib.contextmanager
def _locked(folder: Path):
    """An exclusive lock on ``folder`` (flock on the folder itself: no lock file is left)."""
    fd = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        fcntl.flock(fd, fcntl.LOCK_UN)
        os.close(fd)


def _read(path: Path) -> dict | None:
    try:
        return json.loads(path.read_text())
    except (OSError, ValueError):
        return None


def _now() -> _dt.datetime:
    return _dt.datetime.now(_dt.UTC)


def _process_started(pid) -> str | None:
    """When process ``pid`` started, as the kernel counts it (field 22 of /proc/PID/stat, clock
    ticks since boot), or None where there is no /proc or no such process."""
    try:
        text = Path(f"/proc/{int(pid)}/stat").read_text()
    except (OSError, TypeError, ValueError):
        return None
    return text.rsplit(")", 1)[-1].split()[19]  # the name, in brackets, may hold spaces


def _alive(run: dict, now: _dt.datetime | None = None) -> bool:
    """Whether the run ``run`` of a marker still lasts (module docstring)."""
    if run.get("host", socket.gethostname()) != socket.gethostname():
        try:
            beat = _dt.datetime.fromisoformat(run.get("heartbeat") or run["started"])
        except (KeyError, TypeError, ValueError):
            return False
        return ((now or _now()) - beat).total_seconds() < STALE_AFTER
    pid = run.get("pid")
    try:
        if not process_running(int(pid)):
            return False
    except (TypeError, ValueError):
        pass
    started = run.get("pid_started")
    return started is None or _process_started(pid) in (None, started)


def _holder(run: dict) -> str:
    """Who a run is, for messages."""
    return (f"process {run.get('pid')} on {run.get('host', 'this host')}, last heard from at "
            f"{run.get('heartbeat', run.get('started'))}")


def _summarise(marker: dict) -> dict:
    """The marker with its top level summarising its runs and completed observers."""
    runs = marker.get("runs", {})
    files = {name: entry["files"] for name, entry in marker.get("completed", {}).items()}
    for run in runs.values():
        files.update({n: run["files"][n] for n in run["finished"] if n in run.get("files", {})})
    latest = max(runs.values(), key=lambda r: r["started"], default=None)
    marker["finished"] = list(files)
    marker["files"] = files
    if latest is not None:
        marker["scene"], marker["scene_sha256"] = latest["scene"], latest["scene_sha256"]
    return marker


def _manifest_entries(folder: Path, observer: str, names) -> list[dict]:
    entries = []
    for name in names:
        for path in _files_of(folder / name):  # a Zarr store: each of its files
            entries.append({"file": os.path.relpath(path, folder), "observer": observer,
                            "bytes": path.stat().st_size, "sha256": _sha256(path)})
    return entries


def _stopped_runs(marker: dict, digest: str, variant: str | None = None) -> dict:
    """The runs of the marker of the scene with SHA-256 ``digest`` (and the same ``variant``:
    a sequence's span) that stopped midway."""
    return {key: run for key, run in marker.get("runs", {}).items()
            if run.get("scene_sha256") == digest and run.get("variant") == variant
            and not _alive(run)}


def finished(folder, scene_file, variant: str | None = None) -> list[str]:
    """Observers that stopped runs of ``scene_file`` (and finished ones) completed in
    ``folder``, with their files still there (for --resume).

    Parameters
    ----------
    folder, scene_file : path
    variant : str, optional
        What else the runs must share: a sequence's span.

    Raises
    ------
    radscene.errors.ConfigError
        When the folder holds no interrupted run, only runs of another scene file (or
        variant), or only runs that still last (:func:`_alive`).
    """
    folder = Path(folder)
    marker_path = folder / MARKER
    if not marker_path.is_file():
        if (folder / MANIFEST).is_file():
            raise ConfigError(f"{folder} holds a complete run ({MANIFEST}); nothing to resume",
                              key="--resume")
        raise ConfigError(f"{folder} holds no interrupted run to resume (no {MARKER})",
                          key="--resume")
    marker = _read(marker_path)
    if not isinstance(marker, dict) or not isinstance(marker.get("runs"), dict):
        raise ConfigError(f"{marker_path} is not a radscene run marker", key="--resume")
    digest = _sha256(Path(scene_file))
    stopped = _stopped_runs(marker, digest, variant)
    if not stopped:
        lasting = [run for run in marker["runs"].values() if _alive(run)]
        if lasting:
            raise ConfigError(f"a run still writes into {folder} ({_holder(lasting[0])}); a run "
                              f"of another host counts as stopped {STALE_AFTER / 60:g} min after "
                              f"its last heartbeat. To take over sooner, remove {marker_path} "
                              "(what it finished is rendered again) or render into a new folder",
                              key="--resume")
        raise ConfigError(f"the run in {folder} was of another scene file (or the file has "
                          "changed since, or another span); render into a new folder",
                          key="--resume")
    done = {}
    for run in stopped.values():
        done.update({n: run["files"].get(n, []) for n in run["finished"]})
    done.update({n: c["files"] for n, c in marker.get("completed", {}).items()
                 if c.get("scene_sha256") == digest and c.get("variant") == variant})
    return [name for name, names in done.items() if all((folder / f).exists() for f in names)]


class RunRecord:
    """Context manager of one run into ``folder``: its entry in the marker on entry, updated by
    :meth:`finish`; on a clean exit its observers move to the completed ones, and the last run
    out writes the manifest. SIGTERM ends the run as Ctrl-C does, so the temporaries of the
    files being written are removed."""

    def __init__(self, folder, scene_file, observers, done=(), variant: str | None = None):
        self.folder = Path(folder)
        self.scene_file = Path(scene_file)
        started = _now()
        self.id = f"{socket.gethostname()}-{os.getpid()}-{started.strftime('%Y%m%dT%H%M%S.%f')}"
        self.record = {
            "scene": str(self.scene_file),
            "scene_sha256": _sha256(self.scene_file),
            "observers": list(observers),
            "finished": [],
            "files": {},
            "started": started.isoformat(timespec="seconds"),
            "heartbeat": started.isoformat(timespec="seconds"),
            "host": socket.gethostname(),
            "pid": os.getpid(),
            "pid_started": _process_started(os.getpid()),
        }
        if variant is not None:
            self.record["variant"] = variant
        self.done = list(done)  # observers a stopped run of the same scene finished
        self._handlers = {}
        self._stop = threading.Event()
        self._beat = None
        self._record_lock = threading.Lock()  # the heartbeat's thread and the run's

    def _update(self, change) -> None:
        """Read the marker, apply ``change(marker)``, write it back, under the folder's lock."""
        with _locked(self.folder):
            marker = _read(self.folder / MARKER) or {}
            marker.setdefault("runs", {})
            marker.setdefault("completed", {})
            change(marker)
            _write_json(self.folder / MARKER, _summarise(marker))

    def __enter__(self):
        self.folder.mkdir(parents=True, exist_ok=True)
        with _locked(self.folder):  # what runs killed outright (SIGKILL) left half written
            remove_stale_temporaries(self.folder)

        def enter(marker):
            previous = _read(self.folder / MANIFEST)
            if previous and not marker["runs"]:  # a finished folder that gets more results
                for entry in previous.get("files", []):
                    item = marker["completed"].setdefault(
                        entry["observer"], {"files": [], "scene": previous.get("scene"),
                                            "scene_sha256": previous.get("scene_sha256")})
                    item["files"].append(entry["file"])
            (self.folder / MANIFEST).unlink(missing_ok=True)  # no longer describes the folder
            digest = self.record["scene_sha256"]
            for key in list(_stopped_runs(marker, digest, self.record.get("variant"))) if self.done else ():
                old = marker["runs"].pop(key)  # a resumed run takes over what it finished
                for name in old["finished"]:
                    if name in self.done:
                        self.record["finished"].append(name)
                        self.record["files"][name] = old["files"].get(name, [])
            for key, run in list(marker["runs"].items()):  # stopped runs this one redoes
                if not _alive(run) and set(run["observers"]) <= set(self.record["observers"]):
                    marker["runs"].pop(key)
            for name in self.record["observers"]:  # rendered again here
                if name not in self.done:
                    marker["completed"].pop(name, None)
            marker["runs"][self.id] = self.record

        self._update(enter)

        self._handlers = stop.install()
        self._beat = threading.Thread(target=self._heartbeat, name="radscene-heartbeat",
                                      daemon=True)
        self._beat.start()
        return self

    def _heartbeat(self) -> None:
        """Rewrite this run's heartbeat in the marker every HEARTBEAT seconds until the end."""
        def change(marker):
            if self.id in marker["runs"]:
                marker["runs"][self.id] = self.record

        while not self._stop.wait(HEARTBEAT):
            try:
                with self._record_lock:
                    self.record["heartbeat"] = _now().isoformat(timespec="seconds")
                    self._update(change)
            except OSError:  # a folder gone or unwritable: the run itself will say so
                return

    def finish(self, observer: str, files) -> None:
        """Record that ``observer``'s files are written."""
        stop.check()  # a stop whose exception was dropped: not finished
        names = [os.path.relpath(f, self.folder) for f in files]

        def change(marker):
            marker["runs"][self.id] = self.record

        with self._record_lock:
            self.record["finished"].append(observer)
            self.record["files"][observer] = names
            self.record["heartbeat"] = _now().isoformat(timespec="seconds")
            self._update(change)

    def __exit__(self, kind, value, traceback):
        self._stop.set()
        if self._beat is not None:
            self._beat.join()
        stop.restore(self._handlers)
        if kind is not None:
            return False  # this run's entry stays: the folder is incomplete
        stop.check()  # a stop whose exception was dropped ends the run as stopped
        with _locked(self.folder):
            marker = _read(self.folder / MARKER) or {"runs": {}, "completed": {}}
            marker.setdefault("completed", {})
            marker.setdefault("runs", {}).pop(self.id, None)
            for name in self.record["finished"]:
                marker["completed"][name] = {"files": self.record["files"].get(name, []),
                                             "scene": self.record["scene"],
                                             "scene_sha256": self.record["scene_sha256"],
                                             "started": self.record["started"]}
                if "variant" in self.record:
                    marker["completed"][name]["variant"] = self.record["variant"]
            if marker["runs"]:  # other runs still write here (or stopped midway)
                _write_json(self.folder / MARKER, _summarise(marker))
                return False
            entries = []
            for name, item in marker["completed"].items():
                entries += _manifest_entries(self.folder, name, item["files"])
            scenes = {(c["scene"], c["scene_sha256"]) for c in marker["completed"].values()}
            manifest = {key: self.record[key] for key in ("scene", "scene_sha256", "started")}
            manifest["observers"] = list(marker["completed"])
            if len(scenes) > 1:
                manifest["scenes"] = [{"scene": a, "scene_sha256": b} for a, b in sorted(scenes)]
            manifest["finished"] = _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds")
            manifest["files"] = entries
            _write_json(self.folder / MANIFEST, manifest)
            (self.folder / MARKER).unlink(missing_ok=True)
        return False
