"""Every dynamic model on a family of simulated sensors with known truth.

Sensors (each calibrated on a short sine sweep, 1000 Hz sensor and 1250 Hz load cell,
and tested blind on random sine sets, both from :mod:`tactilecal.simulate`; the
sensors are :class:`~tactilecal.simulate.DynamicSensor` responses):

* ``thesis``: Gillis's log10 gain law, A = 0.11, zero phase;
* ``visco1``: first-order relaxation, zero 40 Hz, pole 10 Hz (gain falls to 0.25);
* ``visco2``: second order, zeros 30 and 120 Hz, poles 8 and 60 Hz;
* ``creep``: slow relaxation, zero 6 Hz, pole 2 Hz, behind the thesis' log law;
* ``resonant``: a 60 Hz resonance, damping 0.1 (no model of the family describes it).

For each sensor and model (``auto`` and each model forced): the blind test's dynamic RMS
error before / after the offline inverse filter. Goals (issue 13): thesis blind ratio >= 5;
viscoelastic: rational chosen by ``auto``, blind ratio >= 10; resonant: ``auto`` refuses
(a refused fit is tracked as NaN).
"""

import warnings

RATES = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
         "reference_noise_N": 0.05}
SENSORS = ["thesis", "visco1", "visco2", "creep", "resonant"]
MODELS = ["auto", "log10", "rational", "wiener"]


def _sensor(name):
    from tactilecal.simulate import DynamicSensor

    return {"thesis": DynamicSensor(),
            "visco1": DynamicSensor(A=0.0, zeros_hz=(40.0,), poles_hz=(10.0,)),
            "visco2": DynamicSensor(A=0.0, zeros_hz=(30.0, 120.0), poles_hz=(8.0, 60.0)),
            "creep": DynamicSensor(A=0.11, zeros_hz=(6.0,), poles_hz=(2.0,)),
            "resonant": DynamicSensor(A=0.0, resonances=((60.0, 0.1),))}[name]


def _records(name):
    """The sweep and the blind test of one sensor: two (sensor, reference) pairs."""
    from tactilecal.simulate import random_sine_sets, sine_sweep

    sweep = sine_sweep(seed=0, response=_sensor(name), step_hz=2, cycles_high=10, **RATES)
    blind = random_sine_sets(seed=5, response=_sensor(name), **RATES)
    return (sweep.sensor, sweep.reference), (blind.sensor, blind.reference)


class Models:
    params = [SENSORS, MODELS]
    param_names = ["sensor", "model"]
    timeout = 600

    def setup_cache(self):
        return {name: _records(name) for name in SENSORS}

    def track_blind_ratio(self, records, sensor, model):
        """Blind test: dynamic RMS error before / after the offline inverse filter."""
        from tactilecal.dynamic import evaluate, fit_filter

        sweep, blind = records[sensor]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                filt = fit_filter(*sweep, model=model, force=model != "auto")
            except ValueError:
                return float("nan")  # refused, with its reason (the resonant sensor's goal)
            return evaluate(filt, *blind).improvement

    track_blind_ratio.unit = "ratio"


class AutoChoice:
    params = SENSORS
    param_names = ["sensor"]
    timeout = 600

    def setup(self, sensor):
        self.sweep = _records(sensor)[0]

    def track_auto_chose_rational(self, sensor):
        """1 when ``model="auto"`` chose a rational model, 0 another, NaN when it refused."""
        from tactilecal.dynamic import fit_filter

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                return float(fit_filter(*self.sweep, model="auto").model == "rational")
        except ValueError:
            return float("nan")

    track_auto_chose_rational.unit = "bool"

    def time_fit_filter_auto(self, sensor):
        """``fit_filter(model="auto")`` on the sweep: the rational structures' fits dominate."""
        from tactilecal.dynamic import fit_filter

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                fit_filter(*self.sweep, model="auto")
            except ValueError:
                pass  # refused (the resonant sensor): the fits were made all the same


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])
