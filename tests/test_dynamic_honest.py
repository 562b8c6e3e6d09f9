"""Honest failure of the dynamic fit: a model that misses the phase is refused."""

import json

import numpy as np
import pytest

from tactilecal.cli import main
from tactilecal.dynamic import CorrectionFilter, fit_filter
from tactilecal.dynamic._fit import complex_r2
from tactilecal.simulate import DynamicSensor, sine_sweep

FAST = {"step_hz": 2, "cycles_high": 10, "fs_sensor_hz": 1000.0, "fs_reference_hz": 1250.0,
        "sensor_noise_N": 0.2, "reference_noise_N": 0.05}
VISCO = DynamicSensor(A=0.0, zeros_hz=(40.0,), poles_hz=(10.0,))  # gain 1 -> 0.25


@pytest.fixture(scope="module")
def thesis():
    return sine_sweep(seed=0, **FAST)


@pytest.fixture(scope="module")
def viscoelastic():
    sweep = sine_sweep(seed=0, response=VISCO, **FAST)
    return sweep.sensor, sweep.reference


def test_thesis_sensor_is_explained_by_its_zero_phase_model(thesis):
    filt = fit_filter(thesis.sensor, thesis.reference)
    assert filt.fit.r2_complex >= 0.9 and filt.forced is None


def test_viscoelastic_sensor_is_refused_with_the_reason(viscoelastic):
    with pytest.raises(ValueError, match=r"explains -?[\d.]+% of the complex correction .* phase "
                                         r"of up to \d+ degrees"):
        fit_filter(*viscoelastic, model="log")


def test_forced_filter_is_marked_in_filter_json(viscoelastic, tmp_path):
    filt = fit_filter(*viscoelastic, model="log", force=True)
    assert "zero-phase model" in filt.forced and "FORCED" in filt.summary()
    path = tmp_path / "FILTER.json"
    filt.to_json(path)
    saved = json.loads(path.read_text())
    assert saved["forced"] is True and saved["fit"]["r2_complex"] < 0.9
    assert CorrectionFilter.from_json(path).forced == filt.forced


def test_cli_refuses_in_one_line_and_forces_on_request(viscoelastic, tmp_path, capsys):
    sensor, reference = viscoelastic
    files = []
    for name, record in (("sensor.csv", sensor), ("ref.csv", reference)):
        path = tmp_path / name
        path.write_text("time_s,load_N\n" + "".join(
            f"{t:.17g},{v:.17g}\n" for t, v in zip(record.time.values, record.values, strict=True)))
        files.append(str(path))
    out = tmp_path / "F.json"
    assert main(["-q", "dynamic", "fit", *files, "--out", str(out), "--model", "log"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "complex correction" in err and not out.exists()
    assert err.startswith("tactilecal dynamic fit: error:")  # the action in the prefix
    assert "(pass --force to write the filter anyway" in err  # a switch, said as one
    assert main(["-q", "dynamic", "fit", *files, "--out", str(out), "--model", "log",
                 "--force"]) == 0
    assert "written with --force" in capsys.readouterr().err
    assert json.loads(out.read_text())["forced"] is True


def test_complex_r2_counts_a_missing_phase_as_unexplained():
    f_hz = np.linspace(1, 100, 100)
    gain = 1 + 0.2 * np.log(f_hz)
    assert complex_r2(gain, gain) == pytest.approx(1.0)
    lagged = gain * np.exp(-1j * 2 * np.pi * f_hz * 0.004)  # a 4 ms lag
    assert complex_r2(lagged, gain) < 0.5
    assert complex_r2(lagged, lagged) == pytest.approx(1.0)


def test_no_coherent_band_names_the_records_and_the_time_range():
    import xarray as xr

    rng = np.random.default_rng(0)
    t = np.arange(0, 20, 1 / 500)
    load = np.sin(2 * np.pi * 0.1 * t)  # a slow common load the alignment can lock onto
    sensor = xr.DataArray(load + rng.normal(scale=0.3, size=t.size), dims="time",
                          coords={"time": t}, attrs={"source": "s.csv"})
    reference = xr.DataArray(load + rng.normal(scale=0.3, size=t.size), dims="time",
                             coords={"time": t}, attrs={"source": "r.csv"})
    with pytest.raises(ValueError, match=r"s.csv and r.csv \(\d.*-\d.* s after alignment\): "
                                         r"only \d+ frequency bins have coherence"), \
            pytest.warns(UserWarning, match=r"the lag is ambiguous: .* s apart \(a periodic"):
        fit_filter(sensor, reference, model="log")  # two cycles of one sine: ambiguous
