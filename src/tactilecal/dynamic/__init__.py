"""Dynamic calibration of tactile sensors (Gillis 2013, section 4).

Tactile sensors under-read fast loads. A sine sweep recorded by the sensor and a reference
load cell gives the transfer function ``|reference(f)| / |sensor(f)|``; its fitted model
(eq. 4.1, ``Y = A log(f + 1) + 1``) becomes a zero-phase correction filter applied to every
sensel of a recording.

Time convention: ``lag_s`` is the shift to add to the reference's time stamps to put them
on the sensor's clock, positive when the reference record starts later.
"""

from tactilecal.dynamic._align import align, estimate_lag, resample_to

__all__ = ["align", "estimate_lag", "resample_to"]
