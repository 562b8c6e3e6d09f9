import json

import pytest

from tactilecal.cli import main
from tactilecal.demo import bundle_path


@pytest.mark.parametrize("mode", ["faithful", "robust"])
def test_zvyagin_mode_reaches_the_method(tmp_path, mode):
    out = tmp_path / "cal.json"
    manifest = bundle_path() / "session-a" / "manifest.csv"
    assert main(["-q", "calibrate", str(manifest), "--method", "zvyagin", "--mode", mode,
                 "--out", str(out)]) == 0
    cal = json.loads(out.read_text())
    assert cal["method"] == "zvyagin"
    assert cal["options"]["mode"] == cal["diagnostics"]["mode"] == mode


def test_mode_with_another_method_is_an_error(capsys):
    manifest = bundle_path() / "session-a" / "manifest.csv"
    assert main(["calibrate", str(manifest), "--method", "power", "--mode", "robust"]) == 1
    assert "--mode applies to --method zvyagin; not 'power'" in capsys.readouterr().err
