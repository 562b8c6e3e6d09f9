"""Wall-clock timing shared by the benchmark scripts (run them as ``python benchmarks/x.py``)."""

import time

import numpy as np


def run_times(func, repeat):
    """Call ``func()`` ``repeat`` times; return the wall-clock seconds of each call."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        times.append(time.perf_counter() - start)
    return np.array(times)
