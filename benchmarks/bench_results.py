"""Cost of the result base (issue 14): import time and loading a Zvyagin calibration.

Also prints the length of each result's ``repr`` in this tree and in the baseline (the
issue's goal: every repr under 1,000 characters).

``tactilecal.calibration`` imports its Zvyagin method at module level, and loading a
Zvyagin calibration rebuilds its ``ZvyaginResult``
(``cal.method_result``) from ``details``. This script measures both against a baseline
source tree (default ``/work/main/src``, the version before), each in a fresh interpreter,
interleaved, and prints the median ratio (this tree / baseline).

Run: ``python benchmarks/bench_results.py [--baseline SRC] [--repeat N] [--patches N]``.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parents[1] / "src"

IMPORT = ("import time; t = time.perf_counter(); import tactilecal.calibration; "
          "print(time.perf_counter() - t)")
LOAD = ("import time, sys; from tactilecal.calibration import load_calibration; "
        "t = time.perf_counter(); CalibrationResult.from_json(sys.argv[1]); "
        "print(time.perf_counter() - t)")


REPRS = """
import numpy as np
from tactilecal.calibration import calibrate, equilibrate, points_from_frames, validate
from tactilecal.dynamic import CorrectionFilter
from tactilecal.simulate import deadweight_session, make_sensor
from tactilecal.calibration.methods.zvyagin._plots import as_zvyagin_result
s = deadweight_session(make_sensor("5051", seed=1), n_patches=150, seed=2)
pts = points_from_frames(s.raw, s.load_N)
z = calibrate(pts, method="zvyagin")
f_hz = np.linspace(1, 100, 200)
objs = [("CalibrationResult, zvyagin", z), ("ZvyaginResult", as_zvyagin_result(z)),
        ("CalibrationResult, lut", calibrate(pts, method="lut")),
        ("CorrectionFilter, 200-bin response",
         CorrectionFilter.from_response(f_hz, 1 + f_hz / 100, fs_hz=1000)),
        ("Equilibration, 44 x 44", equilibrate([np.full((1, 44, 44), 50.0)])),
        ("validate(), 75 points", validate(calibrate(pts[:75]), pts[75:]))]
for name, obj in objs:
    print(f"{name}|{len(repr(obj))}")
"""


def _reprs(src):
    env = {**os.environ, "PYTHONPATH": str(src)}
    out = subprocess.run([sys.executable, "-c", REPRS], env=env, check=True,
                         capture_output=True, text=True).stdout
    return dict(line.split("|") for line in out.strip().splitlines())


def _run(src, code, *args):
    env = {**os.environ, "PYTHONPATH": str(src)}
    out = subprocess.run([sys.executable, "-c", code, *args], env=env, check=True,
                         capture_output=True, text=True)
    return float(out.stdout.strip().splitlines()[-1])


def _zvyagin_json(folder, n_patches):
    from tactilecal.calibration import calibrate, points_from_frames
    from tactilecal.simulate import deadweight_session, make_sensor

    session = deadweight_session(make_sensor("5051", seed=1), n_patches=n_patches, seed=2)
    cal = calibrate(points_from_frames(session.raw, session.load_N), method="zvyagin")
    path = Path(folder) / "zvyagin.json"
    data = cal.to_dict()
    data.pop("format")  # the baseline reads untagged files only
    path.write_text(json.dumps(data))
    return path, len(data["details"]["pairs"]["b"])


def main(argv=None):
    """Measure and print the ratios."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", default="/work/main/src")
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument("--patches", type=int, default=150)
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as folder:
        path, n_pairs = _zvyagin_json(folder, args.patches)
        times = {(what, tree): [] for what in ("import", "load") for tree in ("new", "base")}
        for _ in range(args.repeat):
            for tree, src in (("new", HERE), ("base", args.baseline)):
                times["import", tree].append(_run(src, IMPORT))
                times["load", tree].append(_run(src, LOAD, str(path)))
    print(f"Zvyagin calibration of {args.patches} patches ({n_pairs} pairs stored), "
          f"{args.repeat} interleaved runs, fresh interpreter each; median seconds")
    for what, label in (("import", "import tactilecal.calibration"),
                        ("load", "CalibrationResult.from_json(zvyagin.json)")):
        new, base = np.median(times[what, "new"]), np.median(times[what, "base"])
        print(f"  {label:<34} this tree {new:.3f} s  baseline {base:.3f} s  "
              f"ratio {new / base:.2f}")
    new, base = _reprs(HERE), _reprs(args.baseline)
    print("len(repr(...)), 150-patch session: this tree / baseline")
    for name, length in new.items():
        print(f"  {name:<36} {length:>7} / {base[name]:>7}")


if __name__ == "__main__":
    main()
