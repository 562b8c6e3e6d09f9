"""
Dynamic calibration and a blind test
====================================

A tactile sensor under a changing load reads too little at high frequency (and, if it is
viscoelastic, late). Gillis (2013, section 4) calibrates that from a sine sweep recorded by
the sensor and a load cell together: align the two records, estimate the transfer function
``|reference| / |sensor|``, fit its model (``1 + A log10(f + 1)``, eq. 4.1) and apply the
inverse as a zero-phase filter to every sensel. An independent blind test then says how
much of the dynamic error the filter removes (:doc:`/dynamic-calibration`).

The records here are simulated with their truth (:func:`tactilecal.simulate.sine_sweep`,
A = 0.11, a load cell starting 0.8373 s later), at 1000 Hz sensor and 1250 Hz load-cell
rates so that the example runs in seconds (the thesis used 4000 and 5000 Hz).
"""

# %%
# Fit the filter on a sweep
# -------------------------
from tactilecal.dynamic import evaluate, fit_filter
from tactilecal.simulate import random_sine_sets, sine_sweep

rates = {"fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0, "sensor_noise_N": 0.2,
         "reference_noise_N": 0.05}
sweep = sine_sweep(seed=0, step_hz=2, cycles_high=10, **rates)
filt = fit_filter(sweep.sensor, sweep.reference, model="log10")
print(filt.summary())
print(f"A = {filt.fit.params['A']:.4f} (true {sweep.A}); lag {filt.lag_s:.4f} s "
      f"(true {sweep.lag_s} s)")

# %%
# The measured transfer function and the fitted model (Gillis 2013, Figure 4.9).
transfer = filt.plot_transfer()

# %%
# Blind test: random sine sets
# ----------------------------
# A separate session (Blind Test 2 of the thesis' Table 4.2: 20 random sine sets of
# 10-200 Hz) with its own noise and lag.
blind = random_sine_sets(seed=5, **rates)
ev = evaluate(filt, blind.sensor, blind.reference)
print(f"RMS error of the dynamic part: {ev.rms_before_N:.2f} N before, "
      f"{ev.rms_after_N:.2f} N after ({ev.improvement:.1f}x smaller)")

# %%
# The records before and after the filter, and their spectra (Figures 4.10-4.13).
in_time = ev.plot_time(window_s=(2.0, 3.0))
spectra = ev.plot_spectra()
