"""Benchmark: per-sensel gains learned from the training frames (issue 12, 9500-b1.4).

Every static method is a global law: one force per raw reading for every sensel. On
``9500-b1.4`` (12 % gain spread, no equilibration, about 12 effective sensels a patch) no
global law reaches issue 12's goal at 36 held-out patches (``docs/static-calibration.md``).
This script tries the one approach that is not a global law: it keeps the power method's
law and learns a force multiplier ``g_k`` for every sensel from the training frames,

    minimise  sum_p (sum_k g_k f(r_pk) / F_p - 1)**2 + lam * s * sum_k (g_k - 1)**2,

a ridge toward 1 on the relative errors of the unsaturated training patches (``f`` the
fitted law, ``F_p`` the applied load, ``s`` the mean diagonal of ``X X^T``), solved in its
dual (45 rows, one unknown per sensel: ``g - 1 = X^T (X X^T + lam s I)^-1 r``) with ``lam``
chosen by leave-one-patch-out (``alpha_p / [(X X^T + lam s I)^-1]_pp``, the ridge's exact
leave-one-out residual) among ``LAMBDAS`` and no gains at all. The held-out patches are
the same sensor's (:func:`family_sessions`), so the gains carry over; the truth's gains
(``gain_k ** -b`` on the true law) are printed as what a perfect equilibration would give.

Usage: ``python benchmarks/bench_static_gains.py [--members 9500-b1.4,...] [--seeds 160]``
"""

import argparse
import time
import warnings

import numpy as np
from bench_static_draw import describe, worst_ratios

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N

#: Ridge strengths tried (times the mean diagonal of ``X X^T``), besides no gains.
LAMBDAS = np.geomspace(1e-3, 1e2, 11)


def learned_gains(force_N, load_N, lambdas=LAMBDAS):
    """Per-sensel multipliers (sensels,) and the chosen ``lam`` (inf: none) for one session.

    ``force_N`` (patches, sensels): the law's force on each sensel of each unsaturated
    training patch; ``load_N`` (patches,): the applied loads. See the module notes.
    """
    x = force_N / load_N[:, None]
    residual = 1.0 - x.sum(axis=1)
    gram = x @ x.T
    scale = np.trace(gram) / len(load_N)
    best_cost, best_lam = np.mean(residual ** 2), np.inf
    for lam in lambdas:
        inverse = np.linalg.inv(gram + lam * scale * np.eye(len(load_N)))
        cost = np.mean(((inverse @ residual) / np.diag(inverse)) ** 2)
        if cost < best_cost:
            best_cost, best_lam = cost, lam
    if np.isinf(best_lam):
        return np.ones(force_N.shape[1]), best_lam
    system = gram + best_lam * scale * np.eye(len(load_N))
    return 1.0 + x.T @ np.linalg.solve(system, residual), best_lam


def share_within_5pct(predicted_N, load_N, clean):
    """Share of the unsaturated (``clean``) patches predicted within 5 % of their load."""
    return np.sum((np.abs(predicted_N / load_N - 1) <= 0.05) & clean) / clean.sum()


def seed_scores(member, seed):
    """Shares of the truth, the power law, the law with learned gains, the true gains."""
    train, test = family_sessions(member, seed)
    raw_train, raw_test = (s.raw.values.reshape(len(s.load_N), -1).astype(int)
                           for s in (train, test))
    load_train, load_test = (np.asarray(s.load_N, dtype=float) for s in (train, test))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        law = calibrate(points_from_frames(train.raw.values, train.load_N),
                        method="power").force_table()
    truth = true_force_table_N(train.sensor)
    fit = raw_train.max(axis=1) < 255
    gains, lam = learned_gains(law[raw_train[fit]], load_train[fit])
    clean = raw_test.max(axis=1) < 255
    true_gains = train.sensor.gain.ravel() ** -train.sensor.b
    return {"truth": share_within_5pct(truth[raw_test].sum(1), load_test, clean),
            "power": share_within_5pct(law[raw_test].sum(1), load_test, clean),
            "power + learned gains": share_within_5pct(law[raw_test] @ gains, load_test, clean),
            "truth + true gains": share_within_5pct(truth[raw_test] @ true_gains, load_test,
                                                    clean)}, lam


def report(member, scores, lams):
    """Print each candidate's shares and worst-of-8 / worst-of-20 ratios to the truth."""
    truth = scores["truth"]
    chosen = ", ".join(f"{lam:g}: {n}" for lam, n in zip(*np.unique(lams, return_counts=True),
                                                          strict=True))
    print(f"\n{member}: {truth.size} seeds x 36 held-out patches; lam chosen ({chosen}); "
          "quantiles min / 10 % / median / 90 % / max, then share >= 0.95")
    for name, share in scores.items():
        print(f"  {name}")
        print(f"    share within 5 %:        {describe(share)}")
        if name == "truth":
            continue
        print(f"    per-session ratio:       {describe(share / truth)}")
        for k in (k for k in (8, 20) if k <= truth.size):
            print(f"    worst-of-{k:<2} seed runs:  "
                  f"{describe(worst_ratios(share[:, None], truth[:, None], k))}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--members", default="9500-b1.4",
                        help=f"comma-separated members of {list(FAMILY)}, or 'all'")
    parser.add_argument("--seeds", type=int, default=160)
    args = parser.parse_args()
    start = time.perf_counter()
    members = list(FAMILY) if args.members == "all" else args.members.split(",")
    for member in members:
        runs = [seed_scores(member, seed) for seed in range(args.seeds)]
        scores = {name: np.array([r[0][name] for r in runs]) for name in runs[0][0]}
        report(member, scores, np.array([r[1] for r in runs]))
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
