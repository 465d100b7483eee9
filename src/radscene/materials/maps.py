"""Material maps: a classified image → a material per ground point, and per-class fractions.

A :class:`MaterialMap` places a classified image (integer class values) on a rectangle of the
ground plane exactly as :class:`~radscene.materials.Texture` places its image: ``size =
(width, height)`` [m], ``origin`` the south-west corner [m], row 0 along the north edge,
column 0 along the west edge. A ``classes`` mapping turns class values into material names;
every value in the image must be mapped (an unmapped value raises, listing them).

Sub-pixel mixing: :meth:`MaterialMap.fractions` block-averages the map by an integer
``factor`` into a :class:`MaterialFractions` grid, whose cell (r, c) holds the areal fraction
of each material among the fine pixels it covers (fractions sum to 1). A renderer that samples
the coarse grid mixes materials linearly by area (:func:`mix_materials`, exact for the
piecewise-linear spectra of :class:`~radscene.materials.Material`, and Kirchhoff-consistent:
ε of the mixture is the area-weighted ε).

Examples
--------
>>> mm = MaterialMap([[1, 2], [2, 2]], {1: "asphalt", 2: "dry_grass"}, size=(2.0, 2.0))
>>> mm.materials
['asphalt', 'dry_grass']
>>> mm.material_index([0.5, 1.5], [1.5, 1.5]).tolist()
[0, 1]
>>> mm.fractions(2).values[:, 0, 0].tolist()
[0.25, 0.75]
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from pathlib import Path

import numpy as np

from radscene.errors import ConfigError, unreadable

__all__ = ["MaterialMap", "MaterialFractions", "mix_materials"]


def _pair(value, key, positive):
    try:
        a, b = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ConfigError(f"expected a pair of numbers [m]; got {value!r}", key=key) from None
    if not (math.isfinite(a) and math.isfinite(b)) or (positive and (a <= 0 or b <= 0)):
        raise ConfigError(f"expected {'positive ' if positive else ''}finite numbers [m]; got {value!r}", key=key)
    return a, b


class _Placed:
    """Shared placement of an image on the ground (row 0 north, column 0 west)."""

    _shape: tuple[int, int]

    def _place(self, size, origin, key):
        self.size = _pair(size, f"{key}.size", positive=True)
        self.origin = _pair(origin, f"{key}.origin", positive=False)

    def _pixels(self, x, y, key):
        """(row, col, finite) of the pixel containing each point; raises outside."""
        x, y = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
        rows, cols = self._shape
        x0, y0 = self.origin
        w, h = self.size
        finite = np.isfinite(x) & np.isfinite(y)
        outside = finite & ((x < x0) | (x > x0 + w) | (y < y0) | (y > y0 + h))
        if np.any(outside):
            i = int(np.argmax(outside.ravel()))
            raise ConfigError(
                f"point ({x.ravel()[i]:g}, {y.ravel()[i]:g}) m is outside the map, which covers "
                f"x in [{x0:g}, {x0 + w:g}] m and y in [{y0:g}, {y0 + h:g}] m",
                key=key,
            )
        col = np.clip(np.floor((np.where(finite, x, x0) - x0) / w * cols), 0, cols - 1).astype(np.int64)
        row = np.clip(np.floor((y0 + h - np.where(finite, y, y0)) / h * rows), 0, rows - 1).astype(np.int64)
        return row, col, finite


class MaterialMap(_Placed):
    """A classified image on the ground: class values → material names.

    Parameters
    ----------
    classes : array_like of int
        2-D image of class values (row 0 north, column 0 west).
    class_materials : mapping of int to str
        Material name of every class value in the image (extra entries are allowed).
    size : (float, float)
        (width, height) [m].
    origin : (float, float), optional
        South-west corner [m].
    name : str, optional
        Name (e.g. the file) for messages.

    Attributes
    ----------
    materials : list of str
        The distinct material names, in order of their smallest class value.
    index : numpy.ndarray
        2-D int array: the index into :attr:`materials` of every pixel (read-only).

    Raises
    ------
    ConfigError
        A non-integer or non-2-D image, or class values without a material (listed).
    """

    def __init__(self, classes, class_materials: Mapping, size, origin=(0.0, 0.0), name: str = ""):
        key = name or "material_map"
        image = np.asarray(classes)
        if image.ndim != 2 or image.size == 0:
            raise ConfigError(f"classes must be a non-empty 2-D image; got shape {image.shape}", key=key)
        if image.dtype.kind == "f":
            if not np.all(np.isfinite(image)) or np.any(image != np.round(image)):
                raise ConfigError("class values must be integers", key=key)
            image = image.astype(np.int64)
        elif image.dtype.kind not in "iu":
            raise ConfigError(f"class values must be integers; got dtype {image.dtype}", key=key)
        if not isinstance(class_materials, Mapping) or not class_materials:
            raise ConfigError("class_materials must map class values to material names", key=f"{key}.classes")
        lut = {}
        for value, material in class_materials.items():
            if isinstance(value, bool) or not isinstance(value, numbers.Integral | str):
                raise ConfigError(f"class value {value!r} is not an integer", key=f"{key}.classes")
            try:
                lut[int(value)] = str(material).strip().lower()
            except ValueError:
                raise ConfigError(f"class value {value!r} is not an integer", key=f"{key}.classes") from None
        present = np.unique(image)
        unmapped = sorted(set(present.tolist()) - set(lut))
        if unmapped:
            raise ConfigError(
                f"the image holds class values {unmapped} that have no material; mapped: "
                f"{sorted(lut)}",
                key=f"{key}.classes",
            )
        self.materials: list[str] = []
        for value in sorted(v for v in lut if v in set(present.tolist())):
            if lut[value] not in self.materials:
                self.materials.append(lut[value])
        to_index = {v: self.materials.index(m) for v, m in lut.items() if m in self.materials}
        index = np.empty(image.shape, dtype=np.int64)
        for value in present.tolist():
            index[image == value] = to_index[value]
        index.setflags(write=False)
        self.index = index
        self.class_materials = dict(lut)
        self._shape = image.shape
        self.name = str(name)
        self._place(size, origin, key)

    @classmethod
    def from_image(cls, path, class_materials: Mapping, size, origin=(0.0, 0.0)) -> MaterialMap:
        """Read a classified image: PNG (grey or palette values 0-255) or ``.npy``.

        Parameters
        ----------
        path : str or path-like
            Pillow's pixel-count limit does not apply (:mod:`radscene.materials.imagefile`):
            the image's size is the caller's to check (a scene's images are sized from their
            headers by :mod:`radscene.scene.memory`).
        class_materials, size, origin : see :class:`MaterialMap`.

        Raises
        ------
        ConfigError
            Naming the file: unknown format, unreadable, or a colour image.
        """
        path = Path(path)
        suffix = path.suffix.lower()
        try:
            if suffix == ".npy":
                image = np.load(path, allow_pickle=False)
            elif suffix == ".png":
                from PIL import Image

                from radscene.materials.imagefile import pil_unlimited

                with pil_unlimited(), Image.open(path) as im:
                    if im.mode not in ("L", "P", "I", "I;16", "1"):
                        raise ConfigError(
                            f"a classified image must be single-band (grey or palette); got mode {im.mode}",
                            key=str(path),
                        )
                    image = np.asarray(im)
            else:
                raise ConfigError(f"unknown material-map format {suffix!r}; accepted: .png, .npy", key=str(path))
        except ConfigError:
            raise
        except Exception as exc:  # noqa: BLE001 - any reader failure is a bad file
            raise ConfigError(f"cannot read material map: {unreadable(exc)}", key=str(path)) from None
        return cls(image, class_materials, size=size, origin=origin, name=str(path))

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols) [px]."""
        return self._shape

    def material_index(self, x, y) -> np.ndarray:
        """Index into :attr:`materials` of the pixel under each point (nearest pixel).

        Parameters
        ----------
        x, y : array_like
            [m], broadcastable. Non-finite points give −1.

        Returns
        -------
        numpy.ndarray of int64

        Raises
        ------
        ConfigError
            A finite point outside the map.
        """
        row, col, finite = self._pixels(x, y, self.name or "material_map")
        return np.where(finite, self.index[row, col], -1)

    def fractions(self, factor: int) -> MaterialFractions:
        """Areal fraction of each material in blocks of ``factor`` x ``factor`` pixels.

        Parameters
        ----------
        factor : int
            ≥ 1; must divide both image dimensions (no partial blocks).

        Returns
        -------
        MaterialFractions
            Same ground rectangle, ``rows // factor`` x ``cols // factor`` cells.
        """
        if isinstance(factor, bool) or not isinstance(factor, numbers.Integral) or factor < 1:
            raise ConfigError(f"factor must be an integer >= 1; got {factor!r}", key="factor")
        rows, cols = self._shape
        if rows % factor or cols % factor:
            raise ConfigError(
                f"factor {factor} does not divide the map shape {rows} x {cols} px", key="factor"
            )
        n = len(self.materials)
        onehot = np.zeros((n, rows, cols))
        onehot[self.index, np.arange(rows)[:, None], np.arange(cols)[None, :]] = 1.0
        blocks = onehot.reshape(n, rows // factor, factor, cols // factor, factor).mean(axis=(2, 4))
        return MaterialFractions(blocks, self.materials, size=self.size, origin=self.origin, name=self.name)

    def __repr__(self) -> str:
        return f"MaterialMap({self._shape[0]}x{self._shape[1]} px, size={self.size} m, materials={self.materials})"


class MaterialFractions(_Placed):
    """Per-cell areal fractions of materials over a ground rectangle.

    Parameters
    ----------
    values : array_like
        Shape (n_materials, rows, cols), each in [0, 1], summing to 1 over materials (to 1e-9).
    materials : sequence of str
        One name per first-axis entry.
    size, origin : see :class:`MaterialMap`.
    name : str, optional
    """

    def __init__(self, values, materials, size, origin=(0.0, 0.0), name: str = ""):
        key = name or "material_fractions"
        v = np.array(values, dtype=float)
        materials = [str(m) for m in materials]
        if v.ndim != 3 or v.shape[0] != len(materials) or v.shape[1] == 0 or v.shape[2] == 0:
            raise ConfigError(
                f"values must have shape (n_materials={len(materials)}, rows, cols); got {v.shape}", key=key
            )
        if not np.all(np.isfinite(v)) or np.any(v < 0) or np.any(v > 1):
            raise ConfigError("fractions must be finite and in [0, 1]", key=key)
        total = v.sum(axis=0)
        if np.any(np.abs(total - 1.0) > 1e-9):
            r, c = np.unravel_index(int(np.argmax(np.abs(total - 1.0))), total.shape)
            raise ConfigError(f"fractions of cell ({r}, {c}) sum to {total[r, c]:.6g}, not 1", key=key)
        v.setflags(write=False)
        self.values = v
        self.materials = materials
        self._shape = v.shape[1:]
        self.name = str(name)
        self._place(size, origin, key)

    def sample(self, x, y) -> np.ndarray:
        """Fractions of the cell under each point, shape ``broadcast(x, y).shape + (n_materials,)``.

        Non-finite points give NaN; finite points outside raise :class:`ConfigError`.
        """
        row, col, finite = self._pixels(x, y, self.name or "material_fractions")
        out = np.moveaxis(self.values[:, row, col], 0, -1)
        return np.where(finite[..., None], out, np.nan)

    def dominant(self) -> np.ndarray:
        """Index of the largest fraction in each cell, shape (rows, cols)."""
        return np.argmax(self.values, axis=0)

    def __repr__(self) -> str:
        return f"MaterialFractions({self._shape[0]}x{self._shape[1]} cells, materials={self.materials})"


def mix_materials(parts, name: str = "mixture"):
    """Areal (linear) mixture of materials: every spectrum is the fraction-weighted sum.

    Parameters
    ----------
    parts : sequence of (float, Material)
        Fractions (≥ 0, summing to 1 within 1e-9) and materials.
    name : str, optional

    Returns
    -------
    Material
        ρ_d, ρ_s, τ (and so ε, by Kirchhoff) are the weighted sums; the Phong exponent is the
        common exponent of the parts that have a specular part.

    Raises
    ------
    ConfigError
        Bad fractions, or specular parts with different exponents (a mixture of two Phong lobes
        is not one Phong lobe).
    """
    from radscene.materials.material import Material
    from radscene.materials.spectrum import linear_combination

    parts = list(parts)
    if not parts:
        raise ConfigError("give at least one (fraction, material) pair", key=name)
    weights = []
    for i, item in enumerate(parts):
        try:
            w, m = item
        except (TypeError, ValueError):
            raise ConfigError("each part is a (fraction, Material) pair", key=f"{name}[{i}]") from None
        if not isinstance(m, Material):
            raise ConfigError(f"expected a Material; got {type(m).__name__}", key=f"{name}[{i}]")
        if isinstance(w, bool) or not isinstance(w, numbers.Real) or not (0.0 <= w <= 1.0):
            raise ConfigError(f"fraction must be in [0, 1]; got {w!r}", key=f"{name}[{i}]")
        weights.append(float(w))
    if abs(sum(weights) - 1.0) > 1e-9:
        raise ConfigError(f"fractions sum to {sum(weights):.6g}, not 1", key=name)
    exponents = {
        m.specular_exponent for w, (_, m) in zip(weights, parts, strict=True)
        if w > 0 and not (m.specular_reflectance.is_constant and float(m.specular_reflectance.values) == 0.0)
    }
    if len(exponents) > 1:
        raise ConfigError(
            f"materials with specular parts of different exponents {sorted(exponents)} cannot be "
            "mixed into one Phong lobe",
            key=name,
        )
    used = [(w, m) for w, (_, m) in zip(weights, parts, strict=True) if w > 0]
    combo = {
        attr: linear_combination([(w, getattr(m, attr)) for w, m in used], name=f"{name}.{attr}")
        for attr in ("diffuse_reflectance", "specular_reflectance", "transmittance")
    }
    return Material(
        name=name,
        specular_exponent=exponents.pop() if exponents else 0.0,
        source="areal mixture: " + ", ".join(f"{w:g} x {m.name}" for w, m in used),
        description="linear (areal) mixture",
        category="mixture",
        **combo,
    )
