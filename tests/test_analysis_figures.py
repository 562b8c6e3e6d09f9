"""Looking at a recording: maps mark saturation and the centre of force; plot REC; movie."""

import json

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal import TactilecalError
from tactilecal.cli import main


def moving_raw(n=12, saturate=((3, 4, 5),)):
    """A raw 2 x 2 patch moving one row per frame; a saturated sensel in some frames."""
    values = np.zeros((n, 20, 8))
    for k in range(n):
        values[k, k % 16:k % 16 + 2, 3:5] = 100.0
    for k, r, c in saturate:
        values[k, r, c] = 255.0
    return xr.DataArray(values, dims=("frame", "row", "col"),
                        coords={"frame": np.arange(1, n + 1),
                                "time": ("frame", np.arange(n) * 0.1)},
                        attrs={"units": "raw", "row_spacing_mm": 2.0, "col_spacing_mm": 2.0,
                               "sensel_area_mm2": 4.0, "source": "moving.csv"})


def _marks(ax):
    """Offsets of the saturated-sensel crosses (mm), from the legend label 'saturated ...'."""
    hits = [c for c in ax.collections if str(c.get_label()).startswith("saturated")]
    return [tuple(map(float, xy)) for c in hits for xy in c.get_offsets()]


def test_every_map_marks_its_saturated_sensels():
    rec = moving_raw()
    # frame 3 (position 3) has raw 255 at row 4, col 5: a cross at (10 mm, 8 mm)
    assert _marks(rec.tactile.plot_pressure_map(position=3)) == [(10.0, 8.0)]
    assert _marks(rec.tactile.plot_pressure_map(position=2)) == []
    assert _marks(rec.tactile.plot_pressure_map()) == [(10.0, 8.0)]  # saturated in any frame
    kpa = rec.where(rec < 255, 200.0).assign_attrs(units="kPa", saturation_pressure_kPa=200.0)
    assert _marks(kpa.tactile.plot_pressure_map(position=3)) == [(10.0, 8.0)]


def test_the_centre_of_force_is_drawn_over_the_map_at_the_sensor_scale():
    rec = moving_raw(saturate=()).assign_attrs(units="kPa")
    ax = rec.tactile.plot_pressure_map(position=5)
    (line,) = [ln for ln in ax.lines if ln.get_label() == "centre of force"]
    # frame 5: rows 5-6, cols 3-4 at equal pressure: centre (row 11 mm, col 7 mm)
    assert (float(line.get_xdata()[0]), float(line.get_ydata()[0])) == (7.0, 11.0)
    path = rec.tactile.plot_cof_path()
    assert path.get_xlim() == (-1.0, 15.0) and path.get_ylim() == (39.0, -1.0)  # whole sensor


def test_a_given_summary_draws_the_centre_of_force_the_maps_compute():
    """``plot_pressure_map(summary=)`` (the report passes the summary it has) draws the same
    centre of force as the map computes itself: over the peak map and in one frame."""
    rec = moving_raw(saturate=()).assign_attrs(units="kPa")
    summary = rec.tactile.frame_summary().compute()
    for kwargs in ({}, {"position": 5}):
        own, given = (rec.tactile.plot_pressure_map(**kwargs, **extra)
                      for extra in ({}, {"summary": summary}))
        (a,), (b,) = ([ln for ln in ax.lines if ln.get_label() == "centre of force"]
                      for ax in (own, given))
        for get in ("get_xdata", "get_ydata"):
            np.testing.assert_allclose(getattr(b, get)(), getattr(a, get)(), rtol=0,
                                       atol=1e-12, equal_nan=True)


def test_png_pixels_are_those_savefig_writes():
    """Figures are drawn once and encoded by tactilecal._png: the same pixels as
    ``savefig`` at the same dpi (RGB where every pixel is opaque)."""
    import io

    from PIL import Image

    from tactilecal._png import png_bytes

    ax = moving_raw().tactile.plot_pressure_map()
    buf = io.BytesIO()
    ax.figure.savefig(buf, format="png", dpi=60)
    ours = np.asarray(Image.open(io.BytesIO(png_bytes(ax.figure, 60))))
    theirs = np.asarray(Image.open(buf))
    assert ours.shape[2] == 3 and (theirs[..., 3] == 255).all()
    np.testing.assert_array_equal(ours, theirs[..., :3])


def test_units_and_saturated_frames_on_the_force_plot():
    raw = moving_raw()  # as MPa: 0.1 MPa under the patch, 0.25 MPa = saturation where 255
    rec = raw.where(raw < 255, 250.0) / 1000.0
    rec.attrs = {**raw.attrs, "units": "MPa", "saturation_pressure_kPa": 250.0}
    ax = rec.tactile.plot_pressure_map(position=3)
    assert ax.images[0].colorbar.ax.get_ylabel() == "pressure [MPa]"  # its own unit
    psi = rec.tactile.plot_pressure_map(position=3, units="psi")
    assert psi.images[0].colorbar.ax.get_ylabel() == "pressure [psi]"
    force = rec.tactile.plot_force_time()
    ticks = [ln for ln in force.lines if str(ln.get_label()).startswith("saturated frames")]
    assert len(ticks) == 1 and ticks[0].get_xdata().tolist() == [pytest.approx(0.3)]


@pytest.mark.slow  # end to end: a command through every figure file
def test_plot_a_recording_from_the_command_line(fscan_asf, iscan_csv, tmp_path, capsys):
    out = tmp_path / "figs"
    assert main(["-q", "plot", str(fscan_asf), "--out", str(out), "--split-contacts",
                 "--json", "--dpi", "30"]) == 0
    names = sorted(p.rsplit("/", 1)[-1] for p in json.loads(capsys.readouterr().out)["figures"])
    assert names == ["cof_path.png", "cof_time.png", "force_time.png", "frame.png",
                     "peak_map.png", "region_centres.png", "region_forces.png"]
    assert all((out / n).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" for n in names)
    # a raw recording without a calibration: its maps in raw readings, no force
    assert main(["-q", "plot", str(iscan_csv), "--out", str(tmp_path / "raw"),
                 "--frame", "100", "--dpi", "30"]) == 0
    assert sorted(p.name for p in (tmp_path / "raw").iterdir()) == ["frame.png", "peak_map.png"]


def test_plot_refuses_a_frame_the_recording_lacks(iscan_csv, tmp_path, capsys):
    assert main(["-q", "plot", str(iscan_csv), "--out", str(tmp_path / "x"),
                 "--frame", "999"]) == 1
    assert "--frame 999 is not a frame of the recording (frames 1..309)" in capsys.readouterr().err


def test_a_figure_that_fails_to_write_leaves_the_file_as_it_was(tmp_path, monkeypatch):
    """Figures are written under a temporary name and renamed: a write that fails half way
    (a full disk) leaves no partial PNG and an earlier one untouched."""
    import pathlib

    rec = moving_raw()
    (tmp_path / "frame.png").write_bytes(b"earlier")
    written = rec.tactile.save_figures(tmp_path)
    assert (tmp_path / "frame.png").read_bytes().startswith(b"\x89PNG")
    (tmp_path / "frame.png").write_bytes(b"earlier")
    (tmp_path / "peak_map.png").unlink()

    def half_then_fail(self, data):
        with open(self, "wb") as out:
            out.write(data[:len(data) // 2])
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(pathlib.Path, "write_bytes", half_then_fail)
    with pytest.raises(OSError, match="No space left"):
        rec.tactile.save_figures(tmp_path)
    assert (tmp_path / "frame.png").read_bytes() == b"earlier"
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(
        p.name for p in written if p.name != "peak_map.png")


def test_movie_gif_shows_every_frame_with_its_centre(tmp_path):
    from PIL import Image

    from tactilecal.analysis._movie import _animator

    rec = moving_raw()
    path = rec.tactile.write_movie(tmp_path / "m.gif", max_frames=6)
    with Image.open(path) as gif:
        assert gif.n_frames == 6  # every 2nd of 12 frames
        first = np.asarray(gif.convert("RGB"))
        gif.seek(3)
        assert np.abs(np.asarray(gif.convert("RGB")).astype(int) - first).sum() > 0
    fig, update = _animator(rec, np.arange(12), rec["time"].values, None, None, 72)
    update(5)
    (cross,) = [ln for ln in fig.axes[0].lines if ln.get_marker() == "P"]
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == (7.0, 11.0)
    assert fig.axes[0].get_title() == "frame 6, t = 0.500 s"


def test_movie_mp4_falls_back_to_gif_without_ffmpeg(tmp_path, monkeypatch, capsys):
    from matplotlib import animation

    from tactilecal.io import write_tekscan

    monkeypatch.setattr(animation.writers, "is_available", lambda name: False)
    write_tekscan(moving_raw(), tmp_path / "m.csv")
    assert main(["movie", str(tmp_path / "m.csv"), "--out", str(tmp_path / "m.mp4")]) == 0
    assert (tmp_path / "m.gif").is_file() and not (tmp_path / "m.mp4").exists()
    assert "ffmpeg is not installed: wrote an animated GIF" in capsys.readouterr().err
    with pytest.raises(TactilecalError, match=r"movie .*m.avi ends in '.avi'; expected .mp4"):
        moving_raw().tactile.write_movie(tmp_path / "m.avi")


def test_movie_mp4_with_ffmpeg(tmp_path):
    from matplotlib import animation

    if not animation.writers.is_available("ffmpeg"):
        pytest.skip("ffmpeg not installed: the MP4 path is not exercised (GIF is)")
    path = moving_raw().tactile.write_movie(tmp_path / "m.mp4")
    assert path.suffix == ".mp4" and path.read_bytes()[4:8] == b"ftyp"


def test_a_failing_ffmpeg_is_one_error_naming_the_file(tmp_path):
    from tactilecal.analysis._movie import _write_mp4

    frames = iter([(4, 2, bytes(32))] * 3)
    with pytest.raises(TactilecalError, match=r"ffmpeg could not write .*m.mp4: .*expected "
                                              r"an MP4 \(write a .gif instead\)"):
        _write_mp4(frames, tmp_path / "m.mp4", 10.0, "false")


def test_info_and_plot_say_what_a_file_is(tmp_path, capsys, fscan_asf):
    from tactilecal.io import read_tekscan, write_netcdf

    write_netcdf(read_tekscan(fscan_asf), tmp_path / "walk.nc")
    assert main(["info", str(tmp_path / "walk.nc")]) == 0
    text = capsys.readouterr().out
    assert "frames: 205" in text and "max_value: 760 kPa" in text
    assert "calibration_point_1_raw_sum: 4798\n" in text
    from tactilecal.calibration import header_calibration

    cal = tmp_path / "cal.json"
    header_calibration(read_tekscan(fscan_asf)).to_json(cal)
    for command in ("info", "movie"):
        argv = [command, str(cal)] + (["--out", str(tmp_path / "m.gif")] if command == "movie"
                                      else [])
        assert main(argv) == 1
        assert "cal.json is a calibration file; expected a recording" in capsys.readouterr().err
