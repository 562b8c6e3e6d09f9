"""Dead-weight sessions: exact loads, readings from the law, Figure-4-like uneven patches."""

import re

import numpy as np
import pytest

from tactilecal.simulate import deadweight_session, make_sensor
from tactilecal.simulate._deadweight import DeadweightSession
from tactilecal.simulate._loads import PAD_MASS_G

G = 9.80665


@pytest.fixture(scope="module")
def sensor():
    return make_sensor("5051", seed=0)


@pytest.fixture(scope="module")
def session(sensor):
    return deadweight_session(sensor, n_patches=150, seed=0)


def peak_to_periphery(raw):
    """Peak reading over the 25th percentile of the patch's non-zero readings."""
    loaded = raw[raw > 0]
    return raw.max() / np.percentile(loaded, 25)


def test_true_total_force_equals_load(session):
    assert isinstance(session, DeadweightSession) and len(session) == 150
    total = session.force_N.sum(axis=(1, 2))
    np.testing.assert_allclose(total, session.load_N, rtol=1e-9, atol=0)
    assert (session.force_N >= 0).all()


def test_loads_use_zvyagin_table1_pad_masses(session):
    expected = (session.mass_kg + session.pad_mass_g / 1000) * G
    np.testing.assert_allclose(session.load_N, expected, rtol=1e-15)
    for side, pad in zip(session.pad_side_cm, session.pad_mass_g, strict=True):
        assert PAD_MASS_G[int(side)] == pad
    assert (PAD_MASS_G[1], PAD_MASS_G[5]) == (0.6, 16.1)
    one = (session.mass_kg == 2) & (session.pad_side_cm == 1)
    assert one.any()
    np.testing.assert_allclose(session.load_N[one], 19.619, atol=5e-4)  # paper's number
    assert set(session.mass_kg) <= {2, 5, 10} and set(session.pad_side_cm) <= {1, 2, 3}


def test_force_stays_under_the_pad(session, sensor):
    for i in range(0, 150, 10):
        rows, cols = np.nonzero(session.force_N[i])
        # a pad of side s cm covers at most ceil(s / pitch) + 1 sensels per axis
        limit = int(np.ceil(session.pad_side_cm[i] * 10 / sensor.row_spacing_mm)) + 1
        assert np.ptp(rows) + 1 <= limit and np.ptp(cols) + 1 <= limit


def test_readings_come_from_law_gain_and_noise(session, sensor):
    expected = sensor.gain * (session.force_N / sensor.A_N) ** (1 / sensor.b)
    raw = session.raw.values
    ok = ~sensor.dead & (expected > 4) & (expected < 254)
    assert ok.sum() > 10_000
    assert np.abs(raw - expected)[ok].max() <= 0.5 + 6 * sensor.read_noise
    unloaded = session.force_N == 0
    assert (raw[unloaded] == 0).all()


def test_peaks_are_5_to_10_times_the_periphery(session):
    # Zvyagin (2022), Figure 4: peak pressures 5-10x the periphery of the patch.
    ratios = np.array([peak_to_periphery(r) for r in session.raw.values])
    assert 5 <= ratios.mean() <= 10
    assert 0.6 <= np.mean((ratios >= 4) & (ratios <= 12)) <= 1


def test_no_saturation_by_default_and_dead_sensels_read_zero(session, sensor):
    raw = session.raw.values
    assert not session.saturated.any() and raw.max() < 255
    assert (raw[:, sensor.dead] == 0).all()
    assert sensor.dead.sum() == 3


def test_saturated_share_is_met_exactly(sensor):
    s = deadweight_session(sensor, n_patches=40, saturated_share=0.25, seed=4)
    assert s.saturated.sum() == 10
    np.testing.assert_array_equal(s.saturated, (s.raw.values == 255).any(axis=(1, 2)))
    np.testing.assert_allclose(s.force_N.sum(axis=(1, 2)), s.load_N, rtol=1e-9)


def test_deterministic_per_seed(sensor):
    a = deadweight_session(sensor, n_patches=12, seed=5)
    b = deadweight_session(sensor, n_patches=12, seed=5)
    c = deadweight_session(sensor, n_patches=12, seed=6)
    np.testing.assert_array_equal(a.raw.values, b.raw.values)
    np.testing.assert_array_equal(a.force_N, b.force_N)
    assert a.labels == b.labels
    assert not np.array_equal(a.force_N, c.force_N)


def test_labels_raw_dataarray_and_manifest_rows(session):
    assert all(re.fullmatch(r"(2|5|10)kg-[123]cm-\d{3}", x) for x in session.labels)
    assert session.labels[16].endswith("-017")
    assert session.raw.dims == ("frame", "row", "col") and session.raw.shape == (150, 44, 44)
    assert session.raw.attrs["units"] == "raw" and session.raw.attrs["sensor_type"] == "5051"
    rows = session.manifest_rows()
    assert list(rows[0]) == ["file", "frame", "mass_kg", "pad_mass_g", "label"]
    blanks = [r for r in rows if r["frame"] == ""]
    assert len(blanks) == 30  # blank_frame_share 0.2: every 5th row


def test_recording_has_ramp_then_plateau_holding_raw(session):
    rec = session.recording(3)
    n_ramp, n_plateau = session.ramp_frames, session.plateau_frames
    assert rec.sizes["frame"] == n_ramp + n_plateau
    sums = rec.sum(dim=("row", "col")).values
    assert (np.diff(sums[:n_ramp + 1]) > 0).all()
    plateau = sums[n_ramp:]
    assert np.ptp(plateau) / plateau.mean() < 0.02
    frame = session.plateau_frame[3]
    assert frame > n_ramp
    np.testing.assert_array_equal(rec.sel(frame=frame).values, session.raw.values[3])


@pytest.mark.parametrize(("kwargs", "match"), [
    ({"pad_sides_cm": (1, 7)}, r"pad_sides_cm: got \[7\]; expected sides of Zvyagin's Table 1"),
    ({"pad_sides_cm": ()}, r"pad_sides_cm: got \[\]; expected sides of Zvyagin's Table 1"),
    ({"masses_kg": (2, -5)}, r"masses_kg: got \(2, -5\); expected one or more positive"),
    ({"masses_kg": ()}, r"masses_kg: got \(\); expected one or more positive"),
    ({"saturated_share": 1.5}, r"saturated_share: got 1.5; expected a share between 0 and 1"),
    ({"blank_frame_share": -0.1}, r"blank_frame_share: got -0.1"),
    ({"n_patches": 0}, r"n_patches: got 0; expected a positive integer"),
    ({"plateau_frames": 0}, r"ramp_frames/plateau_frames: got 4/0"),
    ({"saturated_share": 1.0, "masses_kg": (2,), "pad_sides_cm": (3,), "n_patches": 2},
     r"saturated_share: 1.0 asks for 2 saturated and 0 unsaturated patches"),
])
def test_bad_arguments(sensor, kwargs, match):
    with pytest.raises(ValueError, match=match):
        deadweight_session(sensor, **kwargs)


def test_pad_larger_than_sensor():
    small = make_sensor((10, 10, 1.27), n_dead=0)
    with pytest.raises(ValueError, match=r"pad_sides_cm: a 3 cm pad is larger than the sensor"):
        deadweight_session(small, pad_sides_cm=(3,), n_patches=2)


def test_sensor_type_checked():
    with pytest.raises(TypeError, match="sensor: expected a SimulatedSensor"):
        deadweight_session("5051")


def test_written_session_reads_back_with_manifest_contract(tmp_path, sensor):
    import csv
    import json

    from tactilecal import read_tekscan

    s = deadweight_session(sensor, n_patches=10, seed=8)
    manifest = s.write(tmp_path / "session")
    assert manifest == tmp_path / "session" / "manifest.csv"
    with manifest.open(newline="") as fh:
        rows = list(csv.DictReader(fh))
    assert list(rows[0]) == ["file", "frame", "mass_kg", "pad_mass_g", "label"]
    assert [r["label"] for r in rows] == s.labels
    assert sum(r["frame"] == "" for r in rows) == 2
    for i, row in enumerate(rows):
        data = read_tekscan(manifest.parent / row["file"])
        assert data.shape == (12, 44, 44) and data.attrs["units"] == "raw"
        assert data.attrs["sensor_type"] == "5051"
        assert data.attrs["row_spacing_mm"] == pytest.approx(1.27)
        load = (float(row["mass_kg"]) + float(row["pad_mass_g"]) / 1000) * G
        assert load == pytest.approx(s.load_N[i], rel=1e-12)
        frame = int(row["frame"]) if row["frame"] else int(s.plateau_frame[i])
        np.testing.assert_array_equal(data.sel(frame=frame).values, s.raw.values[i])
    truth = json.loads((manifest.parent / "truth.json").read_text())
    assert truth["sensor"]["A_N"] == sensor.A_N and truth["sensor"]["b"] == sensor.b
    assert truth["sensor"]["dead_sensels"] == np.argwhere(sensor.dead).tolist()
