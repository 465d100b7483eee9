"""The CF form in which outputs are written: the coordinates' axes and cell bounds through
cf-xarray, and the grid mapping listed among each map variable's coordinates."""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["with_cf_coordinates", "with_grid_mapping_coordinates", "is_map_grid"]


def with_cf_coordinates(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` (a shallow copy) in the CF form radscene writes.

    - A map product's ``x`` and ``y`` (eastings and northings [m]) get their CF ``axis`` from
      cf-xarray (``guess_coord_axis``) and the pixels' edges as cell bounds (``add_bounds``:
      ``x_bounds``, ``y_bounds``, each coordinate's ``bounds`` attribute), so CF readers know
      the cells, not only their centres. A sequence's ``time`` gets its ``T`` axis likewise.
    - Each variable with a grid mapping lists it among its coordinates
      (:func:`with_grid_mapping_coordinates`).

    Images in pixel rows and columns (perspective cameras, scanners) keep plain ``x``/``y``:
    a pixel index is not a CF spatial axis."""
    out = ds.copy(deep=False)
    guess = [name for name in ("x", "y") if is_map_grid(out, name)]
    if "time" in out.coords and out["time"].dtype.kind == "M":
        guess.append("time")
    if guess:
        import cf_xarray  # noqa: F401  (the .cf accessor)

        tagged = out[guess].cf.guess_coord_axis()
        for name in guess:
            out[name].attrs.update({k: v for k, v in tagged[name].attrs.items() if k == "axis"})
        maps = [name for name in ("x", "y") if name in guess and f"{name}_bounds" not in out]
        if maps:
            out = out.cf.add_bounds(maps)
    return with_grid_mapping_coordinates(out)


def is_map_grid(ds: xr.Dataset, name: str) -> bool:
    """Whether ``ds[name]`` is a map axis: a 1-D coordinate in metres, evenly spaced."""
    if name not in ds.coords or ds[name].ndim != 1 or ds[name].attrs.get("units") != "m":
        return False
    values = np.asarray(ds[name].values, dtype=float)
    if values.size < 2:
        return False
    step = np.diff(values)
    return bool(np.all(step != 0.0) and np.allclose(step, step[0], rtol=1e-9, atol=0.0))


def with_grid_mapping_coordinates(ds: xr.Dataset) -> xr.Dataset:
    """``ds`` (a shallow copy) whose variables with a grid mapping list it among their
    coordinates, as rioxarray's own files do, so that a file opened plainly
    (``xr.open_dataset(path)``) keeps it as a coordinate and ``ds.rio.crs`` finds it; xarray
    leaves it out of ``coordinates`` by itself, and the file then needs
    ``decode_coords="all"``."""
    out = ds.copy(deep=False)
    for var in out.data_vars.values():
        mapping = var.encoding.get("grid_mapping")
        if mapping and "coordinates" not in var.encoding:
            names = [str(c) for c in var.coords
                     if c not in var.dims and c != mapping and "bounds" not in out[c].dims]
            var.encoding["coordinates"] = " ".join([*names, mapping])
    return out
