"""Movie calibration at memory speed: ``frame_histograms`` and ``calibrate_movie`` timed.

Run: ``python benchmarks/bench_movie.py [--sizes 10000 100000 1000000] [--repeat 3]``
(all three sizes: about 5 minutes and 15 GB resident at the 1M size; ``--sizes 10000
100000`` peaked at 5.2 GB).

A simulated 5051 sensor (44 x 44 sensels) under a ramp-and-hold load (4 levels up to
889.6 N, load cell at 500 Hz on its own clock, ``tactilecal.simulate.ramp_hold``). The
largest size is the 100,000-frame movie with every frame repeated (1M frames of 44 x 44
are 15.5 GB in float64, so that size is stored as uint8 only, 1.9 GB).

For each size and storage dtype, interleaved in one run (best of ``--repeat``):

- ``np.sum`` over the same array, ``np.sum`` of its bytes viewed as uint64 words and
  ``np.copyto`` into a ready buffer (up to 1 GB): the fastest is "one pass at memory
  speed", the baseline every time is divided by (for uint8, ``np.sum`` widens every value
  and is no read at memory speed);
- ``frame_histograms`` on its two paths, the compiled one-pass kernel and NumPy (taken
  below ``COMPILED_MIN_VALUES`` readings), and the former NumPy version (round, check the
  range, add frame offsets, ``bincount`` per 64 frames), kept below as
  ``old_frame_histograms``; and numba's start-up in a new process, which decides the switch;
- ``calibrate_movie``, its peak memory (tracemalloc), where it spends its time
  (histograms; the first pass: an alignment on the decimated raw sum and a fit on 5000
  frames; the final alignment in ``tactilecal.dynamic``; the final fit in
  ``calibration._calibrate``; the rest), and on the same recording as a dask array of
  16,384-frame blocks (threads; its result must equal the in-memory one).

Each line also checks that ``calibrate_movie``'s uint16 histograms equal
``frame_histograms``' counts, and prints the largest relative difference of the fitted
parameters from the same call with the reference searches (once, untimed): the second
alignment over every lag (not near the first's) and the power fit's nested grids over all
the points (``_powerfit._minimise_b_grid``, not a bracket from a subsample and Brent).

The former implementation (session 7's code at bbea5f0, ``benchmarks/_former_movie.py``)
was timed beside it until session 9; the speed-ups measured then are in
``benchmarks/README.md``, and git keeps the copy (``git show dde0562:benchmarks/_former_movie.py``).
"""

import argparse
import os
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
import xarray as xr

import tactilecal.calibration._movie as movie
import tactilecal.calibration._powerfit as powerfit
import tactilecal.dynamic  # noqa: F401  (import time is not part of the calibration)
from tactilecal.calibration import calibrate_movie, frame_histograms
from tactilecal.calibration._histogram import COMPILED_MIN_VALUES
from tactilecal.calibration._points import _frame_histograms
from tactilecal.calibration._powerfit import COMPILED_MIN_POINTS
from tactilecal.simulate import make_sensor, ramp_hold
from tactilecal.simulate._static import ramp_hold_profile


# ----------------------------------------------------------- the former implementation
def old_frame_histograms(raw, *, chunk_frames=64, out=None, prepare=None):
    """``frame_histograms`` before the compiled kernel (git main at 70e9e75)."""
    raw = np.asarray(raw)
    if raw.ndim == 2:
        raw = raw[None]
    n = raw.shape[0]
    flat = raw.reshape(n, -1)
    out = np.empty((n, 256), dtype=np.int64) if out is None else out
    offsets = (np.arange(chunk_frames, dtype=np.intp) * 257)[:, None]
    work = np.empty((chunk_frames, flat.shape[1]))
    index = np.empty((chunk_frames, flat.shape[1]), dtype=np.intp)
    for start in range(0, n, chunk_frames):
        block = flat[start:start + chunk_frames]
        m = len(block)
        if prepare is not None:
            block = np.asarray(prepare(block.reshape(m, *raw.shape[1:])),
                               dtype=float).reshape(m, -1)
        values = _old_rounded(block, work[:m])
        np.add(values, offsets[:m], out=index[:m], casting="unsafe")
        counts = np.bincount(index[:m].ravel(), minlength=m * 257)
        out[start:start + m] = counts.reshape(m, 257)[:, :256]
    return out


def _old_rounded(block, work):
    if block.dtype.kind in "ui":
        values, lo, hi = block, block.min(), block.max()
    else:
        values = np.rint(block, out=work)
        lo, hi = np.fmin.reduce(values, axis=None), np.fmax.reduce(values, axis=None)
    if lo < 0 or hi > 255:
        bad = values[(values < 0) | (values > 255)].flat[0]
        raise ValueError(f"raw frames contain the value {bad:g}; expected raw readings 0..255")
    if values is work:
        nan = np.isnan(work)
        if nan.any():
            work[nan] = 256
    return values


# ------------------------------------------------------------------------ workloads
def simulate(n_frames):
    """Ramp-and-hold movie of ``n_frames`` frames (float64) and its load-cell record."""
    times, _ = ramp_hold_profile((222.4, 444.8, 667.2, 889.6))  # ramp_hold's default levels
    rh = ramp_hold(make_sensor("5051", seed=0), frame_rate_hz=n_frames / times[-1],
                   loadcell_rate_hz=500.0, seed=1)
    return rh.raw, rh.loadcell


def stored(raw, dtype, repeat_frames):
    """The movie in ``dtype`` storage, each frame repeated ``repeat_frames`` times."""
    values = raw.values.astype(dtype) if dtype != np.float64 else raw.values
    if repeat_frames > 1:
        values = np.repeat(values, repeat_frames, axis=0)
    n = len(values)
    spf = float(raw.attrs["seconds_per_frame"]) / repeat_frames
    coords = {"frame": np.arange(1, n + 1), "time": ("frame", np.arange(n) * spf)}
    return xr.DataArray(values, dims=raw.dims, coords=coords,
                        attrs={**raw.attrs, "seconds_per_frame": spf})


class Stopwatch:
    """Wrap functions of the movie module to add up the seconds spent in each."""

    def __init__(self, names):
        self.seconds = dict.fromkeys(names, 0.0)
        self.saved = {}
        for name in names:
            self.saved[name] = getattr(movie, name)
            setattr(movie, name, self._timed(name, self.saved[name]))

    def _timed(self, name, func):
        def wrapper(*args, **kwargs):
            t0 = time.perf_counter()
            try:
                return func(*args, **kwargs)
            finally:
                self.seconds[name] += time.perf_counter() - t0
        return wrapper

    def restore(self):
        for name, func in self.saved.items():
            setattr(movie, name, func)


def best(func, repeat):
    times, result = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        result = func()
        times.append(time.perf_counter() - t0)
    return min(times), result


def reference_searches(rec, loadcell):
    """``calibrate_movie`` with every lag searched and the power fit's nested grids."""
    lag_on, many = movie._lag_on, powerfit._minimise_b_many
    movie._lag_on = lambda total, times, loads, max_lag_s, near=None: lag_on(
        total, times, loads, max_lag_s)
    powerfit._minimise_b_many = powerfit._minimise_b_grid
    try:
        return calibrate_movie(rec, loadcell)
    finally:
        movie._lag_on, powerfit._minimise_b_many = lag_on, many


def run_size(raw, loadcell, dtype, repeat_frames, repeat):
    rec = stored(raw, dtype, repeat_frames)
    values = rec.values
    n = len(values)
    buf = np.empty_like(values) if values.nbytes <= 1e9 else None  # room for a copy
    words = values.reshape(-1).view(np.uint64)  # every byte read once as 64-bit integers
    hist, old_hist = np.zeros((n, 256)), np.zeros((n, 256))  # both written before timing
    frame_histograms(values[:2], out=hist[:2])  # numba compiles (or loads its cache)
    lazy = rec.chunk({"frame": 16_384})  # dask copies the array
    t = {k: [] for k in ("sum", "words", "copy", "hist", "hist_numpy", "hist_old", "movie",
                         "dask")}
    parts = []
    res_new = None
    for _ in range(repeat):
        t["sum"].append(best(lambda: values.sum(), 1)[0])
        t["words"].append(best(lambda: words.sum(), 1)[0])
        if buf is not None:
            t["copy"].append(best(lambda: np.copyto(buf, values), 1)[0])
        t["hist"].append(best(lambda: _frame_histograms(values, out=hist, compiled=True),
                              1)[0])
        t["hist_numpy"].append(best(lambda: _frame_histograms(values, out=old_hist,
                                                              compiled=False), 1)[0])
        assert np.array_equal(hist, old_hist)
        t["hist_old"].append(best(lambda: old_frame_histograms(values, out=old_hist), 1)[0])
        watch = Stopwatch(["_histograms", "_first_pass", "_align_loads", "calibrate_arrays"])
        try:
            dt, res_new = best(lambda: calibrate_movie(rec, loadcell), 1)
        finally:
            watch.restore()
        t["movie"].append(dt)
        parts.append((dt, watch.seconds))
        dt, res_dask = best(lambda: calibrate_movie(lazy, loadcell), 1)
        t["dask"].append(dt)
        assert res_dask.params == res_new.params
    counts = movie._histograms(values, None, None, lambda spans, **_: spans, True)
    same_hist = bool(np.array_equal(hist, old_hist) and np.array_equal(counts, hist))
    del counts
    base = min(t["sum"] + t["words"] + t["copy"])
    copy = f"{min(t['copy']):.3f} s" if t["copy"] else "- (no room for a copy)"
    print(f"\n{n:>9,} frames 44 x 44 {np.dtype(dtype).name:<8} ({values.nbytes / 1e9:.2f} GB):"
          f" np.sum {min(t['sum']):.3f} s, as uint64 words {min(t['words']):.3f} s, np.copyto "
          f"{copy}; one pass = the fastest, {base:.3f} s ({values.nbytes / base / 1e9:.1f} GB/s);"
          f" load (1, 5 min) {os.getloadavg()[0]:.1f}, {os.getloadavg()[1]:.1f}")
    path = "compiled" if values.size >= COMPILED_MIN_VALUES else "NumPy"
    movie_path = "compiled" if path == "compiled" or n >= COMPILED_MIN_POINTS else "NumPy"
    print(f"  ({n * 1936:,} readings: frame_histograms takes the {path} path, the switch is "
          f"at {COMPILED_MIN_VALUES:,}; calibrate_movie (power, numba loaded for its fit from "
          f"{COMPILED_MIN_POINTS:,} frames) the {movie_path} one)")
    for name, key in (("frame_histograms, compiled", "hist"),
                      ("  NumPy path", "hist_numpy"), ("  former NumPy version", "hist_old"),
                      ("calibrate_movie", "movie"), ("  dask-backed, 16k frames/block", "dask")):
        if t[key]:
            s = min(t[key])
            print(f"  {name:<26} {s:8.3f} s  {s / base:7.2f} x one pass  "
                  f"({s / n * 1e5:.3f} s per 100k frames)")
    print(f"  speed-up of frame_histograms over the former NumPy version: "
          f"{min(t['hist_old']) / min(t['hist']):.1f} x")
    tracemalloc.start()
    calibrate_movie(rec, loadcell)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(f"  calibrate_movie peak (tracemalloc, numba's work arrays not traced): "
          f"{peak / 1e6:.0f} MB, {peak / values.nbytes:.2f} x the array")
    total, sec = min(parts, key=lambda p: p[0])
    rest = total - sum(sec.values())
    print(f"  calibrate_movie's time: histograms {sec['_histograms']:.3f} s, first pass "
          f"(decimated alignment, fit on 5000 frames) {sec['_first_pass']:.3f} s, final "
          f"alignment (dynamic.estimate_lag, resample_to) {sec['_align_loads']:.3f} s, final "
          f"fit (_calibrate) {sec['calibrate_arrays']:.3f} s, rest {rest:.3f} s")
    res_ref = reference_searches(rec, loadcell)
    rel = max(abs(res_new.params[k] - res_ref.params[k]) / abs(res_ref.params[k])
              for k in res_ref.params)
    print(f"  histograms identical (frame_histograms' paths and the former NumPy version; "
          f"calibrate_movie's uint16 counts): {same_hist}; largest relative parameter "
          f"difference from the reference searches (every lag, nested grids) {rel:.1e}; "
          f"A = {res_new.params['A']:.10g}, b = {res_new.params['b']:.10g}")


STARTUP = """
import time, numpy as np
import tactilecal.dynamic  # imports numba, as calibrate_movie does
from tactilecal.calibration._points import _frame_histograms
t0 = time.perf_counter()
_frame_histograms(np.zeros((2, 44, 44)), compiled=True)
t1 = time.perf_counter()
_frame_histograms(np.zeros((2, 44, 44), np.uint8), compiled=True)
print(t1 - t0, time.perf_counter() - t1)
"""


def numba_startup(repeat):
    """First compiled call in a new process (kernels cached on disk), and a second kernel."""
    import subprocess

    runs = [tuple(map(float, subprocess.run([sys.executable, "-c", STARTUP], check=True,
                                            capture_output=True, text=True).stdout.split()))
            for _ in range(repeat)]
    first, second = min(r[0] for r in runs), min(r[1] for r in runs)
    print(f"numba in a new process: first kernel call {first:.3f} s (start-up and cache "
          f"load), a second kernel {second:.3f} s; best of {repeat}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000, 1_000_000])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"{Path(__file__).name}: times are the best of {args.repeat}, interleaved; ratios "
          "to one pass (np.sum or np.copyto) over the same array in the same run")
    numba_startup(args.repeat)
    for size in args.sizes:
        repeat_frames = max(1, size // 100_000)
        raw, loadcell = simulate(size // repeat_frames)
        dtypes = [np.uint8] if size * 1936 * 8 > 4e9 else [np.float64, np.float32, np.uint8]
        for dtype in dtypes:
            run_size(raw, loadcell, dtype, repeat_frames, args.repeat)


if __name__ == "__main__":
    main()
