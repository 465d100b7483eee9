"""Tile assembly: the helpers that sum a render's tiles of ray samples per pixel.

A render traces its ray samples in tiles of whole pixels; each tile's terms, transmittance
and truth are weighted by the samples' weights and summed per pixel into the image.
"""

from __future__ import annotations

import numpy as np

__all__ = ["tile_slices", "pixel_sums", "as_slice", "touch_pages"]


def tile_slices(total, per_pixel, tile_samples):
    """Slices of ``total`` ray samples into tiles of whole pixels (``per_pixel`` samples
    each), about ``tile_samples`` long."""
    tile = max(per_pixel, (tile_samples // per_pixel) * per_pixel)
    return [slice(start, min(start + tile, total)) for start in range(0, total, tile)]


def as_slice(index):
    """``index`` as a slice where it is a run of consecutive integers, else itself."""
    if len(index) and index[-1] - index[0] == len(index) - 1 and np.all(np.diff(index) == 1):
        return slice(int(index[0]), int(index[-1]) + 1)
    return index


def pixel_sums(pixel, weight, rows):
    """Weighted sums of sample columns per pixel: (unique pixels, (n_rows, n_unique)).

    ``rows`` is (n_rows, N), one row per quantity. Rays come ordered pixel by pixel (each
    pixel's sub-samples together), so the samples of a pixel form one contiguous run that
    ``np.add.reduceat`` sums; with one sample per pixel there is nothing to sum.
    """
    weighted = rows * weight[None, :]
    if len(pixel) > 1 and np.any(pixel[1:] < pixel[:-1]):  # not ordered: sort first
        order = np.argsort(pixel, kind="stable")
        pixel, weighted = pixel[order], weighted[:, order]
    starts = np.flatnonzero(np.r_[True, pixel[1:] != pixel[:-1]])
    if len(starts) == len(pixel):
        return pixel, weighted
    return pixel[starts], np.add.reduceat(weighted, starts, axis=1)


def touch_pages(array, part, parts):
    """Write a zero into every memory page of the ``part``-th of ``parts`` equal spans of
    ``array`` (a zeroed array): the pages' first touch, done where the thread would wait."""
    flat = array.reshape(-1)
    lo, hi = flat.size * part // parts, flat.size * (part + 1) // parts
    flat[lo:hi:max(1, 4096 // flat.itemsize)] = 0.0
