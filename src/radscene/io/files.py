"""Writing output files whole or not at all.

Each file is written under a temporary name beside its own, ``.NAME.~HOST~PID~<random><suffix>``,
and moved into place when whole; a run that stops (an error, Ctrl-C, SIGTERM) removes its
temporaries on the way out. A run killed outright (SIGKILL, the machine's power) cannot: the
name records the host and process that wrote it, and :func:`remove_stale_temporaries`, called
by the next run into the folder, removes those of this host whose process is gone.
"""

from __future__ import annotations

import contextlib
import glob
import os
import re
import shutil
import socket
import tempfile
from pathlib import Path

from radscene.errors import ConfigError

__all__ = ["atomic_output", "atomic_output_dir", "check_output_folder", "check_output_file",
           "process_running", "remove_stale_temporaries"]

#: A temporary's name: '.', the file's name, '.~HOST~PID~', a random part and a suffix.
_TEMPORARY = re.compile(r"^\..+\.~(?P<host>[^~/]+)~(?P<pid>\d+)~")


def _owner() -> str:
    """The part of a temporary's name that says which host and process writes it."""
    return f"~{socket.gethostname()}~{os.getpid()}~"


def process_running(pid: int) -> bool:
    """Whether a process of this id runs on this host (one of another user's counts)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def remove_stale_temporaries(folder, names=None) -> list[Path]:
    """Remove the temporaries under ``folder`` that runs of this host left when they were
    killed outright: those whose writing process no longer runs. Those of running processes
    and of other hosts (a shared folder) are left. With ``names`` (file names), only the
    temporaries of those files directly in ``folder`` are looked for. Returns what was
    removed."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    host = socket.gethostname()
    stale = []
    found_paths = (folder.rglob(".*") if names is None
                   else (p for name in names for p in folder.glob(f".{glob.escape(name)}.~*")))
    for path in sorted(found_paths):
        found = _TEMPORARY.match(path.name)
        if (found and found["host"] == host and not process_running(int(found["pid"]))
                and not any(path.is_relative_to(p) for p in stale)):
            stale.append(path)
    for path in stale:
        if path.is_dir() and not path.is_symlink():
            shutil.rmtree(path, ignore_errors=True)
        else:
            path.unlink(missing_ok=True)
    return stale


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


@contextlib.contextmanager
def atomic_output(path, suffix=".tmp"):
    """Yield a unique temporary path beside ``path``; on success move it into place with the
    permissions an ordinary new file gets (0666 less the umask), on failure remove it.

    ``tempfile.mkstemp`` creates its file readable by its owner alone (0600); a result left
    so would be unreadable to colleagues on shared storage. A unique name per call keeps two
    runs writing into one folder from colliding.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.{_owner()}", suffix=suffix,
                               dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


@contextlib.contextmanager
def atomic_output_dir(path, suffix=".tmp"):
    """As :func:`atomic_output` for an output that is a folder (a Zarr store): yield a unique
    empty temporary folder beside ``path``; on success move it into place, on failure remove it.

    An earlier ``path`` is first renamed aside and removed only once the new folder is in
    place, so ``path`` is always either the old whole result, the new one, or (between the two
    renames) absent — never a mixture. Folders and files get the permissions ordinary new ones
    get (0777 and 0666 less the umask).
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = tempfile.mkdtemp(prefix=f".{path.name}.{_owner()}", suffix=suffix, dir=path.parent)
    old = None
    try:
        yield tmp
        mask = _umask()
        for root, _dirs, files in os.walk(tmp):
            os.chmod(root, 0o777 & ~mask)
            for name in files:
                os.chmod(os.path.join(root, name), 0o666 & ~mask)
        if path.exists() or path.is_symlink():
            old = tempfile.mkdtemp(prefix=f".{path.name}.{_owner()}", suffix=".old",
                                   dir=path.parent)
            os.replace(path, os.path.join(old, path.name))
        os.replace(tmp, path)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old is not None and not path.exists():  # put the earlier result back
            os.replace(os.path.join(old, path.name), path)
        raise
    finally:
        if old is not None:
            shutil.rmtree(old, ignore_errors=True)


def _writable_parent(path: Path, key: str) -> None:
    """Refuse ``path`` when a parent is a file or the nearest existing folder is not writable."""
    for parent in path.absolute().parents:
        if parent.exists():
            if not parent.is_dir():
                raise ConfigError(f"{parent} is a file, so {path} cannot be created under it",
                                  key=key)
            if not os.access(parent, os.W_OK | os.X_OK):
                raise ConfigError(f"cannot write {path}: {parent} is not writable", key=key)
            _probe(parent, path, key)
            return


def _probe(folder: Path, path: Path, key: str) -> None:
    """Create and remove an empty folder in ``folder``: what the permission bits do not tell
    (a read-only or special file system, a root-squashed share; root passes every access
    check) is refused before any work, and nothing is left behind."""
    try:
        os.rmdir(tempfile.mkdtemp(prefix=".radscene-probe-", dir=folder))
    except OSError as err:
        raise ConfigError(f"cannot write {path}: {err.strerror or err}", key=key) from None


def check_output_folder(folder, files=(), overwrite: bool = False, key: str = "--output") -> None:
    """Check before any work that results can be written into ``folder``.

    Parameters
    ----------
    folder : path
        The output folder; it may not exist yet.
    files : iterable of str
        Names of the files the run will write there; any that exists is refused unless
        ``overwrite``.
    overwrite : bool
    key : str
        What the error names (the command-line option).

    Raises
    ------
    radscene.errors.ConfigError
        When ``folder`` is a file, lies under a file, cannot be created or written, or holds
        one of ``files`` and ``overwrite`` is false.
    """
    folder = Path(folder)
    if folder.exists():
        if not folder.is_dir():
            raise ConfigError(f"{folder} is a file; give a folder", key=key)
        if not os.access(folder, os.W_OK | os.X_OK):
            raise ConfigError(f"cannot write into {folder}: not writable", key=key)
        _probe(folder, folder, key)
    else:
        _writable_parent(folder, key)
    existing = sorted(name for name in files if (folder / name).exists())
    if existing and not overwrite:
        raise ConfigError(f"{folder} already holds {', '.join(existing)}; give --overwrite to "
                          "replace them or another folder", key=key)


def check_output_file(path, overwrite: bool = False, key: str = "--output") -> None:
    """As :func:`check_output_folder` for a single output file ``path``."""
    path = Path(path)
    if path.exists():
        if path.is_dir():
            raise ConfigError(f"{path} is a folder; give a file name", key=key)
        if not overwrite:
            raise ConfigError(f"{path} exists; give --overwrite to replace it", key=key)
        if not os.access(path.parent, os.W_OK | os.X_OK):
            raise ConfigError(f"cannot write {path}: {path.parent} is not writable", key=key)
        _probe(path.parent, path, key)
    else:
        _writable_parent(path, key)
