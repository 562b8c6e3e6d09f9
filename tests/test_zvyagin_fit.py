"""Zvyagin (2022) end to end: truth recovered, Table 2, bad input, JSON round trip."""

import json
import warnings

import numpy as np
import pytest

import tactilecal
from tactilecal.calibration import CalibrationPoint, CalibrationResult, points_from_frames
from tactilecal.calibration.methods.zvyagin import Options, ZvyaginResult
from tactilecal.calibration.methods.zvyagin._calibrate import load_groups
from tactilecal.calibration.methods.zvyagin._calibrate import zvyagin_fit as _zvyagin_fit
from tactilecal.calibration.methods.zvyagin._fit import patch_power_sums, saturation_pressure_MPa
from tactilecal.sensors import get_sensor
from tactilecal.simulate import patch_histograms

SENSEL_AREA_5051_MM2 = get_sensor("5051").sensel_area_mm2


def zvyagin_fit(h, load, *, labels=None, sensel_area_mm2=SENSEL_AREA_5051_MM2, censored=None,
                **options):
    """Zvyagin's procedure on histograms, its options as keywords (the tests' shorthand)."""
    return _zvyagin_fit(h, load, Options(**options), labels=labels,
                        sensel_area_mm2=sensel_area_mm2, censored=censored)


def _points(h, load, area=1.6129):
    return [CalibrationPoint(histogram=hh, load_N=f, raw_sum=float(hh @ np.arange(256)),
                             loaded_cells=int(hh[1:].sum()), saturated_cells=int(hh[255]),
                             sensel_area_mm2=area) for hh, f in zip(h, load, strict=True)]

# Table 2 of Zvyagin (2022) as printed in the source: A0 (as printed), b0, p_s (MPa).
TABLE2 = [
    ("Sensor1 21 Mar", "0.00358", 1.164, 1.403), ("Sensor1 31 Mar", "0.00398", 1.136, 1.336),
    ("Sensor1 14 Apr", "0.00413", 1.120, 1.268), ("Sensor1 18 Apr", "0.00379", 1.141, 1.306),
    ("Sensor2 21 Mar", "0.0023", 1.236, 1.347), ("Sensor2 31 Mar", "0.00232", 1.227, 1.289),
    ("Sensor2 14 Apr", "0.00255", 1.205, 1.252), ("Sensor2 18 Apr", "0.00265", 1.201, 1.273),
]


@pytest.mark.parametrize(("row", "a_txt", "b0", "ps_MPa"), TABLE2)
def test_table2_saturation_pressure(row, a_txt, b0, ps_MPa):
    """p_s = A0 255^b0 / (1.27 mm)^2 (eq. 16) within what the printed rounding allows.

    A0 is printed to its last digit u (0.00001, or 0.0001 for '0.0023'): relative slack
    u / 2 / A0 (0.12-2.2%); b0 to 0.001: 0.0005 ln 255 = 0.28%; p_s to 0.001 MPa.
    """
    a0 = float(a_txt)
    unit = 10.0 ** -len(a_txt.split(".")[1])
    tol = 0.5 * unit / a0 + 0.0005 * np.log(255) + 0.0005 / ps_MPa
    got = saturation_pressure_MPa(a0, b0, SENSEL_AREA_5051_MM2)
    assert got == pytest.approx(ps_MPa, rel=tol), row


def _synthetic(n=60, seed=3, **kw):
    return patch_histograms(n, A_N=0.0035, b=1.16, seed=seed, **kw)


@pytest.mark.parametrize("mode", ["faithful", "robust"])
def test_truth_recovered_on_patch_histograms(mode):
    h, load, _ = _synthetic(seed=3)
    res = zvyagin_fit(h, load, mode=mode)
    # A and b trade off along a ridge (the pairs' power law); loads are what is pinned down
    assert res.b0 == pytest.approx(1.16, abs=0.08)
    assert res.A0 == pytest.approx(0.0035, rel=0.35)
    hv, fv, _ = _synthetic(seed=4)
    err = res.A0 * patch_power_sums(hv, res.b0)[:, 0] / fv - 1
    assert np.mean(np.abs(err) < 0.05) >= 0.8
    assert res.power_law["r2"] > 0.8
    assert res.p_s_MPa == pytest.approx(saturation_pressure_MPa(res.A0, res.b0, 1.6129))
    assert set(res.category_counts()) <= set("VORNX")
    assert sum(res.category_counts().values()) == 60 * 59 // 2
    assert np.all(res.pair_matrix == res.pair_matrix.T)
    assert sum(r["pairs"] for r in res.share_table) == 60 * 59 // 2


def test_share_table_and_groups():
    g, names = load_groups(np.array([19.619, 49.1, 98.2, 19.7, 98.07]))
    assert g.tolist() == [0, 1, 2, 0, 2] and names == ["2 kg", "5 kg", "10 kg"]
    h, load, _ = _synthetic(seed=5)
    res = zvyagin_fit(h, load)
    rows = {r["loads"]: r for r in res.share_table}
    assert list(rows) == ["2 kg - 2 kg", "2 kg - 5 kg", "2 kg - 10 kg", "5 kg - 5 kg",
                          "5 kg - 10 kg", "10 kg - 10 kg"]
    for r in rows.values():
        assert r["share"] == pytest.approx(r["valid"] / r["pairs"])


def test_modes_differ_only_where_documented():
    h, load, _ = _synthetic(seed=6)
    faithful = zvyagin_fit(h, load, mode="faithful")
    robust = zvyagin_fit(h, load, mode="robust")
    assert faithful.separation == robust.separation
    assert faithful.options["outliers"] == "none" and robust.options["outliers"] == "trim"
    assert (robust.pairs["category"] == "O").sum() > 0
    assert (faithful.pairs["category"] == "O").sum() == 0
    assert robust.final["b_range"][1] < faithful.final["b_range"][1]


def test_calibrate_entry_point_and_json_round_trip(tmp_path):
    from tactilecal.simulate import deadweight_session, make_sensor

    s = deadweight_session(make_sensor("5051", seed=1), n_patches=40, seed=2)
    points = points_from_frames(s.raw, s.load_N)
    cal = tactilecal.calibrate(points, method="zvyagin", mode="robust")
    assert cal.method == "zvyagin" and cal.model == "power"
    assert cal.params["A"] == pytest.approx(cal.diagnostics["final"]["A0"])
    assert cal.saturation_pressure_kPa == pytest.approx(1000 * cal.diagnostics["p_s_MPa"])
    path = tmp_path / "cal.json"
    cal.to_json(path)
    back = CalibrationResult.from_json(path)
    assert back == cal
    res = back.method_result
    direct = ZvyaginResult.from_details(json.loads(json.dumps(cal.diagnostics)))
    assert res.summary() == direct.summary() == cal.method_result.summary()
    assert res.separation == tuple(cal.diagnostics["separation"])
    assert res.d_summary["n_vectors"] == 725_305


def test_saturation_is_calibrates_and_an_unknown_option_is_a_type_error():
    h, load, _ = _synthetic(n=10, seed=7)
    pts = _points(h, load)
    assert tactilecal.calibrate(pts, method="zvyagin").options["saturated"] == "drop"
    with pytest.raises(TypeError, match=r"method='zvyagin' does not take the option\(s\) "
                                        r"\['extra'\]; expected some of \['mode', "):
        tactilecal.calibrate(pts, method="zvyagin", extra=10)
    for p in pts:
        p.sensel_area_mm2 = float("nan")
    with pytest.warns(UserWarning, match=r"no sensel area .* p_s \(eq. 16\) is unknown"):
        tactilecal.calibrate(pts, method="zvyagin")


# ---------------------------------------------------------------- bad input
def test_fewer_than_two_usable_patches():
    h, load, _ = _synthetic(n=3, seed=8)
    h[1:] = 0
    h[1:, 0] = 100
    with pytest.warns(UserWarning, match=r"patches patch 1, patch 2 have no loaded sensel"):
        with pytest.raises(ValueError, match=r"1 usable patch\(es\) of 3; expected at least 2 "
                                             r"\(left out: patch 1: empty frame"):
            zvyagin_fit(h, load)


def test_empty_frames_are_left_out_with_a_warning():
    h, load, _ = _synthetic(n=30, seed=9)
    h[4] = 0
    with pytest.warns(UserWarning, match=r"patches patch 4 have no loaded sensel"):
        res = zvyagin_fit(h, load)
    assert not res.usable[4] and res.excluded == {4: "empty frame"}
    assert (res.pair_matrix[4, np.arange(30) != 4] == "X").all()


def test_saturated_patches_are_dropped_by_default():
    h, load, _ = _synthetic(n=30, seed=10, pad_sides_cm=(1, 2))
    sat = np.nonzero(h[:, 255] > 0)[0]
    assert sat.size > 0
    cal = tactilecal.calibrate(_points(h, load), method="zvyagin")
    assert np.flatnonzero(~cal.points["used"].to_numpy()).tolist() == sat.tolist()
    assert cal.points["reason"][sat[0]].startswith("saturated")
    kept = np.setdiff1d(np.arange(30), sat)
    direct = zvyagin_fit(h[kept], load[kept], labels=[f"frame {k + 1}" for k in kept])
    assert (cal.params["A"], cal.params["b"]) == (direct.A0, direct.b0)


def test_one_load_warns():
    h, load, _ = patch_histograms(30, masses_kg=(5,), pad_sides_cm=(2, 3, 4), seed=11)
    with pytest.warns(UserWarning, match=r"all 30 usable patches carry one load \(5 kg\)"):
        zvyagin_fit(h, load)


def test_no_root_above_three():
    h = np.zeros((3, 256), dtype=np.int64)
    h[:, 50] = [10, 20, 40]           # more sensels ...
    load = np.array([100.0, 50.0, 25.0])   # ... carry less load: no root Y > 3
    with pytest.raises(ValueError, match=r"no pair of the 3 usable patches has a root Y > 3 "):
        zvyagin_fit(h, load, mode="faithful")
    with pytest.raises(ValueError, match=r"has a root Y > 1.732 of eq"):  # robust: b > 0.5
        zvyagin_fit(h, load)


def test_too_few_valid_pairs():
    h, load, _ = _synthetic(n=6, seed=12)
    with pytest.raises(ValueError, match=r"valid pair\(s\) \(A, b\); expected at least 3 .* "
                                         r"rejected by the 0% raw-sum rule"):
        zvyagin_fit(h, load, max_relerr=0.0)


def test_bad_loads_labels_and_options():
    h, load, _ = _synthetic(n=5, seed=13)
    bad = load.copy()
    bad[2] = -1
    with pytest.raises(ValueError, match=r"load_N of patches patch 2 is \[-1.0\]; expected"):
        zvyagin_fit(h, bad)
    with pytest.raises(ValueError, match=r"load_N has 4 values; expected one per patch \(5\)"):
        zvyagin_fit(h, load[:4])
    with pytest.raises(ValueError, match=r"labels has 2 names; expected one per patch \(5\)"):
        zvyagin_fit(h, load, labels=["a", "b"])
    with pytest.raises(ValueError, match=r"mode='paper' is not an option of zvyagin; "
                                         r"expected one of \('faithful', 'robust'\)"):
        zvyagin_fit(h, load, mode="paper")
    with pytest.raises(ValueError, match=r"saturated='clip' is not an option of every method"):
        tactilecal.calibrate(_points(h, load), method="zvyagin", saturated="clip")
    with pytest.raises(ValueError, match=r"b_range = \(1.5, 1.2\); expected 0 < b_min < b_max"):
        zvyagin_fit(h, load, b_range=(1.5, 1.2))
    with pytest.raises(ValueError, match=r"b_range='all'; expected"):
        zvyagin_fit(h, load, b_range="all")


def test_energy_minimum_at_range_end_warns():
    h, load, _ = _synthetic(n=30, seed=14)
    with pytest.warns(UserWarning, match=r"E\(b0\) is smallest at the end of the b range"):
        res = zvyagin_fit(h, load, b_range=(1.3, 1.5), mode="faithful")
    assert res.final["at_bound"] and res.b0 == pytest.approx(1.3)


def test_no_silent_nan():
    h, load, _ = _synthetic(n=30, seed=15)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = zvyagin_fit(h, load)
    assert np.isfinite([res.A0, res.b0, res.alpha, res.beta, res.p_s_MPa, res.d_min]).all()
    assert np.isfinite(res.error_pct).all()


def test_grey_patch_pairs_with_nothing():
    h, load, _ = _synthetic(n=30, seed=16)
    load = load.copy()
    # a heavy load on a few low readings: every coefficient of eq. (12) is negative with
    # any partner, so no root Y > 3 (Descartes' rule of signs)
    h[7] = 0
    h[7, 4] = 20
    load[7] = 98.1
    res = zvyagin_fit(h, load)
    assert res.grey.tolist() == [7]
    assert res.partner_share[7] == 0.0
    assert set(np.delete(res.pair_matrix[7], 7)) == {"N"}


def test_mislabelled_heavy_load_drives_faithful_E_to_the_range_end():
    h, load, _ = _synthetic(n=30, seed=16)
    load = load.copy()
    load[7] *= 50.0
    with pytest.warns(UserWarning, match=r"E\(b0\) is smallest at the end of the b range"):
        zvyagin_fit(h, load, mode="faithful")
