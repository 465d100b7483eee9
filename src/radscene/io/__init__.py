"""Writers and quicklooks."""

from radscene.io.animation import band_animations, band_videos
from radscene.io.cog import write_cog, write_map_cogs
from radscene.io.envi import write_envi
from radscene.io.netcdf import read_netcdf, write_netcdf
from radscene.io.quicklook import band_quicklooks, signal_quicklooks, terms_figure, truth_figure
from radscene.io.spectral import write_spectral
from radscene.io.zarr_store import read_zarr, write_zarr

__all__ = ["band_animations", "band_videos", "band_quicklooks", "signal_quicklooks", "read_netcdf",
           "read_zarr", "terms_figure", "truth_figure", "write_cog", "write_envi",
           "write_map_cogs", "write_netcdf", "write_spectral", "write_zarr"]
