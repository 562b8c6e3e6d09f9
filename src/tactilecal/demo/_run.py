"""``tactilecal demo``: the whole path on bundled synthetic data, with its truth beside it.

Steps (each writes its files under ``out_dir``):

1. Static calibration of the bundled session ``a`` (80 dead-weight patches, Zvyagin 2022
   style) by every method, saved as calibration JSON (``calibrations/``).
2. Validation of each on the held-out session ``b`` (``validation/``), and the fitted
   (A, b) against the simulated sensor's true law.
3. A loading-machine recording of the same sensor (ramp and hold, Gillis 2013, 5.3.2) with
   its load-cell record, simulated and written as I-Scan ASCII + CSV (``experiment/``);
   movie calibration on it; the dead-weight calibration applied to it, analysed per frame
   and compared with the true load at every hold.
4. Dynamic calibration (Gillis 2013, section 4): a simulated sine sweep fits the correction
   filter; a separate blind test (random sine sets) evaluates it (``dynamic/``).
5. ``report.html`` with all of it (every calibration and their comparison), and
   ``summary.json`` with the headline numbers.
"""

import shutil
import time
import warnings

import numpy as np

from tactilecal._atomic import OUTPUT_FOLDERS, check_folder, make_folder
from tactilecal._jsonutil import write_json
from tactilecal._provenance import provenance_of, write_sidecar

#: Methods run by the demo, in the order of the printed table.
DEMO_METHODS = ("auto", "power", "zvyagin", "power-2pt", "linear", "linear-offset", "piecewise",
                "lut", "polynomial")


def _say(quiet, message):
    if not quiet:
        print(message, flush=True)


def _static_calibrations(manifests, out, quiet):
    from tactilecal.calibration import calibrate, load_points, validate

    points_a = load_points(manifests["a"])
    points_b = load_points(manifests["b"])
    rows, results = [], {}
    for method in DEMO_METHODS:
        with warnings.catch_warnings():  # a law that does not fit is said in the table
            warnings.filterwarnings("ignore", message=f"{method} calibration: ")
            result = calibrate(points_a, method=method)
        result.to_json(out / "calibrations" / f"{method}.json", overwrite=True)
        check = validate(result, points_b)
        check.to_json(out / "validation" / f"{method}.json", overwrite=True)
        results[method] = result
        rows.append({"method": method, **check.metrics,
                     "A": result.params.get("A"), "b": result.params.get("b")})
        _say(quiet, f"  {method:<14} held-out patches within 5%: "
                    f"{check.metrics['within_5pct']:6.1%}  "
                    f"median |error| {check.metrics['median_abs_error_pct']:.2f}%"
                    + ("  (the law does not fit: lack_of_fit)" if result.lack_of_fit is not None
                       and result.lack_of_fit.flagged else ""))
    return rows, results


def _hold_errors(force_N, time_s, truth):
    """Mean calibrated force over the middle of each hold against its true level (%)."""
    errors = []
    for (start, stop), level in zip(truth.hold_windows_s, truth.loads_N, strict=True):
        mid = (time_s > start + 0.25 * (stop - start)) & (time_s < stop - 0.25 * (stop - start))
        errors.append(100.0 * (float(np.mean(force_N[mid])) - level) / level)
    return errors


def _experiment(sensor, calibration, out, quiet):
    from tactilecal._atomic import atomic_path
    from tactilecal.calibration import calibrate_movie
    from tactilecal.io import read_tekscan, write_netcdf
    from tactilecal.simulate import ramp_hold

    truth = ramp_hold(sensor, frame_rate_hz=20.0, loadcell_rate_hz=500.0, seed=5)
    paths = truth.write(out / "experiment", overwrite=True)
    recording = read_tekscan(paths["recording"])
    movie = calibrate_movie(recording, paths["loadcell"], method="power")
    movie.to_json(out / "calibrations" / "movie-power.json", overwrite=True)
    pressure = calibration.apply(recording, units="kPa")
    write_netcdf(pressure, out / "experiment" / "pressure.nc", overwrite=True)
    per_frame = pressure.tactile.frame_table()  # the columns of 'tactilecal analyze --out' (time_s)
    with atomic_path(out / "experiment" / "summary.csv") as tmp:
        per_frame.to_csv(tmp, index=False)
    write_sidecar(out / "experiment" / "summary.csv", provenance_of([recording]))
    errors = _hold_errors(per_frame["force_N"].to_numpy(), per_frame["time_s"].to_numpy(), truth)
    _say(quiet, "  ramp-and-hold recording, dead-weight 'power' calibration, error at each "
                "hold: " + ", ".join(f"{e:+.1f}%" for e in errors))
    _say(quiet, f"  movie calibration on the same recording: A = {movie.params['A']:.5f} N, "
                f"b = {movie.params['b']:.3f}")
    return {"hold_error_pct": errors, "movie_params": movie.params,
            "recording": str(out / "experiment" / "pressure.nc")}


def _dynamic(out, quiet):
    from tactilecal.dynamic import evaluate, fit_filter
    from tactilecal.simulate import random_sine_sets, sine_sweep

    sweep = sine_sweep(seed=0)
    filt = fit_filter(sweep.sensor, sweep.reference, model="log10")
    filt.to_json(out / "dynamic" / "filter.json", overwrite=True)
    blind = random_sine_sets(seed=1)
    evaluation = evaluate(filt, blind.sensor, blind.reference)
    write_json(out / "dynamic" / "blind-test.json", evaluation.to_dict())
    _say(quiet, f"  filter A = {filt.fit.params['A']:.4f} (true {sweep.A}), lag "
                f"{filt.lag_s:.4f} s (true {sweep.lag_s}); blind test RMS error of the "
                f"dynamic part {evaluation.rms_before_N:.2f} N -> "
                f"{evaluation.rms_after_N:.2f} N ({evaluation.improvement:.1f}x smaller)")
    return {"A": filt.fit.params["A"], "A_true": sweep.A, "lag_s": filt.lag_s,
            "lag_true_s": sweep.lag_s, "blind_rms_before_N": evaluation.rms_before_N,
            "blind_rms_after_N": evaluation.rms_after_N,
            "blind_improvement": evaluation.improvement, "filter": out / "dynamic" / "filter.json"}


def run_demo(out_dir="tactilecal-demo", *, quiet=False, overwrite=False):
    """Run the end-to-end example and write its results into ``out_dir``.

    Parameters
    ----------
    out_dir : str or os.PathLike
        Output folder (created if missing).
    quiet : bool
        No progress messages.
    overwrite : bool, keyword-only
        Write into a folder that holds files: only an earlier demo's (its ``summary.json``),
        whose files are replaced. Default False: a folder with files is an error.

    Returns
    -------
    dict
        The headline numbers, also written to ``out_dir/summary.json``.

    Examples
    --------
    It takes tens of seconds (the report's figures most of it), so this example is not run
    as a doctest; the test suite runs the demo.

    >>> headline = run_demo("tactilecal-demo", quiet=True)  # doctest: +SKIP
    >>> sorted(headline)  # doctest: +SKIP
    ['dynamic', 'elapsed_s', 'experiment', 'methods', 'report', 'true_law']
    """
    from tactilecal.demo._bundle import BUNDLE, bundle_path, demo_sensor
    from tactilecal.report import write_report

    check_folder(out_dir, overwrite=overwrite, **OUTPUT_FOLDERS["demo"])
    out = make_folder(out_dir)
    for sub in ("calibrations", "validation", "experiment", "dynamic"):
        (out / sub).mkdir(exist_ok=True)
    start = time.perf_counter()
    bundle = bundle_path()
    shutil.copytree(bundle, out / "data", dirs_exist_ok=True)
    manifests = {name: out / "data" / f"session-{name}" / "manifest.csv"
                 for name in BUNDLE["sessions"]}
    sensor = demo_sensor()
    _say(quiet, f"1-2. static calibration on session a ({BUNDLE['sessions']['a']['n_patches']} "
                f"patches), validation on session b; true law A = {sensor.A_N} N, "
                f"b = {sensor.b}")
    rows, results = _static_calibrations(manifests, out, quiet)
    _say(quiet, "3. a loading-machine recording of the same sensor")
    experiment = _experiment(sensor, results["power"], out, quiet)
    _say(quiet, "4. dynamic calibration")
    dynamic = _dynamic(out, quiet)
    _say(quiet, "5. report")
    report = write_report(
        [*(out / "calibrations" / f"{m}.json" for m in DEMO_METHODS),
         *(out / "validation" / f"{m}.json" for m in DEMO_METHODS),
         experiment["recording"], out / "dynamic" / "blind-test.json"],
        out / "report.html", filter=dynamic["filter"], title="tactilecal demo",
        command="tactilecal demo", overwrite=True)
    headline = {"true_law": {"A_N": sensor.A_N, "b": sensor.b}, "methods": rows,
                "experiment": experiment, "dynamic": dynamic, "report": report,
                "elapsed_s": time.perf_counter() - start}
    write_json(out / "summary.json", headline)
    _say(quiet, f"wrote {out}/ (report: {report}) in {headline['elapsed_s']:.1f} s")
    return headline
