"""Benchmark: peak memory of read_tekscan, as a ratio to the array it returns.

Each measurement runs in a fresh interpreter (``ru_maxrss`` of the child), and the same
interpreter's baseline (imports only, ``--baseline``) is subtracted, so the ratio is
``(peak RSS - baseline RSS) / array bytes``. Issue 11's goal: <= 3x the array + 100 MB for
any file, whatever its header says; issue 16's: <= 1.5x.

Usage: ``python benchmarks/bench_read_memory.py [--frames 20000]``
"""

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

from bench_io import simulated

from tactilecal.io import write_tekscan

CHILD = """
import resource, sys
import tactilecal.io
if sys.argv[1] != "--baseline":
    data = tactilecal.io.read_tekscan(sys.argv[1])
    print(data.nbytes)
else:
    print(0)
print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024)
"""


def peak(arg):
    out = subprocess.run([sys.executable, "-c", CHILD, arg], capture_output=True, text=True,
                         check=True).stdout.split()
    return int(out[0]), int(out[1])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=20000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "movie.csv"
        write_tekscan(simulated(args.frames), path)
        _, base = peak("--baseline")
        nbytes, rss = peak(str(path))
        size = path.stat().st_size
    print(f"44 x 44 x {args.frames} frames: file {size / 1e6:.0f} MB, array "
          f"{nbytes / 1e6:.0f} MB, peak RSS above imports {(rss - base) / 1e6:.0f} MB = "
          f"{(rss - base) / nbytes:.2f}x the array")


if __name__ == "__main__":
    main()
