"""Tile assembly: the per-pixel sums a render accumulates, tile by tile.

A render traces its ray samples in tiles of whole pixels; each tile's terms, transmittance
and truth are weighted by the samples' weights and summed per pixel into the image
(:class:`TileSums`). With one sample per pixel a tile's pixels are final once written: their
total radiance and brightness temperatures are formed then (:meth:`TileSums.totals`), while
the next tiles' rays are traced.
"""

from __future__ import annotations

import numba
import numpy as np

from radscene.render import terms
from radscene.render.outputs import BACKGROUND_TERM, TERMS, THERMAL_BAND_START
from radscene.render.sky_split import PART_NAMES, part_layers
from radscene.render.truth import TRUTH_SUMS

__all__ = ["TileSums", "tile_slices", "pixel_sums", "pixel_runs", "as_slice", "touch_pages"]


def tile_slices(total, per_pixel, tile_samples):
    """Slices of ``total`` ray samples into tiles of whole pixels (``per_pixel`` samples
    each), about ``tile_samples`` long."""
    tile = max(per_pixel, (tile_samples // per_pixel) * per_pixel)
    return [slice(start, min(start + tile, total)) for start in range(0, total, tile)]


class TileSums:
    """The per-pixel sums of one render (band radiance [W m-2 sr-1], weighted sums).

    Attributes
    ----------
    acc : (term, band, pixel) the signature terms, :data:`~radscene.render.outputs.TERMS`
    sums : dict — each layer (band, pixel) by name: the terms (views of ``acc``) and the
        reflected background; after :meth:`finish` also their parts
        (:mod:`radscene.render.sky_split`)
    sky_thermal, background_thermal : the sky's emission reflected in the bands whose sky
        also holds sunlight (split band, pixel) (None: no such band yet), and the reflected
        background's self-emitted part (band, pixel)
    transmittance : (band, pixel) the path transmittance
    truth : dict — :data:`~radscene.render.truth.TRUTH_SUMS`, (pixel,) each
    object_id, material_id, normal_map : the labels of the sub-sample nearest each centre
    media_light, media_heat, sky_open : (band, pixel) or None — the volumes' own radiance
        reflected along the sky rays, its part that is their emission, and the sky view
        through volumes and sheets (where the scene has any)
    radiance, brightness : (band, pixel) or None — the total radiance and brightness
        temperature [K], formed per tile where ``direct`` (one sample per pixel, no BRDF)

    Parameters
    ----------
    bands : list — objects with ``response``
    n_pix : int
    central : (samples,) bool — the sub-sample nearest each pixel centre
    direct : bool — one sample per pixel and no BRDF model: the terms are written straight
        into ``acc``, the totals formed per tile
    media, background : bool — the scene's volumes or sheets change the sky rays; the
        render has a reflected-background pass
    """

    def __init__(self, bands, n_pix, central, direct, media, background):
        n_b = len(bands)
        self.bands = bands
        self.acc = np.zeros((len(TERMS), n_b, n_pix))
        self.sums = dict(zip(TERMS, self.acc, strict=True))
        self.transmittance = np.zeros((n_b, n_pix))
        self.truth = {k: np.zeros(n_pix) for k in TRUTH_SUMS}
        self.central = central
        self.object_id = np.full(n_pix, -1, dtype=np.int32)
        self.material_id = np.full(n_pix, -1, dtype=np.int32)
        self.normal_map = np.full((3, n_pix), np.nan)
        self.sky_open = np.zeros((n_b, n_pix)) if media else None
        self.media_light = np.zeros((n_b, n_pix)) if media else None
        self.media_heat = np.zeros((n_b, n_pix)) if media else None
        self.direct = direct
        self.thermal = [b for b, band in enumerate(bands)
                        if band.response.center >= THERMAL_BAND_START]
        self.brightness = np.full((n_b, n_pix), np.nan) if direct and self.thermal else None
        self.radiance = np.empty((n_b, n_pix)) if direct else None
        self.has_background = background
        self.sums[BACKGROUND_TERM] = self.background = np.zeros((n_b, n_pix))
        self.background_thermal = np.zeros((n_b, n_pix)) if background else None
        self.sky_thermal = None

    def leaving(self, pixel, weight, directions, sky_nodes, sky_view):
        """Add the path radiance of samples whose rays leave the scene: the sky (upwards)
        or nothing (downwards); ``sky_view`` (band, sky node) [W m-2 sr-1]."""
        n_pix = self.acc.shape[2]
        sky_seen = terms.leaving_sky(directions, sky_nodes, sky_view)
        path = self.sums["path_radiance"]
        for b in range(path.shape[0]):
            path[b] += np.bincount(pixel, weight * sky_seen[:, b], n_pix)

    def buffers(self, pixel, weight):
        """Where a tile's hits write their terms: (terms (term, band, ·), transmittance
        (band, ·), each hit's column, its weight) — the image itself where ``direct``, else
        arrays of the tile's hits, weighted and summed by :meth:`add`."""
        if self.direct:
            return self.acc, self.transmittance, pixel, weight
        n_hits, n_b = len(pixel), self.acc.shape[1]
        out, tau = np.empty((len(TERMS), n_b, n_hits)), np.empty((n_b, n_hits))
        return out, tau, np.arange(n_hits), np.ones(n_hits)

    def add(self, pixel, weight, out, tau, truth_rows, per_pixel, unit_weight):
        """Add a tile's terms (term, band, hit), transmittance and truth rows (one per
        :data:`TRUTH_SUMS`, None: the weight itself) at its hits' ``pixel``."""
        acc, truth = self.acc, self.truth
        if per_pixel == 1:  # one sample per pixel: no sums, only weighted copies
            at = as_slice(pixel)  # a tile of whole rows: plain slices
            if not self.direct:
                acc[:, :, at] = out if unit_weight else out * weight
                self.transmittance[:, at] = tau if unit_weight else tau * weight
            for key, row in zip(TRUTH_SUMS, truth_rows, strict=True):
                truth[key][at] = weight if row is None else row if unit_weight else row * weight
            return
        n_hits, n_b = len(pixel), acc.shape[1]
        runs = pixel_runs(pixel)
        if runs is None:  # not ordered pixel by pixel: sorted, as pixel_sums does
            rows = np.concatenate([out.reshape(-1, n_hits), tau, np.vstack(
                [np.ones(n_hits) if row is None else row for row in truth_rows])])
            pixels, totals = pixel_sums(pixel, weight, rows)
            n_rows = len(TERMS) * n_b
            acc[:, :, pixels] += totals[:n_rows].reshape(len(TERMS), n_b, -1)
            self.transmittance[:, pixels] += totals[n_rows:n_rows + n_b]
            for c, key in enumerate(TRUTH_SUMS):
                truth[key][pixels] += totals[n_rows + n_b + c]
            return
        # straight into the image: each pixel's run of samples, weighted and summed
        at = pixel[runs[:-1]]
        weight = np.ascontiguousarray(weight, dtype=np.float64)
        _run_sums(runs, at, weight, out.reshape(-1, n_hits), acc.reshape(-1, acc.shape[2]))
        _run_sums(runs, at, weight, np.ascontiguousarray(tau), self.transmittance)
        rows = np.vstack([np.ones(n_hits) if row is None else row for row in truth_rows])
        totals = np.zeros((len(rows), len(at)))
        _run_sums(runs, np.arange(len(at)), weight, rows, totals)
        for c, key in enumerate(TRUTH_SUMS):
            truth[key][at] += totals[c]

    def label(self, pixel, sample, obj, mat, nrm, per_pixel):
        """Label the pixels of a tile's hits (``sample``: their ray samples) with the object,
        material and normal of the sub-sample nearest each pixel centre."""
        if per_pixel == 1:  # every sample is its pixel's central one
            at = as_slice(pixel)
            self.object_id[at], self.material_id[at], self.normal_map[:, at] = obj, mat, nrm.T
        else:
            c = self.central[sample]
            self.object_id[pixel[c]] = obj[c]
            self.material_id[pixel[c]] = mat[c]
            self.normal_map[:, pixel[c]] = nrm[c].T

    def add_background(self, pixel, weight, values, emitted):
        """Add the reflected background of a tile's hits, ``values`` (band, hit), and its
        self-emitted part ``emitted`` (band, hit)."""
        n_b = len(values)
        pixels, totals = pixel_sums(pixel, weight, np.vstack([values, emitted]))
        self.background[:, pixels] += totals[:n_b]
        self.background_thermal[:, pixels] += totals[n_b:]

    def add_sky_thermal(self, pixel, weight, values):
        """Add the sky's emission reflected by a tile's hits in the bands whose sky also
        holds sunlight, ``values`` (split band, hit)."""
        if self.sky_thermal is None:
            self.sky_thermal = np.zeros((len(values), self.acc.shape[2]))
        pixels, totals = pixel_sums(pixel, weight, values)
        self.sky_thermal[:, pixels] += totals

    def finish(self, split):
        """The layers once the tiles and the coupling pass are done: the volumes' own
        radiance reflected along the sky rays added to ``sky_reflected`` (it is not light
        from the sky, so after the coupling pass), and the parts of the reflected sky and
        background (:func:`~radscene.render.sky_split.part_layers`; ``split`` the render's
        :class:`~radscene.render.sky_split.SkySplit`) into :attr:`sums`."""
        sky = self.sums["sky_reflected"]
        thermal = self.sky_thermal if self.sky_thermal is not None else np.zeros(
            (len(split.split),) + sky.shape[1:])
        parts = part_layers(sky, thermal, split.solar, split.thermal, split.split)
        if self.media_light is not None:  # the volumes' light by its origin, in every band
            sky += self.media_light
            parts[0][...] += self.media_light - self.media_heat
            parts[1][...] += self.media_heat
        if self.background_thermal is None:  # no background pass: nothing to split
            parts += (np.zeros(sky.shape), np.zeros(sky.shape))
        else:
            parts += part_layers(self.background, self.background_thermal, None, None, None)
        self.sums.update(zip(PART_NAMES, parts, strict=True))

    def add_media(self, pixel, weight, light, view, heat):
        """Add the volumes' own radiance reflected along the sky rays of a tile's hits,
        ``light`` (band, hit), its part that is their emission, ``heat`` (band, hit), and
        their sky view through volumes and sheets, ``view`` (band, hit)."""
        n_b = len(light)
        pixels, totals = pixel_sums(pixel, weight, np.vstack([light, heat, view]))
        self.media_light[:, pixels] += totals[:n_b]
        self.media_heat[:, pixels] += totals[n_b:2 * n_b]
        self.sky_open[:, pixels] += totals[2 * n_b:]

    def totals(self, pixel):
        """The total radiance (the terms summed in TERMS order, as the Dataset would) and
        brightness temperatures of a tile's pixels, where they are formed per tile."""
        from radscene.radiometry import band_brightness_temperature

        if self.radiance is None:
            return
        at = as_slice(pixel)
        total = self.radiance[:, at]
        np.copyto(total, self.acc[0, :, at])
        for t in range(1, len(TERMS)):
            total += self.acc[t, :, at]
        if self.has_background:
            total += self.background[:, at]
        if self.media_light is not None:
            total += self.media_light[:, at]
        if self.brightness is not None:
            for b in self.thermal:
                self.brightness[b, at] = band_brightness_temperature(total[b],
                                                                     self.bands[b].response)


def as_slice(index):
    """``index`` as a slice where it is a run of consecutive integers, else itself."""
    if len(index) and index[-1] - index[0] == len(index) - 1 and np.all(np.diff(index) == 1):
        return slice(int(index[0]), int(index[-1]) + 1)
    return index


def pixel_runs(pixel):
    """Where each pixel's run of samples starts, and the end (n_runs + 1,) int64, when the
    samples come ordered pixel by pixel (each pixel's sub-samples together, pixels rising);
    None otherwise."""
    if len(pixel) > 1 and np.any(pixel[1:] < pixel[:-1]):
        return None
    starts = np.flatnonzero(np.r_[True, pixel[1:] != pixel[:-1]]) if len(pixel) else np.zeros(0, int)
    return np.append(starts, len(pixel)).astype(np.int64)


@numba.njit(parallel=True, cache=True)
def _run_sums(runs, column, weight, rows, out):
    """``out[r, column[k]] += Σ weight[i] rows[r, i]`` over the samples ``i`` of run ``k``
    (``runs[k]`` to ``runs[k + 1]``), summed in order: a row per work item."""
    for r in numba.prange(rows.shape[0]):
        for k in range(runs.shape[0] - 1):
            total = 0.0
            for i in range(runs[k], runs[k + 1]):
                total += rows[r, i] * weight[i]
            out[r, column[k]] += total


def pixel_sums(pixel, weight, rows):
    """Weighted sums of sample columns per pixel: (unique pixels, (n_rows, n_unique)).

    ``rows`` is (n_rows, N), one row per quantity. Rays come ordered pixel by pixel (each
    pixel's sub-samples together), so the samples of a pixel form one contiguous run, summed
    in order (:func:`_run_sums`); samples in another order are sorted first.
    """
    weight = np.ascontiguousarray(weight, dtype=np.float64)
    rows = np.ascontiguousarray(rows, dtype=np.float64)
    runs = pixel_runs(pixel)
    if runs is None:  # not ordered: sort first
        order = np.argsort(pixel, kind="stable")
        pixel, weight, rows = pixel[order], weight[order], rows[:, order]
        runs = pixel_runs(pixel)
    if len(runs) - 1 == len(pixel):  # one sample per pixel: nothing to sum
        return pixel, rows * weight[None, :]
    totals = np.zeros((rows.shape[0], len(runs) - 1))
    _run_sums(runs, np.arange(len(runs) - 1), weight, rows, totals)
    return pixel[runs[:-1]], totals


def touch_pages(array, part, parts):
    """Write a zero into every memory page of the ``part``-th of ``parts`` equal spans of
    ``array`` (a zeroed array): the pages' first touch, done where the thread would wait."""
    flat = array.reshape(-1)
    lo, hi = flat.size * part // parts, flat.size * (part + 1) // parts
    flat[lo:hi:max(1, 4096 // flat.itemsize)] = 0.0
