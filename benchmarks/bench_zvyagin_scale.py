"""Zvyagin (2022) at 45, 150 and 1000 patches: time and peak memory against same-run baselines.

Run: ``python benchmarks/bench_zvyagin_scale.py [--sizes 45 150 1000] [--repeat 3] [--cold]``

For each size, one simulated dead-weight session (5051, A = 0.0035 N, b = 1.16) and, in
interleaved rounds (best and median of ``--repeat``):

- ``zvyagin_fit`` in robust mode (the default) and in faithful mode;
- one static power fit on the same points (``calibrate(points, method="power")``), the
  baseline.

Peak memory is ``tracemalloc``'s peak over one call (NumPy's allocations; the numba kernels'
small work arrays, ~0.5 MB at 1000 patches, are not traced), as a ratio to the size of the
patches' histograms. ``--cold`` also times one fit in a fresh interpreter (numba's import and
the loading of the cached kernels included). Times are noisy on shared cores: read the
ratios. (Until 0.2 the script also timed the search and pair stage that issue 16 replaced,
from a copy in ``tests/zvyagin_reference.py``; that file is now a plain solver of the paper's
equations for the equality tests, and the speed-ups measured then are in
``benchmarks/README.md``.)
"""

import argparse
import subprocess
import sys
import tempfile
import time
import tracemalloc
import warnings
from pathlib import Path

import numpy as np

from tactilecal.calibration import calibrate, points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration.methods.zvyagin import zvyagin_fit
from tactilecal.simulate import deadweight_session, make_sensor


def session(n_patches):
    sensor = make_sensor("5051", seed=1)
    s = deadweight_session(sensor, n_patches=n_patches, seed=2)
    points = points_from_frames(s.raw, s.load_N)
    h, f = points_to_arrays(points)
    return points, h, f


def workloads(points, h, f):
    return {
        "robust": lambda: zvyagin_fit(h, f),
        "faithful": lambda: zvyagin_fit(h, f, mode="faithful"),
        "power fit": lambda: calibrate(points, method="power"),
    }


def peak_bytes(func):
    tracemalloc.start()
    try:
        func()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def measure(n_patches, repeat):
    points, h, f = session(n_patches)
    work = workloads(points, h, f)
    for func in work.values():  # warm-up: numba's kernels loaded or compiled, caches filled
        func()
    times = {name: [] for name in work}
    for _ in range(repeat):
        for name, func in work.items():
            start = time.perf_counter()
            func()
            times[name].append(time.perf_counter() - start)
    peaks = {name: peak_bytes(work[name]) for name in ("robust", "faithful")}
    n_pairs = n_patches * (n_patches - 1) // 2
    return times, peaks, n_pairs, h.nbytes


COLD = """
import sys, time
import numpy as np
data = np.load(sys.argv[1])
start = time.perf_counter()
{setup}
from tactilecal.calibration.methods.zvyagin import zvyagin_fit
fit = {fit}
fit(data["h"], data["f"])
first = time.perf_counter() - start
start = time.perf_counter()
fit(data["h"], data["f"])
print(first, time.perf_counter() - start)
"""


def cold(n_patches):
    """One fit in a fresh interpreter: (first call incl. imports, second call) in seconds."""
    _, h, f = session(n_patches)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "session.npz"
        np.savez(path, h=h, f=f)
        code = COLD.format(setup="", fit="zvyagin_fit")
        res = subprocess.run([sys.executable, "-c", code, str(path)], check=True,
                             capture_output=True, text=True)
    return [float(x) for x in res.stdout.split()]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[45, 150, 1000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cold", action="store_true")
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # E(b0) at a bound etc.: not what is timed here
    print(f"{'patches':>7} {'pairs':>7} {'workload':<16} {'best s':>8} {'median s':>9} "
          f"{'/ power fit':>11} {'peak MB':>8} {'peak / histograms':>17}")
    for n in args.sizes:
        times, peaks, n_pairs, h_bytes = measure(n, args.repeat)
        best = {k: min(v) for k, v in times.items()}
        for name in ("robust", "faithful", "power fit"):
            peak = f"{peaks[name] / 1e6:.1f}" if name in peaks else ""
            peak_ratio = f"{peaks[name] / h_bytes:.1f}" if name in peaks else ""
            print(f"{n:>7} {n_pairs:>7} {name:<16} {best[name]:>8.4f} "
                  f"{np.median(times[name]):>9.4f} {best[name] / best['power fit']:>11.2f} "
                  f"{peak:>8} {peak_ratio:>17}")
    if args.cold:
        for n in args.sizes:
            first, second = cold(n)
            print(f"fresh interpreter, {n} patches: {first:.2f} s first call (imports, "
                  f"numba's cached kernels) then {second:.3f} s")


if __name__ == "__main__":
    main()
