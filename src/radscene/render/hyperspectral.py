"""Hyperspectral mode: spectral radiance on a grid of hundreds of channels, in passes.

Each channel of a :class:`radscene.radiometry.ChannelGrid` is a band whose response is a
triangle on the grid (a partition of unity), so the band machinery integrates the spectral
factors per material × channel × atmospheric node exactly as it does for any band
(ARCHITECTURE.md, "Speed comes from separating the spectrum from space"). The channels are
rendered a few at a time — one pass of the integrator per group, with the same rays, random
numbers and truth maps — so that the memory of a pass stays bounded whatever the number of
channels; a pass's radiance [W m-2 sr-1] is divided by its channels' equivalent widths into
spectral radiance [W m-2 sr-1 um-1] and handed on (:func:`render_passes`), to be gathered in
memory (:func:`render_hyperspectral`) or written as it comes (:mod:`radscene.io.spectral`).

Integrated with a band's response S, the cube gives that band's radiance
(:func:`band_radiance`): exactly (to rounding) for an S linear between the grid's centres and
zero outside the grid, because every signature term is linear in the response; see
docs/hyperspectral.md for what else holds and what does not.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np
import xarray as xr

from radscene.errors import ConfigError
from radscene.radiometry import ChannelGrid
from radscene.render.outputs import PART_NAMES, TERM_LAYERS  # the layers that sum to the radiance

#: The spectral term layers of a cube rendered with ``terms``: those that sum to the radiance
#: (:data:`TERM_LAYERS`), then the parts of the reflected sky and background by the light's
#: origin (:data:`radscene.render.outputs.PART_NAMES`, not summed again).
SPECTRAL_TERMS = TERM_LAYERS + PART_NAMES

__all__ = ["Channel", "channels", "pass_size", "render_passes", "render_hyperspectral",
           "band_radiance", "spectral_attributes", "term_attributes", "spectral_variables",
           "PASS_MEMORY", "LAYERS_PER_CHANNEL", "TERM_LAYERS", "SPECTRAL_TERMS"]

#: Memory a pass may hold in its per-channel image layers [bytes]; with the fifteen float64
#: layers a render keeps per band (five terms, three coupling layers, the four parts of the
#: reflected sky and background, the total, the brightness temperature, the transmittance)
#: that is 11 channels per pass at 1024 × 1024.
PASS_MEMORY = 1.5e9
#: Per-band image layers of one render (see PASS_MEMORY) and their bytes per value.
LAYERS_PER_CHANNEL = 15
_BYTES = 8


@dataclass(frozen=True)
class Channel:
    """One channel as the integrator takes a band: its ``name`` and ``response``."""

    name: str
    response: object


def channels(grid: ChannelGrid) -> list[Channel]:
    """The grid's channels as bands, in grid order."""
    return [Channel(r.name, r) for r in grid.responses()]


def pass_size(grid: ChannelGrid, pixels: int, memory: float = PASS_MEMORY, *,
              terms: bool = False) -> int:
    """How many channels one pass renders so that its image layers fit in ``memory`` [bytes]
    for ``pixels`` ray samples (at least one, at most all).

    With ``terms`` a pass hands on its term layers (:data:`SPECTRAL_TERMS`, float64) besides
    the radiance, and they stay alive in the consumer's hands while the next pass renders:
    each channel counts ``len(SPECTRAL_TERMS)`` layers more than :data:`LAYERS_PER_CHANNEL`.
    """
    layers = LAYERS_PER_CHANNEL + (len(SPECTRAL_TERMS) if terms else 0)
    per_channel = layers * _BYTES * max(int(pixels), 1)
    return int(min(len(grid), max(1, memory // per_channel)))


def _specular_flags(scene, grid: ChannelGrid) -> np.ndarray:
    """Per material: a specular reflectance above zero somewhere on the grid (its centres,
    the midpoints between them, and the spectrum's own samples inside the grid)."""
    wl = grid.wavelength
    probe = [wl, 0.5 * (wl[1:] + wl[:-1])]
    flags = []
    for m in scene.materials:
        spectrum = m.specular_reflectance
        own = getattr(spectrum, "wavelength", None)
        if own is not None:
            own = np.asarray(own, dtype=float)
            probe_m = np.concatenate(probe + [own[(own >= wl[0]) & (own <= wl[-1])]])
        else:
            probe_m = np.concatenate(probe)
        flags.append(bool(np.any(np.asarray(spectrum(probe_m), dtype=float) != 0.0)))
    return np.array(flags, dtype=bool)


def spectral_attributes(grid: ChannelGrid) -> dict:
    """CF attributes of a spectral radiance cube on ``grid``."""
    return {
        "units": "W m-2 sr-1 um-1",
        "long_name": "at-aperture spectral radiance, the channel's response-weighted mean",
        "comment": (
            "channel c has a triangular response peaking at its wavelength and zero at the "
            "neighbouring centres (half triangles at the two ends), full width at half maximum "
            "= equivalent width = fwhm; value = integral of response x L d lambda / fwhm. "
            "For a band response S linear between the centres and zero outside the grid, "
            "sum over c of S(wavelength_c) fwhm_c radiance_c = integral of S L d lambda"),
        "grid_step_um": float(grid.step),
    }


def term_attributes(grid: ChannelGrid, attrs: dict) -> dict:
    """CF attributes of a term layer of a spectral cube on ``grid``, from the band render's
    attributes ``attrs`` of that layer (its ``long_name``)."""
    what = "spectral radiance, the channel's response-weighted mean"
    return {
        "units": "W m-2 sr-1 um-1",
        "long_name": f"{attrs['long_name']}: {what}" if attrs.get("long_name") else what,
        "comment": "one of the layers that sum to radiance, channel by channel; integrated "
                   "with a band response as radiance is",
        "grid_step_um": float(grid.step),
    }


def _coords(grid: ChannelGrid, part=slice(None)) -> dict:
    return {
        "wavelength": ("wavelength", grid.wavelength[part],
                       {"units": "um", "long_name": "channel centre wavelength",
                        "standard_name": "radiation_wavelength"}),
        "fwhm": ("wavelength", grid.width[part],
                 {"units": "um", "long_name": "channel full width at half maximum, equal to "
                  "its equivalent width (integral of the response)"}),
    }


def render_passes(scene, observer: str | None = None, grid: ChannelGrid | None = None, *,
                  channels_per_pass: int | None = None, memory: float = PASS_MEMORY,
                  terms: bool | None = None,
                  progress: Callable[[int, int], None] | None = None
                  ) -> Iterator[xr.Dataset]:
    """Render an observer's spectral grid a group of channels at a time.

    Parameters
    ----------
    scene : radscene.scene.Scene
    observer : str, optional
        Observer name; the first by default.
    grid : radscene.radiometry.ChannelGrid, optional
        Default the observer's ``spectral`` grid.
    channels_per_pass : int, optional
        Channels per pass; default from ``memory`` (:func:`pass_size`).
    memory : float
        Bytes a pass may hold in its image layers.
    terms : bool, optional
        Keep every layer that sums to the radiance (:data:`TERM_LAYERS`) as spectral radiance
        too; default the observer's ``spectral.terms`` (false). Counted in the pass's
        memory (:func:`pass_size`).
    progress : callable, optional
        ``progress(done, total)`` in ray samples over all passes.

    Yields
    ------
    xarray.Dataset
        One per pass, in grid order: ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1]
        (float64) of its channels with their ``wavelength`` and ``fwhm`` [um], with
        ``terms`` each term layer ``<term>(wavelength, y, x)`` [W m-2 sr-1 um-1] the render
        has (their sum is the radiance), and the render's per-pixel maps that do not depend
        on the band (``object_id``, ``range``, geolocation, ...), the same in every pass.

    Raises
    ------
    ConfigError
        No grid, or a grid beyond the atmosphere's wavelengths (the message names the key).
    """
    from radscene.render.integrator import render

    setup = scene.observers[0] if observer is None else scene.observer(observer)
    key = f"observers[{next(i for i, o in enumerate(scene.observers) if o is setup)}].spectral"
    if grid is None:
        grid = getattr(setup, "spectral", None)
        if grid is None:
            raise ConfigError(f"observer {setup.name!r} has no spectral grid: give "
                              "spectral: {min, max, step}", key=key)
    scene.atmosphere.check_wavelength(grid.wavelength[[0, -1]], key=key)
    if terms is None:
        terms = bool(getattr(setup, "spectral_terms", False))
    if not isinstance(terms, bool | np.bool_):
        raise ConfigError(f"must be true or false; got {terms!r}", key="terms")
    bands = channels(grid)
    samples = int(np.prod(setup.camera.shape)) * setup.supersample**2
    per_pass = (pass_size(grid, samples, memory, terms=bool(terms)) if channels_per_pass is None
                else channels_per_pass)
    if isinstance(per_pass, bool) or not isinstance(per_pass, int | np.integer) or per_pass < 1:
        raise ConfigError(f"must be a whole number >= 1; got {per_pass!r}",
                          key="channels_per_pass")
    specular = _specular_flags(scene, grid)
    starts = range(0, len(bands), per_pass)
    for n, start in enumerate(starts):
        part = slice(start, min(start + per_pass, len(bands)))

        def report(done, total, n=n):
            if progress is not None:
                progress(n * total + done, len(starts) * total)

        ds = render(scene, setup.name, bands=bands[part], specular=specular, progress=report)
        yield _spectral_part(ds, grid, part, terms=bool(terms))
        del ds


#: Band-dependent variables of a band render that hyperspectral mode does not keep.
_BAND_VARIABLES = ("band", "wavelength_center", "wavelength_min", "wavelength_max",
                   "equivalent_width")


def _spectral_part(ds: xr.Dataset, grid: ChannelGrid, part: slice, terms: bool = False
                   ) -> xr.Dataset:
    """A band render of channels ``part`` as spectral radiance (and, with ``terms``, each of
    its term layers), with its band-free maps."""
    width = grid.width[part][:, None, None]
    radiance = ds["radiance"].values
    radiance /= width  # the render's own array, no copy
    keep = {name: var for name, var in ds.data_vars.items() if "band" not in var.dims}
    out = xr.Dataset(keep, coords={k: v for k, v in ds.coords.items()
                                   if k not in _BAND_VARIABLES})
    out["radiance"] = xr.Variable(("wavelength", "y", "x"), radiance, spectral_attributes(grid))
    for name in SPECTRAL_TERMS if terms else ():
        if name in ds.data_vars:
            layer = ds[name].values
            layer /= width  # in place, as the radiance
            out[name] = xr.Variable(("wavelength", "y", "x"), layer,
                                    term_attributes(grid, ds[name].attrs))
    out = out.assign_coords(_coords(grid, part))
    out.attrs = dict(ds.attrs)
    out.attrs.pop("band_radiance_definition", None)
    return out


def render_hyperspectral(scene, observer: str | None = None, grid: ChannelGrid | None = None,
                         *, dtype=np.float32, **kwargs) -> xr.Dataset:
    """Render an observer's spectral grid into one in-memory Dataset.

    Parameters
    ----------
    scene, observer, grid
        As for :func:`render_passes`.
    dtype : numpy dtype
        Of the cube; float32 (seven significant digits) holds 1024 × 1024 × 200 channels in
        0.84 GB.
    **kwargs
        ``channels_per_pass``, ``memory``, ``terms``, ``progress`` of :func:`render_passes`.

    Returns
    -------
    xarray.Dataset
        ``radiance(wavelength, y, x)`` [W m-2 sr-1 um-1], with ``terms`` each term layer
        ``<term>(wavelength, y, x)`` [W m-2 sr-1 um-1] (of the same dtype; their sum is the
        radiance to its rounding), coordinates ``wavelength`` and ``fwhm`` [um], and the
        per-pixel truth and geolocation maps.

    Examples
    --------
    >>> ds = render_hyperspectral(scene, "hsi")                        # doctest: +SKIP
    >>> band_radiance(ds, scene.band("red").response)                  # doctest: +SKIP
    """
    cubes, first, done = None, None, 0
    for part in render_passes(scene, observer, grid, **kwargs):
        spectral = spectral_variables(part)
        k = part.sizes["wavelength"]
        if cubes is None:
            if grid is None:
                setup = scene.observers[0] if observer is None else scene.observer(observer)
                grid = setup.spectral
            cubes = {name: xr.Variable(("wavelength", "y", "x"),
                                       np.empty((len(grid),) + part[name].shape[1:], dtype=dtype),
                                       part[name].attrs) for name in spectral}
            first = part.drop_vars(spectral + ["wavelength", "fwhm"])
        for name in spectral:
            cubes[name].values[done:done + k] = part[name].values
        done += k
        del part
    out = first.assign(cubes)
    out = out.assign_coords(_coords(grid))
    out.attrs["spectral_mode"] = "hyperspectral"
    return out


def spectral_variables(part: xr.Dataset) -> list[str]:
    """The names of a pass's (or cube's) spectral variables: ``radiance``, then its term
    layers in :data:`SPECTRAL_TERMS` order."""
    return ["radiance"] + [name for name in SPECTRAL_TERMS
                           if name in part.data_vars and "wavelength" in part[name].dims]


def band_radiance(cube: xr.Dataset, response, variable: str = "radiance") -> xr.DataArray:
    """Integrate a spectral cube with a band's response: Σ_c S(λ_c) fwhm_c L_c.

    Parameters
    ----------
    cube : xarray.Dataset
        From :func:`render_hyperspectral` (or read back from its NetCDF file): ``radiance``
        [W m-2 sr-1 um-1] over ``wavelength`` with ``fwhm`` [um].
    response : radscene.radiometry.SpectralResponse
        The band's response S; its support inside the grid.
    variable : str
        The spectral variable to integrate: ``radiance``, or one of its term layers in a cube
        rendered with ``terms`` (``sun_diffuse``, ...).

    Returns
    -------
    xarray.DataArray
        Band radiance (y, x) [W m-2 sr-1] (of ``variable``): ∫ S L dλ, exact when S is linear
        between the centres (accumulated in float64, channel by channel).

    Raises
    ------
    ConfigError
        A response beyond the grid.
    """
    wl = np.asarray(cube["wavelength"].values, dtype=float)
    lo, hi = response.support
    if lo < wl[0] - 1e-12 or hi > wl[-1] + 1e-12:
        raise ConfigError(f"response {response.name!r} spans {lo:g}–{hi:g} µm, beyond the "
                          f"cube's {wl[0]:g}–{wl[-1]:g} µm", key="response")
    if variable not in cube.data_vars or "wavelength" not in cube[variable].dims:
        raise ConfigError(f"the cube has no spectral variable {variable!r}; it has "
                          f"{', '.join(spectral_variables(cube))}", key="variable")
    weights = np.asarray(response(wl), dtype=float) * np.asarray(cube["fwhm"].values, float)
    radiance = cube[variable]
    total = np.zeros(radiance.shape[1:])
    for c in np.flatnonzero(weights):
        total += weights[c] * np.asarray(radiance[c].values, dtype=float)
    dims = radiance.dims[1:]
    return xr.DataArray(total, dims=dims, coords={d: cube[d] for d in dims if d in cube.coords},
                        name=variable,
                        attrs={"units": "W m-2 sr-1",
                               "long_name": f"band radiance of {response.name!r} from the "
                                            f"spectral cube's {variable}"})
