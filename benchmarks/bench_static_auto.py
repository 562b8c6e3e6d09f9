"""Static calibration on the family of simulated sensors: every method, ``auto``, the floor.

For each member of :data:`tactilecal.simulate.FAMILY` and each seed: a training session
(45 patches), a held-out session (``--test-patches``, 500 by default) and a floor session
(``--floor-patches``, 2000) of the same sensor. The statistic is the RMS relative error of
the held-out patch loads (unsaturated patches), divided by the floor's: the best global
power law (least squares on relative errors) fitted on the floor session's patches. Also:
the ratio of ``auto`` (the default) to the best method of the same session (an oracle that
knows which wins) and to the true law's error, whether the default said the law does not
fit (lack of fit), and the CPU time of ``auto``.

The tracks of :class:`Family` (asv) return the worst case over members and seeds, the
family computed once per run; ``python benchmarks/bench_static_auto.py`` prints the whole
table (median / worst per member), ``--gains`` the learned gains' ratios.
"""

import argparse
import time
import warnings
from dataclasses import replace

import numpy as np

import tactilecal as tc
from tactilecal.calibration import points_from_frames
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N

METHODS = {"power": {"method": "power"},
           "power relative": {"method": "power", "objective": "relative"},
           "zvyagin": {"method": "zvyagin"}, "piecewise": {"method": "piecewise"},
           "lut": {"method": "lut"}, "polynomial": {"method": "polynomial"},
           "auto": {"method": "auto"}}
SEEDS = (0, 1, 2)
POWER_LAW = ("5051-zvyagin", "5051-sensor2", "5101-b1.0", "9500-b1.4", "5051-saturating")
"""Members whose readings follow a power law (gains, noise and saturation aside)."""
BENT = ("5051-bent", "5051-concave")
"""Members whose response bends away from any power law by more than the patches' scatter."""
NO_GAIN_FIELD = ("5051-zvyagin", "5101-b1.0", "5051-saturating", "5051-curved")
"""Members whose sensels have independent random gains only (no spatial field)."""
GAIN_MEMBERS = ("5051-edges", "9500-b1.4", *NO_GAIN_FIELD)
"""Members the learned gains are measured on."""


def _points(session):
    return points_from_frames(session.raw.values, session.load_N,
                              sensel_area_mm2=session.sensor.sensel_area_mm2)


def _rms(table, hist, load):
    return float(np.sqrt(np.mean((hist @ table / load - 1.0) ** 2)))


_SESSIONS = {}
"""Results of :func:`session_errors` by ``(member, seed)`` (asv fills it from its cache)."""
_GAINS = {}
"""Results of :func:`gains_ratio` by ``(member, seed)``."""


def session_errors(member, seed, test_patches=500, floor_patches=2000):
    """Held-out RMS relative error of every method, the floor and the truth in one session."""
    if (member, seed) not in _SESSIONS:
        _SESSIONS[member, seed] = _session_errors(member, seed, test_patches, floor_patches)
    return _SESSIONS[member, seed]


def _session_errors(member, seed, test_patches, floor_patches):
    train, test = family_sessions(member, seed, n_test=test_patches)
    _, floor = family_sessions(member, seed, n_test=floor_patches, test_seed=10_000 + seed)
    held = [p for p in _points(test) if p.saturated_cells == 0]
    hist = np.array([p.histogram for p in held], dtype=float)
    load = np.array([p.load_N for p in held])
    out, seconds = {}, {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        points = _points(train)
        for name, kwargs in METHODS.items():
            start = time.process_time()
            try:
                cal = tc.calibrate(points, **kwargs)
            except ValueError:  # e.g. a polynomial that decreases: refused
                out[name] = float("nan")
                continue
            seconds[name] = time.process_time() - start
            out[name] = _rms(cal.force_table(), hist, load)
            if name == "auto":
                out["auto chose"] = cal.selection.chosen
                out["auto flagged"] = cal.lack_of_fit.flagged
        best = tc.calibrate(_points(floor), method="power", objective="relative")
    out["floor"] = _rms(best.force_table(), hist, load)
    out["truth"] = _rms(true_force_table_N(train.sensor), hist, load)
    out["n_test"] = len(held)
    out["seconds"] = seconds
    return out


def gains_ratio(member, seed, test_patches=500):
    """Held-out RMS of the power law (relative objective) with learned gains over without.

    Both calibrations are applied to the held-out frames as a user applies them
    (``CalibrationResult.apply``, which applies learned gains first).
    """
    if (member, seed) not in _GAINS:
        _GAINS[member, seed] = _gains_ratio(member, seed, test_patches)
    return _GAINS[member, seed]


def _gains_ratio(member, seed, test_patches):
    train, test = family_sessions(member, seed, n_test=test_patches)
    clean = np.array([p.saturated_cells == 0 for p in _points(test)])
    load = np.asarray(test.load_N, dtype=float)[clean]
    errors = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for gains in ("none", "learn"):
            cal = tc.calibrate(_points(train), method="power", objective="relative",
                               gains=gains)
            force = cal.apply(test.raw, units="N").sum(("row", "col")).values[clean]
            errors.append(float(np.sqrt(np.mean((force / load - 1.0) ** 2))))
    return errors[1] / errors[0]


def learned_gains_edges():
    """Worst held-out RMS with learned gains over without, edges 15 % less sensitive."""
    return max(gains_ratio("5051-edges", s) for s in SEEDS)


def learned_gains_spread():
    """Worst held-out RMS with learned gains over without, 12 % gain spread (9500-b1.4)."""
    return max(gains_ratio("9500-b1.4", s) for s in SEEDS)


def learned_gains_no_field():
    """Worst held-out RMS with learned gains over without, on members without a gain field."""
    return max(gains_ratio(m, s) for m in NO_GAIN_FIELD for s in SEEDS)


def _ratios(key, against="floor", members=None, seeds=SEEDS):
    values = {}
    for member in members or FAMILY:
        for seed in seeds:
            e = session_errors(member, seed)
            if against == "oracle":
                ref = np.nanmin([e[m] for m in METHODS if m != "auto"])
            else:
                ref = e[against]
            values.setdefault(member, []).append(e[key] / ref)
    return values


def pooled(key, member, seeds=SEEDS):
    """RMS relative error of ``key`` over the held-out patches of every session of a member.

    One session's RMS over a few hundred patches moves with its few worst patches; pooling
    the sessions' patches (``sqrt(sum n_i rms_i^2 / sum n_i)``) measures the method, not them.
    """
    runs = [session_errors(member, s) for s in seeds]
    n = np.array([r["n_test"] for r in runs], dtype=float)
    if key == "oracle":  # the method best over the pooled patches, chosen knowing them
        return float(np.nanmin([pooled(m, member, seeds) for m in METHODS if m != "auto"]))
    rms = np.array([r[key] for r in runs], dtype=float)
    return float(np.sqrt(np.sum(n * rms**2) / n.sum()))


def auto_over_oracle_pooled_worst():
    """Worst over members of auto's pooled held-out RMS over the best method's."""
    return max(pooled("auto", m) / pooled("oracle", m) for m in FAMILY)


def auto_over_truth_pooled_worst():
    """Worst over members of auto's pooled held-out RMS over the true law's."""
    return max(pooled("auto", m) / pooled("truth", m) for m in FAMILY)


def auto_over_truth_pooled_worst_power_law():
    """The same over the members whose readings follow a power law (the docs' figure)."""
    return max(pooled("auto", m) / pooled("truth", m) for m in POWER_LAW)


def auto_over_oracle_worst():
    """Worst ratio of auto's held-out RMS error to the best method's in the same session."""
    return max(max(v) for v in _ratios("auto", "oracle").values())


def auto_over_truth_worst():
    """Worst ratio of auto's held-out RMS error to the true law's in the same session."""
    return max(max(v) for v in _ratios("auto", "truth").values())


def _flag_share(members, seeds=SEEDS):
    flags = [session_errors(m, s)["auto flagged"] for m in members for s in seeds]
    return float(np.mean(flags))


def lack_of_fit_on_bent_sessions():
    """Share of sessions of a bent response where the default says the law does not fit."""
    return _flag_share(BENT)


def lack_of_fit_on_power_law_sessions():
    """Share of sessions of power-law sensors where the default says the law does not fit."""
    return _flag_share(POWER_LAW)


class Family:
    """The family computed once per asv run (``setup_cache``); each figure is a track."""

    timeout = 3600

    def setup_cache(self):
        for member in FAMILY:
            for seed in SEEDS:
                session_errors(member, seed)
        for member in GAIN_MEMBERS:
            for seed in SEEDS:
                gains_ratio(member, seed)
        return {"sessions": dict(_SESSIONS), "gains": dict(_GAINS)}

    def _use(self, cache):
        _SESSIONS.update(cache["sessions"])
        _GAINS.update(cache["gains"])


def _track(function, unit):
    def track(self, cache):
        self._use(cache)
        return function()

    track.__name__, track.__doc__, track.unit = f"track_{function.__name__}", \
        function.__doc__, unit
    return track


for _function, _unit in ((auto_over_oracle_pooled_worst, "ratio"),
                         (auto_over_truth_pooled_worst, "ratio"),
                         (auto_over_truth_pooled_worst_power_law, "ratio"),
                         (auto_over_oracle_worst, "ratio"), (auto_over_truth_worst, "ratio"),
                         (lack_of_fit_on_bent_sessions, "share"),
                         (lack_of_fit_on_power_law_sessions, "share"),
                         (learned_gains_edges, "ratio"), (learned_gains_spread, "ratio"),
                         (learned_gains_no_field, "ratio")):
    setattr(Family, f"track_{_function.__name__}", _track(_function, _unit))


class FitSpeed:
    """``piecewise`` (l1, the default) and ``auto`` on the 45-patch session of a member, seed 0."""

    params = ["5051-zvyagin", "5051-bent", "4010N-noisy"]
    param_names = ["member"]

    def setup(self, member):
        self.points = _points(family_sessions(member, 0)[0])
        exact = [p for p in self.points if p.saturated_cells == 0]
        self.hist = np.array([p.histogram for p in exact], dtype=float)
        self.load = np.array([p.load_N for p in exact])

    def time_piecewise_fit(self, member):
        """The fit on fresh data (a FitData keeps the power law it was given)."""
        from tactilecal.calibration._fit import FitData
        from tactilecal.calibration.methods import piecewise

        piecewise.fit(FitData(self.hist, self.load), piecewise.Options())

    def time_auto(self, member):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            tc.calibrate(self.points)


CURVATURES = {f"5051-bent c={c:g}": replace(FAMILY["5051-bent"], name=f"5051-bent c={c:g}",
                                           curvature=c) for c in (0.05, 0.15, -0.05)}
"""Bent members of other log-log curvatures (5051-bent is 0.08, 5051-concave -0.1)."""


def says_no_fit(member, seed):
    """Whether the default calibration of one training session says the law does not fit."""
    train, _ = family_sessions(CURVATURES.get(member, member), seed)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return bool(tc.calibrate(_points(train)).lack_of_fit.flagged)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", nargs="*", default=list(FAMILY))
    parser.add_argument("--seeds", type=int, default=len(SEEDS))
    parser.add_argument("--lack-of-fit", type=int, metavar="N",
                        help="only the lack-of-fit flags of the default over N seeds, for "
                             "every member and bent variants of curvature 0.05, 0.15, -0.05")
    parser.add_argument("--gains", action="store_true",
                        help="only the learned gains: held-out RMS with over without them")
    args = parser.parse_args()
    seeds = tuple(range(args.seeds))
    if args.lack_of_fit:
        print(f"sessions where the default (auto) says the law does not fit, of "
              f"{args.lack_of_fit}")
        for member in [*args.members, *CURVATURES]:
            flags = [says_no_fit(member, s) for s in range(args.lack_of_fit)]
            print(f"{member:<17}{sum(flags):>4} of {len(flags)}", flush=True)
        return
    if args.gains:
        print("held-out RMS with learned gains / without (power, relative objective), by seed")
        for member in GAIN_MEMBERS:
            ratios = [gains_ratio(member, s) for s in seeds]
            print(f"{member:<17}" + "".join(f"{r:8.3f}" for r in ratios)
                  + f"   worst {max(ratios):.3f}", flush=True)
        return
    names = [*METHODS, "truth"]
    print(f"held-out RMS relative error / floor (median / worst over {len(seeds)} sessions); "
          "auto over the best method and over the true law: worst session, and pooled over "
          "the sessions' patches")
    print(f"{'member':<17}" + "".join(f"{n:>16}" for n in names) + f"{'auto/oracle':>13}"
          f"{'auto/truth':>12}{'pooled':>16}{'flagged':>9}  auto chose")
    for member in args.members:
        cells = []
        for name in names:
            r = _ratios(name, "floor", [member], seeds)[member]
            cells.append(f"{np.nanmedian(r):7.2f} / {np.nanmax(r):5.2f}" if np.isfinite(r).any()
                         else f"{'refused':>15}")
        oracle = _ratios("auto", "oracle", [member], seeds)[member]
        truth = _ratios("auto", "truth", [member], seeds)[member]
        runs = [session_errors(member, s) for s in seeds]
        flagged = sum(r["auto flagged"] for r in runs)
        print(f"{member:<17}" + "".join(f"{c:>16}" for c in cells)
              + f"{max(oracle):>13.3f}{max(truth):>12.3f}"
              + f"{pooled('auto', member, seeds) / pooled('oracle', member, seeds):>8.3f}"
              + f"{pooled('auto', member, seeds) / pooled('truth', member, seeds):>8.3f}"
              + f"{flagged:>5} of {len(seeds)}  "
              + ", ".join(r["auto chose"] for r in runs), flush=True)
    worst = max(max(v) for v in _ratios("auto", "oracle", args.members, seeds).values())
    cpu = max(session_errors(m, s)["seconds"]["auto"] for m in args.members for s in seeds)
    print(f"worst auto / oracle: {worst:.3f}; slowest auto: {cpu:.2f} s CPU (45 patches)")


if __name__ == "__main__":
    main()
