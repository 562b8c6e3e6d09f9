"""Import times in a fresh interpreter: ``import tactilecal`` stays light (xarray, numba,
dask and matplotlib are imported where used), and opening a saved calibration.

``timeraw_*`` functions return code that asv runs and times in a fresh interpreter each
time. The ``track_*`` ratios are medians of whole processes, interleaved with their
baselines in the same run.
"""

from benchmarks._common import child_wall


def timeraw_import_tactilecal():
    return "import tactilecal"


def timeraw_import_tactilecal_calibration():
    return "import tactilecal.calibration"


def timeraw_import_tactilecal_analysis():
    return "import tactilecal.analysis"


def track_import_tactilecal_over_python():
    """Wall time of ``python -c "import tactilecal"`` / ``python -c pass`` (medians of 7)."""
    return child_wall("import tactilecal", 7) / child_wall("pass", 7)


track_import_tactilecal_over_python.unit = "ratio"


def track_import_analysis_over_xarray():
    """``import tactilecal.analysis`` (registers ``recording.tactile``) / ``import xarray``:
    what the accessor costs on top of xarray (medians of 7 processes)."""
    return child_wall("import tactilecal.analysis", 7) / child_wall("import xarray", 7)


track_import_analysis_over_xarray.unit = "ratio"


class LoadCalibration:
    """``tactilecal.load`` of a Zvyagin calibration (its intermediate results rebuilt)."""

    def setup_cache(self):
        import os
        from pathlib import Path

        from tactilecal import calibrate
        from tactilecal.calibration import points_from_frames
        from tactilecal.simulate import deadweight_session, make_sensor

        session = deadweight_session(make_sensor("5051", seed=0), n_patches=45, seed=1)
        points = points_from_frames(session.raw.values, session.load_N,
                                    sensel_area_mm2=session.sensor.sensel_area_mm2)
        path = Path(os.getcwd()) / "zvyagin.json"
        calibrate(points, method="zvyagin").to_json(path, overwrite=True)
        return str(path)

    def setup(self, path):
        import tactilecal

        tactilecal.load(path)  # the imports and numba's cached kernels are not the load

    def time_load(self, path):
        import tactilecal

        tactilecal.load(path)


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])
