"""Benchmark of the dynamic calibration (issues 5 and 16): accuracy on simulated truth, speed.

Run: ``python benchmarks/bench_dynamic.py [--seconds 8] [--seeds 0 1 2] [--skip-accuracy]
[--skip-throughput] [--stages] [--cluster [--dtype float32]] [--chunk-frames 8192] [--frames
8192 32768 131072 --chunks 8192 16384 4096]`` (``--frames``: the scaling rows at those record
lengths in place of the ``--seconds`` throughput, and the cluster at each of them)

Accuracy (Gillis 2013 Table 4.2 sessions from ``tactilecal.simulate``): the full sine sweep
1..140 Hz (sensor 4000 Hz, load cell 5000 Hz starting ``lag_s`` later, white noise) with a
known gain law ``1 + 0.11 log10(f + 1)``; the fitted A against the truth, the lag error in
sensor samples; then the filter on Blind Test 1 (reverse sweep) and Blind Test 2 (20 random
sine sets 10..200 Hz), each a separate simulated session with its own seed and lag: RMS error
of the dynamic part before / after.

Throughput: every sensel of a 1936-sensel (44 x 44) recording at 4000 Hz (float64, random
walk plus noise on an offset of 100) corrected with ``apply_filter``, all runs interleaved
(``--repeat`` rounds, each running every case once; best and median). Baselines in the same
run: one whole-record float32 ``scipy.fft.rfft`` + ``irfft`` (all cores) of the same
``(time, sensels)`` array along time, and of a sensel-major copy (contiguous lines: the
fastest layout for the FFT, a stricter baseline); a fresh float64 output plus a copy of the
record (the memory floor of any filter that returns a new array); ``apply_filter`` on a float32
copy of the recording with ``dtype="float32"`` (float32 read and written, like the baseline)
and its memory floor (a fresh float32 output plus a copy); the multirate method as it
was before issue 16 (``benchmarks/_legacy_multirate.py``), in memory and on dask. Also a
rational (phase) filter offline and causal, the causal one against a bare
``scipy.signal.sosfilt`` of the same sections on the same array; ``scipy.signal.filtfilt``
per channel (timed on ``--subset`` channels and scaled) with an FIR of the same length
designed for sqrt(G) (the like-for-like per-channel approach) and with a 4th-order IIR (a
cheap floor for per-channel work). The new output is checked against the old one.

``--cluster``: the same recording written uncompressed to NetCDF and Zarr, filtered on a
``dask.distributed.LocalCluster`` of 2 worker processes (1 thread each) that read it
themselves (``open_dataset(..., chunks=...)`` in the graph: no data inside it), the result
kept on the workers or written by them to Zarr; against ``apply_filter`` in memory on the
same array in the same run, and against the same read and write without filtering.
"""

import argparse
import os

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


def _recording(seconds, fs_hz=4000.0, shape=(44, 44)):
    n = int(seconds * fs_hz)
    rng = np.random.default_rng(0)
    data = 100.0 + 0.05 * rng.standard_normal((n, *shape)).cumsum(axis=0)
    data += rng.standard_normal(data.shape)
    return xr.DataArray(data, dims=("frame", "row", "col"),
                        coords={"time": ("frame", np.arange(n) / fs_hz)})


def _interleaved(runs, repeat, usage=None, settle=None):
    """Run every case once per round, ``repeat`` rounds; return the seconds of each run.

    Every case first runs once untimed: a first call compiles the numba kernels of its
    array types (or loads them from numba's cache), starts dask's thread pool and faults
    in the heap, which the first timed round measured otherwise (with the in-memory warm-up
    alone, the dask cases' first rounds were up to 5x slower than the next). ``usage``, a
    dict, receives per case and run this process's ``(user, system)`` CPU seconds and
    minor page faults (:func:`_usage`): wall time on the shared cores moves with the
    other sessions, and the system time of faulting in fresh arrays moves on its own.
    ``settle``, if given, is called (untimed) before every timed run.
    """
    for fn in runs.values():
        fn()
    times = {name: [] for name in runs}
    for _ in range(repeat):
        for name, fn in runs.items():
            if settle is not None:
                settle()
            before = _usage()
            times[name].extend(run_times(fn, 1))
            if usage is not None:
                usage.setdefault(name, []).append(_usage() - before)
    return {name: np.array(t) for name, t in times.items()}


def _usage():
    """This process's user and system CPU seconds and minor page faults so far."""
    import resource

    now = resource.getrusage(resource.RUSAGE_SELF)
    return np.array([now.ru_utime, now.ru_stime, now.ru_minflt])


def _usage_line(rows):
    """``user + system CPU s (system s), faults`` of the run with the least CPU, and the range."""
    rows = np.array(rows)
    cpu = rows[:, 0] + rows[:, 1]
    k = int(np.argmin(cpu))
    return (f"CPU {cpu[k]:.3f} s ({rows[k, 1]:.3f} s system; all runs {cpu.min():.2f}-"
            f"{cpu.max():.2f} s, system {rows[:, 1].min():.2f}-{rows[:, 1].max():.2f} s), "
            f"{rows[k, 2]:.0f} minor faults")


def _report(times, samples, baseline, usage=None):
    base = times[baseline].min()
    for name, t in times.items():
        best, median = t.min(), np.median(t)
        print(f"{name}: {best:.3f} / {median:.3f} s = {samples / best / 1e6:.0f} / "
              f"{samples / median / 1e6:.0f} M samples/s; {base / best:.2f}x the baseline")
        if usage is not None and name in usage:
            print(f"    {_usage_line(usage[name])}")


def throughput(seconds, subset, repeat):
    import _legacy_multirate as legacy
    from scipy import fft

    rec = _recording(seconds)
    data, fs_hz = rec.values, 4000.0
    n = data.shape[0]
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=fs_hz, band_hz=(1, 140))
    plan = legacy.plan_multirate(filt)
    samples = data.size
    print(f"== throughput: {data[0].size} sensels x {n} frames ({seconds:g} s at "
          f"{fs_hz:g} Hz) = {samples / 1e6:.1f} M float64 samples, FIR {filt.n_taps} taps, "
          f"multirate P = {plan.factor}, {repeat} interleaved rounds (best / median); load "
          f"{_load()} ==")
    flat = data.reshape(n, -1)
    head = rec.isel(frame=slice(0, 3 * filt.n_taps))
    apply_filter(head, filt)  # numba compiles (cached)
    legacy.apply_multirate(flat[:3 * filt.n_taps], plan, 2, None, "single")
    rational = CorrectionFilter("rational", {"order": 1}, fs_hz, (1, 140), rational=RATIONAL)
    apply_filter(head, rational, causal=True)
    sos = rational.sos()
    as_float32 = flat.astype(np.float32)
    sensel_major = np.ascontiguousarray(as_float32.T)
    rec32 = rec.astype(np.float32)
    apply_filter(rec32.isel(frame=slice(0, 3 * filt.n_taps)), filt, dtype="float32")

    def fft_time_axis():
        fft.irfft(fft.rfft(as_float32, axis=0, workers=-1), n=n, axis=0, workers=-1)

    def fft_sensel_major():
        fft.irfft(fft.rfft(sensel_major, axis=-1, workers=-1), n=n, axis=-1, workers=-1)

    def fresh_copy(x=data):  # what any float64 -> new float64 output costs (faults + copy)
        out = np.empty_like(x)
        out[...] = x

    one_chunk, chunks = rec.chunk({"frame": 65536}), rec.chunk({"frame": 8192})
    chunks32 = rec32.chunk({"frame": 8192})
    held = chunks.persist()  # a dask array already in memory: its chunks are not re-cut
    baseline = "float32 rfft + irfft of the (time, sensels) array along time [baseline]"
    runs = {
        baseline: fft_time_axis,
        "float32 rfft + irfft of a sensel-major copy (contiguous lines)": fft_sensel_major,
        "fresh float64 output + copy (memory floor)": fresh_copy,
        "apply_filter (multirate)": lambda: apply_filter(rec, filt),
        "fresh float32 output + copy of a float32 recording (its memory floor)":
            lambda: fresh_copy(as_float32),
        "apply_filter, float32 recording, dtype='float32' (float32 in and out)":
            lambda: apply_filter(rec32, filt, dtype="float32"),
        "multirate before issue 16 (_legacy_multirate.py)":
            lambda: legacy.apply_multirate(flat, plan, 2, None, "single"),
        "apply_filter on dask, 65536-frame chunks, .compute()":
            lambda: apply_filter(one_chunk, filt).compute(),
        "before issue 16 on dask, 65536-frame chunks":
            lambda: legacy.legacy_apply_dask(one_chunk.data, filt).compute(),
        "apply_filter on dask, 8192-frame chunks, .compute()":
            lambda: apply_filter(chunks, filt).compute(),
        "apply_filter on dask, 8192-frame chunks, float32 in and out, .compute()":
            lambda: apply_filter(chunks32, filt, dtype="float32").compute(),
        "apply_filter on dask, 8192-frame chunks, .persist() (no final concatenation)":
            lambda: apply_filter(chunks, filt).persist(),
        "apply_filter on dask, 8192-frame chunks held in memory (persisted), .compute()":
            lambda: apply_filter(held, filt).compute(),
        "before issue 16 on dask, 8192-frame chunks":
            lambda: legacy.legacy_apply_dask(chunks.data, filt).compute(),
        "rational inverse, offline (centred FIR with phase, multirate)":
            lambda: apply_filter(rec, rational),
        "rational inverse, causal (apply_filter(causal=True))":
            lambda: apply_filter(rec, rational, causal=True),
        "scipy.signal.sosfilt of the same sections on the same array":
            lambda: signal.sosfilt(sos, flat, axis=0),
    }
    usage = {}
    times = _interleaved(runs, repeat, usage)
    _report(times, samples, baseline, usage)
    new, old = times["apply_filter (multirate)"], times[
        "multirate before issue 16 (_legacy_multirate.py)"]
    narrow = times["apply_filter, float32 recording, dtype='float32' (float32 in and out)"]
    lazy32 = times["apply_filter on dask, 8192-frame chunks, float32 in and out, .compute()"]
    print(f"run by run (same round): new / baseline speed {np.round(times[baseline] / new, 2)}, "
          f"float32 in and out / baseline {np.round(times[baseline] / narrow, 2)}, "
          f"in-memory / dask (8192), float32 in and out {np.round(narrow / lazy32, 2)}, "
          f"new / before {np.round(old / new, 2)}, in-memory / dask (65536) "
          f"{np.round(new / times['apply_filter on dask, 65536-frame chunks, .compute()'], 2)}, "
          f"in-memory / dask (8192) "
          f"{np.round(new / times['apply_filter on dask, 8192-frame chunks, .compute()'], 2)}")
    causal = times["scipy.signal.sosfilt of the same sections on the same array"] / times[
        "rational inverse, causal (apply_filter(causal=True))"]
    print(f"causal apply_filter speed / bare sosfilt, run by run: {np.round(causal, 2)}")
    out = apply_filter(rec, filt).values.reshape(n, -1)
    span = np.ptp(flat - flat[0], axis=0).max()
    checks = {
        "before issue 16": legacy.apply_multirate(flat, plan, 2, None, "single"),
        "dask, 8192-frame chunks": apply_filter(chunks, filt).values.reshape(n, -1),
        "double precision": apply_filter(rec, filt, precision="double").values.reshape(n, -1),
        "method='direct'": apply_filter(rec, filt, method="direct").values.reshape(n, -1),
    }
    checks["float32 in and out"] = apply_filter(rec32, filt, dtype="float32").values.reshape(
        n, -1)
    print("max |apply_filter - x| / the largest sensel's dynamic range: " + ", ".join(
        f"{name} {np.abs(out - other).max() / span:.1e}" for name, other in checks.items()))
    x = flat[:, :subset].T.copy()
    grid = np.linspace(0, fs_hz / 2, 4097)
    sqrt_fir = signal.firwin2(filt.n_taps, grid, np.sqrt(filt.gain(grid)), fs=fs_hz)
    t_fir = run_times(lambda: [signal.filtfilt(sqrt_fir, [1.0], row) for row in x], 1).min()
    b, a = signal.butter(4, 140.0, fs=fs_hz)
    t_iir = run_times(lambda: [signal.filtfilt(b, a, row) for row in x], repeat).min()
    scale = samples / x.size
    best = new.min()
    print(f"filtfilt per channel, timed on {subset} channels and scaled x{scale:.0f}: "
          f"same-length FIR (sqrt gain) {t_fir * scale:.1f} s ({t_fir * scale / best:.0f}x "
          f"apply_filter), 4th-order IIR {t_iir * scale:.2f} s ({t_iir * scale / best:.1f}x)")


def scaling(frames, chunk_list, repeat):
    """The filter's rows of the scaling table: each size in its own interleaved rounds.

    Per size: the float32 whole-record ``rfft`` + ``irfft`` baseline, ``apply_filter`` in
    memory (and on a float32 copy with ``dtype="float32"``), and on dask (threaded
    scheduler) in each of ``chunk_list``'s chunk sizes with ``.compute()`` (dask
    concatenates the chunks into a new array) and, for the first size shorter than the
    record, ``.persist()`` (the chunks stay apart) and ``.compute()`` of chunks already in
    memory (``rec.chunk()`` of a NumPy array otherwise cuts and copies every chunk inside
    the timed call: 0.66 s more system time at 131 072 frames). Best of
    ``repeat`` rounds; the ratios are of best times, and run by run (same round) in
    brackets.
    """
    from scipy import fft

    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000.0, band_hz=(1, 140))
    print(f"== scaling: 1936 sensels, FIR {filt.n_taps} taps; dask chunks {chunk_list} frames; "
          f"{repeat} interleaved rounds per size (best) ==")
    for n in frames:
        rec = _recording(n / 4000.0)
        apply_filter(rec.isel(frame=slice(0, 3 * filt.n_taps)), filt)  # numba (cached)
        as_float32 = rec.values.reshape(n, -1).astype(np.float32)
        rec32 = rec.astype(np.float32)

        def fft_time_axis(x=as_float32, n=n):
            fft.irfft(fft.rfft(x, axis=0, workers=-1), n=n, axis=0, workers=-1)

        runs = {"rfft + irfft": fft_time_axis, "in memory": lambda rec=rec: apply_filter(rec, filt),
                "in memory, float32 in and out":
                    lambda rec=rec32: apply_filter(rec, filt, dtype="float32")}
        shorter = [size for size in chunk_list if size < n]
        for size in shorter:
            chunked = rec.chunk({"frame": size})
            runs[f"dask {size}, .compute()"] = (
                lambda c=chunked: apply_filter(c, filt).compute())
            if size == shorter[0]:
                runs[f"dask {size}, .persist()"] = (
                    lambda c=chunked: apply_filter(c, filt).persist())
                held = chunked.persist()
                runs[f"dask {size} held in memory (persisted), .compute()"] = (
                    lambda c=held: apply_filter(c, filt).compute())
        usage = {}
        times = _interleaved(runs, repeat, usage)
        base, memory = times["rfft + irfft"], times["in memory"]
        print(f"{n} frames ({rec.size / 1e6:.0f} M samples, {rec.nbytes / 1e9:.2f} GB float64; "
              f"load {_load()}):")
        for name, t in times.items():
            print(f"  {name}: best {t.min():.3f} s = {rec.size / t.min() / 1e6:.0f} M samples/s; "
                  f"{base.min() / t.min():.2f}x the baseline {np.round(base / t, 2)}; "
                  f"{memory.min() / t.min():.2f}x in memory {np.round(memory / t, 2)}")
            print(f"      {_usage_line(usage[name])}")
        del rec, rec32, as_float32, runs


def cluster(seconds, repeat, chunk_frames, malloc_trim=True, dtype="float64"):
    import shutil
    import tempfile
    from pathlib import Path

    folder = Path(tempfile.mkdtemp(prefix="bench_dynamic_"))
    try:
        _cluster(seconds, repeat, chunk_frames, folder, malloc_trim, dtype)
    finally:
        shutil.rmtree(folder)


def _load():
    """The 1-, 5- and 15-minute load averages (``uptime``), or "n/a" where there are none."""
    try:
        return " ".join(f"{v:.2f}" for v in os.getloadavg())
    except OSError:
        return "n/a"


def _rusage():
    """CPU seconds (user + system) and minor page faults of this process so far."""
    import resource

    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime, usage.ru_minflt


def _cpu_timed(client, runs):
    """Wrap each run so that it also records the CPU seconds and page faults it cost.

    Summed over the cluster's worker processes (``client.run``) and this process: wall
    time on 2 shared cores moves with the other sessions' load, CPU time much less; a
    run's wall time is at least its CPU seconds over the 2 cores.
    """
    usage = {name: [] for name in runs}

    def total():
        return np.sum([*client.run(_rusage).values(), _rusage()], axis=0)

    def wrap(name, fn):
        def run():
            before = total()
            fn()
            usage[name].append(total() - before)
        return run

    return {name: wrap(name, fn) for name, fn in runs.items()}, usage


def _cluster(seconds, repeat, chunk_frames, folder, malloc_trim=True, dtype="float64"):
    import warnings

    import dask
    from dask.distributed import Client, LocalCluster, wait

    from tactilecal.io import write_netcdf

    rec = _recording(seconds).astype(dtype)
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=4000.0, band_hz=(1, 140))
    filt_kw = {"dtype": dtype}  # the result's type: the recording's
    nc, zarr_in, zarr_out = folder / "rec.nc", folder / "rec.zarr", folder / "out.zarr"
    write_netcdf(rec, nc)
    rec.to_dataset(name="x").to_zarr(zarr_in, mode="w", consolidated=False, encoding={
        "x": {"compressors": None, "chunks": (chunk_frames, 44, 44)}})
    memory = apply_filter(rec, filt, **filt_kw).values
    environ = dict(dask.config.get("distributed.nanny.pre-spawn-environ"))
    if not malloc_trim:  # distributed's default returns freed memory to the system at once
        environ.pop("MALLOC_TRIM_THRESHOLD_", None)
    print(f"== dask.distributed: LocalCluster, 2 worker processes x 1 thread; {rec.size / 1e6:.1f} "
          f"M {dtype} samples (in and out) read by the workers in {chunk_frames}-frame chunks "
          f"from {folder} "
          f"(uncompressed, removed after); {repeat} interleaved rounds; worker environment "
          f"{environ} ==")

    def opened(source):
        if source == "netcdf":
            return xr.open_dataarray(nc, chunks={"frame": chunk_frames})
        return xr.open_zarr(zarr_in, consolidated=False, chunks={"frame": chunk_frames})["x"]

    def kept(client, source, filtered=True):
        lazy = opened(source)
        data = (apply_filter(lazy, filt, **filt_kw) if filtered else lazy).data
        wait(client.persist(data))
        lazy.close()

    def written(source, filtered=True):
        lazy = opened(source)
        out = (apply_filter(lazy, filt, **filt_kw) if filtered else lazy).to_dataset(name="x")
        out["time"] = out["time"].load()
        for variable in out.variables.values():
            variable.encoding = {}  # the source's chunking and compression
        out.to_zarr(zarr_out, mode="w", consolidated=False,
                    encoding={"x": {"compressors": None}})
        lazy.close()

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with dask.config.set({"distributed.nanny.pre-spawn-environ": environ}), LocalCluster(
                n_workers=2, threads_per_worker=1, processes=True,
                dashboard_address=":0") as cl, Client(cl) as client:
            kept(client, "netcdf")  # workers import tactilecal and load the numba kernels
            runs = {
                "apply_filter in memory (this process) [baseline]":
                    lambda: apply_filter(rec, filt, **filt_kw),
                "cluster: read NetCDF, filter, keep on the workers":
                    lambda: kept(client, "netcdf"),
                "cluster: read Zarr, filter, keep on the workers":
                    lambda: kept(client, "zarr"),
                "cluster: read NetCDF, keep on the workers (no filter)":
                    lambda: kept(client, "netcdf", filtered=False),
                "cluster: read Zarr, filter, write Zarr": lambda: written("zarr"),
                "cluster: read Zarr, write Zarr (no filter)":
                    lambda: written("zarr", filtered=False),
            }
            runs, usage = _cpu_timed(client, runs)
            # os.sync: the Zarr writes leave up to the record's size of dirty pages, whose
            # writeback otherwise lands in the next run's time (the in-memory filter right
            # after "write Zarr" took 2-3x its time without a cluster at 131 072 frames)
            times = _interleaved(runs, repeat, settle=os.sync)
            written("netcdf")
    _report(times, rec.size, "apply_filter in memory (this process) [baseline]")
    print("CPU seconds (user + system, the workers' and this process's; least of the timed "
          "runs) and minor page faults of that run:")
    memory_cpu = min(u[0] for u in usage["apply_filter in memory (this process) [baseline]"][1:])
    for name, rows in usage.items():
        cpu, faults = min((tuple(u) for u in rows[1:]), default=(np.nan, np.nan))
        print(f"  {name}: {cpu:.2f} s CPU ({memory_cpu / cpu:.2f}x in memory's), "
              f"{faults:.0f} page faults")
    with xr.open_zarr(zarr_out, consolidated=False) as written_back:
        back = written_back["x"].values
    span = np.ptp(memory - memory[:1], axis=0).max()
    large = [w for w in caught if "large graph" in str(w.message).lower()]
    print(f"NetCDF -> cluster -> Zarr against in memory: max |difference| "
          f"{np.abs(back - memory).max() / span:.1e} of the largest sensel's dynamic range; "
          f"'large graph' warnings: {len(large)}; other warnings: "
          f"{sorted({f'{w.category.__name__}: {str(w.message)[:80]}' for w in caught})}")


def _page_faults():
    try:
        with open("/proc/vmstat") as f:
            return dict(line.split() for line in f).get("pgfault")
    except OSError:  # not Linux
        return None


def stages(seconds, repeat):
    """Seconds of each multirate stage and page faults, run by run (same record as above)."""
    from tactilecal.dynamic._multirate import apply_multirate, plan_multirate

    fs_hz = 4000.0
    x64 = _recording(seconds, fs_hz).values.reshape(int(seconds * fs_hz), -1)
    n = x64.shape[0]
    filt = CorrectionFilter.from_model(("log10", {"A": 0.11}), fs_hz=fs_hz, band_hz=(1, 140))
    plan = plan_multirate(filt)
    print(f"== multirate stages, 1936 sensels x {n} frames, P = {plan.factor} ==")
    for x2d in (x64, x64.astype(np.float32)):
        name = f"{x2d.dtype} in and out"
        apply_multirate(x2d[:3 * filt.n_taps], plan, 2, None, "single", dtype=x2d.dtype)  # numba
        for run in range(repeat):
            timings, before = {}, _page_faults()
            apply_multirate(x2d, plan, 2, None, "single", timings=timings, dtype=x2d.dtype)
            after = _page_faults()
            faults = "" if before is None else f", {int(after) - int(before)} page faults"
            print(f"{name}, run {run + 1}: " + ", ".join(f"{k} {v:.3f} s" for k, v in
                                                          timings.items()) + faults)


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
    parser.add_argument("--cluster", action="store_true",
                        help="also filter on a 2-worker dask.distributed LocalCluster")
    parser.add_argument("--no-malloc-trim", action="store_true",
                        help="--cluster without distributed's MALLOC_TRIM_THRESHOLD_=65536 "
                             "in the workers' environment")
    parser.add_argument("--chunk-frames", type=int, default=8192,
                        help="frames per chunk read by the cluster's workers")
    parser.add_argument("--dtype", default="float64", choices=["float64", "float32"],
                        help="--cluster: the recording's type on disk and the result's")
    parser.add_argument("--frames", type=int, nargs="+",
                        help="scaling table: the filter at these record lengths (frames), "
                             "against the baseline and in memory, each size on its own, "
                             "instead of the --seconds throughput (unless "
                             "--skip-throughput); --cluster at each of them")
    parser.add_argument("--chunks", type=int, nargs="+", default=[8192],
                        help="dask chunk sizes (frames) of --frames")
    args = parser.parse_args()
    if not args.skip_accuracy:
        accuracy(args.seeds)
    if not args.skip_throughput and not args.frames:
        throughput(args.seconds, args.subset, args.repeat)
    if args.stages:
        stages(args.seconds, args.repeat)
    if args.frames and not args.skip_throughput:
        scaling(args.frames, args.chunks, args.repeat)
    if args.cluster:
        for n in args.frames or [int(args.seconds * 4000)]:
            size = args.chunk_frames
            while size >= n:  # at least two chunks
                size //= 2
            cluster(n / 4000.0, args.repeat, size, malloc_trim=not args.no_malloc_trim,
                    dtype=args.dtype)


if __name__ == "__main__":
    main()
