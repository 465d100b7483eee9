"""Exceptions raised by radscene.

Every error that comes from user input says what was wrong, where (the key path in the
scene file or the argument name) and what would be accepted.
"""

from __future__ import annotations

import re

__all__ = ["RadsceneError", "ConfigError", "EngineError", "did_you_mean", "unreadable"]


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


def did_you_mean(name, known, *, cutoff: float = 0.6) -> str:
    """The closest of *known* to a misspelt *name*, as an error message ends with it.

    Parameters
    ----------
    name : str
        What was given.
    known : iterable of str
        What would be accepted.
    cutoff : float, optional
        How close (``difflib`` ratio, 0 to 1) a known name must be to be suggested.

    Returns
    -------
    str
        ``"; did you mean 'x'?"``, to append to a refusal that lists the known names, or ``""``
        when none is close.

    >>> did_you_mean("asfalt", ["asphalt", "concrete"])
    "; did you mean 'asphalt'?"
    >>> did_you_mean("cma", ["map", "cam"])
    "; did you mean 'cam'?"
    """
    import difflib

    known = [str(k) for k in known]
    # the same letters in another order (two swapped keys: 'cma' for 'cam') first
    close = [k for k in known if sorted(k.lower()) == sorted(str(name).lower()) and k != name][:1] \
        or difflib.get_close_matches(str(name), known, n=1, cutoff=cutoff)
    if not close:  # a name typed in another case than the known ones
        lowered = {k.lower(): k for k in known}
        close = [lowered[c] for c in difflib.get_close_matches(str(name).lower(), list(lowered), n=1,
                                                               cutoff=cutoff)]
    return f"; did you mean {close[0]!r}?" if close else ""


#: A quoted stretch of a library's message (an opening quote that does not follow a letter, as
#: an apostrophe does): what it quotes is usually the bad file's own text.
_QUOTED = re.compile("(?<![\\w])b?'[^']*'|(?<![\\w])b?\"[^\"]*\"")


def unreadable(err: BaseException) -> str:
    """Why a library could not read a file, in a few words that quote none of the file.

    A message that quotes the file's content (a line, a field, the bytes a decoder choked on)
    would show a file that is not what it should be — a scene of unknown origin may name any
    file — to whoever reads the error. So a text decoding error is only "not a text (UTF-8)
    file", an operating-system error its ``strerror``, and any other message its first line
    with every quoted stretch replaced by ``…``, at most 120 characters.

    >>> unreadable(ValueError("could not convert string to float: 'hunter2'"))
    'could not convert string to float: …'
    """
    if isinstance(err, UnicodeError):
        return "not a text (UTF-8) file"
    if isinstance(err, OSError) and err.strerror:
        return err.strerror
    text = str(err).strip().splitlines()[0] if str(err).strip() else ""
    text = _QUOTED.sub("…", text).strip()
    if not text:
        return type(err).__name__
    return text if len(text) <= 120 else text[:119] + "…"
