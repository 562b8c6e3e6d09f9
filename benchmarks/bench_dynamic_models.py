"""Benchmark: every dynamic model on a family of simulated sensors with known truth (issue 13).

Sensors (each calibrated on a sine sweep and tested blind on random sine sets, both from
:mod:`tactilecal.simulate`; the viscoelastic ones pass the records through a rational
response with :class:`~tactilecal.simulate.DynamicSensor`):

* ``thesis``: Gillis's log10 gain law, A = 0.11, zero phase;
* ``visco1``: first-order relaxation, zero 40 Hz, pole 10 Hz (gain falls to 0.25);
* ``visco2``: second order, zeros 30 and 120 Hz, poles 8 and 60 Hz;
* ``creep``: slow relaxation, zero 6 Hz, pole 2 Hz, behind the thesis' log law;
* ``resonant``: a 60 Hz resonance, damping 0.1 (no model of the family describes it).

For each sensor: the model ``auto`` chooses and why, then every model forced (``log10``,
``rational``, ``wiener``) with its complex R2 and the blind test's dynamic RMS ratio
(before / after) for the offline inverse and, for a rational model, the causal one, and the
largest phase error left. Goals (issue 13): thesis A within 2 %, lag within one sample,
blind ratio >= 5x; viscoelastic: rational chosen, corners within 5 %, blind ratio >= 10x;
resonant: ``auto`` refuses.

Usage: ``python benchmarks/bench_dynamic_models.py [--full]`` (``--full``: the thesis' rates,
4000 / 5000 Hz and 1 Hz steps; default a short sweep at 1000 / 1250 Hz).
"""

import argparse
import time
import warnings

import numpy as np

from tactilecal.dynamic import evaluate, fit_filter
from tactilecal.simulate import DynamicSensor, random_sine_sets, sine_sweep

RATES = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
         "reference_noise_N": 0.05}
SHORT = ({"step_hz": 2, "cycles_high": 10, **RATES}, RATES)  # (sweep, blind test) options
FULL = ({}, {})
LAG_S = 0.8373
SENSORS = {
    "thesis": DynamicSensor(),
    "visco1": DynamicSensor(A=0.0, zeros_hz=(40.0,), poles_hz=(10.0,)),
    "visco2": DynamicSensor(A=0.0, zeros_hz=(30.0, 120.0), poles_hz=(8.0, 60.0)),
    "creep": DynamicSensor(A=0.11, zeros_hz=(6.0,), poles_hz=(2.0,)),
    "resonant": DynamicSensor(A=0.0, resonances=((60.0, 0.1),)),
}
MODELS = ("log10", "rational", "wiener")


def corners_hz(model):
    """Sorted zero and pole corner frequencies (Hz) of a rational model."""
    return ([round(-complex(r).real / (2 * np.pi), 3) for r in sorted(
        model.zeros_rad_s, key=lambda r: -r.real)],
            [round(-complex(r).real / (2 * np.pi), 3) for r in sorted(
                model.poles_rad_s, key=lambda r: -r.real)])


def records(name, options):
    """The sweep and the blind test of one sensor: (sensor, reference) pairs."""
    sweep = sine_sweep(seed=0, response=SENSORS[name], **options[0])
    blind = random_sine_sets(seed=5, response=SENSORS[name], **options[1])
    return (sweep.sensor, sweep.reference), (blind.sensor, blind.reference)


def describe_auto(name, sweep):
    """One line: what ``model="auto"`` chose, or why it refused."""
    try:
        filt = fit_filter(*sweep, model="auto")
    except ValueError as exc:
        return f"auto refused: {str(exc)[:150]}"
    extra = (f"A = {filt.params['A']:.4g}" if "A" in filt.params else
             f"corners (zeros, poles) Hz {corners_hz(filt.rational)}" if filt.rational else "")
    return f"auto -> {filt.model} ({extra}); clock offset {filt.lag_s:.6f} s (true {LAG_S})"


def model_row(model, sweep, blind):
    """Complex R2, blind RMS ratios (offline, causal) and the largest phase error left."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            filt = fit_filter(*sweep, model=model, force=True)
        except ValueError as exc:
            return f"{model:>9}: no fit ({str(exc)[:90]})"
        r2 = filt.fit.model_choice.r2_complex
        offline = evaluate(filt, *blind)
        causal = evaluate(filt, *blind, causal=True) if filt.rational is not None else None
    r2_text = f"complex R2 {r2:.3f}, "
    causal_text = "" if causal is None else f", causal {causal.improvement:.3g}x"
    phase = np.abs(offline.phase_after_deg).max() if len(offline.f_hz) else float("nan")
    return (f"{model:>9}: {r2_text}blind RMS {offline.rms_before_N:.3g} N -> "
            f"{offline.rms_after_N:.3g} N, offline {offline.improvement:.3g}x{causal_text}; "
            f"phase error left {phase:.3g} deg; {filt.summary()[:80]}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--full", action="store_true", help="the thesis' rates and steps")
    parser.add_argument("--sensors", default=",".join(SENSORS))
    args = parser.parse_args()
    rates = FULL if args.full else SHORT
    start = time.perf_counter()
    for name in args.sensors.split(","):
        sweep, blind = records(name, rates)
        print(f"{name}: {describe_auto(name, sweep)}")
        for model in MODELS:
            print("  " + model_row(model, sweep, blind))
    print(f"{time.perf_counter() - start:.0f} s; data: tactilecal.simulate sweeps (seed 0) "
          f"and blind sine sets (seed 5), {'full' if args.full else 'short'} rates")


if __name__ == "__main__":
    main()
