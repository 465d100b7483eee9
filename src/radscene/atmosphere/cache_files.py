"""Entries of the engines' result caches (6S, LOWTRAN) written whole and readable as other
files are.

An entry is written to a unique temporary beside it and moved into place, so that a reader
never sees half of one and parallel runs may share a cache folder. The temporary is created
with the permissions an ordinary new file gets (0666 less the umask, or a default ACL of the
folder): ``tempfile.mkstemp`` would make it readable by its owner alone (0600), and a cache
folder on shared storage (``RADSCENE_CACHE_DIR``, ``RADSCENE_CACHE``) of no use to colleagues.
"""

from __future__ import annotations

import os
import secrets
from collections.abc import Callable
from pathlib import Path
from typing import IO

__all__ = ["write_entry"]


def write_entry(path, write: Callable[[IO], object], binary: bool = True) -> Path:
    """Write the cache entry ``path`` by ``write(handle)``, atomically.

    Parameters
    ----------
    path : str or pathlib.Path
        The entry; its folder must exist.
    write : callable
        Called with the open file (binary, or text in UTF-8 when ``binary`` is false).
    binary : bool
        Open the file in binary mode.

    Returns
    -------
    pathlib.Path
        ``path``, in place with the mode 0666 less the umask.

    Raises
    ------
    OSError
        The folder cannot be written; the temporary is removed.
    """
    path = Path(path)
    flags = os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0)
    for _ in range(100):
        tmp = path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(6)}.tmp")
        try:
            fd = os.open(tmp, flags, 0o666)  # the umask applies, as to any new file
            break
        except FileExistsError:
            continue
    else:
        raise FileExistsError(f"no free temporary name beside {path}")
    try:
        with (os.fdopen(fd, "wb") if binary else
              os.fdopen(fd, "w", encoding="utf-8")) as handle:
            write(handle)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    return path
