"""``tactilecal report``: writes the page, records the command, exit codes."""

import re

import pytest

from tactilecal.cli import main


@pytest.mark.slow  # end to end: a command through every figure of a report
def test_report_cli_writes_page(fscan_asf, tmp_path, capsys):
    out = tmp_path / "walk.html"
    assert main(["-q", "report", str(fscan_asf), "--out", str(out), "--title", "walk <p10>"]) == 0
    text = out.read_text()
    assert "<title>walk &lt;p10&gt;</title>" in text
    # frame 9: sum of its kPa values x 25.8064 mm2 x 1e-3 = 924.359 N (numpy nansum),
    # written for people to four significant digits
    assert "<td>peak total force</td><td>924.4 N</td>" in text
    # force/area, the three maps (one figure), profiles, the steps' centre-of-pressure paths
    assert len(re.findall(r'<img alt="[^"]*" width="\d+" height="\d+" '
                          r'src="data:image/png;base64,', text)) == 4
    assert text.count('<div class="player"') == 1
    assert "<td>command</td><td>tactilecal " in text
    assert capsys.readouterr().err == ""  # --quiet: no bar, no message


def test_report_cli_exit_codes(tmp_path, capsys):
    bad = tmp_path / "x.json"
    bad.write_text("[1, 2]")
    assert main(["report", str(bad), "--out", str(tmp_path / "r.html")]) == 1
    assert "x.json: JSON list; expected an object" in capsys.readouterr().err
    assert not (tmp_path / "r.html").exists()
    with pytest.raises(SystemExit) as usage:
        main(["report", str(bad)])  # --out missing
    assert usage.value.code == 2


def test_report_cli_options_are_checked_before_reading(fscan_asf, tmp_path, capsys):
    out = tmp_path / "r.html"
    assert main(["-q", "report", str(fscan_asf), "--out", str(out), "--align", "x"]) == 1
    assert "alignment (how=, --align) 'x'; expected one of time, start, onset" in \
        capsys.readouterr().err
    assert main(["-q", "report", str(fscan_asf), "--out", str(out), "--units", "N"]) == 1
    assert "units (--units) 'N' is a force unit" in capsys.readouterr().err
    assert not out.exists()
