"""The bundled demo data are reproducible from their seeds, and the demo runs end to end."""

import filecmp
import json

import pytest

from tactilecal.cli import main
from tactilecal.demo import BUNDLE, bundle_path, make_bundle


def test_bundle_is_reproducible_from_its_seeds(tmp_path):
    make_bundle(tmp_path)
    for name in BUNDLE["sessions"]:
        for filename in ("deadweights.csv", "manifest.csv", "truth.json"):
            assert filecmp.cmp(tmp_path / f"session-{name}" / filename,
                               bundle_path() / f"session-{name}" / filename, shallow=False), (
                f"bundled session-{name}/{filename} differs from what its seeds give")


@pytest.mark.slow
def test_demo_runs_end_to_end_and_recovers_the_truth(tmp_path, capsys):
    out = tmp_path / "demo"
    assert main(["--quiet", "demo", "--out", str(out)]) == 0
    assert capsys.readouterr().out == ""  # --quiet prints nothing
    summary = json.loads((out / "summary.json").read_text())
    by_method = {row["method"]: row for row in summary["methods"]}
    # Session a calibrates, held-out session b validates (unsaturated patches).
    assert by_method["power"]["within_5pct"] >= 0.95
    assert by_method["zvyagin"]["within_5pct"] >= 0.80
    assert by_method["power"]["b"] == pytest.approx(BUNDLE["sensor"]["b"], abs=0.05)
    # The dead-weight calibration reads the loading-machine holds within 3%.
    assert max(abs(e) for e in summary["experiment"]["hold_error_pct"]) < 3.0
    # Dynamic filter: A within 5% of the truth, blind-test dynamic RMS error 3x smaller.
    dyn = summary["dynamic"]
    assert dyn["A"] == pytest.approx(dyn["A_true"], rel=0.05)
    assert dyn["blind_improvement"] >= 3.0
    html = (out / "report.html").read_text()
    assert html.count("<img") >= 5 and "data:image/png;base64," in html
    for method in by_method:
        assert (out / "calibrations" / f"{method}.json").is_file()
        assert (out / "validation" / f"{method}.json").is_file()
