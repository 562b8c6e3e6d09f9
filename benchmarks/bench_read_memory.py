"""Benchmark: peak memory of read_tekscan, as a ratio to the array it returns.

Each measurement runs in a fresh interpreter and reads its own peak, the VmHWM line of
``/proc/self/status``, before and after the read: the ratio is
``(peak after - peak after imports) / array bytes``. (The child's ``ru_maxrss`` is not used:
Linux keeps it across exec, so a child started by a large parent reports the parent's peak;
before issue 16 this script subtracted such an inherited figure and printed 0.48x for a read
that peaked at 2.6x.) ``pandas.read_csv`` on a plain CSV of the same numbers is measured the
same way as a baseline. Issue 11's goal: <= 3x the array + 100 MB for any file, whatever its
header says; issue 16's: <= 1.5x.

Usage: ``python benchmarks/bench_read_memory.py [--frames 20000]``
"""

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
from bench_io import simulated

from tactilecal.io import write_tekscan

CHILD = """
import sys
import numpy as np, pandas as pd
import tactilecal.io

def hwm():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM"))

base = hwm()
if sys.argv[1] == "reader":
    nbytes = tactilecal.io.read_tekscan(sys.argv[2]).nbytes
else:
    nbytes = pd.read_csv(sys.argv[2], header=None, engine="c", dtype=np.float64,
                         na_values=["B"]).to_numpy().nbytes
print(nbytes, hwm() - base)
"""


def peak(what, path):
    out = subprocess.run([sys.executable, "-c", CHILD, what, str(path)], capture_output=True,
                         text=True, check=True).stdout.split()
    return int(out[0]), int(out[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path, plain = Path(folder) / "movie.csv", Path(folder) / "plain.csv"
        data = simulated(args.frames)
        write_tekscan(data, path)
        pd.DataFrame(data.values.reshape(-1, data.sizes["col"])).to_csv(
            plain, header=False, index=False, na_rep="B", float_format="%.0f")
        del data
        nbytes, rss = peak("reader", path)
        base_bytes, base_rss = peak("pandas", plain)
        size = path.stat().st_size
    assert base_bytes == nbytes and np.isfinite(rss)
    print(f"44 x 44 x {args.frames} frames: file {size / 1e6:.0f} MB, array "
          f"{nbytes / 1e6:.0f} MB, peak above imports: read_tekscan {rss / 1e6:.0f} MB = "
          f"{rss / nbytes:.2f}x the array, pandas.read_csv {base_rss / 1e6:.0f} MB = "
          f"{base_rss / nbytes:.2f}x (goal <= 1.5x)")


if __name__ == "__main__":
    main()
