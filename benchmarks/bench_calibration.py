"""Static calibration benchmark: accuracy of every method on held-out dead weights, and the
speed of movie calibration against a straightforward per-frame ``sum(raw ** b)``.

Run: ``python benchmarks/bench_calibration.py [--quick] [--skip-movie] [--skip-accuracy]``.

Accuracy: a simulated 5051 sensor (A = 0.0035 N, b = 1.16, 5 % gain spread, read noise 0.5,
3 dead sensels); a calibration session and a validation session with different seeds, 150
patches each (2/5/10 kg on 1-3 cm pads), 5 % of the patches saturated; every method is fitted
on the first and validated on the unsaturated patches of the second. The objective of the
default ``power`` method is chosen over several session pairs.

Speed: 100,000 frames of 44 x 44 sensels (ramp-and-hold, load cell at 500 Hz on its own
clock). Times are noisy on a shared machine, so ratios measured in the same run are printed.
"""

import argparse
import time

import numpy as np

from tactilecal.calibration import (
    calibrate,
    calibrate_movie,
    find_dead_sensels,
    points_from_frames,
    validate,
)
from tactilecal.simulate import deadweight_session, make_sensor, ramp_hold

METHODS = [
    ("linear", {}), ("power-2pt", {}), ("power", {"objective": "l2"}),
    ("power", {"objective": "l1"}), ("power", {"objective": "relative"}),
    ("power", {"objective": "relative", "keep_saturated": True}),
    ("linear-offset", {}), ("piecewise", {}), ("lut", {}), ("polynomial", {}), ("zvyagin", {}),
]


def _sessions(pair, n_patches):
    sensor = make_sensor("5051", seed=100 + pair)
    cal = deadweight_session(sensor, n_patches=n_patches, saturated_share=0.05, seed=2 * pair + 1)
    val = deadweight_session(sensor, n_patches=n_patches, saturated_share=0.05, seed=2 * pair + 2)
    return (points_from_frames(cal.raw, cal.load_N), points_from_frames(val.raw, val.load_N))


def _row(method, options, cal, val):
    t0 = time.perf_counter()
    res = calibrate(cal, method=method, **options)
    fit_s = time.perf_counter() - t0
    s = validate(res, val)["summary"]
    return res, s, fit_s


def accuracy_table(n_patches=150):
    """Print every method's held-out accuracy on one session pair (pair 0)."""
    cal, val = _sessions(0, n_patches)
    print(f"\nAccuracy: calibrate on {len(cal)} patches (seed 1), validate on {len(val)} "
          "(seed 2), unsaturated held-out patches only")
    print(f"{'method':<30}{'n':>4}{'<=3%':>8}{'<=5%':>8}{'<=10%':>8}{'median%':>9}"
          f"{'max%':>8}{'fit s':>8}  params")
    for method, options in METHODS:
        res, s, fit_s = _row(method, options, cal, val)
        name = " ".join([method, *(str(v) if k == "objective" else k
                                   for k, v in options.items())])
        params = {k: round(v, 5) for k, v in res.params.items() if np.ndim(v) == 0}
        print(f"{name:<30}{s['n']:>4}{s['within_3pct']:>8.3f}{s['within_5pct']:>8.3f}"
              f"{s['within_10pct']:>8.3f}{s['median_abs_error_pct']:>9.2f}"
              f"{s['max_abs_error_pct']:>8.2f}{fit_s:>8.3f}  {params}")


def objective_choice(n_pairs=6, n_patches=150):
    """Compare the power objectives over several independent session pairs."""
    print(f"\nPower objectives over {n_pairs} session pairs ({n_patches} patches each): mean "
          "of the held-out share within 3 % and of the median |error|")
    scores = {o: [] for o in ("l2", "l1", "relative")}
    for pair in range(n_pairs):
        cal, val = _sessions(pair, n_patches)
        for objective in scores:
            _, s, _ = _row("power", {"objective": objective}, cal, val)
            scores[objective].append((s["within_3pct"], s["median_abs_error_pct"],
                                      s["max_abs_error_pct"]))
    for objective, rows in scores.items():
        a = np.array(rows)
        print(f"  {objective:<9} within 3 %: mean {a[:, 0].mean():.3f} (min {a[:, 0].min():.3f})"
              f"  median |err| {a[:, 1].mean():.3f} %  max |err| {a[:, 2].mean():.2f} %")


def dead_sensel_detection(n_sensors=8, n_patches=150):
    """True and false detections of non-working sensels for several neighbour rules."""
    print(f"\nNon-working sensels: {n_sensors} sensors with 6 dead sensels, {n_patches} "
          "dead-weight patches each")
    totals = {}
    for k in range(n_sensors):
        sensor = make_sensor("5051", seed=100 + k, n_dead=6)
        raw = deadweight_session(sensor, n_patches=n_patches, saturated_share=0.05,
                                 seed=2 * k + 1).raw.values
        for share in (0.75, 1.0):
            for min_frames in (1, 2):
                found = find_dead_sensels(raw, neighbour_share=share, min_frames=min_frames)
                t = totals.setdefault((share, min_frames), [0, 0, 0])
                t[0] += int((found.mask & sensor.dead).sum())
                t[1] += int((found.mask & ~sensor.dead).sum())
                t[2] += int(sensor.dead.sum())
    for (share, min_frames), (tp, fp, n) in totals.items():
        print(f"  neighbour_share {share:<5} min_frames {min_frames}: found {tp} of {n} dead, "
              f"{fp} working sensels wrongly reported")


def _baseline_sum_pow(raw, b):
    """Straightforward per-frame sum(raw ** b): the cost of one objective evaluation."""
    return np.array([np.nansum(frame ** b) for frame in raw])


def movie_speed(n_frames=100_000):
    """Time movie calibration of n_frames 44 x 44 frames against the per-frame baseline."""
    sensor = make_sensor("5051", seed=0)
    from tactilecal.simulate._static import ramp_hold_profile

    times, _ = ramp_hold_profile((222.4, 444.8, 667.2, 889.6))  # ramp_hold's default levels
    rate = n_frames / times[-1]
    t0 = time.perf_counter()
    rh = ramp_hold(sensor, frame_rate_hz=rate, loadcell_rate_hz=500.0, seed=1)
    sim_s = time.perf_counter() - t0
    raw = rh.raw
    print(f"\nMovie calibration: {raw.sizes['frame']} frames of 44 x 44 "
          f"(simulated in {sim_s:.1f} s)")
    import tactilecal.dynamic  # noqa: F401  (import time is not part of the calibration)

    t0 = time.perf_counter()
    res = calibrate_movie(raw, rh.loadcell)
    ours_s = time.perf_counter() - t0
    t0 = time.perf_counter()
    _baseline_sum_pow(raw.values, res.params["b"])
    base_s = time.perf_counter() - t0
    n_eval = res.details.get("n_evaluations", 0)
    print(f"  calibrate_movie (align, resample, 2 fits): {ours_s:.2f} s; "
          f"lag {res.details['movie']['lag_s']:.4f} s (truth {rh.loadcell_start_offset_s}), "
          f"A = {res.params['A']:.6f}, b = {res.params['b']:.4f}")
    print(f"  one per-frame sum(raw ** b) pass over all frames: {base_s:.2f} s")
    print(f"  ratio calibrate_movie / one baseline pass: {ours_s / base_s:.3f}")
    if n_eval:
        print(f"  the fits evaluated the objective {n_eval} times: a per-frame implementation "
              f"would need about {n_eval * base_s:.0f} s, ratio "
              f"{ours_s / (n_eval * base_s):.4f}")
    print(f"  within the 5 s target: {ours_s <= 5.0}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer pairs and frames")
    parser.add_argument("--skip-movie", action="store_true")
    parser.add_argument("--skip-accuracy", action="store_true")
    args = parser.parse_args()
    if not args.skip_accuracy:
        accuracy_table()
        objective_choice(n_pairs=2 if args.quick else 6)
        dead_sensel_detection(n_sensors=2 if args.quick else 8)
    if not args.skip_movie:
        movie_speed(10_000 if args.quick else 100_000)


if __name__ == "__main__":
    main()
