"""File input/output: Tekscan ASCII exports, load-cell time series, NetCDF/Zarr, unit helpers."""

from tactilecal.io._convert import convert
from tactilecal.io._netcdf import read_netcdf, write_netcdf
from tactilecal.io._open import open_recording, recording_format
from tactilecal.io._tekscan_read import read_tekscan
from tactilecal.io._tekscan_write import write_tekscan
from tactilecal.io._timeseries import read_timeseries, unit_from_column
from tactilecal.io._units import (
    G_STANDARD,
    area_to_mm2,
    force_to_N,
    length_to_mm,
    mass_to_N,
    normalise_unit,
    pressure_to_kPa,
    time_to_s,
    unit_kind,
)

__all__ = [
    "G_STANDARD", "area_to_mm2", "convert", "force_to_N", "length_to_mm", "mass_to_N",
    "normalise_unit", "open_recording", "pressure_to_kPa", "read_netcdf", "read_tekscan",
    "read_timeseries", "recording_format", "time_to_s", "unit_from_column", "unit_kind",
    "write_netcdf", "write_tekscan",
]
