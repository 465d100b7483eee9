"""Band values of the spectra of :func:`~radscene.atmosphere.api.line_of_sight` and
:func:`~radscene.atmosphere.api.sky_radiance`: response-weighted integrals, means and
brightness temperatures.

A band is a spectral response S(λ) (:class:`~radscene.radiometry.srf.SpectralResponse`): a
rectangle (a ``(min, max)`` pair [um] becomes a
:class:`~radscene.radiometry.srf.RectangularResponse`), a sensor's tabulated relative response
(:class:`~radscene.radiometry.srf.TabulatedResponse`), or any other registered response. For
each spectrum v(λ) of the Dataset (piecewise linear between its wavelengths) the band gets

===================================  ============================  ===========================
variable                             value                         unit
===================================  ============================  ===========================
``band_<v>``                         ∫ S v dλ (transmittances:     v's unit × um (e.g.
                                     the mean)                     W m-2 sr-1)
``band_mean_<v>``                    ∫ S v dλ / ∫ S dλ (radiances  v's unit (e.g.
                                     and irradiances)              W m-2 sr-1 um-1)
``band_<r>_brightness_temperature``  the temperature of the        K (NaN for bands centred
                                     blackbody with the same       below
                                     ∫ S L dλ                      :data:`THERMAL_BAND_MIN`)
===================================  ============================  ===========================

For a rectangular or tabulated S both factors are linear on every interval between the union of
their breakpoints, so the integral is exact (Simpson's rule on each interval); other responses
use their own quadrature (:meth:`~radscene.radiometry.srf.SpectralResponse.integrate`). The
brightness temperature inverts the band-integrated Planck function of the same response
(:func:`~radscene.radiometry.planck.band_brightness_temperature`), the quantity a thermal
sensor's calibration reports.
"""

from __future__ import annotations

import numpy as np

from radscene.errors import ConfigError
from radscene.radiometry.srf import RectangularResponse, SpectralResponse, TabulatedResponse

__all__ = ["THERMAL_BAND_MIN", "band_responses", "band_integral", "attach_bands"]

#: Bands whose response centroid lies at or beyond this wavelength [um] get brightness
#: temperatures (the mid-wave and long-wave infrared, where sensors are calibrated in them).
THERMAL_BAND_MIN = 3.0
#: Spectra integrated per band: name → "mean" (transmittances) or "integral".
_SPECTRA = (("transmittance", "mean"), ("path_radiance", "integral"),
            ("path_thermal_radiance", "integral"), ("path_scattered_radiance", "integral"),
            ("apparent_radiance", "integral"), ("sky_radiance", "integral"),
            ("downwelling_irradiance", "integral"), ("direct_irradiance", "integral"))
#: Radiances whose band values get brightness temperatures, and the temperature's name.
_TEMPERATURES = {"apparent_radiance": "band_apparent_brightness_temperature",
                 "path_radiance": "band_path_brightness_temperature",
                 "sky_radiance": "band_sky_brightness_temperature"}
_EDGE = 1e-9  # [um] how far a band edge may lie outside the wavelengths (rounding)


def band_responses(bands, wavelength) -> list[SpectralResponse]:
    """The bands as responses, each checked to lie within ``wavelength``.

    Parameters
    ----------
    bands : sequence or None
        ``(min, max)`` pairs [um] and/or :class:`SpectralResponse` objects; None: one
        rectangle over all of ``wavelength`` (none for a single wavelength).
    wavelength : numpy.ndarray
        Increasing wavelengths [um] of the spectra.

    Returns
    -------
    list of SpectralResponse

    Raises
    ------
    ConfigError
        A pair that is not increasing, or a band reaching beyond the wavelengths (key
        ``bands[i]``).
    """
    wl = np.asarray(wavelength, dtype=float)
    if bands is None:
        if wl.size < 2:  # one wavelength: no band
            return []
        return [RectangularResponse(wl[0], wl[-1], name=f"{wl[0]:g}-{wl[-1]:g} um")]
    out = []
    for i, b in enumerate(bands):
        if isinstance(b, SpectralResponse):
            response = b
        else:
            try:
                lo, hi = (float(v) for v in b)
            except (TypeError, ValueError):
                raise ConfigError("(min, max) pairs [µm] or spectral responses",
                                  key=f"bands[{i}]") from None
            if not lo < hi:
                raise ConfigError(f"({lo:g}, {hi:g}) must be increasing", key=f"bands[{i}]")
            response = RectangularResponse(lo, hi, name=f"{lo:g}-{hi:g} um")
        lo, hi = response.support
        if lo < wl[0] - _EDGE or hi > wl[-1] + _EDGE:
            raise ConfigError(f"band {response.name!r} spans {lo:g}-{hi:g} µm, beyond the "
                              f"wavelengths {wl[0]:g}-{wl[-1]:g} µm", key=f"bands[{i}]")
        out.append(response)
    return out


def _interp_rows(wl, values, x):
    """Rows of ``values`` (…, n) linear in ``wl``, evaluated at ``x`` (k,) → (…, k)."""
    i = np.clip(np.searchsorted(wl, x, side="right") - 1, 0, wl.size - 2)
    f = np.clip((x - wl[i]) / (wl[i + 1] - wl[i]), 0.0, 1.0)
    return values[..., i] * (1.0 - f) + values[..., i + 1] * f


def band_integral(wavelength, values, response: SpectralResponse):
    """∫ S(λ) v(λ) dλ of spectra v, linear between ``wavelength``, over a response.

    Parameters
    ----------
    wavelength : numpy.ndarray
        Increasing wavelengths [um], shape (n,), covering the response's support.
    values : numpy.ndarray
        Spectra, shape (..., n).
    response : SpectralResponse

    Returns
    -------
    numpy.ndarray
        Shape (...) [values' unit × um].

    Notes
    -----
    For a rectangular or tabulated S the product S v is quadratic between consecutive
    breakpoints of S and v, so Simpson's rule there is exact:

    .. math:: \\int S v \\, d\\lambda = \\sum_k \\frac{h_k}{6}
              \\left[(Sv)_k + 4 (Sv)_{k+1/2} + (Sv)_{k+1}\\right]

    Examples
    --------
    >>> from radscene.radiometry.srf import TabulatedResponse
    >>> tri = TabulatedResponse([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])
    >>> float(band_integral(np.array([0.5, 3.5]), np.array([0.5, 3.5]), tri))  # ∫ S λ dλ
    2.0
    """
    wl = np.asarray(wavelength, dtype=float)
    vals = np.asarray(values, dtype=float)
    if isinstance(response, RectangularResponse):
        knots = np.zeros(0)
    elif isinstance(response, TabulatedResponse):
        knots = response.wavelength
    else:
        return response.integrate(wl, vals)
    lo, hi = response.support
    grid = np.unique(np.concatenate([[lo, hi], knots, wl[(wl > lo) & (wl < hi)]]))
    mid = 0.5 * (grid[1:] + grid[:-1])
    at_grid = response(grid) * _interp_rows(wl, vals, grid)
    at_mid = response(mid) * _interp_rows(wl, vals, mid)
    h = np.diff(grid)
    return ((at_grid[..., :-1] + 4.0 * at_mid + at_grid[..., 1:]) * h / 6.0).sum(axis=-1)


def _width(response: SpectralResponse) -> float:
    if isinstance(response, RectangularResponse):
        lo, hi = response.support
        return hi - lo
    return response.equivalent_width()


def attach_bands(ds, bands):
    """``ds`` with the band coordinates and every band value of the module table.

    Parameters
    ----------
    ds : xarray.Dataset
        Spectra with ``wavelength`` [um] as their last dimension.
    bands : sequence or None
        As :func:`band_responses`.

    Returns
    -------
    xarray.Dataset
        With coordinates ``band`` (index), ``band_name``, ``band_min``, ``band_max`` (the
        response's support) [um], ``band_center`` (its centroid) [um], ``band_width`` (its
        equivalent width ∫ S dλ) [um], and the band variables.
    """
    from radscene.radiometry.planck import band_brightness_temperature

    wl = ds["wavelength"].values
    responses = band_responses(bands, wl)
    width = np.array([_width(r) for r in responses], dtype=float)
    center = np.array([r.center for r in responses], dtype=float)
    ds = ds.assign_coords({
        "band": ("band", np.arange(len(responses))),
        "band_name": ("band", [r.name for r in responses]),
        "band_min": ("band", [r.support[0] for r in responses], {"units": "um"}),
        "band_max": ("band", [r.support[1] for r in responses], {"units": "um"}),
        "band_center": ("band", center, {"units": "um", "long_name": "centroid of the "
                                         "band's response"}),
        "band_width": ("band", width, {"units": "um", "long_name": "equivalent width "
                                       "of the band's response, integral of S"}),
    })
    thermal = center >= THERMAL_BAND_MIN
    if not responses:
        return ds
    for name, kind in _SPECTRA:
        if name not in ds or ds[name].dims[-1] != "wavelength":
            continue
        values = ds[name].values
        dims = ds[name].dims[:-1] + ("band",)
        integral = np.stack([band_integral(wl, values, r) for r in responses], axis=-1)
        units = ds[name].attrs.get("units", "")
        if kind == "mean":
            ds[f"band_{name}"] = (dims, integral / width, {
                "units": "1", "long_name": f"response-weighted band mean of {name}"})
            continue
        ds[f"band_{name}"] = (dims, integral, {
            "units": units.replace(" um-1", ""),
            "long_name": f"response-weighted band integral of {name}"})
        ds[f"band_mean_{name}"] = (dims, integral / width, {
            "units": units, "long_name": f"response-weighted band mean of {name}"})
        if name in _TEMPERATURES:
            bt = np.full(integral.shape, np.nan)
            for b in np.flatnonzero(thermal):
                bt[..., b] = band_brightness_temperature(integral[..., b], responses[b])
            ds[_TEMPERATURES[name]] = (dims, bt, {
                "units": "K", "long_name": f"band brightness temperature of {name} (bands "
                f"centred at or beyond {THERMAL_BAND_MIN:g} um)"})
    return ds
