"""Peak memory of every reader, valid and hostile inputs: <= 3x the final array + 100 MB?

Each read runs in a fresh interpreter that reports its own peak resident size (``VmHWM`` of
``/proc/self/status``) after its imports and after the read; the read's cost is the
difference. The bound of issue 31 is ``3 x (bytes of what the read returns) + 100 MB``; a read
that fails returns nothing, so its bound is 100 MB. Inputs (generated in a temporary folder):
Tekscan exports read eagerly and lazily, one of kPa with as many digits as ``write_tekscan``
writes, one huge row (of raw readings and of such kPa), a 16 MiB header, a line of 200 MB
without a line end; load-cell CSVs with 2 and with 40 columns; a NetCDF recording; a
calibration JSON of 60 MB.
:func:`track_worst_peak_over_bound` is the largest peak over its bound (asv; goal <= 1).

    python -m benchmarks.bench_read_peak [--frames 6000]
"""

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

CHILD = """
import sys
import numpy as np
import tactilecal, tactilecal.io, tactilecal.calibration

def hwm():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM"))

kind, path = sys.argv[1], sys.argv[2]
base = hwm()
try:
    if kind == "tekscan":
        out = tactilecal.io.read_tekscan(path).values
    elif kind == "tekscan-lazy":
        out = tactilecal.io.read_tekscan(path, chunks=1000).values
    elif kind == "timeseries":
        series = tactilecal.io.read_timeseries(path)
        out = np.stack([series.values, series.time.values])
    elif kind == "recording":
        out = tactilecal.io.open_recording(path).values
    else:
        out = tactilecal.load(path)
        out = np.zeros(0)
    nbytes, error = out.nbytes, ""
except (ValueError, TypeError) as exc:
    nbytes, error = 0, type(exc).__name__
print(nbytes, hwm() - base, error)
"""


def _export(path, n_frames, rows=44, cols=44, seed=0, kpa_per_count=None):
    rng = np.random.default_rng(seed)
    units, text = ("raw", str) if kpa_per_count is None else (
        "KPa", lambda count: repr(count * kpa_per_count))
    with open(path, "w") as out:
        out.write(f"ROWS {rows}\nCOLS {cols}\nUNITS {units}\nSECONDS_PER_FRAME 0.01\n"
                  f"START_FRAME 1\nEND_FRAME {n_frames}\nASCII_DATA @@\n")
        for first in range(0, n_frames, 500):
            block = rng.integers(0, 256, size=(min(500, n_frames - first), rows, cols))
            for k, frame in enumerate(block):
                body = "\n".join(",".join(map(text, r)) for r in frame.tolist())
                out.write(f"Frame {first + k + 1}\n{body}\n")
        out.write("@@\n")
    return path


def make_inputs(folder, n_frames):
    """Write every input; return ``[(name, kind, path)]``."""
    folder = Path(folder)
    cases = [("Tekscan export", "tekscan", _export(folder / "movie.csv", n_frames)),
             ("Tekscan export, lazy", "tekscan-lazy", folder / "movie.csv"),
             ("Tekscan export of kPa, 17 digits", "tekscan",
              _export(folder / "kpa.csv", n_frames, kpa_per_count=5.9379)),
             ("one row of 2,000,000 values", "tekscan",
              _export(folder / "row.csv", 1, rows=1, cols=2_000_000)),
             ("one row of 2,000,000 kPa values, 17 digits", "tekscan",
              _export(folder / "row_kpa.csv", 1, rows=1, cols=2_000_000, kpa_per_count=5.9379))]
    header = folder / "header.csv"
    header.write_text("ROWS 1\nCOLS 1\n" + "NOTE x\n" * (16 * 2**20 // 7)
                      + "ASCII_DATA @@\n1\n@@\n")
    cases.append(("header of 16 MiB (refused)", "tekscan", header))
    line = folder / "line.csv"
    with open(line, "wb") as out:
        out.write(b"ROWS 1\nCOLS 3\nASCII_DATA @@\nFrame 1\n")
        for _ in range(200):
            out.write(b"1," * (2**19))
    cases.append(("a 200 MB line without end (refused)", "tekscan", line))
    rng = np.random.default_rng(1)
    for n_cols, rows in ((2, 2_000_000), (40, 200_000)):
        path = folder / f"loadcell_{n_cols}.csv"
        values = rng.random((rows, n_cols))
        values[:, 0] = np.arange(rows) * 1e-3
        header_row = ",".join(["Time (s)", "Load (N)"] + [f"c{j}" for j in range(n_cols - 2)])
        np.savetxt(path, values, delimiter=",", header=header_row, comments="", fmt="%.10g")
        cases.append((f"load-cell CSV, {n_cols} columns x {rows} rows", "timeseries", path))
    from tactilecal.io import read_tekscan, write_netcdf

    write_netcdf(read_tekscan(folder / "movie.csv"), folder / "movie.nc")
    cases.append(("NetCDF recording", "recording", folder / "movie.nc"))
    eq = folder / "eq.json"
    gain = np.round(1 + 0.1 * rng.random((1100, 1100)), 6)
    eq.write_text(json.dumps({"format": "tactilecal-equilibration/1", "gain": gain.tolist(),
                              "levels": []}))
    cases.append((f"equilibration JSON of {eq.stat().st_size / 1e6:.0f} MB", "json", eq))
    return cases


def measure(kind, path):
    out = subprocess.run([sys.executable, "-c", CHILD, kind, str(path)], capture_output=True,
                         text=True, check=True).stdout.split()
    return int(out[0]), int(out[1]), out[2] if len(out) > 2 else ""


def peaks(n_frames):
    """Yield ``(input, bytes returned, peak bytes, bound bytes, error)`` for every input."""
    with tempfile.TemporaryDirectory(prefix="tactilecal-peak-") as folder:
        for name, kind, path in make_inputs(folder, n_frames):
            nbytes, peak, error = measure(kind, path)
            yield name, nbytes, peak, 3 * nbytes + 100e6, error


def track_worst_peak_over_bound():
    """The largest peak memory of a read over its bound, 3x its array + 100 MB (goal <= 1)."""
    return max(peak / bound for _, _, peak, bound, _ in peaks(6000))


track_worst_peak_over_bound.unit = "ratio"
track_worst_peak_over_bound.timeout = 600


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=6000)
    args = parser.parse_args(argv)
    print(f"{'input':<46} {'array MB':>9} {'peak MB':>8} {'bound MB':>9}  ok")
    for name, nbytes, peak, bound, error in peaks(args.frames):
        print(f"{name:<46} {nbytes / 1e6:>9.1f} {peak / 1e6:>8.1f} {bound / 1e6:>9.0f}  "
              f"{'yes' if peak <= bound else 'NO'} {error}")


if __name__ == "__main__":
    main()
