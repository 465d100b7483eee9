"""Confinement of an untrusted scene file to its own folder.

With ``confine`` (``load_scene(..., confine=True)``, ``radscene render/check --confine``)
every file a scene names — under a ``file`` or ``temperature_map`` key, or any string that
ends in a data file's extension — must resolve, symbolic links followed, inside the scene's
folder; anything else is refused before a byte of it is read, naming the key. A program a
scene names to run (an engine's ``executable``) and a folder it names to write into (an
engine's ``cache_dir``) are refused wherever they lie: a confined scene runs only the engines
radscene finds itself and writes only where the command line says.
"""

from __future__ import annotations

import os
from pathlib import Path

from radscene.errors import ConfigError

__all__ = ["check_confined", "named_files", "with_files", "FILE_KEYS", "FILE_SUFFIXES", "REFUSED_KEYS"]

#: Keys whose string value is a file path.
FILE_KEYS = frozenset({"file", "temperature_map"})
#: Keys a confined scene may not set at all, and why.
REFUSED_KEYS = {"executable": "runs no program a scene names",
                "cache_dir": "writes into no folder a scene names"}
#: Extensions of the files a scene may name under other keys.
FILE_SUFFIXES = (".csv", ".txt", ".dat", ".npy", ".npz", ".tif", ".tiff", ".png", ".jpg",
                 ".jpeg", ".nc", ".nc4", ".h5", ".obj", ".ply", ".stl", ".glb", ".gltf", ".off",
                 ".yaml", ".yml", ".json", ".wth", ".hdr", ".img", ".sli", ".srf")


def _walk(node, key):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _walk(v, f"{key}.{k}" if key else str(k))
            if isinstance(v, str) and str(k) in FILE_KEYS:
                yield f"{key}.{k}" if key else str(k), v
    elif isinstance(node, (list, tuple)):
        for i, v in enumerate(node):
            yield from _walk(v, f"{key}[{i}]")
    elif isinstance(node, str) and node.lower().endswith(FILE_SUFFIXES):
        yield key, node


def _refused(node, key):
    if isinstance(node, dict):
        for k, v in node.items():
            here = f"{key}.{k}" if key else str(k)
            if str(k) in REFUSED_KEYS and v is not None:
                yield here, v
            yield from _refused(v, here)
    elif isinstance(node, (list, tuple)):
        for i, v in enumerate(node):
            yield from _refused(v, f"{key}[{i}]")


def named_files(data: dict) -> list[tuple[str, str]]:
    """Every ``(key, value)`` of the raw scene ``data`` that names a file (the keys of
    :data:`FILE_KEYS`, and strings ending in one of :data:`FILE_SUFFIXES`), each once."""
    seen: dict[tuple[str, str], None] = {}
    for item in _walk(data, ""):
        seen.setdefault(item)
    return list(seen)


def with_files(data, replaced: dict[str, str], key: str = ""):
    """A copy of the raw scene ``data`` with the file names at the keys of ``replaced`` (as
    :func:`named_files` gives them) replaced by its values."""
    if isinstance(data, dict):
        out = {}
        for k, v in data.items():
            here = f"{key}.{k}" if key else str(k)
            out[k] = replaced[here] if isinstance(v, str) and here in replaced else with_files(
                v, replaced, here)
        return out
    if isinstance(data, (list, tuple)):
        return [replaced.get(f"{key}[{i}]", v) if isinstance(v, str)
                else with_files(v, replaced, f"{key}[{i}]") for i, v in enumerate(data)]
    return data


def check_confined(data: dict, base: Path) -> None:
    """Refuse any file named in the raw scene ``data`` that lies outside ``base``.

    Raises
    ------
    radscene.errors.ConfigError
        Naming the key of the first such file.
    """
    root = Path(os.path.realpath(base))
    for key, _value in _refused(data, ""):
        raise ConfigError(f"--confine {REFUSED_KEYS[key.rsplit('.', 1)[-1]]}; remove it (the "
                          "engine is then found as usual)", key=key)
    for key, value in named_files(data):
        path = Path(os.path.expanduser(value))
        if not path.is_absolute():
            path = root / path
        real = Path(os.path.realpath(path))
        if real != root and root not in real.parents:
            raise ConfigError(f"{value!r} lies outside the scene's folder {root}, which "
                              "--confine does not allow", key=key)
