"""Synthetic tactile-sensor data with the truth returned beside it.

Power-law sensels with gain spread, read noise, noise threshold, saturation and dead sensels
(:func:`make_sensor`); dead-weight calibration sessions on uneven pads like Zvyagin (2022)
(:func:`deadweight_session`), or only their histograms under a known law
(:func:`patch_histograms`); uniform loads for equilibration (:func:`uniform_load`);
ramp-and-hold loading-machine sessions with a load-cell record like Gillis (2013)
(:func:`ramp_hold`); sine sweeps and blind tests of Gillis (2013) Table 4.2 seen by a sensor
with a known frequency-dependent gain (:func:`sine_sweep`, :func:`random_sine_sets`); a
family of sensors for sweeping static methods (:data:`FAMILY`, :func:`family_sessions`).
"""

from tactilecal._deprecated import moved_names
from tactilecal.simulate._deadweight import ContactModel, deadweight_session
from tactilecal.simulate._dynamic import random_sine_sets, sine_sweep, through_response
from tactilecal.simulate._family import FAMILY, family_sessions, true_force_table_N
from tactilecal.simulate._patches import patch_histograms
from tactilecal.simulate._sensor import make_sensor
from tactilecal.simulate._static import ramp_hold, uniform_load

__all__ = [
    "make_sensor", "deadweight_session", "ContactModel", "uniform_load",
    "ramp_hold",
    "sine_sweep", "random_sine_sets", "through_response",
    "FAMILY", "family_sessions", "true_force_table_N", "patch_histograms",
]

_RETURNED = "{} returns it; use its attributes"
__getattr__ = moved_names(__name__, {
    "SimulatedSensor": ("_sensor", "SimulatedSensor", _RETURNED.format("make_sensor()")),
    "DeadweightSession": ("_deadweight", "DeadweightSession",
                          _RETURNED.format("deadweight_session()")),
    "MANIFEST_COLUMNS": ("_deadweight", "MANIFEST_COLUMNS", "see docs/static-calibration.md"),
    "PAD_MASS_G": ("_loads", "PAD_MASS_G", "see deadweight_session()'s docstring"),
    "UniformLoad": ("_static", "UniformLoad", _RETURNED.format("uniform_load()")),
    "RampHold": ("_static", "RampHold", _RETURNED.format("ramp_hold()")),
    "ramp_hold_profile": ("_static", "ramp_hold_profile", "use ramp_hold()"),
    "DynamicSession": ("_dynamic", "DynamicSession", _RETURNED.format("sine_sweep()")),
    "sensel_matrix": ("_dynamic", "sensel_matrix", "use sine_sweep()"),
    "FamilyMember": ("_family", "FamilyMember", "the members of FAMILY are its instances"),
    "sensor_geometry": ("_sensor", "sensor_geometry", "use tactilecal.sensors.get_sensor(name) "
                        "or custom_sensor(...), or the attributes of make_sensor()"),
})
