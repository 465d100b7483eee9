"""Reading PNG/JPEG images whose size has been checked beforehand.

Pillow refuses an image of more than ``2 × PIL.Image.MAX_IMAGE_PIXELS`` pixels (about 179 M)
with its own ``DecompressionBombError``, and warns above half that. radscene sizes every image
a scene names from its header against the memory limit before reading it
(:mod:`radscene.scene.memory`), so its readers lift Pillow's limit while they read
(:func:`pil_unlimited`): an image within the memory limit is read whatever its pixel count, and
one beyond it is refused by radscene's own check, naming the scene key.
"""

from __future__ import annotations

import contextlib
import threading

__all__ = ["pil_unlimited"]

_lock = threading.Lock()
_depth = 0
_saved = None


@contextlib.contextmanager
def pil_unlimited():
    """Lift Pillow's pixel-count limit (``PIL.Image.MAX_IMAGE_PIXELS``) for the duration.

    The limit in force before is restored when the last of the nested or concurrent uses ends.

    Examples
    --------
    >>> from PIL import Image
    >>> before = Image.MAX_IMAGE_PIXELS
    >>> with pil_unlimited():
    ...     Image.MAX_IMAGE_PIXELS is None
    True
    >>> Image.MAX_IMAGE_PIXELS == before
    True
    """
    global _depth, _saved
    from PIL import Image

    with _lock:
        if _depth == 0:
            _saved = Image.MAX_IMAGE_PIXELS
            Image.MAX_IMAGE_PIXELS = None
        _depth += 1
    try:
        yield
    finally:
        with _lock:
            _depth -= 1
            if _depth == 0:
                Image.MAX_IMAGE_PIXELS = _saved
