"""Regions: boxes, polygons, mask files, contacts found automatically, per-region numbers.

Truth: a simulated two-compartment knee recording (its contacts' sensels and forces are
known), and the real exports placed side by side (each sensel's file is known).
"""

import numpy as np
import pytest
import xarray as xr

import tactilecal.analysis  # noqa: F401 - registers recording.tactile
from tactilecal import TactilecalError
from tactilecal.analysis import Regions
from tactilecal.simulate import compartment_recording


def _matched(regions, truth_sets, loaded):
    """Share of the loaded sensels of each truth set that lie in its best region."""
    shares = []
    for truth in truth_sets:
        hits = [(regions[name] & truth & loaded).sum() for name in regions]
        shares.append(max(hits) / (truth & loaded).sum())
    return shares


@pytest.fixture(scope="module")
def knee():
    return compartment_recording(seed=3)


def test_two_compartments_are_found_with_their_forces_and_centres(knee):
    rec = knee.recording
    regions = rec.tactile.split_contacts()
    assert regions.names == ["contact 1", "contact 2"] and regions.is_partition()
    loaded = knee.contact_sensels.any(axis=0)
    assert min(_matched(regions, knee.contact_sensels, loaded)) >= 0.99  # measured: 1.0
    out = rec.tactile.regions(regions)
    force = out.summary["force_N"].values.T  # (frame, region): left, right
    np.testing.assert_allclose(force, knee.force_N, rtol=1e-12, atol=1e-9)
    total = rec.tactile.force().values
    assert np.max(np.abs(force.sum(axis=1) - total)) <= 1e-9 * total.max()
    loaded_frames = knee.force_N.min(axis=1) > 0
    centres = np.stack([out.summary["cof_row_mm"].values.T, out.summary["cof_col_mm"].values.T],
                       axis=-1)
    np.testing.assert_allclose(centres[loaded_frames], knee.centre_mm[loaded_frames],
                               atol=1e-9)
    # the whole-sensor centre lies between the compartments, on no contact at all
    whole = rec.tactile.centre()["cof_col_mm"].values[loaded_frames]
    pad_gap = np.flatnonzero(~knee.pads.any(axis=(0, 1))) * rec.attrs["col_spacing_mm"]
    assert np.mean((whole > pad_gap.min() - 6) & (whole < pad_gap.max() + 6)) > 0.5
    dt = 1 / 100.0
    impulse = (knee.force_N[1:] + knee.force_N[:-1]).sum(axis=0) * dt / 2
    np.testing.assert_allclose(out.table["impulse_N_s"], impulse, rtol=1e-12)
    np.testing.assert_allclose(out.table["share_of_impulse"].sum(), 1.0, rtol=1e-12)
    assert out.table["peak_force_N"].tolist() == pytest.approx(knee.force_N.max(axis=0).tolist())


def _side_by_side(left, right, gap_cols=3):
    """Two recordings of one clock next to each other, blank columns between them."""
    gap = np.full((left.sizes["frame"], left.sizes["row"], gap_cols), np.nan)
    values = np.concatenate([left.values, gap, right.values], axis=2)
    out = xr.DataArray(values, dims=("frame", "row", "col"),
                       coords={"time": ("frame", left["time"].values)},
                       attrs={**left.attrs, "source": "side by side"})
    truth_left = np.zeros(values.shape[1:], bool)
    truth_left[:, :left.sizes["col"]] = True
    truth_right = np.zeros(values.shape[1:], bool)
    truth_right[:, left.sizes["col"] + gap_cols:] = True
    return out, [truth_left, truth_right]


def test_real_exports_one_contact_each_and_two_side_by_side(realdata):
    from tactilecal.io import read_tekscan

    left = read_tekscan(realdata / "footPress_FrasP01L.asf")
    right = read_tekscan(realdata / "footPress_FrasP01R.asf")
    finger = read_tekscan(realdata / "pressuRe_iscan_test.csv")
    for rec in (left, right, finger):
        regions = rec.tactile.split_contacts()
        assert len(regions) == 1 and regions.is_partition(), rec.attrs["source"]
    for a, b in ((left, right), (finger, finger.isel(col=slice(None, None, -1)))):
        both, truth = _side_by_side(a, b.assign_coords(col=a["col"]))
        regions = both.tactile.split_contacts()
        loaded = np.nan_to_num(both.values).max(axis=0) > 0
        assert len(regions) == 2
        assert min(_matched(regions, truth, loaded)) >= 0.99  # measured: 1.0 for both pairs
        if both.attrs["units"] == "raw":
            continue  # forces need a calibration
        out = both.tactile.regions(regions)
        total = both.tactile.force().values
        summed = out.summary["force_N"].sum("region").values
        assert np.max(np.abs(summed - total)) <= 1e-9 * np.nanmax(total)
        np.testing.assert_allclose(out.summary["force_N"].values,
                                   [a.tactile.force().values, b.tactile.force().values],
                                   rtol=1e-12)


def _two_dots(gap_sensels, *, pitch=2.0, blank=False):
    values = np.zeros((1, 3, 4 + gap_sensels))
    values[0, 1, 1] = values[0, 1, 2 + gap_sensels] = 100.0
    if blank:
        values[0, :, 2] = np.nan
    return xr.DataArray(values, dims=("frame", "row", "col"),
                        attrs={"units": "kPa", "row_spacing_mm": pitch,
                               "col_spacing_mm": pitch, "sensel_area_mm2": pitch * pitch})


@pytest.mark.parametrize(("gap_sensels", "gap_mm", "contacts"),
                         [(4, 8.0, 1), (4, 7.9, 2), (5, 8.0, 2), (6, 12.0, 1), (0, 0.0, 1)])
def test_gaps_up_to_gap_mm_are_one_contact(gap_sensels, gap_mm, contacts):
    # 2 mm sensels; gaps of up to gap_mm, rounded down to an even number of sensels, close
    assert len(_two_dots(gap_sensels).tactile.split_contacts(gap_mm=gap_mm)) == contacts


def test_blank_sensels_always_separate_contacts():
    rec = _two_dots(2, blank=True)
    assert len(rec.tactile.split_contacts(gap_mm=100.0)) == 2
    assert len(_two_dots(2).tactile.split_contacts(gap_mm=100.0)) == 1


def test_a_small_area_joins_the_nearest_contact():
    values = np.zeros((1, 1, 30))
    values[0, 0, 0:5] = 100.0
    values[0, 0, 20:25] = 100.0
    values[0, 0, 10] = 10.0  # 10 / 1010 = 1 % of the load, nearer the first contact
    rec = xr.DataArray(values, dims=("frame", "row", "col"),
                       attrs={"units": "kPa", "row_spacing_mm": 1.0, "col_spacing_mm": 1.0})
    regions = rec.tactile.split_contacts(gap_mm=2.0)
    assert regions.names == ["contact 1", "contact 2"]
    # every sensel goes to the nearest contact: columns 0..11 to the first, 13.. to the second
    assert regions["contact 1"][0, :12].all() and regions["contact 2"][0, 13:].all()
    assert len(rec.tactile.split_contacts(gap_mm=2.0, min_share=0.005)) == 3


def test_regions_from_boxes_polygons_and_mask_files(tmp_path):
    shape = (4, 5)
    (tmp_path / "m.csv").write_text("0,0,0,0,0\n0,1,1,0,0\n0 1 1 0 0\n0,0,0,0,0\n")
    np.save(tmp_path / "m.npy", np.eye(4, 5, dtype=bool))
    regions = Regions.from_specs({
        "box": (0, 2, 0, 5), "text box": "2:,3:", "poly": "poly:0,0;3,0;3,3",
        "csv": tmp_path / "m.csv", "npy": str(tmp_path / "m.npy")}, shape=shape)
    assert regions["box"].sum() == 10 and regions["text box"].sum() == 4
    # the triangle (0,0)-(3,0)-(3,3) holds the sensel centres with col <= row
    np.testing.assert_array_equal(regions["poly"][:, :4], np.tril(np.ones((4, 4), bool)))
    assert regions["csv"].sum() == 4 and regions["npy"].sum() == 4
    assert not regions.is_partition()
    assert regions.how["csv"] == "mask file m.csv" and regions.how["poly"].startswith("polygon")
    with pytest.raises(TactilecalError, match="regions .* overlap"):
        regions.labels()


def test_user_regions_give_the_hand_computed_numbers():
    p = np.zeros((3, 2, 4))
    p[:, 0, 0] = [0.0, 100.0, 50.0]
    p[:, 1, 3] = [200.0, 200.0, 0.0]
    rec = xr.DataArray(p, dims=("frame", "row", "col"),
                       coords={"time": ("frame", [0.0, 0.5, 1.0])},
                       attrs={"units": "kPa", "sensel_area_mm2": 10.0, "row_spacing_mm": 1.0,
                              "col_spacing_mm": 2.0})
    out = rec.tactile.regions({"left": (0, 2, 0, 2), "right": "0:2,2:4"})
    table = out.table.set_index("region")
    assert table.loc["left", "peak_force_N"] == pytest.approx(1.0)  # 100 kPa x 10 mm2
    assert table.loc["left", "impulse_N_s"] == pytest.approx(0.5 * (0 + 1) / 2 + 0.5 * 1.5 / 2)
    assert table.loc["right", "pti_max_sensel_kPa_s"] == pytest.approx(150.0)
    assert table.loc["right", "mean_cof_col_mm"] == pytest.approx(6.0)
    assert out.summary["cof_row_mm"].sel(region="right").values[:2].tolist() == [1.0, 1.0]


@pytest.mark.parametrize(("spec", "message"), [
    ((0, 9, 0, 2), r"region 'r': box \(0, 9, 0, 2\) is empty or outside the 4 x 5 sensels"),
    ("poly:10,10;11,10;11,11", r"region 'r': polygon .* holds no sensel centre"),
    ("poly:1,1;2", r"region 'r': polygon vertex 2 is '2'; expected 'ROW,COL'"),
    ("poly:1,1;2,2", r"region 'r': polygon has 2 vertices; expected at least 3"),
    (np.ones((2, 2), bool), r"region 'r' mask has shape \(2, 2\); expected \(4, 5\)"),
    (np.zeros((4, 5), bool), r"region 'r' mask selects no sensel"),
    (3.5, r"region 'r' is 3.5; expected a box 'R0:R1,C0:C1'"),
])
def test_bad_region_specs_are_refused_naming_the_region(spec, message):
    with pytest.raises(TactilecalError, match=message):
        Regions.from_specs({"r": spec}, shape=(4, 5))


def test_bad_mask_files_are_refused_naming_the_file(tmp_path):
    (tmp_path / "two.csv").write_text("0,2,0,0,0\n" * 4)
    (tmp_path / "ragged.csv").write_text("0,1,0,0,0\n0,1\n0,0,0,0,0\n0,0,0,0,0\n")
    with pytest.raises(TactilecalError, match=r"line 1 of two.csv is 2.0; expected a whole "
                                              r"number .*<= 1"):
        Regions.from_specs({"r": tmp_path / "two.csv"}, shape=(4, 5))
    with pytest.raises(TactilecalError, match=r"ragged.csv: rows have \[2, 5\] values"):
        Regions.from_specs({"r": tmp_path / "ragged.csv"}, shape=(4, 5))
    with pytest.raises(FileNotFoundError, match="mask file .*nope.csv does not exist"):
        Regions.from_specs({"r": tmp_path / "nope.csv"}, shape=(4, 5))


def test_split_contacts_refuses_what_it_cannot_split():
    empty = _two_dots(2) * 0
    with pytest.raises(TactilecalError, match="no sensel is ever loaded"):
        empty.tactile.split_contacts()
    with pytest.raises(TactilecalError, match="gap_mm is -1; expected a width >= 0"):
        _two_dots(2).tactile.split_contacts(gap_mm=-1)
    with pytest.raises(TactilecalError, match="min_share is 1.5; expected a share in 0..1"):
        _two_dots(2).tactile.split_contacts(min_share=1.5)
    with pytest.raises(TactilecalError, match=r"regions are for a 4 x 5 sensor; .* has 3 x 6"):
        _two_dots(2).tactile.regions(Regions({"a": np.ones((4, 5), bool)}))
