"""File input/output: Tekscan ASCII exports, load-cell time series, NetCDF and Zarr."""

from tactilecal.io._convert import convert
from tactilecal.io._header_law import header_law
from tactilecal.io._netcdf import read_netcdf, write_netcdf
from tactilecal.io._open import open_recording, recording_format
from tactilecal.io._tekscan_read import read_tekscan
from tactilecal.io._tekscan_write import write_tekscan
from tactilecal.io._timeseries import read_timeseries, write_timeseries

__all__ = ["open_recording", "recording_format", "read_tekscan", "write_tekscan",
           "read_timeseries", "write_timeseries", "read_netcdf", "write_netcdf", "convert",
           "header_law"]
