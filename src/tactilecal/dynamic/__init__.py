"""Dynamic calibration of tactile sensors (Gillis 2013, section 4).

Tactile sensors under-read fast loads. A sine sweep recorded by the sensor and a reference
load cell gives the transfer function ``|reference(f)| / |sensor(f)|``; its fitted model
(eq. 4.1, ``Y = A log(f + 1) + 1``, log base stored) becomes a zero-phase correction filter
applied to every sensel of a recording.

Time convention: ``lag_s`` is the shift to add to the reference's time stamps to put them
on the sensor's clock, positive when the reference record starts later. Recordings keep
the data model of ``docs/data-model.md``: time along the first dimension.
"""

from tactilecal._deprecated import moved_names
from tactilecal.dynamic._align import align, estimate_lag, resample_to
from tactilecal.dynamic._apply import apply_filter
from tactilecal.dynamic._calibrate import (
    Evaluation,
    compare_filters,
    evaluate,
    fit_filter,
    static_factor,
)
from tactilecal.dynamic._centrifuge import row_mean, water_head_factor
from tactilecal.dynamic._files import filter_recording, filter_timeseries_csv
from tactilecal.dynamic._filter import CorrectionFilter
from tactilecal.dynamic._fit import fit_transfer
from tactilecal.dynamic._io import read_record
from tactilecal.dynamic._rational import RationalModel
from tactilecal.dynamic._transfer import transfer_function

__all__ = [
    "align", "estimate_lag", "resample_to",
    "transfer_function", "fit_transfer", "RationalModel",
    "fit_filter", "CorrectionFilter", "apply_filter", "read_record",
    "evaluate", "Evaluation", "compare_filters", "static_factor",
    "row_mean", "water_head_factor",
    "filter_recording", "filter_timeseries_csv",
]

__getattr__ = moved_names(__name__, {
    "MODELS": ("_fit", "MODELS", "fit_transfer()'s docstring lists the models"),
    "TransferFunction": ("_transfer", "TransferFunction", "transfer_function() returns it"),
    "TransferFit": ("_fit", "TransferFit", "fit_transfer() returns it"),
    "model_gain": ("_fit", "model_gain", "use TransferFit.gain(f_hz)"),
    "complex_r2": ("_fit", "complex_r2", "fit_transfer() reports r2_complex"),
    "dynamic_part": ("_calibrate", "dynamic_part", "use fit_filter()"),
    "water_head_pressure_kPa": ("_centrifuge", "water_head_pressure_kPa",
                                "use tactilecal.geotech.hydrostatic_pressure_kPa"),
    "to_prototype": ("tactilecal.geotech", "to_prototype", "use tactilecal.geotech.to_prototype"),
    "prototype_frequency_hz": ("tactilecal.geotech", "prototype_frequency_hz",
                               "use tactilecal.geotech.prototype_frequency_hz"),
    "plot_transfer": ("_plots", "plot_transfer", "use the method CorrectionFilter.plot_transfer()"),
    **{name: ("_plots", name, f"use the method Evaluation.{name}()")
       for name in ("plot_time", "plot_spectra", "plot_error")},
    "write_evaluation": ("_files", "write_evaluation", "use the method Evaluation.save(folder, "
                         "filt)"),
    "load_filter": ("_filter", "load_filter", "use CorrectionFilter.from_json(path) or "
                    "tactilecal.load(path)"),
})
