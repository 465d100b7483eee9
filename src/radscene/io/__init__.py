"""Writers and quicklooks."""

from radscene.io.animation import band_animations, band_videos
from radscene.io.netcdf import read_netcdf, write_netcdf
from radscene.io.quicklook import band_quicklooks, signal_quicklooks, terms_figure, truth_figure
from radscene.io.spectral import write_spectral
from radscene.io.stream import FrameStream

__all__ = ["FrameStream", "band_animations", "band_videos", "band_quicklooks", "signal_quicklooks", "read_netcdf", "terms_figure", "truth_figure", "write_netcdf",
           "write_spectral"]
