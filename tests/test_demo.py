"""The bundled demo data are reproducible from their seeds, and the demo runs end to end."""

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from tactilecal._text import number
from tactilecal.cli import main
from tactilecal.demo import bundle_path
from tactilecal.demo._bundle import BUNDLE, make_bundle
from tactilecal.io import read_tekscan


def _assert_close(made, bundled, where):
    """Same JSON structure; numbers equal to 1e-9 relative (library builds differ in ulps)."""
    if isinstance(made, dict):
        assert made.keys() == bundled.keys(), where
        for key in made:
            _assert_close(made[key], bundled[key], f"{where}.{key}")
    elif isinstance(made, list):
        assert len(made) == len(bundled), where
        for i, (a, b) in enumerate(zip(made, bundled, strict=True)):
            _assert_close(a, b, f"{where}[{i}]")
    elif isinstance(made, float) or isinstance(bundled, float):
        assert math.isclose(made, bundled, rel_tol=1e-9, abs_tol=1e-12), where
    else:
        assert made == bundled, where


def test_bundle_is_reproducible_from_its_seeds(tmp_path):
    make_bundle(tmp_path)
    for name in BUNDLE["sessions"]:
        made, bundled = tmp_path / f"session-{name}", bundle_path() / f"session-{name}"
        assert (made / "manifest.csv").read_text() == (bundled / "manifest.csv").read_text()
        _assert_close(json.loads((made / "truth.json").read_text()),
                      json.loads((bundled / "truth.json").read_text()), f"session-{name}")
        new, old = read_tekscan(made / "deadweights.csv"), read_tekscan(bundled / "deadweights.csv")
        assert new.shape == old.shape
        assert {k: v for k, v in new.attrs.items() if k != "source"} == \
            {k: v for k, v in old.attrs.items() if k != "source"}
        # readings are rounded floats: a build that differs in the last digit may move a
        # reading that sits on a rounding edge by one count, and nothing else
        diff = np.abs(np.nan_to_num(new.values) - np.nan_to_num(old.values))
        assert diff.max() <= 1 and np.count_nonzero(diff) <= 1e-4 * diff.size
        np.testing.assert_array_equal(np.isnan(new.values), np.isnan(old.values))


def _assert_recovers_the_truth(out):
    """The numbers of ``summary.json`` against the bundle's truth; returns the methods."""
    summary = json.loads((out / "summary.json").read_text())
    by_method = {row["method"]: row for row in summary["methods"]}
    # Session a calibrates, held-out session b validates (unsaturated patches).
    assert by_method["power"]["within_5pct"] >= 0.95
    assert by_method["auto"]["within_5pct"] >= 0.95  # the default
    assert by_method["zvyagin"]["within_5pct"] >= 0.80
    assert by_method["power"]["b"] == pytest.approx(BUNDLE["sensor"]["b"], abs=0.05)
    # The dead-weight calibration reads the loading-machine holds within 3%.
    assert max(abs(e) for e in summary["experiment"]["hold_error_pct"]) < 3.0
    # Dynamic filter: A within 5% of the truth, blind-test dynamic RMS error 3x smaller.
    dyn = summary["dynamic"]
    assert dyn["A"] == pytest.approx(dyn["A_true"], rel=0.05)
    assert dyn["blind_improvement"] >= 3.0
    for method in by_method:
        assert (out / "calibrations" / f"{method}.json").is_file()
        assert (out / "validation" / f"{method}.json").is_file()
    return by_method


@pytest.mark.slow  # the whole demo but its report
def test_demo_recovers_the_truth_report_aside(tmp_path, monkeypatch):
    """Every step of the demo but drawing the report (most of its time: its figures, which
    tests/test_report_html.py checks); the report is handed every file the demo wrote."""
    import tactilecal.report
    from tactilecal.demo import run_demo

    handed = {}

    def write_report(inputs, out, **options):
        handed.update(inputs=[str(i) for i in inputs], **options)
        return out

    monkeypatch.setattr(tactilecal.report, "write_report", write_report)
    out = tmp_path / "demo"
    run_demo(out, quiet=True)
    by_method = _assert_recovers_the_truth(out)
    assert all(Path(i).is_file() for i in handed["inputs"])
    assert {Path(i).name for i in handed["inputs"]} >= {
        *(f"{m}.json" for m in by_method), "pressure.nc", "blind-test.json"}
    assert "calibration" not in handed  # pressure.nc is calibrated already: none is applied


@pytest.mark.slow
def test_demo_runs_end_to_end_and_recovers_the_truth(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["--quiet", "demo", "--out", str(out)]) == 0
    assert capsys.readouterr().out == ""  # --quiet prints nothing
    by_method = _assert_recovers_the_truth(out)
    html = (out / "report.html").read_text()
    assert html.count("<img") >= 5 and "data:image/png;base64," in html
    # every calibration the demo made is in the report, compared with held-out errors
    comparison = html[html.index("<h2>Method comparison</h2>"):html.index("<h2>Calibration")]
    for method in by_method:  # auto's file holds the method it chose
        chosen = json.loads((out / "calibrations" / f"{method}.json").read_text())["method"]
        row = re.search(rf"<tr><td>{method}.json</td><td>{chosen}</td>.*?</tr>", comparison)
        held_out = by_method[method]["median_abs_error_pct"]
        assert row and f"<td>{number(held_out)}</td>" in row.group(0), method
    assert "Blind test of a dynamic filter: blind-test.json" in html
    # one vocabulary (issue 15): no JSON key or table column spells a unit another way
    names = _output_names(out)
    assert "time_s" in names and len(names) > 100
    assert sorted(n for n in names if OTHER_SPELLING.search(n)) == []


#: Unit spellings the package does not write (it writes _s, _kPa, _N, _mm2, _hz, _pct);
#: a bare "time" column is a time without its unit.
OTHER_SPELLING = re.compile(r"^(time|sec|secs|seconds)$|_(sec|secs|seconds|kpa|Kpa|KPa|pa|Hz|"
                            r"HZ|n|newton|percent|mm\^2|sqmm)$")


def _output_names(folder):
    """Every JSON key and every column of the tables tactilecal wrote under ``folder``.

    The simulated load-cell files are left out: they imitate an instrument's own header.
    """
    import pandas as pd

    from tactilecal.io import recording_format

    names = set()

    def walk(value):
        if isinstance(value, dict):
            names.update(value)
            for item in value.values():
                walk(item)
        elif isinstance(value, list):
            for item in value:
                walk(item)

    for path in folder.rglob("*.json"):
        walk(json.loads(path.read_text()))
    for path in folder.rglob("*.csv"):
        if recording_format(path) is None and "loadcell" not in path.name:
            names.update(pd.read_csv(path, nrows=1).columns)
    return names
