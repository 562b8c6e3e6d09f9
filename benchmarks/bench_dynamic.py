"""Benchmark of the dynamic calibration (issue 5): accuracy on simulated truth, throughput.

Run: ``python benchmarks/bench_dynamic.py [--seconds 8] [--seeds 0 1 2] [--skip-accuracy]
[--skip-throughput] [--stages]``

Accuracy (Gillis 2013 Table 4.2 sessions from ``tactilecal.simulate``): the full sine sweep
1..140 Hz (sensor 4000 Hz, load cell 5000 Hz starting ``lag_s`` later, white noise) with a
known gain law ``1 + 0.11 log10(f + 1)``; the fitted A against the truth, the lag error in
sensor samples; then the filter on Blind Test 1 (reverse sweep) and Blind Test 2 (20 random
sine sets 10..200 Hz), each a separate simulated session with its own seed and lag: RMS error
of the dynamic part before / after.

Throughput: every sensel of a 1936-sensel (44 x 44) recording at 4000 Hz corrected with
``apply_filter`` (multirate, direct, and dask-backed) against ``scipy.signal.filtfilt`` per
channel in the same run; a rational (phase) filter offline and causal, the causal one against
a bare ``scipy.signal.sosfilt`` of the same sections on the same array. filtfilt is timed
on a subset of channels and scaled to all of them (said in the output). Two baselines:
filtfilt with an FIR of the same length designed for sqrt(G) (filtfilt applies it twice, so
the same gain: the like-for-like per-channel approach) and filtfilt with a 4th-order IIR (a
cheap per-channel filter of another, lower quality: a floor for per-channel work). Times are
best and median of ``--repeat`` runs.
"""

import argparse

import numpy as np
import xarray as xr
from _timing import run_times
from scipy import signal

from tactilecal.dynamic import (
    CorrectionFilter,
    RationalModel,
    apply_filter,
    evaluate,
    fit_filter,
)
from tactilecal.simulate import random_sine_sets, sine_sweep


def accuracy(seeds):
    print("== accuracy: full thesis sweep, truth A = 0.11 (log10), 4000 Hz sensor, "
          "5000 Hz load cell ==")
    rows = []
    for seed in seeds:
        lag_true = 0.8373 + 0.1 * seed
        sweep = sine_sweep(seed=seed, lag_s=lag_true)
        filt = fit_filter(sweep.sensor, sweep.reference, model="log10")
        filt_e = fit_filter(sweep.sensor, sweep.reference, model="log")
        a_err = filt.fit.A / 0.11 - 1
        a_err_e = filt_e.fit.A / (0.11 / np.log(10)) - 1
        lag_err = (filt.lag_s - lag_true) * 4000
        blind1 = sine_sweep(reverse=True, seed=100 + seed, lag_s=0.31 + 0.05 * seed)
        blind2 = random_sine_sets(seed=200 + seed, lag_s=0.6121 + 0.05 * seed)
        ev1 = evaluate(filt, blind1.sensor, blind1.reference)
        ev2 = evaluate(filt, blind2.sensor, blind2.reference)
        hold = CorrectionFilter.from_model(filt.fit, fs_hz=filt.fs_hz, outside="hold")
        ev2h = evaluate(hold, blind2.sensor, blind2.reference)
        rows.append((a_err, lag_err, ev2.improvement))
        print(f"seed {seed}: A = {filt.fit.A:.5f} ({100 * a_err:+.2f} %), natural-log A = "
              f"{filt_e.fit.A:.5f} ({100 * a_err_e:+.2f} % of 0.11/ln10), R2 = "
              f"{filt.fit.r2:.4f}, band {filt.band_hz[0]:g}..{filt.band_hz[1]:g} Hz")
        print(f"        lag error {lag_err:+.4f} sensor samples "
              f"(blind tests: {(ev1.lag_s - blind1.lag_s) * 4000:+.4f}, "
              f"{(ev2.lag_s - blind2.lag_s) * 4000:+.4f})")
        print(f"        blind test 1 (reverse sweep): RMS {ev1.rms_before_N:.3f} -> "
              f"{ev1.rms_after_N:.3f} N = {ev1.improvement:.2f}x")
        print(f"        blind test 2 (random sets): RMS {ev2.rms_before_N:.3f} -> "
              f"{ev2.rms_after_N:.3f} N = {ev2.improvement:.2f}x (taper above band); "
              f"{ev2h.improvement:.2f}x with outside='hold'")
    a = np.array(rows)
    print(f"worst |A error| {100 * np.abs(a[:, 0]).max():.2f} % (goal 5 %), worst |lag error| "
          f"{np.abs(a[:, 1]).max():.4f} samples (goal 1), smallest blind-2 improvement "
          f"{a[:, 2].min():.2f}x (goal 3x)")


#: A first-order viscoelastic sensor (zero 40 Hz, pole 10 Hz): the rational filter timed.
RATIONAL = RationalModel.from_corners_hz(zeros_hz=[40.0], poles_hz=[10.0])


def throughput(seconds, subset, repeat):
    fs_hz, shape = 4000.0, (44, 44)
    n = int(seconds * fs_hz)
    rng = np.random.default_rng(0)
    data = 100.0 + rng.standard_normal((n, *shape))
    rec = xr.DataArray(data, dims=("frame", "row", "col"),
                       coords={"time": ("frame", np.arange(n) / fs_hz)})
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=fs_hz, band_hz=(1, 140))
    samples = data.size
    print(f"== throughput: {shape[0] * shape[1]} sensels x {n} frames ({seconds:g} s at "
          f"{fs_hz:g} Hz) = {samples / 1e6:.1f} M float64 samples, FIR {filt.n_taps} taps, "
          f"{repeat} runs each (best / median) ==")
    apply_filter(rec.isel(frame=slice(0, 3 * filt.n_taps)), filt)  # numba compiles (cached)

    def fresh_copy():  # what any float64 -> new float64 output costs (page faults + copy)
        out = np.empty_like(data)
        out[...] = data

    t_first_copy = run_times(fresh_copy, 1)[0]  # memory this process never held before
    chunked = rec.chunk({"frame": 65536})
    rational = CorrectionFilter("rational", {"order": 1}, fs_hz, (1, 140), rational=RATIONAL)
    flat, sos = data.reshape(n, -1), rational.sos()
    runs = {
        "apply_filter, method='auto' (multirate)": lambda: apply_filter(rec, filt),
        "apply_filter, method='direct'": lambda: apply_filter(rec, filt, method="direct"),
        "apply_filter on dask (65536-frame chunks)":
            lambda: apply_filter(chunked, filt).compute(),
        "rational inverse, offline (centred FIR with phase, multirate)":
            lambda: apply_filter(rec, rational),
        "rational inverse, causal (apply_filter(causal=True))":
            lambda: apply_filter(rec, rational, causal=True),
        "scipy.signal.sosfilt of the same sections on the same array":
            lambda: signal.sosfilt(sos, flat, axis=0),
    }
    times = {name: run_times(fn, repeat) for name, fn in runs.items()}
    t_copy = run_times(fresh_copy, repeat).min()
    x = data.reshape(n, -1)[:, :subset].T.copy()
    sqrt_fir = signal.firwin2(filt.n_taps, np.linspace(0, fs_hz / 2, 4097),
                              np.sqrt(filt.gain(np.linspace(0, fs_hz / 2, 4097))), fs=fs_hz)
    t_fir = run_times(lambda: [signal.filtfilt(sqrt_fir, [1.0], row) for row in x], 1).min()
    b, a = signal.butter(4, 140.0, fs=fs_hz)
    t_iir = run_times(lambda: [signal.filtfilt(b, a, row) for row in x], repeat).min()
    scale = samples / x.size
    t_fir, t_iir = t_fir * scale, t_iir * scale
    print(f"filtfilt per channel, timed on {subset} channels and scaled x{scale:.0f}: "
          f"same-length FIR (sqrt gain) {t_fir:.1f} s, 4th-order IIR {t_iir:.2f} s; "
          f"fresh float64 output + copy (memory floor) {t_copy:.3f} s, the first such copy "
          f"in this process {t_first_copy:.3f} s")
    for name, t in times.items():
        best, median = t.min(), np.median(t)
        print(f"{name}: {best:.3f} / {median:.3f} s = {samples / best / 1e6:.0f} / "
              f"{samples / median / 1e6:.0f} M samples/s; vs filtfilt FIR "
              f"{t_fir / best:.0f}x, vs filtfilt IIR {t_iir / best:.2f}x, "
              f"{best / t_copy:.1f}x the copy")
    auto, direct = apply_filter(rec, filt).values, apply_filter(rec, filt, method="direct").values
    print(f"multirate - direct on this record: max |difference| "
          f"{np.abs(auto - direct).max() / np.ptp(data):.1e} of the record's range")
    ratio = times["apply_filter, method='direct'"] / times[
        "apply_filter, method='auto' (multirate)"]
    print(f"multirate speed-up over direct, run by run: {np.round(ratio, 2).tolist()}")
    rates = samples / times["apply_filter, method='auto' (multirate)"] / 1e6
    print(f"multirate M samples/s, run by run: {np.round(rates).astype(int).tolist()}")
    causal = times["scipy.signal.sosfilt of the same sections on the same array"] / times[
        "rational inverse, causal (apply_filter(causal=True))"]
    print(f"causal apply_filter speed / bare sosfilt, run by run: "
          f"{np.round(causal, 2).tolist()}")


def _page_faults():
    try:
        with open("/proc/vmstat") as f:
            return dict(line.split() for line in f).get("pgfault")
    except OSError:  # not Linux
        return None


def stages(seconds, repeat):
    """Seconds of each multirate stage and page faults, run by run (same record as above)."""
    from tactilecal.dynamic._multirate import apply_multirate, plan_multirate

    fs_hz, n = 4000.0, int(seconds * 4000.0)
    x2d = 100.0 + np.random.default_rng(0).standard_normal((n, 44 * 44))
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=fs_hz, band_hz=(1, 140))
    plan = plan_multirate(filt)
    apply_multirate(x2d[:3 * filt.n_taps], plan, 2, None, "single")  # numba compiles (cached)
    print(f"== multirate stages, 1936 sensels x {n} frames, P = {plan.factor} ==")
    for run in range(repeat):
        timings, before = {}, _page_faults()
        apply_multirate(x2d, plan, 2, None, "single", timings=timings)
        after = _page_faults()
        faults = "" if before is None else f", {int(after) - int(before)} page faults"
        print(f"run {run + 1}: " + ", ".join(f"{k} {v:.3f} s" for k, v in timings.items())
              + faults)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seconds", type=float, default=8.0)
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--subset", type=int, default=16)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--skip-accuracy", action="store_true")
    parser.add_argument("--skip-throughput", action="store_true")
    parser.add_argument("--stages", action="store_true",
                        help="also time each multirate stage, run by run")
    args = parser.parse_args()
    if not args.skip_accuracy:
        accuracy(args.seeds)
    if not args.skip_throughput:
        throughput(args.seconds, args.subset, args.repeat)
    if args.stages:
        stages(args.seconds, args.repeat)


if __name__ == "__main__":
    main()
