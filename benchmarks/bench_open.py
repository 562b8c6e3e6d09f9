"""Benchmark: what sniffing costs, open_recording against the format's own reader.

For each real export in ``../shared/realdata`` (and a NetCDF copy of the first), the reader
of its format (``read_tekscan``, ``read_netcdf``) and :func:`tactilecal.io.open_recording`
are timed in turn, interleaved, ``--repeat`` times; the printed ratio is
``open_recording / reader`` on the median (1.00 = sniffing costs nothing measurable).

Usage: ``python benchmarks/bench_open.py [--repeat 15]``
"""

import argparse
import tempfile
from pathlib import Path

import numpy as np
from _timing import run_times

from tactilecal.io import open_recording, read_netcdf, read_tekscan, write_netcdf

REALDATA = Path(__file__).resolve().parents[1].parent / "shared" / "realdata"


def interleaved(funcs, repeat):
    """Median wall-clock seconds of each function, calls interleaved ``repeat`` times."""
    times = np.array([[run_times(f, 1)[0] for f in funcs] for _ in range(repeat)])
    return np.median(times, axis=0)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=15)
    args = parser.parse_args()
    exports = sorted(p for p in REALDATA.glob("*") if p.suffix.lower() in (".asf", ".csv"))
    if not exports:
        raise SystemExit(f"no exports in {REALDATA}")
    with tempfile.TemporaryDirectory() as tmp:
        nc = Path(tmp) / "copy.nc"
        write_netcdf(read_tekscan(exports[0]), nc)
        cases = [(p.name, read_tekscan, p) for p in exports] + [(nc.name, read_netcdf, nc)]
        print(f"{'file':<28} {'reader s':>9} {'open s':>9} {'open/reader':>12}")
        for name, reader, path in cases:
            reader(path), open_recording(path)  # warm: numba kernels, file cache
            funcs = [lambda r=reader, p=path: r(p), lambda p=path: open_recording(p)]
            t_reader, t_open = interleaved(funcs, args.repeat)
            print(f"{name:<28} {t_reader:9.4f} {t_open:9.4f} {t_open / t_reader:12.2f}")


if __name__ == "__main__":
    main()
