"""Benchmark: every static method on every member of the simulated sensor family (issue 12).

For each member of :data:`tactilecal.simulate.FAMILY` and each seed, a training session
(45 patches) is calibrated by every method x saturation treatment and validated on a
held-out session of the same sensor (36 patches). The score is the share of unsaturated
held-out patches predicted within 5 % of the applied load, beside the share reached by the
true law (a unit-gain sensel's exact response: no global law can do better on average). The
table gives the median and the worst session of each; defaults are chosen on the worst case.

With ``--coverage N`` it also prints, per member, the share of unsaturated held-out patches
inside the power method's 95 % prediction interval over N sessions (goal 90-99 %).

Usage: ``python benchmarks/bench_static_family.py [--seeds 8] [--members a,b] [--coverage 50]``
"""

import argparse
import dataclasses
import time
import warnings

import numpy as np

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames, prediction_interval
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N

CANDIDATES = {
    "power drop": ("power", {"saturated": "drop"}),
    "power relative drop": ("power", {"saturated": "drop", "objective": "relative"}),
    "power l2 drop": ("power", {"saturated": "drop", "objective": "l2"}),
    "power keep": ("power", {"saturated": "keep"}),
    "power censored": ("power", {"saturated": "censored"}),
    "zvyagin faithful drop": ("zvyagin", {"mode": "faithful", "saturated": "drop"}),
    "zvyagin faithful keep": ("zvyagin", {"mode": "faithful", "saturated": "keep"}),
    "zvyagin robust drop": ("zvyagin", {"mode": "robust", "saturated": "drop"}),
    "zvyagin robust keep": ("zvyagin", {"mode": "robust", "saturated": "keep"}),
    "zvyagin faithful censored": ("zvyagin", {"mode": "faithful", "saturated": "censored"}),
    "zvyagin robust censored": ("zvyagin", {"mode": "robust", "saturated": "censored"}),
}


def within_5pct(table_N, hist, load_N):
    """Share of patches whose predicted load ``hist @ table_N`` is within 5 % of the load."""
    return float(np.mean(np.abs(hist @ table_N / load_N - 1) <= 0.05))


def session_scores(member, seed):
    """Scores of the truth and of every candidate on one member and seed."""
    train, test = family_sessions(member, seed)
    points = points_from_frames(train.raw.values, train.load_N)
    test_points = points_from_frames(test.raw.values, test.load_N)
    hist = np.array([p.histogram for p in test_points], dtype=float)
    load = np.asarray(test.load_N, dtype=float)
    clean = hist[:, 255] == 0
    scores = {"truth": within_5pct(true_force_table_N(train.sensor), hist[clean], load[clean])}
    for name, (method, options) in CANDIDATES.items():
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                cal = calibrate(points, method=method, **options)
            scores[name] = within_5pct(cal.force_table(), hist[clean], load[clean])
        except ValueError:
            scores[name] = float("nan")  # the method refused this session (counted as 0)
    return scores


def coverage(member, n_sessions, n_resamples=200):
    """Share of unsaturated held-out patches inside the 95 % prediction interval (power)."""
    inside = []
    for seed in range(n_sessions):
        train, test = family_sessions(member, seed)
        points = points_from_frames(train.raw.values, train.load_N)
        interval = prediction_interval(points, "power", n_resamples=n_resamples, seed=seed)
        table = calibrate(points, method="power").force_table()
        hist = np.array([p.histogram for p in points_from_frames(test.raw.values,
                                                                  test.load_N)], dtype=float)
        clean = hist[:, 255] == 0
        low, high = interval.bounds_N(hist[clean] @ table)
        load = np.asarray(test.load_N, dtype=float)[clean]
        inside.extend((low <= load) & (load <= high))
    return float(np.mean(inside)), len(inside)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=8)
    parser.add_argument("--members", default=",".join(FAMILY))
    parser.add_argument("--test-patches", type=int, default=36, metavar="N",
                        help="held-out patches per session (36 as issue 12's sessions; more "
                             "make the worst session depend less on the draw of patches)")
    parser.add_argument("--coverage", type=int, default=0, metavar="N",
                        help="sessions per member for the prediction-interval coverage")
    args = parser.parse_args()
    start = time.perf_counter()
    names = ["truth", *CANDIDATES]
    print(f"share of unsaturated held-out patches within 5 %: median / worst of {args.seeds} "
          "sessions; ratio = worst / truth's worst")
    print(f"{'member':<17}" + "".join(f"{n:>24}" for n in names))
    worst_ratio = {n: [] for n in names}
    for member in args.members.split(","):
        member = dataclasses.replace(FAMILY[member], n_test=args.test_patches)
        runs = [session_scores(member, seed) for seed in range(args.seeds)]
        row = f"{member.name:<17}"
        truth_worst = min(r["truth"] for r in runs)
        for name in names:
            values = np.nan_to_num([r[name] for r in runs], nan=0.0)
            ratio = values.min() / truth_worst if truth_worst > 0 else float("nan")
            worst_ratio[name].append(ratio)
            row += f"{np.median(values):>12.2f} / {values.min():.2f}" + (
                f" ({ratio:.2f})" if name != "truth" else "       ")
        print(row)
    print(f"{'worst ratio':<17}" + "".join(f"{min(worst_ratio[n]):>24.2f}" for n in names))
    for member in args.members.split(",") if args.coverage else []:
        share, n = coverage(member, args.coverage)
        print(f"95 % prediction interval, power, {member}: holds {share:.3f} of {n} held-out "
              f"patches ({args.coverage} sessions)")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
