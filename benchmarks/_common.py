"""Shared helpers of the benchmark suite: same-run ratios, fresh interpreters, test data.

A ratio is always two measurements of the same run, interleaved round by round so that the
load of a shared machine falls on both alike, each side the best of its rounds. In one
process the clock is this process's CPU time (user + system: it moves much less with other
jobs than wall time); a measurement in a fresh interpreter counts that child's CPU time.
"""

import json
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

#: Where the real Tekscan exports are looked for (never copied into the repository).
REALDATA = Path(os.environ.get("TACTILECAL_REALDATA",
                               Path(__file__).resolve().parents[2] / "shared" / "realdata"))

#: Sensels per side of the simulated exports (a 5051's 44 x 44).
SIZE = 44


def cpu_seconds():
    """User + system CPU seconds of this process (all its threads) so far."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def interleaved(funcs, rounds=3, clock=cpu_seconds, warm=True):
    """Run every function of ``funcs`` (name -> callable) once per round.

    Returns name -> array of the seconds of each round. ``warm``: one untimed call of each
    first (numba loads its cached kernels, thread pools start, the heap faults in).
    """
    if warm:
        for func in funcs.values():
            func()
    times = {name: [] for name in funcs}
    for _ in range(rounds):
        for name, func in funcs.items():
            start = clock()
            func()
            times[name].append(clock() - start)
    return {name: np.array(t) for name, t in times.items()}


def ratio(numerator, denominator, rounds=3, clock=cpu_seconds):
    """Best time of ``numerator`` over the best time of ``denominator``, interleaved."""
    times = interleaved({"n": numerator, "d": denominator}, rounds, clock)
    return float(times["n"].min() / times["d"].min())


def child(code, *args):
    """Run ``code`` in a fresh interpreter; return (its last stdout line as JSON, CPU s).

    The CPU seconds are the child's user + system time (``RUSAGE_CHILDREN``).
    """
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    out = subprocess.run([sys.executable, "-c", code, *map(str, args)], capture_output=True,
                         text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode:
        raise RuntimeError(f"child failed: {out.stderr.strip()[-2000:]}")
    lines = out.stdout.strip().splitlines()
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return (json.loads(lines[-1]) if lines else None), cpu


def compile_tactilecal():
    """Write tactilecal's bytecode, as ``pip install`` does, before timing fresh processes.

    Where ``PYTHONDONTWRITEBYTECODE`` is set (or the checkout is read-only), an editable
    install would otherwise compile every module it imports in every timed process, a cost
    no installed package pays (its dependencies' bytecode was written when they were
    installed).
    """
    import compileall

    import tactilecal

    compileall.compile_dir(Path(tactilecal.__file__).parent, quiet=1)


def child_wall(code, rounds=5):
    """Median wall-clock seconds of ``python -c code`` in fresh interpreters."""
    compile_tactilecal()
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        subprocess.run([sys.executable, "-c", code], check=True)
        times.append(time.perf_counter() - start)
    return float(np.median(times))


#: Code a fresh interpreter runs to report its peak resident memory (VmHWM; Linux).
PEAK = """
def peak_bytes():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM"))
"""


def write_export(folder, n_frames, seed=0, distinct=500):
    """Write a raw 44 x 44 I-Scan export and a plain CSV of the same numbers.

    The export has ``Frame N, time,, date,,,Raw Sum=,,S`` frame lines and ``B`` cells like a
    real sensor's; the plain CSV holds the same rows of values without header or frame lines
    (what ``pandas.read_csv`` parses as the baseline). ``distinct`` random frames are
    repeated to make up ``n_frames`` (writing stays fast at any size). Returns both paths.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    frames = rng.integers(0, 256, size=(distinct, SIZE, SIZE)).astype(float)
    frames[:, 0, :2] = np.nan
    texts = ["\n".join(",".join("B" if np.isnan(v) else str(int(v)) for v in row)
                       for row in frame) + "\n" for frame in frames]
    sums = np.nansum(frames, axis=(1, 2)).astype(int)
    export, plain = folder / f"movie{n_frames}.csv", folder / f"plain{n_frames}.csv"
    header = (f"DATA_TYPE MOVIE\nSENSOR_TYPE 5051\nROWS {SIZE}\nCOLS {SIZE}\n"
              "ROW_SPACING 0.127 centimeters\nCOL_SPACING 0.127 centimeters\n"
              "SENSEL_AREA 0.016129 cm2\nNOISE_THRESHOLD 3\nSECONDS_PER_FRAME 0.005\n"
              f"START_FRAME 1\nEND_FRAME {n_frames}\nUNITS raw\nASCII_DATA @@\n\n")
    with open(export, "w") as out, open(plain, "w") as flat:
        out.write(header)
        for lo in range(0, n_frames, 1000):
            ks = range(lo, min(lo + 1000, n_frames))
            out.write("".join(f"Frame {k + 1}, {k * 0.005:.3f},, 1/1/2020 1:00:00.00PM,,,"
                              f"Raw Sum=,,{sums[k % distinct]}\n{texts[k % distinct]}\n"
                              for k in ks))
            flat.write("".join(texts[k % distinct] for k in ks))
        out.write("@@\n")
    return export, plain


def run(module):
    """Run every benchmark of ``module`` once and print its result (``__main__`` of a suite).

    The same functions asv runs (``track_*`` print their value, ``time_*`` their wall time,
    ``peakmem_*`` are skipped: asv measures those), for every combination of ``params``.
    """
    import inspect
    import itertools
    import tempfile

    def cases(obj):
        params = getattr(obj, "params", [])
        if params and not isinstance(params[0], list | tuple):
            params = [params]
        return list(itertools.product(*params)) if params else [()]

    owners = [(None, module)] + [(obj, obj) for _, obj in inspect.getmembers(module,
                                                                            inspect.isclass)
                                 if obj.__module__ == module.__name__]
    with tempfile.TemporaryDirectory() as folder:
        old = os.getcwd()
        os.chdir(folder)
        try:
            for cls, owner in owners:
                names = [n for n, _ in inspect.getmembers(owner)
                         if n.startswith(("track_", "time_"))]
                if not names:
                    continue
                instance = cls() if cls is not None else None
                cache = ()
                if instance is not None and hasattr(instance, "setup_cache"):
                    cache = (instance.setup_cache(),)
                for name in names:
                    func = getattr(instance if instance is not None else module, name)
                    for case in cases(func if cls is None else owner):
                        if instance is not None and hasattr(instance, "setup"):
                            instance.setup(*cache, *case)
                        start = time.perf_counter()
                        value = func(*cache, *case)
                        took = time.perf_counter() - start
                        label = f"{owner.__name__}.{name}{list(case) if case else ''}"
                        if instance is not None and hasattr(instance, "teardown"):
                            instance.teardown(*cache, *case)
                        if name.startswith("track_"):
                            unit = getattr(func, "unit", "")
                            print(f"{label}: {value:.4g} {unit}", flush=True)
                        else:
                            print(f"{label}: {took:.3f} s", flush=True)
        finally:
            os.chdir(old)
