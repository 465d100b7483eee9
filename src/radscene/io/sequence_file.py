"""A frame sequence written to its data file frame by frame, the file moved into place whole.

:class:`SequenceWriter` takes the frames of one observer, each a Dataset with a ``time``
dimension of length 1 (what :func:`radscene.pipeline.simulation.render_sequence` stacks), and
appends each to a temporary file beside the destination as it comes, so that a sequence of any
length holds one frame in memory. The temporary is named as :func:`radscene.io.files.atomic_output`
names them (``.NAME.~HOST~PID~…``): a run that stops removes it on the way out, and the next run
into the folder removes one a killed run left. When the writer's block ends without error the
file takes the destination's place; otherwise it is removed.

The file holds what :func:`radscene.io.write_netcdf` (or :func:`radscene.io.write_zarr` for a
destination named ``*.zarr``) makes of the frames stacked in memory: the same variables,
coordinates, attributes and values (float32 image layers, scalars in float64), ``time`` encoded
in the units xarray picks for the whole span (given up front, so that every frame fits them),
and the global attribute ``frames``. A NetCDF file's ``time`` dimension is unlimited (the file
grows a frame at a time); a Zarr store is chunked one frame at a time.

A variable the first frame holds as a map and a later frame as one value (an angle map that is
constant over that frame's image, :data:`radscene.render.outputs.CONSTANT_ANGLES`) gets that
value over the whole map, as stacking in memory does. The reverse (one value first, a map
later) rewrites the frames written so far with the value spread over the map, a frame at a time.
"""

from __future__ import annotations

import contextlib
import os
import shutil
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.io.files import atomic_output, atomic_output_dir

__all__ = ["SequenceWriter", "open_sequence", "time_encoding"]


def time_encoding(times) -> dict:
    """The CF encoding xarray gives a ``time`` coordinate of these values when it writes them
    all at once: ``units``, ``calendar`` and ``dtype``; empty for times that are not dates
    (elapsed seconds)."""
    values = np.asarray(times)
    if values.dtype.kind != "M":
        return {}
    numbers, units, calendar = xr.coding.times.encode_cf_datetime(values.astype("datetime64[ns]"))
    return {"units": units, "calendar": calendar, "dtype": np.asarray(numbers).dtype}


def open_sequence(path, zarr: bool | None = None) -> xr.Dataset:
    """Open a sequence's data file (NetCDF) or store (``*.zarr``; ``zarr`` True or False says
    which whatever the name) lazily: values are read when used, a frame at a time if so
    indexed. Close it (or use ``with``) when done."""
    path = Path(path)
    if path.suffix.lower() == ".zarr" if zarr is None else zarr:
        return xr.open_dataset(path, engine="zarr", chunks=None)
    return xr.open_dataset(path, engine="h5netcdf")


class SequenceWriter:
    """Frames appended along ``time`` to a data file written under a temporary name.

    Parameters
    ----------
    path : str or path-like
        The destination: a NetCDF file, or a Zarr store (a folder named ``*.zarr``).
    times : array_like, optional
        Every frame's ``time`` (datetime64, for the units of its encoding, see
        :func:`time_encoding`); None or elapsed seconds: no encoding.
    compress : bool
        Compress the image layers (as the whole-file writers do).

    Use it as a context manager: the file is moved into place when the block ends without
    error, removed otherwise.

    Examples
    --------
    >>> with SequenceWriter("out/map_sequence.nc", times) as out:      # doctest: +SKIP
    ...     for layer in layers:
    ...         out.append(layer)
    """

    def __init__(self, path, times=None, compress: bool = True):
        self.path = Path(path)
        self.zarr = self.path.suffix.lower() == ".zarr"
        self.compress = compress
        self.frames = 0
        self._time = {} if times is None else time_encoding(times)
        self._stack = None
        self._tmp = None
        self._file = None  # the NetCDF file, open for appending
        self._shapes = {}  # per variable along time: its dims
        self._first = None  # the first frame's structure: attrs, variables' attrs
        self._store_coordinates = None  # a Zarr store's global `coordinates`
        self._written = {}  # the encoding of the first frame's variables

    def __enter__(self) -> SequenceWriter:
        self._stack = contextlib.ExitStack()
        opener = atomic_output_dir if self.zarr else atomic_output
        self._tmp = self._stack.enter_context(opener(self.path))
        return self

    def __exit__(self, exc_type, exc, tb):
        try:
            if exc_type is None:
                self._finish()
            else:
                self._close()
        except BaseException as err:  # the temporary goes
            self._stack.__exit__(type(err), err, err.__traceback__)
            raise
        return self._stack.__exit__(exc_type, exc, tb)

    # -- appending ------------------------------------------------------------------------

    def append(self, layer: xr.Dataset) -> None:
        """Append one frame: a Dataset whose every variable over ``time`` has one step of it
        (the coordinates without ``time`` are written with the first frame, and must be the
        same in every frame)."""
        if self._tmp is None:
            raise RuntimeError("SequenceWriter.append outside its with block")
        if layer.sizes.get("time") != 1:
            raise ValueError(f"a frame has one time step; this one has {layer.sizes.get('time')}")
        if self.frames == 0:
            self._create(layer)
        else:
            layer = self._conform(layer)
            if layer is not None:  # else a rewrite took it
                self._add(layer)
        self.frames += 1

    def _timed(self, ds) -> list[str]:
        return [name for name, var in ds.variables.items() if "time" in var.dims]

    def _encoding(self, ds: xr.Dataset) -> dict:
        from radscene.io.netcdf import _encoding as netcdf_encoding
        from radscene.io.zarr_store import _encoding as zarr_encoding

        enc = (zarr_encoding if self.zarr else netcdf_encoding)(ds, self.compress)
        if self._time and "time" in ds.variables and ds["time"].dtype.kind == "M":
            enc["time"] = dict(self._time)
        return enc

    def _create(self, layer: xr.Dataset) -> None:
        from radscene.io.cf import with_cf_coordinates

        layer = with_cf_coordinates(layer)
        self._first = {"attrs": dict(layer.attrs),
                       "vars": {n: dict(layer[n].attrs) for n in self._timed(layer)}}
        self._shapes = {n: (layer[n].dims, layer[n].shape[1:]) for n in self._timed(layer)}
        self._written = self._encoding(layer)
        if self.zarr:
            layer.to_zarr(self._tmp, mode="w", zarr_format=2, consolidated=False,
                          encoding=self._written)
            import zarr

            # the coordinates no variable lists (cell bounds): appending frames rewrites the
            # store's attributes without them, so they are put back at the end
            self._store_coordinates = zarr.open_group(self._tmp, mode="r", zarr_format=2) \
                .attrs.get("coordinates")
            return
        layer.to_netcdf(self._tmp, engine="h5netcdf", encoding=self._written,
                        unlimited_dims=["time"])
        import h5netcdf

        self._file = h5netcdf.File(self._tmp, "a")

    def _conform(self, layer: xr.Dataset) -> xr.Dataset | None:
        """The frame with the variables of the file: a value the file holds as a map spread
        over it; a map the file holds as one value: the file rewritten (None: done)."""
        spread = {}
        for name, (dims, shape) in self._shapes.items():
            if name not in layer.variables:
                raise ValueError(f"frame {self.frames + 1} has no variable {name!r} (the first "
                                 "frame has)")
            var = layer[name]
            if var.dims == dims and var.shape[1:] == shape:
                continue
            if var.size == 1 and len(dims) > var.ndim:  # one value, the file holds a map
                spread[name] = (dims, np.full((1, *shape), float(var.values.ravel()[0])), var.attrs)
            elif var.ndim > len(dims) and len(dims) == 1:  # a map, the file holds one value
                self._rewrite(name, var)
                self._add(layer)
                return None
            else:
                raise ValueError(f"frame {self.frames + 1}: {name!r} is {var.dims} "
                                 f"{var.shape}, the first frame's {dims}")
        return layer.assign(spread) if spread else layer

    def _add(self, layer: xr.Dataset) -> None:
        timed = [n for n in self._shapes]
        if self.zarr:
            keep = layer[[n for n in timed if n in layer.data_vars]]
            keep = keep.drop_vars([n for n in keep.coords if n not in timed])
            # the store's attributes stay the first frame's (xarray writes the appended ones)
            keep.attrs = dict(self._first["attrs"])
            for name in keep.variables:
                keep[name].attrs = dict(self._first["vars"][name])
            keep.to_zarr(self._tmp, append_dim="time", zarr_format=2, consolidated=False)
            return
        f = self._file
        n = f.dimensions["time"].size
        f.resize_dimension("time", n + 1)
        for name in timed:
            target = f.variables[name]
            var = layer[name].variable.copy(deep=False)
            var.encoding = {k: v for k, v in self._written.get(name, {}).items()
                            if k in ("units", "calendar", "dtype")}
            encoded = xr.conventions.encode_cf_variable(var, name=name)
            values = np.asarray(encoded.values)
            if values.dtype != target.dtype:
                values = values.astype(target.dtype)
            target[n, ...] = values[0]
        f.flush()

    def _rewrite(self, name: str, var: xr.DataArray) -> None:
        """The file so far with ``name`` a map over ``var``'s dims (its one value of each frame
        spread over the map, the map's attributes), a frame at a time."""
        self._close()
        old = self._tmp + ".part"
        os.replace(self._tmp, old)
        frames, self.frames = self.frames, 0
        dims, shape = var.dims, var.shape[1:]
        try:
            with (xr.open_dataset(old, engine="zarr", chunks=None, consolidated=False) if self.zarr
                  else open_sequence(old, zarr=False)) as ds:
                for k in range(frames):
                    frame = ds.isel(time=[k]).load()
                    value = float(frame[name].values.ravel()[0])
                    frame[name] = (dims, np.full((1, *shape), value), var.attrs)
                    frame.attrs = dict(self._first["attrs"])
                    if self.zarr and k == 0:
                        os.makedirs(self._tmp, exist_ok=True)
                    self.append(frame)
        finally:
            if os.path.isdir(old):
                shutil.rmtree(old, ignore_errors=True)
            else:
                Path(old).unlink(missing_ok=True)

    # -- the end ----------------------------------------------------------------------------

    def _close(self) -> None:
        if self._file is not None:
            try:
                self._file.close()
            finally:
                self._file = None

    def _finish(self) -> None:
        if self.frames == 0:
            raise ValueError(f"no frame was written to {self.path}")
        from radscene.io import scene_files

        if self.zarr:
            import zarr

            group = zarr.open_group(self._tmp, mode="a", zarr_format=2)
            group.attrs["frames"] = self.frames
            if self._store_coordinates:
                group.attrs["coordinates"] = self._store_coordinates
            scene_files.embed(self._tmp, self._first["attrs"], zarr=True)
            zarr.consolidate_metadata(self._tmp, zarr_format=2)
            return
        self._file.attrs["frames"] = self.frames
        self._close()
        scene_files.embed(self._tmp, self._first["attrs"])
