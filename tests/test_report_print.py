"""The walk report on paper: headless Chromium prints it to PDF, pypdf reads the PDF back.

Checked: the full SHA-256 of the input is in the PDF's text (hashes wrap, they are not cut),
every column header and cell of the tables outside the collapsible sections is in it (no
column clipped by a scroll box), and at most one page has no figure. Skips without Chromium
or pypdf, except under ``CI=true`` (``.ci/run`` installs both).
"""

import hashlib
import html
import os
import re
import shutil
import subprocess

import pytest

from tactilecal.report import write_report


def _tools():
    missing = []
    try:
        import pypdf  # noqa: F401
    except ImportError:
        missing.append("the Python package 'pypdf' (test extra)")
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        missing.append("Debian's 'chromium'")
    if missing:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true but {', '.join(missing)} is missing; .ci/run installs them")
        pytest.skip(f"{', '.join(missing)} not installed: the printed report is not checked")
    return browser


def _print(browser, page, pdf, profile):
    run = subprocess.run([browser, "--headless", "--no-sandbox", "--disable-gpu",
                          "--no-first-run", "--disable-background-networking",
                          f"--user-data-dir={profile}", "--no-pdf-header-footer",
                          f"--print-to-pdf={pdf}", page.as_uri()],
                         capture_output=True, text=True, timeout=180)
    assert pdf.is_file(), run.stderr[-2000:]


def _squeeze(text):
    return re.sub(r"\s+", "", text)


def _visible_cells(text):
    """Text of every table cell outside the collapsible <details> sections."""
    text = re.sub(r"<details>.*?</details>", "", text, flags=re.S)
    return [html.unescape(re.sub(r"<[^>]+>", "", cell))
            for cell in re.findall(r"<t[hd]>(.*?)</t[hd]>", text, flags=re.S)]


@pytest.mark.slow
def test_the_walk_report_prints_whole(fscan_asf, tmp_path):
    from pypdf import PdfReader

    browser = _tools()
    page = write_report([fscan_asf], tmp_path / "walk.html", command="tactilecal report ...")
    pdf = tmp_path / "walk.pdf"
    _print(browser, page, pdf, tmp_path / "profile")
    reader = PdfReader(pdf)
    texts = [p.extract_text() for p in reader.pages]
    whole = _squeeze("".join(texts))
    digest = hashlib.sha256(fscan_asf.read_bytes()).hexdigest()
    assert digest in whole
    cells = _visible_cells(page.read_text())
    assert len(cells) > 80
    missing = [cell for cell in cells if _squeeze(cell) not in whole]
    assert missing == []  # every column of every table is on paper
    figureless = [k for k, p in enumerate(reader.pages) if not p.images]
    assert len(figureless) <= 1, (figureless, len(reader.pages))  # measured: 0 of 4 pages
