"""Manifests: loads from load_N or mass_kg + pad, plateau detection, line-numbered errors."""

import numpy as np
import pytest

from tactilecal.calibration import load_points
from tactilecal.calibration._manifest import find_plateau, load_frames
from tactilecal.simulate import deadweight_session, make_sensor

G = 9.80665


@pytest.fixture(scope="module")
def session_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("dw")
    session = deadweight_session(make_sensor("5051", seed=0), n_patches=6, seed=3,
                                 blank_frame_share=0.5)
    return session, session.write(out)


def test_load_points_matches_session(session_dir):
    session, manifest = session_dir
    points = load_points(manifest)
    assert len(points) == 6
    np.testing.assert_allclose([p.load_N for p in points], session.load_N, rtol=1e-12)
    for p, blank, frame, raw in zip(points, session.blank_frame, session.plateau_frame,
                                    session.raw.values, strict=True):
        assert p.sensel_area_mm2 == pytest.approx(1.6129)
        assert p.label and p.source.endswith(".csv")
        if blank:
            # plateau detection reports its choice; the plateau frames differ from the
            # manifest's frame only by read noise, so the raw sum is within 1 %
            assert p.note.startswith("frame blank: chose frame")
            assert p.raw_sum == pytest.approx(raw.sum(), rel=0.01)
        else:
            assert p.note == "" and p.frame == frame and p.raw_sum == raw.sum()
    assert load_frames(manifest).shape == (6, 44, 44)


def test_find_plateau_on_ramp_hold_release():
    total = np.r_[np.linspace(0, 100, 6), 100 + np.array([0.5, -0.3, 0.2, 0.1, -0.4, 0.3]),
                  np.linspace(80, 0, 4)]
    i, first, last, cv = find_plateau(total)
    assert (first, last) == (5, 11) and i == 8 and cv < 0.005
    with pytest.raises(ValueError, match="every frame has a total raw reading of 0"):
        find_plateau(np.zeros(5))


def _write(tmp_path, text):
    path = tmp_path / "m.csv"
    path.write_text(text)
    return path


def test_manifest_mass_and_pad_and_errors(tmp_path, session_dir):
    session, manifest = session_dir
    first = session.manifest_rows()[1]
    src = manifest.parent / first["file"]
    (tmp_path / "a.csv").write_bytes(src.read_bytes())
    pts = load_points(_write(tmp_path, "file,frame,mass_kg,pad_mass_g\na.csv,5,2,0.6\n"))
    assert pts[0].load_N == pytest.approx(19.619, abs=5e-4)  # Zvyagin Table 1
    pts = load_points(_write(tmp_path, "file,frame,load_N\na.csv,5,12.5\n"))
    assert pts[0].load_N == 12.5 and pts[0].frame == 5

    cases = [
        ("file,load_N\na.csv,1\n", r"m.csv has columns \['file', 'load_N'\]; expected file, "),
        ("file,frame,load_N\na.csv,5,\n", "m.csv line 2: load_N and mass_kg are both blank"),
        ("file,frame,load_N\na.csv,5,x\n", "m.csv line 2: load_N is 'x'; expected a number"),
        ("file,frame,load_N\na.csv,5,1\nb.csv,5,1\n", "m.csv line 3: file .*b.csv does not"),
        ("file,frame,load_N\na.csv,99,1\n", r"m.csv line 2: frame 99 is not in a.csv \(frames"),
        ("file,frame,load_N\n", "m.csv has no rows"),
    ]
    for text, message in cases:
        with pytest.raises(ValueError, match=message):
            load_points(_write(tmp_path, text))
    empty = tmp_path / "e.csv"
    empty.write_text("")
    with pytest.raises(ValueError, match="e.csv is empty"):
        load_points(empty)


def test_manifest_rejects_calibrated_file(tmp_path, fscan_asf):
    (tmp_path / "f.asf").write_bytes(fscan_asf.read_bytes())
    with pytest.raises(ValueError, match="m.csv line 2: f.asf has units 'kPa'; expected raw"):
        load_points(_write(tmp_path, "file,frame,load_N\nf.asf,1,10\n"))
