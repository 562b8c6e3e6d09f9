"""Zvyagin's (2022) method at 45, 150 and 1000 patches: time, memory, and against a power fit.

Data: one simulated dead-weight session per size (a 5051, A = 0.0035 N, b = 1.16,
:func:`tactilecal.simulate.deadweight_session`, seed 2), fitted through
``calibrate(points, method="zvyagin", mode=...)``. The baseline in the same run is the
static power fit of the same points (``method="power"``). The goals of issue 16: 0.1 s at
150 patches and 1 s at 1000 (robust mode, the default) on a quiet machine.
"""

import warnings

from benchmarks._common import ratio

SIZES = [45, 150, 1000]
MODES = ["robust", "faithful"]


def _points(n_patches):
    from tactilecal.calibration import points_from_frames
    from tactilecal.simulate import deadweight_session, make_sensor

    s = deadweight_session(make_sensor("5051", seed=1), n_patches=n_patches, seed=2)
    return points_from_frames(s.raw, s.load_N, sensel_area_mm2=s.sensor.sensel_area_mm2)


def _fit(points, **options):
    from tactilecal import calibrate

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # E(b0) at a bound etc.: not what is timed here
        return calibrate(points, **options)


class Zvyagin:
    params = [SIZES, MODES]
    param_names = ["patches", "mode"]
    timeout = 600

    def setup_cache(self):
        return {n: _points(n) for n in SIZES}

    def setup(self, sessions, patches, mode):
        _fit(sessions[patches], method="zvyagin", mode=mode)  # numba loads its kernels

    def time_calibrate(self, sessions, patches, mode):
        _fit(sessions[patches], method="zvyagin", mode=mode)

    def peakmem_calibrate(self, sessions, patches, mode):
        _fit(sessions[patches], method="zvyagin", mode=mode)

    def track_time_over_power_fit(self, sessions, patches, mode):
        """CPU time of Zvyagin's fit / the power fit of the same points."""
        points = sessions[patches]
        return ratio(lambda: _fit(points, method="zvyagin", mode=mode),
                     lambda: _fit(points, method="power"))

    track_time_over_power_fit.unit = "ratio"

    def track_traced_peak_over_histograms(self, sessions, patches, mode):
        """``tracemalloc``'s peak over one fit (NumPy's allocations; the numba kernels'
        small work arrays are not traced) / the bytes of the patches' histograms."""
        import tracemalloc

        points = sessions[patches]
        tracemalloc.start()
        try:
            _fit(points, method="zvyagin", mode=mode)
            peak = tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()
        return peak / (len(points) * 256 * 8)

    track_traced_peak_over_histograms.unit = "ratio"


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])
