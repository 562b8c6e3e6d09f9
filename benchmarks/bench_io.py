"""Benchmark: read_tekscan throughput against pandas.read_csv (C engine) in the same run.

Writes a simulated 44 x 44 export (random raw readings 0..255, I-Scan layout with frame
lines carrying time and Raw Sum, a B border like a real sensor's shape) and a plain CSV
holding the same numbers (one sensel row per line, no header, no frame lines). Times are
the best of ``--repeat`` interleaved runs; the printed ratio is
``baseline time / read_tekscan time`` (1.0 = as fast as pandas; issue 16's goal >= 1.0).
The writer is timed once against ``DataFrame.to_csv`` writing the plain CSV.

Usage: ``python benchmarks/bench_io.py [--frames 10000] [--repeat 3]``
"""

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import xarray as xr
from _timing import run_times

from tactilecal.io import read_tekscan, write_tekscan


def simulated(n_frames, size=44, seed=0):
    rng = np.random.default_rng(seed)
    values = rng.integers(0, 256, size=(n_frames, size, size)).astype(np.float64)
    values[:, 0, :2] = np.nan  # a few B cells, as in real exports
    return xr.DataArray(
        values, dims=("frame", "row", "col"),
        coords={"frame": np.arange(1, n_frames + 1),
                "time": ("frame", np.arange(n_frames) * 0.005)},
        attrs={"sensor_type": "5051", "units": "raw", "row_spacing_mm": 1.27,
               "col_spacing_mm": 1.27, "sensel_area_mm2": 1.6129, "seconds_per_frame": 0.005,
               "noise_threshold": 3})


def best_of(func, repeat):
    return run_times(func, repeat).min()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    data = simulated(args.frames)
    with tempfile.TemporaryDirectory() as folder:
        export, plain = Path(folder) / "sim.csv", Path(folder) / "plain.csv"
        start = time.perf_counter()
        write_tekscan(data, export)
        t_write = time.perf_counter() - start
        values = data.values.reshape(-1, data.sizes["col"])
        start = time.perf_counter()
        pd.DataFrame(values).to_csv(plain, header=False, index=False, na_rep="B",
                                    float_format="%.0f")
        t_to_csv = time.perf_counter() - start
        check = read_tekscan(export)
        assert np.array_equal(check.values, data.values, equal_nan=True)
        n_values = data.size

        def baseline():
            return pd.read_csv(plain, header=None, engine="c", dtype=np.float64,
                               na_values=["B"]).to_numpy()

        assert np.array_equal(baseline(), values, equal_nan=True)
        t_reader, t_base = [], []
        for _ in range(args.repeat):  # interleaved so machine load hits both alike
            t_reader.append(best_of(lambda: read_tekscan(export), 1))
            t_base.append(best_of(baseline, 1))
        t_reader, t_base = min(t_reader), min(t_base)
        print(f"{args.frames} frames x 44 x 44 = {n_values:,} values; "
              f"export {export.stat().st_size / 1e6:.1f} MB, plain CSV "
              f"{plain.stat().st_size / 1e6:.1f} MB")
        print(f"read_tekscan     {n_values / t_reader / 1e6:8.2f} M values/s")
        print(f"pandas.read_csv  {n_values / t_base / 1e6:8.2f} M values/s (C engine, baseline)")
        print(f"write_tekscan    {n_values / t_write / 1e6:8.2f} M values/s (one run)")
        print(f"DataFrame.to_csv {n_values / t_to_csv / 1e6:8.2f} M values/s (one run, "
              f"same numbers, no frame lines): writer ratio {t_to_csv / t_write:.2f}")
        print(f"ratio read_tekscan / pandas.read_csv throughput: {t_base / t_reader:.2f} "
              "(goal >= 1.0)")


if __name__ == "__main__":
    main()
