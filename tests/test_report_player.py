"""The report's frame player: bounded size, and in a real browser (Selenium, chromedriver).

The browser test drives Debian's ``chromium`` through ``chromium-driver`` with Selenium: it
moves the slider with the keyboard, as a reader would, and checks that the frame shown, the
label and the force trace's cursor follow. It skips when the browser, the driver or Selenium
is missing, except under ``CI=true``, where it fails (``.ci/run`` installs them).
"""

import base64
import json
import os
import re
import shutil

import numpy as np
import pytest
import xarray as xr

from tactilecal.report import build_report, write_report


def walking_patch(n=60, rows=30, cols=12, saturate_frame=5):
    """A patch moving down the sensor and back, its force a sine; one saturated sensel."""
    values = np.zeros((n, rows, cols))
    t = np.arange(n) * 0.01
    for k in range(n):
        r = int(round((rows - 4) * (0.5 - 0.5 * np.cos(2 * np.pi * k / n))))
        values[k, r:r + 4, 3:8] = 100.0 + 300.0 * np.sin(np.pi * k / n)
    values[saturate_frame, 0, 0] = 1000.0
    return xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(1, n + 1), "time": ("frame", t)},
                        attrs={"units": "kPa", "sensel_area_mm2": 4.0, "row_spacing_mm": 2.0,
                               "col_spacing_mm": 2.0, "saturation_pressure_kPa": 1000.0,
                               "source": "walking.asf"})


def _player_data(text):
    found = re.findall(r'<script type="application/json" class="player-data">(.*?)</script>',
                       text)
    assert len(found) == 1
    return json.loads(found[0])


def test_player_data_are_the_recording_on_one_scale():
    rec = walking_patch()
    text = build_report([rec])
    data = _player_data(text)
    levels = np.frombuffer(base64.b64decode(data["levels"]), np.uint8).reshape(60, 30, 12)
    assert data["top"] == 1000.0 and data["unit"] == "kPa" and data["shown"] == list(range(60))
    # 254 levels on 0..1000 kPa: a sensel at 400 kPa is level round(400 / 1000 * 254)
    k = 30
    expected = np.rint(np.nan_to_num(rec.values[k]) / 1000.0 * 254)
    np.testing.assert_array_equal(levels[k], expected)
    saturated = np.unpackbits(np.frombuffer(base64.b64decode(data["saturated"]), np.uint8)
                              .reshape(60, -1), axis=1)[:, :360].reshape(60, 30, 12)
    assert saturated.sum() == 1 and saturated[5, 0, 0] == 1
    force = rec.tactile.force().values
    assert data["force"] == pytest.approx(force.tolist(), rel=1e-3)  # 4 significant digits


@pytest.mark.slow  # a size profile: 10,000 frames
def test_a_10000_frame_recording_gives_a_report_under_5_mb(tmp_path):
    # a 44 x 44 sensor (the 5051) for 10,000 frames: 19 MB of frames as bytes, decimated
    n = 10_000
    rows = np.arange(44)[None, :, None]
    top = (20 + 10 * np.sin(np.arange(n) / 300)).astype(int)[:, None, None]
    values = np.where((rows >= top) & (rows < top + 6), 250.0, 0.0) * np.ones((1, 1, 44))
    rec = xr.DataArray(values, dims=("frame", "row", "col"),
                       coords={"frame": np.arange(1, n + 1),
                               "time": ("frame", np.arange(n) / 100.0)},
                       attrs={"units": "kPa", "sensel_area_mm2": 1.6129,
                              "row_spacing_mm": 1.27, "col_spacing_mm": 1.27})
    from tactilecal.report._player import player_html

    s = rec.tactile.frame_summary().compute()
    html = player_html(rec, "long", summary=s, units_label="kPa", factor=1.0, key="p")
    data = _player_data(html)
    assert len(data["shown"]) == 770 and data["shown"][1] == 13  # every 13th frame
    assert len(data["t"]) == n  # the force trace keeps every frame
    assert len(html.encode()) < 2.5e6


@pytest.mark.slow
def test_the_whole_10000_frame_report_is_under_5_mb(tmp_path):
    n = 10_000
    rows = np.arange(44)[None, :, None]
    top = (20 + 10 * np.sin(np.arange(n) / 300)).astype(int)[:, None, None]
    values = np.where((rows >= top) & (rows < top + 6), 250.0, 0.0) * np.ones((1, 1, 44))
    rec = xr.DataArray(values, dims=("frame", "row", "col"),
                       coords={"time": ("frame", np.arange(n) / 100.0)},
                       attrs={"units": "kPa", "sensel_area_mm2": 1.6129,
                              "row_spacing_mm": 1.27, "col_spacing_mm": 1.27})
    out = write_report([rec], tmp_path / "long.html")
    assert out.stat().st_size <= 5_000_000  # measured: 2.37 MB


def _browser():
    """Selenium's Chrome driver on Debian's chromium, or skip (fail under CI=true)."""
    missing = []
    try:
        from selenium import webdriver
        from selenium.webdriver.chrome.service import Service
    except ImportError:
        missing.append("the Python package 'selenium' (test extra)")
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    driver = shutil.which("chromedriver")
    if browser is None:
        missing.append("Debian's 'chromium'")
    if driver is None:
        missing.append("Debian's 'chromium-driver'")
    if missing:
        if os.environ.get("CI") == "true":
            pytest.fail(f"CI=true but {', '.join(missing)} is missing; .ci/run installs them")
        pytest.skip(f"{', '.join(missing)} not installed: the frame player is not checked in "
                    "a browser")
    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 "--window-size=1280,1600"):
        options.add_argument(flag)
    options.binary_location = browser
    return webdriver.Chrome(options=options, service=Service(driver))


@pytest.mark.slow
def test_moving_the_slider_changes_the_frame_and_the_cursor(tmp_path):
    from selenium.webdriver.common.by import By
    from selenium.webdriver.common.keys import Keys

    page = write_report([walking_patch()], tmp_path / "player.html")
    driver = _browser()
    try:
        driver.get(page.as_uri())
        player = driver.find_element(By.CSS_SELECTOR, "div.player")
        slider = player.find_element(By.CSS_SELECTOR, "input.slider")
        cursor = player.find_element(By.CSS_SELECTOR, "svg.trace line.cursor")
        label = player.find_element(By.CSS_SELECTOR, ".frame-label")

        def state():
            image = driver.execute_script(
                "return arguments[0].querySelector('canvas.map').toDataURL()", player)
            return (player.get_attribute("data-frame"), label.text,
                    float(cursor.get_attribute("x1")), image)

        first = state()
        assert first[0] == "31"  # the player opens at the peak-force frame (k = 30)
        assert first[1] == "frame 31, t = 0.300 s, total force = 32.00 N"
        for _ in range(10):
            slider.send_keys(Keys.ARROW_RIGHT)
        moved = state()
        assert moved[0] == "41" and moved[1].startswith("frame 41, t = 0.400 s")
        assert moved[2] > first[2]  # the cursor moved right along the time axis
        assert moved[3] != first[3]  # another frame is drawn
        slider.send_keys(Keys.HOME)
        assert state()[0] == "1" and state()[2] < first[2]
        errors = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
        assert errors == []
    finally:
        driver.quit()
