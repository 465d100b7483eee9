"""Writing output files whole or not at all."""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

__all__ = ["atomic_output"]


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
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=suffix, dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
