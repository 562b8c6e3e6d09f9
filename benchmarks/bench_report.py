"""The HTML report of a long recording: ``write_report`` on 10,000 frames of 44 x 44.

Data: a simulated ramp-and-hold recording (:func:`tactilecal.simulate.ramp_hold`, 100 Hz)
repeated to 10,000 frames, reported calibrated (a power calibration of a simulated
dead-weight session of the same sensor) and raw. The baseline in the same run is
``rec.tactile.frame_summary()`` of the same calibrated recording (the numbers the report
draws), so the ratio is what the figures and the page cost on top. Issue 15's goal: under
10 s.
"""

import numpy as np

from benchmarks._common import interleaved

FRAMES = 10_000


class Report:
    params = ["calibrated", "raw"]
    param_names = ["recording"]
    timeout = 600

    def setup(self, recording):
        import tempfile
        from pathlib import Path

        import xarray as xr

        import tactilecal.analysis  # noqa: F401  (registers recording.tactile)
        from tactilecal import calibrate
        from tactilecal.calibration import points_from_frames
        from tactilecal.simulate import deadweight_session, make_sensor, ramp_hold

        sensor = make_sensor("5051", seed=1)
        raw = ramp_hold(sensor, frame_rate_hz=100.0, loadcell_rate_hz=500.0, seed=5).raw
        copies = -(-FRAMES // raw.sizes["frame"])
        rec = xr.concat([raw] * copies, "frame")[:FRAMES]
        self.rec = rec.assign_coords(frame=np.arange(1, FRAMES + 1),
                                     time=("frame", np.arange(FRAMES) / 100.0))
        session = deadweight_session(sensor, n_patches=40, seed=2)
        self.cal = calibrate(points_from_frames(session.raw, session.load_N), method="power")
        self.options = {"calibration": self.cal} if recording == "calibrated" else {}
        self.out = Path(tempfile.mkdtemp()) / "report.html"

    def time_write_report(self, recording):
        from tactilecal.report import write_report

        write_report([self.rec], self.out, overwrite=True, **self.options)

    def track_report_over_frame_summary(self, recording):
        """CPU time of ``write_report`` / ``frame_summary()`` of the calibrated recording."""
        from tactilecal.report import write_report

        times = interleaved({
            "report": lambda: write_report([self.rec], self.out, overwrite=True, **self.options),
            "summary": lambda: self.cal.apply(self.rec).tactile.frame_summary().compute()},
            rounds=2, warm=False)
        return float(times["report"].min() / times["summary"].min())

    track_report_over_frame_summary.unit = "ratio"


class Figures:
    """The figures of a calibration and of a recording, as the report embeds them (2x PNG).

    Data: a power calibration of a simulated dead-weight session (its curve, points and
    error histogram) and the peak-pressure map of one of its patches. The baseline in the
    same run is matplotlib's ``savefig`` of the same figures at the same dpi, which draws a
    figure with a layout engine twice; the ratio is what :mod:`tactilecal._png` costs
    against it (below 1 is cheaper).
    """

    timeout = 300

    def setup(self):
        import tactilecal.analysis  # noqa: F401  (registers recording.tactile)
        from tactilecal import calibrate
        from tactilecal.calibration import points_from_frames
        from tactilecal.report._figures import new_axes
        from tactilecal.simulate import deadweight_session, make_sensor

        session = deadweight_session(make_sensor("5051", seed=1), n_patches=30, seed=3)
        cal = calibrate(points_from_frames(session.raw, session.load_N), method="power")
        patch = cal.apply(session.recording(0), units="kPa")
        self.makers = [lambda: cal.plot_curve(ax=new_axes()).figure,
                       lambda: cal.plot_points(ax=new_axes()).figure,
                       lambda: cal.plot_error_histogram(ax=new_axes()).figure,
                       lambda: patch.tactile.plot_pressure_map().figure]

    def _png(self):
        from tactilecal._png import png_bytes
        from tactilecal.report._figures import DRAW_DPI

        return [png_bytes(make(), DRAW_DPI) for make in self.makers]

    def _savefig(self):
        import io

        from tactilecal.report._figures import DRAW_DPI

        for make in self.makers:
            make().savefig(io.BytesIO(), format="png", dpi=DRAW_DPI)

    def time_png(self):
        self._png()

    def track_png_over_savefig(self):
        """CPU time of building and writing the figures: tactilecal._png / savefig."""
        times = interleaved({"png": self._png, "savefig": self._savefig}, rounds=3)
        return float(times["png"].min() / times["savefig"].min())

    track_png_over_savefig.unit = "ratio"


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])
