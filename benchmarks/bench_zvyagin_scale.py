"""Zvyagin (2022) at 45, 150 and 1000 patches: time and peak memory against same-run baselines.

Run: ``python benchmarks/bench_zvyagin_scale.py [--sizes 45 150 1000] [--repeat 3] [--cold]``

For each size, one simulated dead-weight session (5051, A = 0.0035 N, b = 1.16) and, in
interleaved rounds (best and median of ``--repeat``):

- ``zvyagin_fit`` in robust mode (the default) and in faithful mode;
- the same with the former I* search and pair stage (``tests/zvyagin_reference.py``, the
  copy the equality tests use; it is not part of the package);
- one static power fit on the same points (``calibrate(points, method="power")``).

Peak memory is ``tracemalloc``'s peak over one call (NumPy's allocations; the numba kernels'
small work arrays, ~0.5 MB at 1000 patches, are not traced), as a ratio to the former
implementation's. ``--cold`` also times one fit in a fresh interpreter (numba's import and
the loading of the cached kernels included) against the former implementation there.
Times are noisy on shared cores: read the ratios.
"""

import argparse
import importlib.util
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
from tactilecal.simulate import deadweight_session, make_sensor
from tactilecal.zvyagin import _calibrate, zvyagin_fit

REFERENCE = Path(__file__).resolve().parents[1] / "tests" / "zvyagin_reference.py"


def _reference():
    spec = importlib.util.spec_from_file_location("zvyagin_reference", REFERENCE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


REF = _reference()


def former_fit(h, f, **options):
    """``zvyagin_fit`` with the former search and pair stage swapped in."""
    saved = _calibrate.search_separation, _calibrate.solve_pairs
    _calibrate.search_separation, _calibrate.solve_pairs = REF.search_separation, REF.solve_pairs
    try:
        return zvyagin_fit(h, f, **options)
    finally:
        _calibrate.search_separation, _calibrate.solve_pairs = saved


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
        "former robust": lambda: former_fit(h, f),
        "former faithful": lambda: former_fit(h, f, mode="faithful"),
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
    peaks = {name: peak_bytes(work[name]) for name in ("robust", "faithful", "former robust",
                                                       "former faithful")}
    n_pairs = n_patches * (n_patches - 1) // 2
    return times, peaks, n_pairs, h.nbytes


COLD = """
import sys, time
import numpy as np
data = np.load(sys.argv[1])
start = time.perf_counter()
{setup}
from tactilecal.zvyagin import zvyagin_fit
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
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "session.npz"
        np.savez(path, h=h, f=f)
        new = COLD.format(setup="", fit="zvyagin_fit")
        old = COLD.format(setup=f"sys.path.insert(0, {str(REFERENCE.parent)!r})\n"
                                "import zvyagin_reference as ref\n"
                                "from tactilecal.zvyagin import _calibrate\n"
                                "_calibrate.search_separation = ref.search_separation\n"
                                "_calibrate.solve_pairs = ref.solve_pairs",
                          fit="zvyagin_fit")
        for name, code in (("new", new), ("former", old)):
            res = subprocess.run([sys.executable, "-c", code, str(path)], check=True,
                                 capture_output=True, text=True)
            out[name] = [float(x) for x in res.stdout.split()]
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[45, 150, 1000])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--cold", action="store_true")
    args = parser.parse_args()
    warnings.simplefilter("ignore")  # E(b0) at a bound etc.: not what is timed here
    print(f"{'patches':>7} {'pairs':>7} {'workload':<16} {'best s':>8} {'median s':>9} "
          f"{'/ power fit':>11} {'former / new':>12} {'peak MB':>8} {'peak / former':>13}")
    for n in args.sizes:
        times, peaks, n_pairs, _ = measure(n, args.repeat)
        best = {k: min(v) for k, v in times.items()}
        for name in ("robust", "faithful", "former robust", "former faithful", "power fit"):
            former = f"former {name}"
            speedup = f"{best[former] / best[name]:.1f}x" if former in best else ""
            peak = f"{peaks[name] / 1e6:.1f}" if name in peaks else ""
            peak_ratio = (f"{peaks[name] / peaks[former]:.2f}" if former in peaks else "")
            print(f"{n:>7} {n_pairs:>7} {name:<16} {best[name]:>8.4f} "
                  f"{np.median(times[name]):>9.4f} {best[name] / best['power fit']:>11.2f} "
                  f"{speedup:>12} {peak:>8} {peak_ratio:>13}")
    if args.cold:
        for n in args.sizes:
            c = cold(n)
            print(f"fresh interpreter, {n} patches: new {c['new'][0]:.2f} s first call "
                  f"(imports, numba's cached kernels) then {c['new'][1]:.3f} s; former "
                  f"{c['former'][0]:.2f} s then {c['former'][1]:.3f} s")


if __name__ == "__main__":
    main()
