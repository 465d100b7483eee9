"""Writers and quicklooks.

Each name is imported from its module on first use (PEP 562), so that writing a NetCDF file
does not import matplotlib.
"""

import importlib
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # for type checkers and the API docs; at run time __getattr__ imports them
    from radscene.io.animation import band_animations, band_videos
    from radscene.io.cog import write_cog, write_map_cogs
    from radscene.io.envi import write_envi
    from radscene.io.netcdf import read_netcdf, write_netcdf
    from radscene.io.quicklook import band_quicklooks, signal_quicklooks, terms_figure, truth_figure
    from radscene.io.spectral import write_spectral
    from radscene.io.stream import FrameStream
    from radscene.io.zarr_store import read_zarr, write_zarr

#: Public name → the module that defines it.
_LAZY = {
    "band_animations": "animation", "band_videos": "animation",
    "write_cog": "cog", "write_map_cogs": "cog",
    "write_envi": "envi",
    "read_netcdf": "netcdf", "write_netcdf": "netcdf",
    "band_quicklooks": "quicklook", "signal_quicklooks": "quicklook", "terms_figure": "quicklook",
    "truth_figure": "quicklook",
    "write_spectral": "spectral",
    "FrameStream": "stream",
    "read_zarr": "zarr_store", "write_zarr": "zarr_store",
}

__all__ = ["FrameStream", "band_animations", "band_quicklooks", "band_videos", "read_netcdf", "read_zarr", "signal_quicklooks",
           "terms_figure", "truth_figure", "write_cog", "write_envi", "write_map_cogs", "write_netcdf",
           "write_spectral", "write_zarr"]


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'radscene.io' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"radscene.io.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
