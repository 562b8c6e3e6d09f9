"""The progress protocol: library loops call the ``progress`` they are given, never the CLI's."""

import numpy as np
import pytest
import xarray as xr

from tactilecal._progress import no_progress, resolve, terminal_bar
from tactilecal.calibration import load_points
from tactilecal.calibration._manifest import load_frames
from tactilecal.io import write_tekscan
from tactilecal.report import build_report


class Recorder:
    """A progress callable that records its calls and passes the items through."""

    def __init__(self):
        self.calls = []

    def __call__(self, iterable, *, total=None, desc=None):
        items = list(iterable)
        self.calls.append((len(items), total, desc))
        return items


@pytest.fixture
def manifest_of(tmp_path):
    """A manifest of ``n`` rows all pointing at one raw 3 x 4 frame carrying 2 N."""
    frame = xr.DataArray(np.arange(12.0).reshape(1, 3, 4), dims=("frame", "row", "col"),
                         coords={"frame": [1], "time": ("frame", [0.0])},
                         attrs={"units": "raw", "sensel_area_mm2": 1.6129})
    write_tekscan(frame, tmp_path / "rec.csv")

    def make(n):
        path = tmp_path / f"manifest{n}.csv"
        path.write_text("file,frame,load_N\n" + "rec.csv,1,2.0\n" * n)
        return path
    return make


def test_long_manifest_calls_progress_once_with_its_total(manifest_of):
    bar = Recorder()
    points = load_points(manifest_of(50), progress=bar)
    assert len(points) == 50
    assert bar.calls == [(50, 50, "reading manifest50.csv")]
    bar = Recorder()
    assert load_frames(manifest_of(60), progress=bar).shape == (60, 3, 4)
    assert bar.calls == [(60, 60, "reading manifest60.csv")]


def test_short_manifest_reads_without_progress(manifest_of):
    bar = Recorder()
    assert len(load_points(manifest_of(49), progress=bar)) == 49
    assert bar.calls == []


def test_resolve_and_no_progress():
    assert resolve(None) is no_progress
    assert resolve(print) is print
    assert list(no_progress(iter("ab"), total=2, desc="x")) == ["a", "b"]
    with pytest.raises(TypeError, match="progress of type int; expected None or a callable"):
        resolve(3)


def test_terminal_bar_passes_items_through_off_a_terminal():
    # pytest captures standard error, which is then no terminal: the bar is disabled
    assert list(terminal_bar(range(4), total=4, desc="t")) == [0, 1, 2, 3]


def test_report_passes_total_and_desc():
    bar = Recorder()
    frame = xr.DataArray(np.ones((2, 3, 4)), dims=("frame", "row", "col"),
                         coords={"frame": [1, 2], "time": ("frame", [0.0, 0.1])},
                         attrs={"units": "raw", "row_spacing_mm": 1.0, "col_spacing_mm": 1.0,
                                "sensel_area_mm2": 1.0})
    build_report([frame], progress=bar)
    # the inputs read, then the recording's section block by block (its length unknown
    # beforehand: each figure is drawn as the bar moves)
    assert bar.calls == [(1, 1, "report"), (6, None, "report: DataArray in memory")]


def test_cli_calibrate_supplies_its_bar(tmp_path, monkeypatch):
    # the CLI passes a progress callable to the library; with -q the bar is off
    import tactilecal.cli._common as common
    from tactilecal.cli import main

    levels = np.array([10.0, 20.0, 40.0, 80.0, 160.0])
    frames = xr.DataArray(np.repeat(levels, 12).reshape(5, 3, 4), dims=("frame", "row", "col"),
                          coords={"frame": np.arange(1, 6), "time": ("frame", np.arange(5.0))},
                          attrs={"units": "raw", "sensel_area_mm2": 1.6129})
    write_tekscan(frames, tmp_path / "rec.csv")
    load_N = 12 * 0.0035 * levels ** 1.16  # f = A X^b per sensel, 12 sensels
    rows = "".join(f"rec.csv,{k % 5 + 1},{float(load_N[k % 5])!r}\n" for k in range(50))
    (tmp_path / "m.csv").write_text("file,frame,load_N\n" + rows)
    calls = []

    def bar(iterable=None, *, total=None, desc=None, quiet=False):
        calls.append((total, desc, quiet))
        return iterable
    monkeypatch.setattr(common, "terminal_bar", bar)
    for flags, quiet in (([], False), (["-q"], True)):
        calls.clear()
        out = tmp_path / f"cal{len(flags)}.json"
        # the bar is the reading's; the fit has none, whatever its method (power: quick)
        assert main([*flags, "calibrate", str(tmp_path / "m.csv"), "--method", "power",
                     "--out", str(out)]) == 0
        assert calls == [(50, "reading m.csv", quiet)]


@pytest.fixture
def no_delay(monkeypatch):
    import tactilecal._progress as progress

    monkeypatch.setattr(progress, "DELAY_S", 0.0)


def test_quick_work_says_nothing(capsys):
    assert list(terminal_bar(range(20), desc="filtering")) == list(range(20))
    assert capsys.readouterr().err == ""  # done within DELAY_S


def test_a_redirected_report_is_a_short_line_per_tenth(capsys, no_delay):
    assert list(terminal_bar(range(20), desc="filtering")) == list(range(20))
    lines = capsys.readouterr().err.splitlines()
    assert [line.split(" (")[0] for line in lines] == [f"filtering: {p}%" for p in
                                                       range(10, 101, 10)]
    assert all(len(line) < 60 for line in lines)
    assert list(terminal_bar(range(20), desc="filtering", quiet=True)) == list(range(20))
    assert capsys.readouterr().err == ""


def test_a_bare_report_is_advanced_by_hand(capsys, no_delay):
    bar = terminal_bar(total=4, desc="analyze")
    for _ in range(4):
        bar.update()
    bar.close()
    assert capsys.readouterr().err.splitlines()[-1].startswith("analyze: 100% (4 of 4, ")
    quiet = terminal_bar(total=4, desc="analyze", quiet=True)
    quiet.update()
    quiet.close()
    assert capsys.readouterr().err == ""


def test_dask_progress_reports_tasks_as_lines_and_is_silent_when_quiet(capsys, no_delay):
    import dask.array as da

    from tactilecal._progress import dask_progress

    x = da.ones((1000, 10), chunks=(100, 10))
    with dask_progress(desc="filtering"):
        assert float((x * 2).sum().compute()) == 20000.0
    lines = capsys.readouterr().err.splitlines()
    assert lines and lines[-1].startswith("filtering: 100% (")
    assert len(lines) <= 10 and all(len(line) < 60 for line in lines)
    with dask_progress(desc="filtering", quiet=True):
        (x * 2).sum().compute()
    assert capsys.readouterr().err == ""
