"""Frames streamed to a NetCDF-4 file as they come: one more step along ``time`` per frame.

:class:`FrameStream` appends each frame of a :class:`radscene.Simulation` (or any render
Dataset of the same shape) to a NetCDF-4 file, through h5netcdf, and flushes it: a run that
stops leaves the frames written so far. The file reads back with ``xarray.open_dataset``
(``engine="h5netcdf"``) as a sequence written by ``radscene render`` does: the variables
chosen with a leading ``time`` dimension, ``elapsed(time)`` [s] and, for a scene with a time,
``time`` in seconds since the first frame's instant (CF).
"""

from __future__ import annotations

import datetime as _dt
from pathlib import Path

import numpy as np
import xarray as xr

from radscene.errors import ConfigError

__all__ = ["FrameStream"]


class FrameStream:
    """A NetCDF-4 file that frames are appended to.

    Parameters
    ----------
    path : str or path
        The file, ``.nc``.
    observer : str, optional
        Whose images a :class:`radscene.Frame` gives; default its only (or first) observer.
    variables : sequence of str
        The image variables to keep, each ``(band, y, x)`` or ``(y, x)``; default the
        radiance and the object map.
    overwrite : bool
        Replace an existing file; default False (an error).

    Examples
    --------
    >>> sim = radscene.Simulation(scene, realtime=True)                     # doctest: +SKIP
    >>> with FrameStream("run.nc") as out:                                  # doctest: +SKIP
    ...     for k in range(1000):
    ...         out.write(sim.step("40 ms"))
    """

    def __init__(self, path, observer: str | None = None,
                 variables=("radiance", "object_id"), overwrite: bool = False):
        from radscene.io.files import check_output_file

        self.path = Path(path)
        check_output_file(self.path, overwrite, key="path")
        self.observer = observer
        self.variables = tuple(variables)
        self.frames = 0
        self._file = None
        self._start = None

    def __enter__(self) -> FrameStream:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def write(self, frame) -> None:
        """Append a frame: a :class:`radscene.Frame` or a render Dataset.

        Raises
        ------
        ConfigError
            An observer or a variable the frame does not have, or images of another shape
            than the first frame's.
        """
        ds = self._images(frame)
        if self._file is None:
            self._create(ds)
        f, n = self._file, self.frames
        for name in self.variables:
            if name not in ds:
                raise ConfigError(f"frame {n + 1} has no variable {name!r}", key="variables")
            values = ds[name].values
            if values.shape != f.variables[name].shape[1:]:
                raise ConfigError(f"frame {n + 1}: {name} has shape {values.shape}, the first "
                                  f"frame's {f.variables[name].shape[1:]}", key="variables")
        f.resize_dimension("time", n + 1)
        for name in self.variables:
            f.variables[name][n] = ds[name].values
        elapsed = float(ds.attrs.get("elapsed_s", n))
        f.variables["elapsed"][n] = elapsed
        when = ds.attrs.get("time") or ""
        if "time" in f.variables:
            instant = _dt.datetime.fromisoformat(when) if when else None
            f.variables["time"][n] = ((instant - self._start).total_seconds() if instant
                                      else np.nan)
        self.frames = n + 1
        f.flush()

    def close(self) -> None:
        """Close the file (also on leaving a ``with`` block)."""
        if self._file is not None:
            self._file.attrs["frames"] = self.frames
            self._file.close()
            self._file = None

    def _images(self, frame):
        if isinstance(frame, xr.Dataset):
            return frame
        radiance = frame.radiance
        name = self.observer or next(iter(radiance))
        if name not in radiance:
            raise ConfigError(f"no observer {name!r}; the frame has {', '.join(radiance)}",
                              key="observer")
        return radiance[name]

    def _create(self, ds) -> None:
        import h5netcdf

        unknown = [v for v in self.variables if v not in ds]
        if unknown:
            raise ConfigError(f"no variable {', '.join(map(repr, unknown))}; the frame has "
                              f"{', '.join(map(str, ds.data_vars))}", key="variables")
        if self.path.exists():  # overwrite (checked on opening the stream)
            self.path.unlink()
        f = h5netcdf.File(self.path, "w")
        dims = {d: ds.sizes[d] for v in self.variables for d in ds[v].dims}
        f.dimensions = {"time": None, **dims}
        if "band" in dims:
            import h5py

            band = f.create_variable("band", ("band",), dtype=h5py.string_dtype(),
                                     data=np.array([str(b) for b in ds.band.values], dtype=object))
            band.attrs["long_name"] = "band name"
        for d in ("y", "x"):
            if d in dims and d in ds.coords:
                f.create_variable(d, (d,), data=ds[d].values).attrs.update(dict(ds[d].attrs))
        for name in self.variables:
            v = ds[name]
            out = f.create_variable(name, ("time", *v.dims), dtype=v.dtype,
                                    chunks=(1, *v.shape))
            out.attrs.update({k: a for k, a in v.attrs.items() if isinstance(a, str | int | float)})
        elapsed = f.create_variable("elapsed", ("time",), dtype=float)
        elapsed.attrs.update({"units": "s", "long_name": "time since the simulation's start"})
        when = ds.attrs.get("time") or ""
        if when:
            self._start = _dt.datetime.fromisoformat(when)
            start = self._start.astimezone(_dt.UTC).replace(tzinfo=None).isoformat()
            time = f.create_variable("time", ("time",), dtype=float)
            time.attrs.update({"units": f"seconds since {start}", "calendar": "standard",
                               "standard_name": "time", "long_name": "frame time (UTC)"})
        f.attrs.update({k: a for k, a in ds.attrs.items()
                        if isinstance(a, str | int | float) and k not in ("time", "elapsed_s",
                                                                          "frame", "render_seconds",
                                                                          "pixels_traced")})
        f.attrs["Conventions"] = "CF-1.10"
        self._file = f
