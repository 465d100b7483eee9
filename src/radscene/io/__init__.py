"""Writers and quicklooks.

Each name is imported from its module on first use (PEP 562), so that writing a NetCDF file
does not import matplotlib.
"""

import importlib

#: Public name → the module that defines it.
_LAZY = {
    "band_animations": "animation", "band_videos": "animation",
    "write_cog": "cog", "write_map_cogs": "cog",
    "write_envi": "envi",
    "read_netcdf": "netcdf", "write_netcdf": "netcdf",
    "band_quicklooks": "quicklook", "signal_quicklooks": "quicklook", "terms_figure": "quicklook",
    "truth_figure": "quicklook",
    "write_spectral": "spectral",
    "read_zarr": "zarr_store", "write_zarr": "zarr_store",
}

__all__ = sorted(_LAZY)


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'radscene.io' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"radscene.io.{module}"), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
