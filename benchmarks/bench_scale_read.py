"""Benchmark: read_tekscan and convert at three sizes, as ratios to pandas.read_csv (issue 16).

For each size a simulated 44 x 44 I-Scan export is written (random raw readings, a B border,
frame lines with time and Raw Sum) with a plain CSV of the same numbers (one sensel row per
line, no frame lines). Every measurement runs in a fresh interpreter; its peak memory is the
VmHWM of /proc/self/status above the same interpreter's after imports (``ru_maxrss`` is not
used: Linux keeps it across exec, so a child inherits the parent's peak). The reader's time
and peak include numba loading its cached kernels on the first call (about 1 s and 100 MB
here, once per process), which weighs on the smallest size only. Reader and baseline
alternate ``--repeat`` times; the best time and the lowest peak are kept.

* ``read_tekscan`` (eager) against ``pandas.read_csv(plain, engine="c")``: throughput ratio
  (pandas time / reader time; goal >= 1.0) and peak memory / the float64 array (goal <= 1.5;
  pandas' own ratio printed beside it); also each of its two readers forced at every size
  (the NumPy reader of plain files, the numba reader). Sizes ``--sizes`` (frames).
* ``convert`` to Zarr in blocks of ``--chunks`` frames against a streamed
  ``pandas.read_csv(plain, chunksize=...)`` over the same numbers (parse only, nothing
  written): time ratio, and peak memory / one block of float64 (bounded, whatever the file).
  At every size and at ``--large`` frames (too large for memory: only streamed; 1 440 000
  frames is about 10 GB of export).

Usage: ``python benchmarks/bench_scale_read.py [--sizes 10000,100000] [--large 300000]
[--chunks 1000] [--repeat 3] [--folder DIR] [--data DIR] [--eager-only]``
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

SIZE = 44
CHILD = r"""
import json, sys, time
import dask.array, numpy as np, pandas as pd, xarray, zarr  # imports are not the work
import tactilecal.io as tio

def hwm():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) * 1024 for l in f if l.startswith("VmHWM"))

what, path, chunks, size = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
base = hwm()
start = time.perf_counter()
if what == "reader":
    nbytes = tio.read_tekscan(path).nbytes
elif what in ("reader-numba", "reader-numpy"):  # one reader whatever the size
    import tactilecal.io._tekscan_read as module
    module.PLAIN_MAX_BYTES = 0 if what == "reader-numba" else None
    nbytes = tio.read_tekscan(path).nbytes
elif what == "pandas":
    nbytes = pd.read_csv(path, header=None, engine="c", dtype=np.float64,
                         na_values=["B"]).to_numpy().nbytes
elif what == "convert":
    nbytes = tio.convert(path, sys.argv[5], chunks=chunks).nbytes
elif what == "pandas-stream":
    nbytes = 0
    with pd.read_csv(path, header=None, engine="c", dtype=np.float64, na_values=["B"],
                     chunksize=chunks * size) as reader:
        for part in reader:
            nbytes += part.to_numpy().nbytes
seconds = time.perf_counter() - start
print(json.dumps({"seconds": seconds, "peak": hwm() - base, "nbytes": nbytes}))
"""


def write_files(folder, n_frames, seed=0, distinct=500):
    """Write the export and the plain CSV of ``n_frames`` frames; return their paths."""
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


def stored_files(folder, n_frames):
    """The files of :func:`write_files` in ``folder``, written first if absent."""
    export, plain = folder / f"movie{n_frames}.csv", folder / f"plain{n_frames}.csv"
    done = folder / f"movie{n_frames}.done"
    if not done.exists():
        folder.mkdir(parents=True, exist_ok=True)
        write_files(folder, n_frames)
        done.touch()
    return export, plain


def measure(what, path, chunks, target=""):
    """Run one measurement in a fresh interpreter; return its JSON dict."""
    out = subprocess.run([sys.executable, "-c", CHILD, what, str(path), str(chunks), str(SIZE),
                          str(target)], capture_output=True, text=True)
    if out.returncode:
        raise RuntimeError(out.stderr.strip().splitlines()[-1])
    return json.loads(out.stdout)


def best(runs):
    return {"seconds": min(r["seconds"] for r in runs), "peak": min(r["peak"] for r in runs),
            "nbytes": runs[0]["nbytes"]}


def interleaved(pairs, repeat):
    """Alternate the measurements of ``pairs`` (name -> args) ``repeat`` times."""
    runs = {name: [] for name in pairs}
    for _ in range(repeat):
        for name, args in pairs.items():
            runs[name].append(measure(*args))
    return {name: best(r) for name, r in runs.items()}


def eager_row(n_frames, export, plain, repeat):
    r = interleaved({"reader": ("reader", export, 0), "numpy": ("reader-numpy", export, 0),
                     "numba": ("reader-numba", export, 0), "pandas": ("pandas", plain, 0)},
                    repeat)
    pandas, array = r["pandas"], r["reader"]["nbytes"]
    size = export.stat().st_size
    cells = [f"{n_frames:>9} {size / 1e6:>9.0f} {array / 1e6:>9.0f}"]
    for name in ("reader", "numpy", "numba"):
        cells.append(f"{pandas['seconds'] / r[name]['seconds']:>8.2f} "
                     f"{r[name]['peak'] / array:>8.2f}")
    cells.append(f"{pandas['peak'] / pandas['nbytes']:>8.2f} {r['reader']['seconds']:>7.2f} "
                 f"{pandas['seconds']:>7.2f}")
    print(" ".join(cells))


def convert_row(n_frames, export, plain, chunks, repeat, folder):
    target = folder / "out.zarr"
    r = interleaved({"convert": ("convert", export, chunks, target),
                     "stream": ("pandas-stream", plain, chunks)}, repeat)
    shutil.rmtree(target, ignore_errors=True)
    conv, stream = r["convert"], r["stream"]
    block = chunks * SIZE * SIZE * 8
    print(f"{n_frames:>9} {export.stat().st_size / 1e6:>9.0f} {conv['nbytes'] / 1e6:>9.0f} "
          f"{chunks:>7} {stream['seconds'] / conv['seconds']:>8.2f} {conv['peak'] / 1e6:>8.0f} "
          f"{conv['peak'] / block:>8.1f} {stream['peak'] / block:>8.1f}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="10000,100000",
                        help="frames of the sizes read eagerly too (comma-separated)")
    parser.add_argument("--large", type=int, default=300_000,
                        help="frames of the size only streamed (0: none)")
    parser.add_argument("--chunks", type=int, default=1000, help="frames per convert block")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--folder", default=None, help="where the files go (default: TMPDIR)")
    parser.add_argument("--data", default=None,
                        help="keep the simulated files in this folder and reuse them "
                             "(1 000 000 frames: 7 GB export + 7 GB CSV)")
    parser.add_argument("--eager-only", action="store_true",
                        help="no convert rows (e.g. to measure a reader without convert)")
    args = parser.parse_args()
    sizes = [int(s) for s in args.sizes.split(",") if s]
    with tempfile.TemporaryDirectory(dir=args.folder) as name:
        folder = Path(name)
        files = {}
        large = [args.large] if args.large and not args.eager_only else []
        for n in sizes + large:
            start = time.perf_counter()
            files[n] = stored_files(Path(args.data), n) if args.data else write_files(folder, n)
            print(f"{n} frames ({files[n][0].stat().st_size / 1e9:.2f} GB) ready in "
                  f"{time.perf_counter() - start:.0f} s", file=sys.stderr)
        print(f"44 x 44 sensels, best of {args.repeat} interleaved runs, fresh interpreter each")
        print("\nread_tekscan (eager) vs pandas.read_csv on the same numbers")
        print("x pd = pandas time / reader time; pk/ar = peak / float64 array; "
              "numpy, numba: that reader forced at every size")
        print(f"{'frames':>9} {'file MB':>9} {'array MB':>9} {'x pd':>8} {'pk/ar':>8} "
              f"{'numpy xpd':>8} {'pk/ar':>8} {'numba xpd':>8} {'pk/ar':>8} {'pd/arr':>8} "
              f"{'s':>7} {'pd s':>7}")
        for n in sizes:
            eager_row(n, *files[n], args.repeat)
        if args.eager_only:
            return
        print(f"\nconvert to Zarr vs streamed pandas.read_csv(chunksize) on the same numbers; "
              f"one block = {args.chunks} frames = {args.chunks * SIZE * SIZE * 8 / 1e6:.1f} MB")
        print(f"{'frames':>9} {'file MB':>9} {'array MB':>9} {'chunks':>7} {'x pandas':>8} "
              f"{'peak MB':>8} {'pk/block':>8} {'pd/block':>8}")
        for n in sizes + large:
            convert_row(n, *files[n], args.chunks, args.repeat if n in sizes else 1, folder)


if __name__ == "__main__":
    main()
