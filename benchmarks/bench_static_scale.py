"""Benchmark: how far a session's own scale moves a power-law fit (issue 12, ``9500-b1.4``).

With b fixed at the true exponent, the l1 scale ``A`` of a set of patches (the
``S``-weighted median of ``F / S``, as the power method profiles it; Gillis 2013 eq. 5.1)
divided by the true ``A`` says how far those patches lead any power law from the truth.
Per seed of a member (:func:`family_sessions`; sensor gains from the seed), it is taken on

- the 45 training patches;
- the benchmark's 36 held-out patches plus 324 more of an independent held-out session
  (``bench_static_draw.py``'s blocks);
- a second 45-patch session on the same sensor (another base relief and placements);
- 45-patch subsets of one 450-patch session (one base relief): the spread from the number
  of patches alone.

The standard deviations of ``log A`` show which part of a fit's scale error is the
session (its base relief decides which sensels, with their gains, carry the load in every
patch) rather than the number of patches, and so cannot be learned from one session.

Usage: ``python benchmarks/bench_static_scale.py [--member 9500-b1.4] [--seeds 40]``
"""

import argparse
import time

import numpy as np
from bench_static_draw import held_out_blocks

from tactilecal.calibration import points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration._powerfit import LEVELS, _censored_median
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N
from tactilecal.simulate._deadweight import deadweight_session


def session(member, sensor, n_patches, seed):
    """Histograms (float) and loads of a new session of ``member`` on ``sensor``."""
    s = deadweight_session(sensor, n_patches=n_patches, masses_kg=member.masses_kg,
                           pad_sides_cm=member.pad_sides_cm,
                           saturated_share=member.saturated_share, blank_frame_share=0.0,
                           seed=seed)
    return arrays(s)


def arrays(s):
    """Histograms (float) and loads of a session's patches."""
    hist, load = points_to_arrays(points_from_frames(s.raw.values, s.load_N))
    return hist.astype(float), load


def log_scale(hist, load, b, A_true):
    """``log(A / A_true)`` of the l1 scale at exponent ``b`` on the unsaturated patches."""
    ok = hist[:, 255] == 0
    sums = hist[ok] @ LEVELS ** b
    return float(np.log(_censored_median(load[ok] / sums, sums, np.zeros(ok.sum(), bool))
                        / A_true))


def seed_figures(member, seed, rng, n_subsets=200):
    """log scales on the four sets of patches, and the truth's median errors, for one seed."""
    train, test = family_sessions(member, seed)
    A_true = true_force_table_N(train.sensor)[1]
    hist, load = arrays(train)
    test_hist, test_load = (x.reshape(-1, *x.shape[2:])
                            for x in held_out_blocks(member, seed, train, test, 10))
    second = session(member, train.sensor, 45, 2 * 10**6 + seed)
    big_hist, big_load = session(member, train.sensor, 450, 3 * 10**6 + seed)
    subsets = [log_scale(big_hist[i], big_load[i], member.b, A_true)
               for i in (rng.permutation(len(big_load))[:45] for _ in range(n_subsets))]
    table = true_force_table_N(train.sensor)
    clean = test_hist[:, 255] == 0
    return {"train": log_scale(hist, load, member.b, A_true),
            "held_out": log_scale(test_hist, test_load, member.b, A_true),
            "second": log_scale(*second, member.b, A_true),
            "subset_sd": float(np.std(subsets)),
            "train_err": float(np.median(hist @ table / load - 1)),
            "held_out_err": float(np.median(test_hist[clean] @ table / test_load[clean] - 1))}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--member", default="9500-b1.4", choices=list(FAMILY))
    parser.add_argument("--seeds", type=int, default=40)
    args = parser.parse_args()
    start = time.perf_counter()
    member = FAMILY[args.member]
    if member.curvature:
        raise SystemExit(f"{member.name}: no power law describes it (curvature)")
    rng = np.random.default_rng(0)
    runs = [seed_figures(member, seed, rng) for seed in range(args.seeds)]
    col = {k: np.array([r[k] for r in runs]) for k in runs[0]}
    print(f"{member.name}, {args.seeds} seeds: standard deviation of log(A / A_true), A the l1 "
          f"scale at the true b = {member.b}")
    print(f"  45 training patches:                         {col['train'].std():.4f}")
    print(f"  360 held-out patches:                        {col['held_out'].std():.4f}")
    print(f"  a second 45-patch session, same sensor:      {col['second'].std():.4f}")
    print(f"  training minus second session:               "
          f"{(col['train'] - col['second']).std():.4f}")
    print(f"  training minus held-out:                     "
          f"{(col['train'] - col['held_out']).std():.4f}")
    print(f"  45-patch subsets of one 450-patch session:   {col['subset_sd'].mean():.4f} "
          "(mean over seeds)")
    print(f"correlation of the true law's median error, training vs held-out: "
          f"{np.corrcoef(col['train_err'], col['held_out_err'])[0, 1]:.2f}")
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
