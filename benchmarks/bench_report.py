"""Time ``write_report`` on a 10k-frame 44 x 44 recording (issue 15: under 10 s).

A simulated ramp-and-hold recording (``simulate.ramp_hold``, 100 Hz) repeated to 10,000
frames, reported calibrated (a power calibration of a simulated dead-weight session) and raw.
The baseline in the same run is ``rec.tactile.frame_summary()`` on the same recording (the
numbers the report draws), so the ratio says what the figures and the page cost on top.

    python benchmarks/bench_report.py [--frames 10000] [--repeat 2]
"""

import argparse
import tempfile
from pathlib import Path

import numpy as np
import xarray as xr
from _timing import run_times

from tactilecal.calibration import calibrate, points_from_frames
from tactilecal.report import write_report
from tactilecal.simulate import deadweight_session, make_sensor, ramp_hold


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    sensor = make_sensor("5051", seed=1)
    raw = ramp_hold(sensor, frame_rate_hz=100.0, loadcell_rate_hz=500.0, seed=5).raw
    copies = -(-args.frames // raw.sizes["frame"])
    rec = xr.concat([raw] * copies, "frame")[:args.frames]
    rec = rec.assign_coords(frame=np.arange(1, args.frames + 1),
                            time=("frame", np.arange(args.frames) / 100.0))
    session = deadweight_session(sensor, n_patches=40, seed=2)
    cal = calibrate(points_from_frames(session.raw, session.load_N), method="power")
    out = Path(tempfile.mkdtemp()) / "report.html"
    base = run_times(lambda: cal.apply(rec).tactile.frame_summary().compute(), args.repeat).min()
    for label, kw in (("calibrated", {"calibration": cal}), ("raw", {})):
        took = run_times(lambda kw=kw: write_report([rec], out, **kw), args.repeat).min()
        print(f"{args.frames} frames {label}: write_report {took:.2f} s, "
              f"{took / base:.1f}x frame_summary ({base:.2f} s), page "
              f"{out.stat().st_size / 1e6:.1f} MB")


if __name__ == "__main__":
    main()
