"""Synthetic tactile-sensor data with the truth returned beside it.

Power-law sensels with gain spread, read noise, noise threshold, saturation and dead sensels
(:func:`make_sensor`); dead-weight calibration sessions on uneven pads like Zvyagin (2022)
(:func:`deadweight_session`), or only their histograms under a known law
(:func:`patch_histograms`); uniform loads for equilibration (:func:`uniform_load`);
ramp-and-hold loading-machine sessions with a load-cell record like Gillis (2013)
(:func:`ramp_hold`); sine sweeps and blind tests of Gillis (2013) Table 4.2 seen by a sensor
with a known frequency-dependent gain (:func:`sine_sweep`, :func:`random_sine_sets`); a
family of sensors for sweeping static methods (:data:`FAMILY`, :func:`family_sessions`),
one for the dynamic calibration (:class:`DynamicSensor`, :data:`DYNAMIC_FAMILY` and its
members' ``session()``), and a recording of separated contacts such as the two compartments
of a knee (:func:`compartment_recording`).
"""

from tactilecal.simulate._compartments import compartment_recording
from tactilecal.simulate._deadweight import ContactModel, deadweight_session
from tactilecal.simulate._dynamic import DynamicSensor, random_sine_sets, sine_sweep
from tactilecal.simulate._dynamic_family import DYNAMIC_FAMILY
from tactilecal.simulate._family import FAMILY, family_sessions, true_force_table_N
from tactilecal.simulate._patches import patch_histograms
from tactilecal.simulate._sensor import make_sensor
from tactilecal.simulate._static import ramp_hold, uniform_load

__all__ = [
    "make_sensor", "deadweight_session", "ContactModel", "uniform_load",
    "ramp_hold", "compartment_recording",
    "sine_sweep", "random_sine_sets", "DynamicSensor", "DYNAMIC_FAMILY",
    "FAMILY", "family_sessions", "true_force_table_N", "patch_histograms",
]
