"""Exceptions raised by radscene.

Every error that comes from user input says what was wrong, where (the key path in the
scene file or the argument name) and what would be accepted.
"""

from __future__ import annotations

__all__ = ["RadsceneError", "ConfigError", "EngineError"]


class RadsceneError(Exception):
    """Base class of every error radscene raises on purpose."""


class ConfigError(RadsceneError, ValueError):
    """Invalid user input: a scene file, a parameter, a data file.

    Parameters
    ----------
    message : str
        What is wrong and what would be accepted.
    key : str, optional
        Dotted key path of the offending value, e.g. ``objects[2].material``.
    """

    def __init__(self, message: str, key: str | None = None):
        self.key = key
        self.message = message
        super().__init__(f"{key}: {message}" if key else message)


class EngineError(RadsceneError, RuntimeError):
    """An external engine (LOWTRAN, 6S, ...) failed for a named case."""
