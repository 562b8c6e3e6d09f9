"""File input/output: Tekscan ASCII exports, load-cell time series, NetCDF and Zarr."""

from tactilecal._deprecated import moved_names
from tactilecal.io._convert import convert
from tactilecal.io._netcdf import read_netcdf, write_netcdf
from tactilecal.io._open import open_recording, recording_format
from tactilecal.io._tekscan_read import read_tekscan
from tactilecal.io._tekscan_write import write_tekscan
from tactilecal.io._timeseries import read_timeseries, write_timeseries

__all__ = ["open_recording", "recording_format", "read_tekscan", "write_tekscan",
           "read_timeseries", "write_timeseries", "read_netcdf", "write_netcdf", "convert"]

_UNITS = "unit conversion is internal (tactilecal._units); recordings carry units in attrs"
__getattr__ = moved_names(__name__, {
    name: ("tactilecal._units", name, _UNITS)
    for name in ("G_STANDARD", "area_to_mm2", "force_to_N", "length_to_mm", "mass_to_N",
                 "normalise_unit", "pressure_to_kPa", "time_to_s", "unit_from_column",
                 "unit_kind")
})
