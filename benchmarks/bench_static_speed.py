"""Benchmark: time of the censored and default static fits against the earlier defaults.

Issue 12's speed goals: with censored fits, 45-patch ``power`` under 0.2 s and 150-patch
Zvyagin under 1 s. Each fit is timed (best of ``--repeat``, interleaved) on sessions of the
simulated family member ``5051-sensor2`` (20 % saturated patches) beside the fit that was
the default before issue 12 in the same run (``power`` relative with saturated patches
dropped; Zvyagin faithful, dropped), and the ratio new / old is printed.

Usage: ``python benchmarks/bench_static_speed.py [--repeat 5]``
"""

import argparse
import dataclasses
import warnings

from _timing import run_times

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames
from tactilecal.simulate import FAMILY, family_sessions

CASES = {  # name: (patches, method, options, baseline options)
    "power default (l1, drop)": (45, "power", {}, {"objective": "relative"}),
    "power censored (l1)": (45, "power", {"saturated": "censored"}, {"objective": "relative"}),
    "power censored (relative)": (45, "power", {"saturated": "censored",
                                                "objective": "relative"},
                                  {"objective": "relative"}),
    "zvyagin default (robust, drop)": (150, "zvyagin", {}, {"mode": "faithful"}),
    "zvyagin robust censored": (150, "zvyagin", {"saturated": "censored"},
                                {"mode": "faithful"}),
    "zvyagin faithful censored": (150, "zvyagin", {"mode": "faithful", "saturated": "censored"},
                                  {"mode": "faithful"}),
}


def points(n_patches):
    member = dataclasses.replace(FAMILY["5051-sensor2"], n_train=n_patches)
    train, _ = family_sessions(member, seed=0)
    return points_from_frames(train.raw.values, train.load_N)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    sessions = {n: points(n) for n in (45, 150)}
    print(f"{'fit':<32}{'patches':>8}{'new s':>10}{'old s':>10}{'new/old':>9}")
    for name, (n, method, options, baseline) in CASES.items():
        def new(n=n, method=method, options=options):
            return calibrate(sessions[n], method=method, sensel_area_mm2=1.6129, **options)

        def old(n=n, method=method, baseline=baseline):
            return calibrate(sessions[n], method=method, sensel_area_mm2=1.6129, **baseline)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            times = {"new": [], "old": []}
            for _ in range(args.repeat):  # interleaved: the shared machine's noise hits both
                times["new"].append(run_times(new, 1)[0])
                times["old"].append(run_times(old, 1)[0])
        t_new, t_old = min(times["new"]), min(times["old"])
        print(f"{name:<32}{n:>8}{t_new:>10.4f}{t_old:>10.4f}{t_new / t_old:>9.2f}")


if __name__ == "__main__":
    main()
