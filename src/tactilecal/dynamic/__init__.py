"""Dynamic calibration of tactile sensors (Gillis 2013, section 4).

Tactile sensors under-read fast loads. A sine sweep recorded by the sensor and a reference
load cell gives the transfer function ``reference(f) / sensor(f)``; its fitted model (eq.
4.1, ``Y = A log(f + 1) + 1``, log base stored; or a rational response with real corners and
resonances, or the measured correction regularised; each with a delay fitted jointly)
becomes a correction filter applied to every sensel of a recording, inside the band where
the sweep carried coherent energy.

Time convention: ``lag_s`` is the shift to add to the reference's time stamps to put them
on the sensor's clock, positive when the reference record starts later. Recordings keep
the data model of ``docs/data-model.md``: time along the first dimension.
"""

from tactilecal.dynamic._align import align, estimate_lag, resample_to
from tactilecal.dynamic._apply import apply_filter
from tactilecal.dynamic._calibrate import fit_filter
from tactilecal.dynamic._centrifuge import row_mean, water_head_factor
from tactilecal.dynamic._evaluate import Evaluation, compare_filters, evaluate
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
    "evaluate", "Evaluation", "compare_filters",
    "row_mean", "water_head_factor",
    "filter_recording", "filter_timeseries_csv",
]

