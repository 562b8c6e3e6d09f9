"""Loading over time: integrals, loading rate, steps and alignment, against a known truth.

The simulated walk below has steps whose force is piecewise linear in time with its knots on
frame times, so the trapezoid rule, linear threshold crossings and the 20-80 % loading rate
are exact; and whose centre of pressure moves along the rows at a known speed.
"""

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal import TactilecalError
from tactilecal.analysis import align_recordings

FS = 100.0
ROW_MM = 5.0
AREA = 25.0


def walk(starts_s=(0.3, 1.3, 2.3), rise_s=0.1, hold_s=0.4, peak_N=800.0, speed_mm_s=200.0,
         end_s=3.2):
    """Trapezoid steps (rise, hold, fall) of a patch moving down the rows during each."""
    t = np.arange(0.0, end_s, 1 / FS)
    force = np.zeros_like(t)
    position = np.full_like(t, 20.0)
    for start in starts_s:
        ramp_up = np.clip((t - start) / rise_s, 0, 1)
        ramp_down = np.clip((start + 2 * rise_s + hold_s - t) / rise_s, 0, 1)
        force += peak_N * np.minimum(ramp_up, ramp_down)
        inside = (t >= start) & (t <= start + 2 * rise_s + hold_s)
        position[inside] = 20.0 + speed_mm_s * (t[inside] - start)
    values = np.zeros((t.size, 40, 3))
    row = np.floor(position / ROW_MM).astype(int)
    frac = position / ROW_MM - row
    frames = np.arange(t.size)
    pressure = force / AREA * 1e3  # kPa on one sensel carrying the whole force
    values[frames, row, 1] = pressure * (1 - frac)
    values[frames, row + 1, 1] = pressure * frac
    rec = xr.DataArray(values, dims=("frame", "row", "col"),
                       coords={"frame": frames + 1, "time": ("frame", t)},
                       attrs={"units": "kPa", "sensel_area_mm2": AREA,
                              "row_spacing_mm": ROW_MM, "col_spacing_mm": ROW_MM,
                              "source": "walk"})
    return rec, force


def test_steps_of_a_known_walk():
    rec, force = walk()
    steps = rec.tactile.steps(threshold_N=200.0)
    table = steps.table
    assert len(steps) == 3 and table["complete"].all()
    # threshold 200 N = 1/4 of the 800 N peak: crossed 0.025 s into the rise and fall
    np.testing.assert_allclose(table["start_s"], [0.325, 1.325, 2.325], atol=1e-12)
    np.testing.assert_allclose(table["duration_s"], 0.55, atol=1e-12)
    np.testing.assert_allclose(table["peak_force_N"], 800.0, rtol=1e-12)
    # impulse of each trapezoid, its parts below the threshold too: 800 N x (0.4 + 0.1) s
    np.testing.assert_allclose(table["impulse_N_s"], 800.0 * 0.5, rtol=1e-12)
    # 20..80 % of 800 N on a ramp of 8000 N/s
    np.testing.assert_allclose(table["loading_rate_N_s"], 8000.0, rtol=1e-12)
    np.testing.assert_allclose(table["peak_pressure_kPa"], 800.0 / AREA * 1e3, rtol=1e-12)
    # the centre moves 200 mm/s from the frame after the start to the last frame above 200 N
    frames_in = table["last_frame"] - table["first_frame"]
    np.testing.assert_allclose(table["cop_path_mm"], 200.0 * frames_in / FS, rtol=1e-9)
    np.testing.assert_allclose(table["cop_start_row_mm"], 20.0 + 200.0 * 0.03, rtol=1e-9)
    assert all(np.all(np.diff(p["cof_row_mm"]) > 0) for p in steps.paths)
    assert rec.tactile.impulse() == pytest.approx(3 * 400.0, rel=1e-12)


def test_partial_steps_are_marked_and_have_no_loading_rate():
    rec, _ = walk(starts_s=(-0.2, 1.0, 2.8))
    table = rec.tactile.steps().table
    assert table["complete"].tolist() == [False, True, False]
    assert np.isnan(table["loading_rate_N_s"][0]) and np.isfinite(table["loading_rate_N_s"][1])
    assert table["start_s"][0] == 0.0  # it started before the recording


def test_default_threshold_and_short_runs():
    rec, _ = walk()
    steps = rec.tactile.steps()
    assert steps.threshold_N == pytest.approx(0.05 * 800.0)
    assert rec.tactile.steps(min_duration_s=1.0).table.attrs[
        "runs_shorter_than_min_duration"] == 3
    with pytest.raises(TactilecalError, match="threshold_N is -1.0; expected a finite force"):
        rec.tactile.steps(threshold_N=-1.0)


def test_loading_rate_of_a_half_sine_is_within_half_a_percent():
    # F = P sin(pi t / D): t20, t80 at D/pi asin(0.2), asin(0.8); linear interpolation at 1 kHz
    duration, peak = 0.6, 1000.0
    t = np.arange(0.0, duration + 1e-9, 1e-3)
    f = peak * np.sin(np.pi * t / duration)
    exact = 0.6 * peak / (duration / np.pi * (np.arcsin(0.8) - np.arcsin(0.2)))
    from tactilecal.analysis._gait import loading_rate

    assert loading_rate(f, t) == pytest.approx(exact, rel=5e-3)


def test_pressure_time_integral_map():
    rec, _ = walk(starts_s=(0.3,), end_s=1.2)
    pti = rec.tactile.pressure_time_integral()
    # the patch's pressure integrated over time: total impulse / sensel area, spread over rows
    assert float(pti.sum()) * AREA / 1e3 == pytest.approx(400.0, rel=1e-12)
    assert pti.dims == ("row", "col") and float(pti.isel(col=0).sum()) == 0.0


def test_align_recordings():
    rec, _ = walk()
    later = rec.assign_coords(time=rec["time"] + 5.0)
    same = align_recordings([rec, later])
    assert [float(r.time[0]) for r in same] == [0.0, 5.0]
    onset = align_recordings([rec, later], how="onset")
    first = [float(r.time[int(np.argmax(r.tactile.force().values > 40.0))]) for r in onset]
    assert first == [0.0, 0.0] and onset[1].attrs["time_shift_s"] == pytest.approx(-5.31)
    with pytest.raises(TactilecalError, match=r"alignment \(how=, --align\) 'x'; expected one "
                                              "of time, start, onset"):
        align_recordings([rec], how="x")


def test_real_walk_left_and_right_steps_alternate(fscan_asf, fscan_right_asf):
    from tactilecal.io import read_tekscan

    left, right = (read_tekscan(p) for p in (fscan_asf, fscan_right_asf))
    steps = {side: rec.tactile.steps().table for side, rec in (("L", left), ("R", right))}
    # five complete stances of each foot (docs/analysis.md), partial ones at the ends
    assert [int(s["complete"].sum()) for s in steps.values()] == [5, 5]
    assert steps["L"]["peak_force_N"].max() == pytest.approx(924.359, abs=1e-3)
    onsets = sorted([(s, side) for side, table in steps.items()
                     for s in table.loc[table["complete"], "start_s"]])
    sides = [side for _, side in onsets]
    assert all(a != b for a, b in zip(sides, sides[1:], strict=False))  # left, right, left ...
    durations = np.concatenate([t.loc[t["complete"], "duration_s"] for t in steps.values()])
    assert np.all((durations > 0.5) & (durations < 0.9))  # walking stance, 0.03 s frames
