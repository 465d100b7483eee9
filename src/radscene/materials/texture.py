"""Spatial texture: a multiplier field over the ground plane (Δρ, Δε, Δτ of the seven-term signature equation (1) / seed
001 eq. 4).

A :class:`Texture` maps an image onto a rectangle of the local east-north-up ground plane:
``size = (width, height)`` [m] with its south-west corner at ``origin = (x0, y0)`` [m]. Image row 0
lies along the **north** edge (y = y0 + height), column 0 along the **west** edge (x = x0), as an
image looks on a map with north up. Each pixel's value sits at its centre; :meth:`Texture.sample`
interpolates bilinearly between centres. With ``wrap=True`` the image tiles the whole plane
periodically (interpolation wraps across the edges); with ``wrap=False`` only points inside the
rectangle may be sampled (within half a pixel of the edge the edge pixels' values are held), and
any other point raises :class:`~radscene.errors.ConfigError`.

Tiling at a given scale: :meth:`Texture.tiled` repeats a small pattern every ``tile_size``
metres over the whole plane. Procedural fields (:class:`~radscene.materials.noise.NoiseTexture`)
have the same ``sample(x, y)`` interface. :func:`make_texture` builds any of them from a
type-tagged mapping (registry :data:`TEXTURE_TYPES`), and :class:`TextureSet` groups the Δρ, Δε
and Δτ multipliers of a surface:

=========  ==============================================================================
type       keys
=========  ==============================================================================
``image``  ``file``, ``size`` [m], ``origin`` [m], ``contrast``, ``wrap``
``tile``   ``values`` (2-D list) or ``file``; ``tile_size`` [m] or ``texel_size`` [m]; ``origin`` [m]
``noise``  ``amplitude``, ``scale`` [m], ``octaves``, ``persistence``, ``lacunarity``, ``seed``
=========  ==============================================================================

Config snippet: ``{reflectance: {type: tile, file: bricks.png, tile_size: [2, 1]},
emissivity: {type: noise, amplitude: 0.02, scale: 5}}``.
"""

from __future__ import annotations

import math
import numbers
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, did_you_mean

__all__ = ["Texture", "TextureSet", "make_texture", "TEXTURE_TYPES", "TEXTURE_KINDS", "LUMINANCE_WEIGHTS"]

#: Weights of R, G, B in the luminance of a colour image, ITU-R BT.709 [-].
LUMINANCE_WEIGHTS = (0.2126, 0.7152, 0.0722)

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg")


def _pair(value, key: str, positive: bool) -> tuple[float, float]:
    try:
        a, b = value
        a, b = float(a), float(b)
    except (TypeError, ValueError):
        raise ConfigError(f"expected a pair of numbers [m]; got {value!r}", key=key) from None
    if not (math.isfinite(a) and math.isfinite(b)) or (positive and (a <= 0 or b <= 0)):
        need = "finite positive" if positive else "finite"
        raise ConfigError(f"expected {need} numbers [m]; got {value!r}", key=key)
    return a, b


class Texture:
    """A multiplier field over the ground plane, bilinear between pixel centres.

    Parameters
    ----------
    values : array_like
        2-D array of finite multipliers ≥ 0 [-]; row 0 north, column 0 west.
    size : (float, float)
        ``(width, height)`` of the image on the ground, east-west and north-south [m].
    origin : (float, float), optional
        ``(x0, y0)``, the south-west corner [m]; default (0, 0).
    wrap : bool, optional
        Tile the plane periodically (default) or refuse points outside the rectangle.
    name : str, optional
        Name (e.g. the file) used in error messages.

    Examples
    --------
    >>> t = Texture([[1.0, 3.0]], size=(2.0, 1.0))
    >>> t.sample([0.5, 1.0, 1.5], 0.5)
    array([1., 2., 3.])
    """

    __slots__ = ("_values", "_size", "_origin", "_wrap", "_name")

    def __init__(self, values, size, origin=(0.0, 0.0), wrap: bool = True, name: str = ""):
        key = name or "texture"
        try:
            v = np.array(values, dtype=float)
        except (TypeError, ValueError):
            raise ConfigError("values must be a 2-D array of numbers", key=key) from None
        if v.ndim != 2 or v.shape[0] < 1 or v.shape[1] < 1:
            raise ConfigError(f"values must be a non-empty 2-D array; got shape {v.shape}", key=key)
        if not np.all(np.isfinite(v)):
            raise ConfigError("values must be finite", key=key)
        if np.any(v < 0.0):
            raise ConfigError(f"multipliers must be >= 0; minimum is {v.min():.6g}", key=key)
        if not isinstance(wrap, bool | np.bool_):
            raise ConfigError(f"wrap must be true or false; got {wrap!r}", key=f"{key}.wrap")
        v.setflags(write=False)
        self._values = v
        self._size = _pair(size, f"{key}.size", positive=True)
        self._origin = _pair(origin, f"{key}.origin", positive=False)
        self._wrap = bool(wrap)
        self._name = str(name)

    @classmethod
    def from_image(cls, path, size, origin=(0.0, 0.0), contrast=None, wrap: bool = True) -> Texture:
        """Read a texture from a PNG/JPEG image or a ``.npy`` array.

        Parameters
        ----------
        path : str or path-like
            ``.png``, ``.jpg``/``.jpeg`` (read with :func:`matplotlib.image.imread`) or ``.npy``.
            Colour images become luminance with the BT.709 weights :data:`LUMINANCE_WEIGHTS`
            (alpha dropped); integer images are divided by their type's maximum (uint8: 255)
            so pixel values lie in [0, 1]. Pillow's pixel-count limit does not apply
            (:mod:`radscene.materials.imagefile`): :func:`radscene.load_scene` sizes a scene's
            textures from their headers against its memory limit before reading them.
        size : (float, float)
            ``(width, height)`` on the ground [m].
        origin : (float, float), optional
            South-west corner [m].
        contrast : float, optional
            None: the pixel values are the multipliers (they must be ≥ 0). A number c: the
            multiplier is :math:`1 + c\\,(v - \\bar v)/(v_{max} - v_{min})`, whose mean is 1
            and whose peak-to-peak range is |c|.
        wrap : bool, optional
            Tile the plane (default) or refuse points outside.

        Returns
        -------
        Texture

        Raises
        ------
        ConfigError
            Naming the file: unreadable or unknown format, not 2-D/RGB(A), non-finite values,
            negative multipliers, or a contrast on an image without variation.
        """
        path = Path(path)
        key = str(path)
        suffix = path.suffix.lower()
        try:
            if suffix == ".npy":
                image = np.load(path, allow_pickle=False)
            elif suffix in _IMAGE_SUFFIXES:
                import matplotlib.image as mpimg

                from radscene.materials.imagefile import pil_unlimited

                with pil_unlimited():  # sized beforehand: radscene.scene.memory
                    image = mpimg.imread(path)
            else:
                raise ConfigError(
                    f"unknown texture format {suffix!r}; accepted: .png, .jpg, .jpeg, .npy",
                    key=key,
                )
        except ConfigError:
            raise
        except Exception as exc:  # noqa: BLE001 - any reader failure (PIL raises SyntaxError) is a bad file
            raise ConfigError(f"cannot read texture image {path.name}: not a readable image "
                              f"({type(exc).__name__})", key=key) from None
        image = np.asarray(image)
        if np.issubdtype(image.dtype, np.integer):
            image = image.astype(float) / float(np.iinfo(image.dtype).max)
        elif image.dtype == bool or not np.issubdtype(image.dtype, np.number):
            raise ConfigError(f"texture must hold numbers; got dtype {image.dtype}", key=key)
        image = image.astype(float)
        if image.ndim == 3 and image.shape[2] in (3, 4):
            image = image[..., :3] @ np.asarray(LUMINANCE_WEIGHTS)
        elif image.ndim == 3 and image.shape[2] in (1, 2):
            image = image[..., 0]
        if image.ndim != 2:
            raise ConfigError(
                f"texture must be a 2-D (grey) or RGB(A) image; got shape {image.shape}", key=key
            )
        if not np.all(np.isfinite(image)):
            raise ConfigError("texture values must be finite", key=key)
        if contrast is None:
            if np.any(image < 0.0):
                raise ConfigError(
                    f"texture multipliers must be >= 0; minimum is {image.min():.6g} (give a "
                    "contrast to use the image as a pattern around 1)",
                    key=key,
                )
            values = image
        else:
            if (
                isinstance(contrast, bool)
                or not isinstance(contrast, numbers.Real)
                or not math.isfinite(contrast)
            ):
                raise ConfigError(
                    f"contrast must be a finite number; got {contrast!r}", key=f"{key}.contrast"
                )
            vmin, vmax, vmean = float(image.min()), float(image.max()), float(image.mean())
            if vmax == vmin:
                raise ConfigError(
                    "image has no variation (max == min), so a contrast cannot be applied; "
                    "use contrast: null for a uniform multiplier",
                    key=key,
                )
            values = 1.0 + float(contrast) * (image - vmean) / (vmax - vmin)
            if np.any(values < 0.0):
                spread = (vmean - vmin) if contrast > 0 else (vmax - vmean)
                limit = (vmax - vmin) / spread
                raise ConfigError(
                    f"contrast {contrast:g} makes multipliers negative (minimum "
                    f"{values.min():.4g}); with this image |contrast| must not exceed "
                    f"{limit:.4g}",
                    key=key,
                )
        return cls(values, size=size, origin=origin, wrap=wrap, name=key)

    @classmethod
    def tiled(cls, values, tile_size, origin=(0.0, 0.0), name: str = "") -> Texture:
        """A pattern repeated every ``tile_size`` over the whole plane.

        Parameters
        ----------
        values : array_like
            One tile of multipliers ≥ 0 [-] (2-D, row 0 north).
        tile_size : (float, float)
            (width, height) of one tile on the ground [m]: the scale of the pattern.
        origin : (float, float), optional
            South-west corner of one tile [m].
        name : str, optional

        Returns
        -------
        Texture
            ``wrap=True``.

        Examples
        --------
        >>> t = Texture.tiled([[0.5, 1.5]], tile_size=(2.0, 2.0))
        >>> t.sample([0.5, 2.5, 100.5], 1.0).tolist()
        [0.5, 0.5, 0.5]
        """
        return cls(values, size=tile_size, origin=origin, wrap=True, name=name)

    # ------------------------------------------------------------------ attributes
    @property
    def values(self) -> np.ndarray:
        """The multipliers, row 0 north, column 0 west (read-only) [-]."""
        return self._values

    @property
    def size(self) -> tuple[float, float]:
        """``(width, height)`` on the ground [m]."""
        return self._size

    @property
    def origin(self) -> tuple[float, float]:
        """``(x0, y0)``, the south-west corner [m]."""
        return self._origin

    @property
    def wrap(self) -> bool:
        """Whether the image tiles the plane."""
        return self._wrap

    @property
    def name(self) -> str:
        """Name used in messages."""
        return self._name

    @property
    def pixel_size(self) -> tuple[float, float]:
        """Ground size of one pixel, ``(dx, dy)`` [m]."""
        rows, cols = self._values.shape
        return (self._size[0] / cols, self._size[1] / rows)

    # ------------------------------------------------------------------ sampling
    def sample(self, x, y) -> np.ndarray:
        """Bilinear multiplier at ground points.

        Parameters
        ----------
        x, y : array_like
            East and north coordinates [m], broadcastable. NaN gives NaN.

        Returns
        -------
        numpy.ndarray
            Multipliers [-], shape ``broadcast(x, y).shape``.

        Raises
        ------
        ConfigError
            With ``wrap=False``, a finite point outside the rectangle.
        """
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        rows, cols = self._values.shape
        x0, y0 = self._origin
        width, height = self._size
        finite = np.isfinite(x) & np.isfinite(y)
        if not self._wrap:
            outside = finite & ((x < x0) | (x > x0 + width) | (y < y0) | (y > y0 + height))
            if np.any(outside):
                i = np.argmax(outside.ravel())
                raise ConfigError(
                    f"point ({x.ravel()[i]:g}, {y.ravel()[i]:g}) m is outside the texture, which "
                    f"covers x in [{x0:g}, {x0 + width:g}] m and y in [{y0:g}, {y0 + height:g}] "
                    "m (wrap=False)",
                    key=self._name or "texture",
                )
        xs = np.where(finite, x, x0)
        ys = np.where(finite, y, y0)
        # continuous pixel coordinates, integer values at pixel centres
        u = (xs - x0) / width * cols - 0.5
        v = (y0 + height - ys) / height * rows - 0.5
        c0 = np.floor(u)
        r0 = np.floor(v)
        fu = u - c0
        fv = v - r0
        c0 = c0.astype(np.int64)
        r0 = r0.astype(np.int64)
        c1 = c0 + 1
        r1 = r0 + 1
        if self._wrap:
            c0, c1, r0, r1 = c0 % cols, c1 % cols, r0 % rows, r1 % rows
        else:
            c0, c1 = np.clip(c0, 0, cols - 1), np.clip(c1, 0, cols - 1)
            r0, r1 = np.clip(r0, 0, rows - 1), np.clip(r1, 0, rows - 1)
        t = self._values
        out = (1.0 - fv) * ((1.0 - fu) * t[r0, c0] + fu * t[r0, c1]) + fv * (
            (1.0 - fu) * t[r1, c0] + fu * t[r1, c1]
        )
        return np.where(finite, out, np.nan)

    def __repr__(self) -> str:
        rows, cols = self._values.shape
        return (
            f"Texture({rows}x{cols} px, size={self._size} m, origin={self._origin} m, "
            f"wrap={self._wrap})"
        )


#: Kinds of multiplier a :class:`TextureSet` holds (Δρ, Δε, Δτ).
TEXTURE_KINDS = ("reflectance", "emissivity", "transmittance")

_TEXTURE_KEYS = {
    "image": {"type", "file", "size", "origin", "contrast", "wrap"},
    "tile": {"type", "values", "file", "tile_size", "texel_size", "origin"},
    "noise": {"type", "amplitude", "scale", "octaves", "persistence", "lacunarity", "seed"},
}


def _make_image(spec, key, base_dir):
    path = _resolve(spec, key, base_dir)
    return Texture.from_image(
        path,
        size=_need(spec, "size", key),
        origin=spec.get("origin", (0.0, 0.0)),
        contrast=spec.get("contrast"),
        wrap=spec.get("wrap", True),
    )


def _make_tile(spec, key, base_dir):
    if ("values" in spec) == ("file" in spec):
        raise ConfigError("a tile texture takes 'values' or 'file', exactly one", key=key)
    if ("tile_size" in spec) == ("texel_size" in spec):
        raise ConfigError(
            "a tile texture takes 'tile_size' (one tile [m]) or 'texel_size' (one pixel [m]), "
            "exactly one", key=key)
    if "file" in spec:
        values = Texture.from_image(_resolve(spec, key, base_dir), size=(1.0, 1.0)).values
    else:
        values = spec["values"]
    if "texel_size" in spec:
        texel = spec["texel_size"]
        texel = (texel, texel) if isinstance(texel, numbers.Real) else texel
        dx, dy = _pair(texel, f"{key}.texel_size", positive=True)
        rows, cols = np.shape(values)[:2] if np.ndim(values) >= 2 else (0, 0)
        if rows == 0 or cols == 0:
            raise ConfigError("a tile needs a 2-D array of values", key=f"{key}.values")
        tile_size = (dx * cols, dy * rows)
    else:
        tile_size = spec["tile_size"]
    return Texture.tiled(values, tile_size=tile_size, origin=spec.get("origin", (0.0, 0.0)), name=key)


def _make_noise(spec, key, base_dir):
    from radscene.materials.noise import NoiseTexture

    kwargs = {k: v for k, v in spec.items() if k != "type"}
    for needed in ("amplitude", "scale"):
        if needed not in kwargs:
            _missing(needed, key)
    return NoiseTexture(name=key, **kwargs)


def _missing(name, key):
    raise ConfigError(f"missing {name!r}", key=key)


def _need(spec, name, key):
    if name not in spec:
        _missing(name, key)
    return spec[name]


def _resolve(spec, key, base_dir):
    if "file" not in spec:
        _missing("file", key)
    path = Path(spec["file"])
    if base_dir is not None and not path.is_absolute():
        path = Path(base_dir) / path
    return path


#: Registered texture types: name -> factory(spec, key, base_dir).
TEXTURE_TYPES = {"image": _make_image, "tile": _make_tile, "noise": _make_noise}


def make_texture(spec, key: str = "texture", base_dir=None):
    """A multiplier field from a type-tagged mapping (see the module table).

    Parameters
    ----------
    spec : mapping or Texture or NoiseTexture
        ``{"type": "image" | "tile" | "noise", ...}``; a ready field is returned as it is.
    key : str
        Config key path for messages.
    base_dir : path-like, optional
        Folder of relative file paths.

    Returns
    -------
    Texture or NoiseTexture
        Both have ``sample(x, y)``.

    Raises
    ------
    ConfigError
        Unknown type (listing the registered ones), unknown or missing keys.

    Examples
    --------
    >>> t = make_texture({"type": "noise", "amplitude": 0.1, "scale": 10.0})
    >>> bool(0.9 <= float(t.sample(3.0, 4.0)) <= 1.1)
    True
    """
    from radscene.materials.noise import NoiseTexture

    if isinstance(spec, Texture | NoiseTexture):
        return spec
    if not isinstance(spec, dict):
        raise ConfigError(f"a texture is a mapping with a 'type'; got {type(spec).__name__}", key=key)
    kind = str(spec.get("type", "")).lower()
    if kind not in TEXTURE_TYPES:
        raise ConfigError(
            f"unknown texture type {spec.get('type')!r}; known: {', '.join(sorted(TEXTURE_TYPES))}"
            f"{did_you_mean(spec.get('type'), sorted(TEXTURE_TYPES))}",
            key=f"{key}.type",
        )
    unknown = set(spec) - _TEXTURE_KEYS[kind]
    if unknown:
        raise ConfigError(
            f"unknown keys {sorted(unknown)} for a {kind} texture; accepted: {sorted(_TEXTURE_KEYS[kind])}",
            key=key,
        )
    return TEXTURE_TYPES[kind](spec, key, base_dir)


class TextureSet:
    """The Δρ, Δε and Δτ multiplier fields of a surface (absent kinds are 1).

    Parameters
    ----------
    reflectance, emissivity, transmittance : Texture, NoiseTexture, mapping or None
        Fields or type-tagged mappings (:func:`make_texture`).
    base_dir : path-like, optional
        Folder of relative file paths.
    key : str, optional

    Examples
    --------
    >>> ts = TextureSet(reflectance={"type": "tile", "values": [[2.0]], "tile_size": [1, 1]})
    >>> {k: float(v) for k, v in ts.sample(0.5, 0.5).items()}
    {'reflectance': 2.0, 'emissivity': 1.0, 'transmittance': 1.0}
    """

    def __init__(self, reflectance=None, emissivity=None, transmittance=None, *, base_dir=None,
                 key: str = "textures"):
        given = {"reflectance": reflectance, "emissivity": emissivity, "transmittance": transmittance}
        self.fields = {
            kind: make_texture(spec, key=f"{key}.{kind}", base_dir=base_dir)
            for kind, spec in given.items()
            if spec is not None
        }

    def sample(self, x, y) -> dict:
        """Multipliers of every kind at ground points [-] (1 where a kind has no field).

        Returns
        -------
        dict of str to numpy.ndarray
            Keys :data:`TEXTURE_KINDS`, arrays of shape ``broadcast(x, y).shape``.
        """
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        return {
            kind: (self.fields[kind].sample(x, y) if kind in self.fields else np.ones(x.shape))
            for kind in TEXTURE_KINDS
        }

    def __repr__(self) -> str:
        return f"TextureSet({', '.join(f'{k}={v!r}' for k, v in self.fields.items())})"
