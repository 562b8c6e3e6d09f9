"""The reader from a cold start: whole fresh processes, import cost included.

What a user waits for: ``python -c "import tactilecal as tc; tc.read_tekscan('f.csv')"``
against ``python -c "import xarray, pandas as pd; pd.read_csv('plain.csv')"`` on the same
numbers (a 44 x 44 export, and the same text as a plain CSV of 44 columns), and
``tactilecal info`` on a small export against ``python -c "import xarray"``. The exports hold
raw readings 0..255 (``raw``), or the same readings in kPa at FrasP01L's 5.9379 kPa a count,
with two decimals (``kpa``) or as ``write_tekscan`` writes them, the shortest text that reads
back (``written``, up to 17 digits).

Each round runs both commands, the first one in turn (one process's exit can slow the next
one's first use of fresh memory), ``--repeat`` rounds (5). A ratio is ``baseline time /
tactilecal time`` (above 1: tactilecal is faster) within each round, and the figure is the
median of the rounds' ratios, with a 95 % bootstrap interval of that median: a drift of the
machine's speed during the run moves both processes of a round alike. Times are the medians
of the rounds. Peak memory is the child's own peak resident size (``VmHWM`` of
``/proc/self/status``, which exec resets; ``ru_maxrss`` keeps the parent's), compared with
the array's size.

    python -m benchmarks.bench_cold_read [--frames 6000 40000] [--kinds raw kpa written]
                                         [--repeat 5]

tactilecal's bytecode is written first (:func:`benchmarks._common.compile_tactilecal`), as
an installation does.

The ``track_*`` functions return the ratios (for an asv suite); each makes its files once in
a temporary folder.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from benchmarks._common import compile_tactilecal

ROWS = COLS = 44
REALDATA = Path(os.environ.get("TACTILECAL_REALDATA",
                               Path(__file__).resolve().parents[2] / "shared" / "realdata"))
_MEASURE = ("; import sys; print(next(int(line.split()[1]) for line in open('/proc/self/status') "
            "if line.startswith('VmHWM')), file=sys.stderr)")


KINDS = ("raw", "kpa", "written")
KPA_PER_COUNT = 5.9379  # FrasP01L's one-point calibration (../shared/realdata/README.md)


def write_files(folder, n_frames, seed=0, kind="raw"):
    """Write the export and the plain CSV of the same ``n_frames`` x 44 x 44 values."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    suffix = "" if kind == "raw" else f"_{kind}"
    export = folder / f"export_{n_frames}{suffix}.csv"
    plain = folder / f"plain_{n_frames}{suffix}.csv"
    if export.exists() and plain.exists():
        return export, plain
    rng = np.random.default_rng(seed)
    units = "raw" if kind == "raw" else "KPa"
    header = (f"DATA_TYPE MOVIE\nSENSOR_TYPE 5101\nROWS {ROWS}\nCOLS {COLS}\n"
              "ROW_SPACING 0.254 centimeters\nCOL_SPACING 0.254 centimeters\n"
              "SENSEL_AREA 0.064516 cm2\nNOISE_THRESHOLD 3\nSECONDS_PER_FRAME 0.01\n"
              f"START_FRAME 1\nEND_FRAME {n_frames}\nUNITS {units}\nASCII_DATA @@\n\n")
    text = {"raw": str, "kpa": lambda v: f"{v * KPA_PER_COUNT:.2f}",
            "written": lambda v: repr(v * KPA_PER_COUNT)}[kind]
    with open(export, "w") as ex, open(plain, "w") as pl:
        ex.write(header)
        pl.write(",".join(f"c{j}" for j in range(COLS)) + "\n")
        for first in range(0, n_frames, 500):
            block = rng.integers(0, 256, size=(min(500, n_frames - first), ROWS, COLS))
            for k, frame in enumerate(block):
                rows = "\n".join(",".join(map(text, row)) for row in frame.tolist()) + "\n"
                raw_sum = f",,,Raw Sum=,,{int(frame.sum())}" if kind == "raw" else ""
                ex.write(f"Frame {first + k + 1}, {(first + k) * 0.01:.2f}{raw_sum}\n{rows}\n")
                pl.write(rows)
        ex.write("@@\n")
    return export, plain


def _run(argv):
    """Wall and CPU seconds and peak RSS (bytes) of one fresh process."""
    before = os.times()
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True, check=True)
    wall = time.perf_counter() - start
    after = os.times()
    cpu = (after.children_user - before.children_user
           + after.children_system - before.children_system)
    rss = int(done.stderr.strip().splitlines()[-1]) * 1024 if _MEASURE in argv[-1] else 0
    return wall, cpu, rss


def compare(commands, repeat):
    """Run ``commands`` (name -> argv) ``repeat`` rounds, each first in turn.

    Returns each command's runs: ``(wall s, CPU s, peak bytes)`` per round.
    """
    compile_tactilecal()
    names = list(commands)
    runs = {name: [] for name in names}
    for round_ in range(repeat):
        for name in names[round_ % len(names):] + names[:round_ % len(names)]:
            runs[name].append(_run(commands[name]))
    return runs


def medians(runs):
    """``(wall, CPU, peak)`` medians of each command's runs."""
    return {name: tuple(float(np.median(column)) for column in zip(*values, strict=True))
            for name, values in runs.items()}


def paired_ratio(runs, baseline, ours, column=0):
    """Median over rounds of ``baseline / ours`` and its 95 % bootstrap interval."""
    ratios = np.array([b[column] / o[column] for b, o in zip(runs[baseline], runs[ours],
                                                              strict=True)])
    rng = np.random.default_rng(0)
    resampled = np.median(rng.choice(ratios, size=(2000, ratios.size)), axis=1)
    low, high = np.quantile(resampled, [0.025, 0.975])
    return float(np.median(ratios)), float(low), float(high)


def read_commands(export, plain):
    python = sys.executable
    return {
        "tactilecal read_tekscan": [python, "-c", "import tactilecal as tc; "
                                    f"tc.read_tekscan({str(export)!r})" + _MEASURE],
        "pandas read_csv": [python, "-c", "import xarray, pandas as pd; "
                            f"pd.read_csv({str(plain)!r})" + _MEASURE],
    }


def info_commands(export):
    python = sys.executable
    return {"tactilecal info": [python, "-m", "tactilecal", "info", str(export)],
            "import xarray": [python, "-c", "import xarray"]}


def small_export():
    """The 205-frame F-Scan export of ../shared/realdata (or a generated 205-frame one)."""
    real = REALDATA / "footPress_FrasP01L.asf"
    if real.is_file():
        return real
    return write_files(tempfile.mkdtemp(prefix="tactilecal-bench-"), 205)[0]


def read_ratio(n_frames, repeat=5, folder=None, kind="raw"):
    """``(pandas / tactilecal wall ratio, peak RSS / array bytes, runs)`` at ``n_frames``.

    The ratio is :func:`paired_ratio`'s median.
    """
    folder = folder or tempfile.mkdtemp(prefix="tactilecal-bench-")
    export, plain = write_files(folder, n_frames, kind=kind)
    runs = compare(read_commands(export, plain), repeat)
    ratio = paired_ratio(runs, "pandas read_csv", "tactilecal read_tekscan")[0]
    array = n_frames * ROWS * COLS * 8
    return ratio, medians(runs)["tactilecal read_tekscan"][2] / array, runs


def track_read_6000_frames_vs_pandas():
    return read_ratio(6000)[0]


def track_read_40000_frames_vs_pandas():
    return read_ratio(40000)[0]


def track_read_6000_kpa_frames_vs_pandas():
    return read_ratio(6000, kind="kpa")[0]


def track_read_6000_written_frames_vs_pandas():
    return read_ratio(6000, kind="written")[0]


def track_info_vs_import_xarray():
    runs = compare(info_commands(small_export()), 5)
    return 1 / paired_ratio(runs, "import xarray", "tactilecal info")[0]


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, nargs="+", default=[6000, 40000])
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=["raw"],
                        help="the exports' values (default: raw)")
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--folder", help="keep the generated files here (default: temporary)")
    args = parser.parse_args(argv)
    folder = args.folder or tempfile.mkdtemp(prefix="tactilecal-bench-")
    print(f"{args.repeat} rounds of fresh processes, each first in turn; ratio = baseline / "
          "tactilecal (wall): median of the rounds' ratios [95 % interval]")
    print(f"{'kind':>7} {'frames':>7} {'MB':>6} {'tactilecal s':>13} {'pandas s':>9} "
          f"{'ratio':>6} {'interval':>12} {'cpu ratio':>10} {'peak MB':>8} {'array MB':>9} "
          f"{'peak limit':>10}")
    for kind in args.kinds:
        for n in args.frames:
            _, _, runs = read_ratio(n, args.repeat, folder, kind)
            tc, pd_ = (medians(runs)[name] for name in ("tactilecal read_tekscan",
                                                         "pandas read_csv"))
            ratio, low, high = paired_ratio(runs, "pandas read_csv", "tactilecal read_tekscan")
            cpu = paired_ratio(runs, "pandas read_csv", "tactilecal read_tekscan", column=1)[0]
            size = write_files(folder, n, kind=kind)[0].stat().st_size / 1e6
            array = n * ROWS * COLS * 8 / 1e6
            print(f"{kind:>7} {n:>7} {size:>6.0f} {tc[0]:>13.3f} {pd_[0]:>9.3f} {ratio:>6.2f} "
                  f"{f'{low:.2f}-{high:.2f}':>12} {cpu:>10.2f} {tc[2] / 1e6:>8.0f} "
                  f"{array:>9.0f} {1.5 * array + 150:>10.0f}")
    runs = compare(info_commands(small_export()), args.repeat)
    info, xarray = (medians(runs)[name][0] for name in ("tactilecal info", "import xarray"))
    ratio, low, high = paired_ratio(runs, "import xarray", "tactilecal info")
    print(f"tactilecal info on {small_export().name}: {info:.3f} s, python -c 'import xarray' "
          f"{xarray:.3f} s: {1 / ratio:.2f}x [{1 / high:.2f}-{1 / low:.2f}] (goal <= 1.3x)")


if __name__ == "__main__":
    main()
