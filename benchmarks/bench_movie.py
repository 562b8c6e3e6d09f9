"""Movie calibration: ``frame_histograms`` and ``calibrate_movie`` against one pass over the
same array.

Data: a simulated 5051 (44 x 44 sensels) under a ramp-and-hold load (4 levels up to 889.6 N,
load cell at 500 Hz on its own clock, :func:`tactilecal.simulate.ramp_hold`), 100,000
frames, stored as float64, float32 or uint8 readings. The floor each time is divided by is
"one pass" over the same array in the same run: the fastest of ``np.sum``, ``np.sum`` of its
bytes as uint64 words and ``np.copyto`` into a ready buffer. The goal of issue 16:
``calibrate_movie`` under 0.5 s per 100,000 frames on a quiet machine.
"""

import numpy as np

from benchmarks._common import interleaved

FRAMES = 100_000
DTYPES = ["float64", "float32", "uint8"]


def _simulate(n_frames):
    """A ramp-and-hold movie of about ``n_frames`` frames (float64) and its load cell."""
    from tactilecal.simulate import make_sensor, ramp_hold

    probe = ramp_hold(make_sensor("5051", seed=0), frame_rate_hz=1.0, seed=1)
    seconds = float(probe.raw.time[-1]) + 1.0
    rh = ramp_hold(make_sensor("5051", seed=0), frame_rate_hz=n_frames / seconds,
                   loadcell_rate_hz=500.0, seed=1)
    return rh.raw, rh.loadcell


def _one_pass(values):
    """The fastest single pass over ``values``: the floor of anything that reads it."""
    words = values.reshape(-1).view(np.uint64)
    buffer = np.empty_like(values)
    times = interleaved({"sum": values.sum, "words": words.sum,
                         "copy": lambda: np.copyto(buffer, values)}, rounds=3)
    return min(t.min() for t in times.values())


class Movie:
    params = DTYPES
    param_names = ["dtype"]
    timeout = 900

    def setup_cache(self):
        raw, loadcell = _simulate(FRAMES)
        assert np.array_equal(raw.values, raw.values.astype(np.uint8))  # whole readings
        return raw.astype(np.uint8), loadcell  # a fifth of the bytes to pickle

    def setup(self, data, dtype):
        raw, self.loadcell = data
        self.rec = raw.astype(dtype)

    def time_frame_histograms(self, data, dtype):
        from tactilecal.calibration import frame_histograms

        frame_histograms(self.rec.values)

    def time_calibrate_movie(self, data, dtype):
        from tactilecal.calibration import calibrate_movie

        calibrate_movie(self.rec, self.loadcell)

    def peakmem_calibrate_movie(self, data, dtype):
        from tactilecal.calibration import calibrate_movie

        calibrate_movie(self.rec, self.loadcell)

    def track_frame_histograms_over_one_pass(self, data, dtype):
        """CPU time of ``frame_histograms`` / one pass over the same array."""
        from tactilecal.calibration import frame_histograms

        values = self.rec.values
        out = np.empty((len(values), 256), dtype=np.int64)
        best = interleaved({"hist": lambda: frame_histograms(values, out=out)})["hist"].min()
        return best / _one_pass(values)

    track_frame_histograms_over_one_pass.unit = "ratio"

    def track_calibrate_movie_over_one_pass(self, data, dtype):
        """CPU time of ``calibrate_movie`` (power law) / one pass over the same array."""
        from tactilecal.calibration import calibrate_movie

        best = interleaved({"movie": lambda: calibrate_movie(self.rec, self.loadcell)})
        return best["movie"].min() / _one_pass(self.rec.values)

    track_calibrate_movie_over_one_pass.unit = "ratio"

    def track_dask_over_memory(self, data, dtype):
        """CPU time of ``calibrate_movie`` on the recording as dask blocks of 16,384 frames
        / in memory (same parameters: checked)."""
        from tactilecal.calibration import calibrate_movie

        lazy = self.rec.chunk({"frame": 16_384})
        results = {}

        def run(name, rec):
            results[name] = calibrate_movie(rec, self.loadcell).params

        times = interleaved({"dask": lambda: run("dask", lazy),
                             "memory": lambda: run("memory", self.rec)})
        assert results["dask"] == results["memory"], results
        return float(times["dask"].min() / times["memory"].min())

    track_dask_over_memory.unit = "ratio"

    def track_per_frame_power_sum_over_calibrate_movie(self, data, dtype):
        """CPU time of the straightforward per-frame force, ``sum(raw ** b)`` of every frame
        at one exponent in NumPy, / the whole ``calibrate_movie`` (alignment and fit)."""
        from tactilecal.calibration import calibrate_movie

        values = self.rec.values

        def straightforward():
            np.nansum(np.asarray(values, dtype=float) ** 1.16, axis=(1, 2))

        times = interleaved({"plain": straightforward,
                             "movie": lambda: calibrate_movie(self.rec, self.loadcell)})
        return float(times["plain"].min() / times["movie"].min())

    track_per_frame_power_sum_over_calibrate_movie.unit = "ratio"


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])
