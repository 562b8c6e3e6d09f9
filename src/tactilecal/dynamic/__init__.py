"""Dynamic calibration of tactile sensors (Gillis 2013, section 4).

Tactile sensors under-read fast loads. A sine sweep recorded by the sensor and a reference
load cell gives the transfer function ``|reference(f)| / |sensor(f)|``; its fitted model
(eq. 4.1, ``Y = A log(f + 1) + 1``, log base stored) becomes a zero-phase correction filter
applied to every sensel of a recording.

Time convention: ``lag_s`` is the shift to add to the reference's time stamps to put them
on the sensor's clock, positive when the reference record starts later. Recordings keep
the data model of ``docs/data-model.md``: time along the first dimension.
"""

from tactilecal.dynamic._align import align, estimate_lag, resample_to
from tactilecal.dynamic._apply import apply_filter
from tactilecal.dynamic._calibrate import (
    Evaluation,
    compare_filters,
    dynamic_part,
    evaluate,
    fit_filter,
    static_factor,
)
from tactilecal.dynamic._centrifuge import (
    prototype_frequency_hz,
    row_mean,
    to_prototype,
    water_head_factor,
    water_head_pressure_kPa,
)
from tactilecal.dynamic._filter import CorrectionFilter, load_filter
from tactilecal.dynamic._fit import MODELS, TransferFit, complex_r2, fit_transfer, model_gain
from tactilecal.dynamic._io import read_record
from tactilecal.dynamic._plots import plot_error, plot_spectra, plot_time, plot_transfer
from tactilecal.dynamic._rational import RationalModel
from tactilecal.dynamic._transfer import TransferFunction, transfer_function

__all__ = [
    "align", "estimate_lag", "resample_to",
    "TransferFunction", "transfer_function",
    "MODELS", "TransferFit", "fit_transfer", "model_gain", "complex_r2", "RationalModel",
    "CorrectionFilter", "load_filter", "read_record",
    "apply_filter",
    "fit_filter", "evaluate", "Evaluation", "compare_filters", "static_factor",
    "dynamic_part",
    "row_mean", "water_head_pressure_kPa", "water_head_factor", "to_prototype",
    "prototype_frequency_hz",
    "plot_transfer", "plot_time", "plot_spectra", "plot_error",
]
