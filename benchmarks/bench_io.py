"""Reading and writing recordings: ``read_tekscan``, ``write_tekscan``, ``open_recording``,
``convert``, ``read_timeseries``, against pandas on the same numbers; a result's JSON text
against :func:`json.dumps` of the same plain data.

Data: a simulated raw 44 x 44 I-Scan export of 10,000 frames (70 MB) and a plain CSV of the
same numbers (:func:`benchmarks._common.write_export`); a load-cell CSV of 1,000,000 rows of
time and force (28 MB); the real exports of
``../shared/realdata`` (or ``$TACTILECAL_REALDATA``) for ``open_recording``, simulated
stand-ins of the same shapes when they are absent.
"""

import numpy as np

from benchmarks._common import PEAK, REALDATA, child, interleaved, ratio, write_export

FRAMES = 10_000


def _pandas_read(plain):
    import pandas as pd

    return pd.read_csv(plain, header=None, engine="c", dtype=np.float64,
                       na_values=["B"]).to_numpy()


class Read:
    """An export of 10,000 frames read whole, in this process and in fresh interpreters."""

    timeout = 600

    def setup_cache(self):
        import os

        export, plain = write_export(os.getcwd(), FRAMES)
        return str(export), str(plain)

    def time_read_tekscan(self, files):
        from tactilecal.io import read_tekscan

        read_tekscan(files[0])

    def time_pandas_read_csv(self, files):
        _pandas_read(files[1])

    def peakmem_read_tekscan(self, files):
        from tactilecal.io import read_tekscan

        read_tekscan(files[0])

    def track_read_tekscan_speed_over_pandas(self, files):
        """CPU time of ``pandas.read_csv`` (C engine) / ``read_tekscan``, warm (> 1: faster)."""
        from tactilecal.io import read_tekscan

        return ratio(lambda: _pandas_read(files[1]), lambda: read_tekscan(files[0]))

    track_read_tekscan_speed_over_pandas.unit = "ratio"

    def track_fresh_process_peak_over_array(self, files):
        """Peak memory of ``read_tekscan`` in a fresh interpreter, above its imports, over
        the float64 array it returns (``VmHWM``; the issue-16 goal is <= 1.5)."""
        code = PEAK + (
            "import json, sys\nimport tactilecal.io\nbase = peak_bytes()\n"
            "n = tactilecal.io.read_tekscan(sys.argv[1]).nbytes\n"
            "print(json.dumps((peak_bytes() - base) / n))")
        return min(child(code, files[0])[0] for _ in range(2))

    track_fresh_process_peak_over_array.unit = "ratio"

    def track_fresh_process_pandas_peak_over_array(self, files):
        """The same for ``pandas.read_csv`` on the plain CSV (the baseline)."""
        code = PEAK + (
            "import json, sys\nimport numpy as np, pandas as pd\nbase = peak_bytes()\n"
            "n = pd.read_csv(sys.argv[1], header=None, engine='c', dtype=np.float64, "
            "na_values=['B']).to_numpy().nbytes\nprint(json.dumps((peak_bytes() - base) / n))")
        return min(child(code, files[1])[0] for _ in range(2))

    track_fresh_process_pandas_peak_over_array.unit = "ratio"


class Convert:
    """``convert`` to Zarr in 1000-frame blocks, in a fresh interpreter each time."""

    timeout = 600
    CHUNKS = 1000

    def setup_cache(self):
        import os

        export, plain = write_export(os.getcwd(), FRAMES)
        return str(export), str(plain)

    def track_convert_peak_over_block(self, files):
        """Peak memory of ``convert`` above its imports over one float64 block: bounded
        by the blocks in flight, whatever the file's size."""
        code = PEAK + (
            "import json, sys, tempfile, os\nimport tactilecal.io, zarr, dask.array\n"
            "base = peak_bytes()\nout = os.path.join(tempfile.mkdtemp(), 'out.zarr')\n"
            f"tactilecal.io.convert(sys.argv[1], out, chunks={self.CHUNKS})\n"
            "print(json.dumps(peak_bytes() - base))")
        peak = min(child(code, files[0])[0] for _ in range(2))
        return peak / (self.CHUNKS * 44 * 44 * 8)

    track_convert_peak_over_block.unit = "ratio"

    def track_convert_speed_over_pandas_stream(self, files):
        """CPU time of a streamed ``pandas.read_csv(chunksize=)`` over the same numbers
        (parsing only, nothing written) / ``convert`` to Zarr; fresh interpreters."""
        convert = ("import json, os, sys, tempfile, time\nimport tactilecal.io, zarr, dask.array\n"
                   "out = os.path.join(tempfile.mkdtemp(), 'out.zarr')\n"
                   "start = time.process_time()\n"
                   f"tactilecal.io.convert(sys.argv[1], out, chunks={self.CHUNKS})\n"
                   "print(json.dumps(time.process_time() - start))")
        stream = ("import json, sys, time\nimport numpy as np, pandas as pd\n"
                  "start = time.process_time()\n"
                  "with pd.read_csv(sys.argv[1], header=None, engine='c', dtype=np.float64, "
                  f"na_values=['B'], chunksize={self.CHUNKS * 44}) as reader:\n"
                  "    for part in reader:\n        part.to_numpy()\n"
                  "print(json.dumps(time.process_time() - start))")
        cpu = {"convert": [], "stream": []}
        for _ in range(2):  # CPU seconds of the work, the imports left out
            cpu["convert"].append(child(convert, files[0])[0])
            cpu["stream"].append(child(stream, files[1])[0])
        return min(cpu["stream"]) / min(cpu["convert"])

    track_convert_speed_over_pandas_stream.unit = "ratio"


class Write:
    """``write_tekscan`` of 2000 raw frames against ``DataFrame.to_csv`` of the same values."""

    def setup(self):
        from tactilecal.simulate import make_sensor, ramp_hold

        rec = ramp_hold(make_sensor("5051", seed=0), frame_rate_hz=100.0, seed=1).raw
        self.rec = rec.isel(frame=slice(0, 2000))

    def time_write_tekscan(self):
        import tempfile
        from pathlib import Path

        from tactilecal.io import write_tekscan

        write_tekscan(self.rec, Path(tempfile.mkdtemp()) / "out.csv")

    def track_write_speed_over_to_csv(self):
        """CPU time of ``DataFrame.to_csv`` of the values (no header, no frame lines) /
        ``write_tekscan`` of the recording (> 1: faster)."""
        import tempfile
        from pathlib import Path

        import pandas as pd

        from tactilecal.io import write_tekscan

        folder = Path(tempfile.mkdtemp())
        frame = pd.DataFrame(self.rec.values.reshape(-1, self.rec.sizes["col"]))
        return ratio(lambda: frame.to_csv(folder / "plain.csv", header=False, index=False,
                                          na_rep="B", float_format="%.0f"),
                     lambda: write_tekscan(self.rec, folder / "out.csv", overwrite=True))

    track_write_speed_over_to_csv.unit = "ratio"


class ReadTimeseries:
    """A load-cell CSV of 1,000,000 rows (time in s, force in N) read by ``read_timeseries``."""

    timeout = 600
    ROWS = 1_000_000

    def setup_cache(self):
        import os
        from pathlib import Path

        path = Path(os.getcwd()) / "loadcell.csv"
        rng = np.random.default_rng(0)
        times = (np.arange(self.ROWS) * 1e-3).tolist()
        forces = rng.normal(100.0, 5.0, self.ROWS).tolist()
        with open(path, "w") as out:
            out.write("Time (s),Load (N)\n")
            for lo in range(0, self.ROWS, 100_000):
                out.write("".join(f"{t!r},{f!r}\n" for t, f in zip(times[lo:lo + 100_000],
                                                                   forces[lo:lo + 100_000],
                                                                   strict=True)))
        return str(path)

    def time_read_timeseries(self, path):
        from tactilecal.io import read_timeseries

        read_timeseries(path)

    def peakmem_read_timeseries(self, path):
        from tactilecal.io import read_timeseries

        read_timeseries(path)

    def track_read_timeseries_speed_over_pandas(self, path):
        """CPU time of ``pandas.read_csv`` (C engine) of the file / ``read_timeseries`` of it,
        warm (> 1: faster; the reader checks every row and parses with that same parser)."""
        import pandas as pd

        from tactilecal.io import read_timeseries

        return ratio(lambda: pd.read_csv(path, engine="c", dtype=np.float64).to_numpy(),
                     lambda: read_timeseries(path))

    track_read_timeseries_speed_over_pandas.unit = "ratio"


class OpenRecording:
    """What sniffing the format costs: ``open_recording`` over the format's own reader."""

    params = ["iscan", "fscan", "netcdf"]
    param_names = ["file"]

    def setup_cache(self):
        import os
        from pathlib import Path

        from tactilecal.io import read_tekscan, write_netcdf, write_tekscan
        from tactilecal.simulate import make_sensor, ramp_hold

        here = Path(os.getcwd())
        files = {"iscan": REALDATA / "pressuRe_iscan_test.csv",
                 "fscan": REALDATA / "footPress_FrasP01L.asf"}
        if not all(path.is_file() for path in files.values()):  # simulated stand-ins
            files = {"iscan": here / "iscan.csv", "fscan": here / "fscan.csv"}
            for name, model, frames in (("iscan", "6900", 309), ("fscan", "FSCAN", 205)):
                rec = ramp_hold(make_sensor(model, seed=0), frame_rate_hz=15.0, seed=1).raw
                write_tekscan(rec.isel(frame=slice(0, frames)), files[name])
        files["netcdf"] = here / "iscan.nc"
        write_netcdf(read_tekscan(files["iscan"]), files["netcdf"])
        return {name: str(path) for name, path in files.items()}

    def track_open_recording_over_reader(self, files, file):
        """CPU time of ``open_recording`` / ``read_tekscan`` or ``read_netcdf`` (1: free)."""
        from tactilecal.io import open_recording, read_netcdf, read_tekscan

        reader = read_netcdf if file == "netcdf" else read_tekscan
        times = interleaved({"open": lambda: open_recording(files[file]),
                             "reader": lambda: reader(files[file])}, rounds=7)
        return float(np.median(times["open"]) / np.median(times["reader"]))

    track_open_recording_over_reader.unit = "ratio"


if __name__ == "__main__":
    import sys

    from benchmarks._common import run

    run(sys.modules[__name__])


class ResultJson:
    """A calibration's JSON text: ``to_json_text`` of Zvyagin's procedure on 120 patches (its
    pairs, maps and tables, about 0.5 MB of JSON)."""

    def setup(self):
        from tactilecal.calibration import calibrate, points_from_frames
        from tactilecal.simulate import deadweight_session, make_sensor

        session = deadweight_session(make_sensor("5051", seed=4), n_patches=120, seed=5)
        self.result = calibrate(points_from_frames(session.raw, session.load_N), "zvyagin")

    def time_to_json_text(self):
        self.result.to_json_text()

    def track_to_json_text_over_json_dumps(self):
        """CPU time of ``json.dumps`` of the text's own plain data / ``to_json_text`` (which
        converts the arrays and NumPy numbers first): the cost of that conversion."""
        import json

        plain = json.loads(self.result.to_json_text())
        return ratio(lambda: json.dumps(plain, indent=2), self.result.to_json_text)

    track_to_json_text_over_json_dumps.unit = "ratio"

