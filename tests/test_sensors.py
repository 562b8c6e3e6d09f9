import dataclasses

import pytest

from tactilecal.sensors import CATALOGUE, SensorModel, custom_sensor, get_sensor, match_sensor


def test_5051_and_5051_350():
    s = get_sensor("5051")
    assert (s.rows, s.cols, s.row_spacing_mm, s.col_spacing_mm) == (44, 44, 1.27, 1.27)
    assert s.sensel_area_mm2 == pytest.approx(1.6129)
    assert s.width_mm == pytest.approx(55.88) and s.height_mm == pytest.approx(55.88)
    assert get_sensor("5051-350").capacity_kPa == pytest.approx(2413.0, abs=0.5)


def test_5101_twice_the_5051():
    small, big = get_sensor("5051"), get_sensor("5101")
    assert (big.rows, big.cols) == (44, 44)
    assert big.width_mm == pytest.approx(2 * small.width_mm)
    assert big.sensel_area_mm2 == pytest.approx(4 * small.sensel_area_mm2)


def test_9500_from_gillis():
    s = get_sensor("9500")
    assert (s.rows, s.cols) == (14, 14)
    assert s.width_mm == pytest.approx(71.1, abs=0.05)
    assert s.max_rate_hz == 4000


def test_6900_matches_the_real_file(iscan_csv):
    from tactilecal.io import read_tekscan

    data = read_tekscan(iscan_csv)
    s = get_sensor(data.attrs["sensor_type"])
    assert (s.rows, s.cols) == (data.sizes["row"], data.sizes["col"])
    assert s.sensel_area_mm2 == pytest.approx(data.attrs["sensel_area_mm2"])
    assert s.row_spacing_mm == pytest.approx(data.attrs["row_spacing_mm"])


def test_every_entry_has_provenance_and_is_frozen():
    for key, s in CATALOGUE.items():
        assert s.name == key and s.notes
    with pytest.raises(dataclasses.FrozenInstanceError):
        CATALOGUE["5051"].rows = 3


def test_lookup_is_case_insensitive():
    assert get_sensor("fscan") is CATALOGUE["FSCAN"]
    assert get_sensor(9500) is CATALOGUE["9500"]


def test_unknown_sensor():
    with pytest.raises(ValueError, match=r"unknown sensor 'XYZ'; expected one of"):
        get_sensor("XYZ")


def test_custom_sensor():
    s = custom_sensor(8, 4, 2.5, capacity_kPa=100.0)
    assert s.col_spacing_mm == 2.5 and s.sensel_area_mm2 == 6.25
    assert s.to_attrs() == {"sensor_type": "custom", "row_spacing_mm": 2.5,
                            "col_spacing_mm": 2.5, "sensel_area_mm2": 6.25}


@pytest.mark.parametrize("kwargs, match", [
    ({"rows": 0}, r"rows must be a positive integer; got 0"),
    ({"cols": 2.5}, r"cols must be a positive integer; got 2.5"),
    ({"row_spacing_mm": -1.0}, r"row_spacing_mm must be a positive number; got -1.0"),
    ({"capacity_kPa": 0}, r"capacity_kPa must be a positive number; got 0"),
])
def test_bad_sensor_fields(kwargs, match):
    args = {"name": "x", "rows": 2, "cols": 2, "row_spacing_mm": 1.0, "col_spacing_mm": 1.0}
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        SensorModel(**args)


def test_4010n_knee_sensor_as_its_exports_describe_it():
    s = get_sensor("4010n")
    assert (s.rows, s.cols) == (22, 34)
    assert s.row_spacing_mm == s.col_spacing_mm == 2.0 and s.sensel_area_mm2 == 4.0


def test_match_by_sensor_type_then_grade_suffix():
    assert match_sensor("9500").entry is CATALOGUE["9500"]
    hit = match_sensor("5051-1000", rows=44, cols=44, row_spacing_mm=1.27, col_spacing_mm=1.27)
    assert hit.entry is CATALOGUE["5051"] and "without the pressure grade" in hit.how
    assert "but the file" not in hit.how


def test_match_by_geometry_when_the_name_is_unknown():
    hit = match_sensor("", rows=22, cols=34, row_spacing_mm=2.0, col_spacing_mm=2.0)
    assert hit.entry is CATALOGUE["4010N"] and hit.how.startswith("geometry 22 x 34")
    miss = match_sensor("XYZ", rows=3, cols=5, row_spacing_mm=2.0, col_spacing_mm=2.0)
    assert miss.entry is None and "no entry with 3 x 5" in miss.how


def test_geometry_shared_by_two_entries_is_not_guessed():
    # the 5051 and the 5051-350 have the same grid: a nameless file cannot tell them apart
    hit = match_sensor(None, rows=44, cols=44, row_spacing_mm=1.27, col_spacing_mm=1.27)
    assert hit.entry is None and "several entries (5051, 5051-350)" in hit.how


def test_a_name_whose_geometry_differs_is_reported_with_the_difference():
    hit = match_sensor("5051", rows=28, cols=28, row_spacing_mm=2.54, col_spacing_mm=1.27)
    assert hit.entry is CATALOGUE["5051"]
    assert "grid is 28 x 28, the entry's 44 x 44" in hit.how
    assert "row spacing is 2.54 mm, the entry's 1.27 mm" in hit.how
