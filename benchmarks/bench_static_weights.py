"""Benchmark: patch weights for the power law's fit on the simulated family (issue 12).

On ``9500-b1.4`` (14 x 14 sensels of 5.08 mm, 12 % gains, b = 1.4) a patch's error comes
from a few large sensels: a sensel of gain g reads ``g (f/A)**(1/b)``, so the true law gives
it ``g**b f``, and the patch's relative error has variance about
``(b sigma_g)**2 / n_eff`` with ``n_eff = (sum f)**2 / sum f**2`` over its sensels (Kish's
effective sample size). Since ``f`` is proportional to ``raw**b`` under the law, ``n_eff``
comes from the histogram alone: ``S(b)**2 / S(2b)`` with ``S(b) = hist @ levels**b``
(Zvyagin 2022, eq. 2). The power method's l1 fit weighs every patch's error in newtons
alike; the candidates here weigh it by the inverse of its expected spread:

- ``l1``: the power method's default, ``sum |A S_T - F_T|``;
- ``l1 relative``: ``sum |A S_T - F_T| / F_T``;
- ``l1 n_eff``: ``sum sqrt(n_eff_T) |A S_T - F_T| / F_T`` (a Laplace likelihood whose scale
  is the expected spread), ``n_eff`` at the l1 fit's b, refitted twice;
- ``relative n_eff``: ``sum n_eff_T ((A S_T - F_T) / F_T)**2`` (the Gaussian one);
- ``l1 n_eff-trim``: as ``l1 n_eff`` with weights capped at their median (only patches with
  fewer effective sensels than the median are down-weighted).

Each is scored as ``benchmarks/bench_static_family.py`` does: per member and seed, the share
of unsaturated held-out patches within 5 % of the load, at 36 and at 150 held-out patches
(the same 45 training patches), and the worst of the seeds divided by the true law's worst.

Usage: ``python benchmarks/bench_static_weights.py [--seeds 20] [--members a,b]``
"""

import argparse
import dataclasses
import time
import warnings

import numpy as np

from tactilecal.calibration import points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration._powerfit import LEVELS, _censored_median, fit_power
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N


def effective_sensels(hist, b):
    """Kish's effective number of sensels of each patch under the law ``raw**b``."""
    s1, s2 = (hist @ (LEVELS ** (k * b)) for k in (1, 2))
    return s1 * s1 / np.maximum(s2, 1e-300)


def weighted_l1_power(hist, load_N, weight, b_bounds=(0.2, 4.0), n_grid=13, xtol=1e-8):
    """Minimise ``sum w_T |A S_T(b) - F_T|``: A by a (w S)-weighted median, b by nested grids."""
    def costs(bs):
        out = []
        for b in bs:
            sums = hist @ (LEVELS ** b)
            A = _censored_median(load_N / sums, weight * sums, np.zeros(len(sums), bool))
            out.append((np.sum(weight * np.abs(A * sums - load_N)), A))
        return np.array(out)

    lo, hi = b_bounds
    while hi - lo > xtol:
        grid = np.linspace(lo, hi, n_grid)
        k = int(np.argmin(costs(grid)[:, 0]))
        lo, hi = grid[max(k - 1, 0)], grid[min(k + 1, n_grid - 1)]
    b = float(grid[k])
    return float(costs([b])[0, 1]), b


def weighted_relative_power(hist, load_N, weight, b_bounds=(0.2, 4.0)):
    """Minimise ``sum w_T ((A S_T(b) - F_T) / F_T)**2``: A closed form, b bounded scalar."""
    from scipy.optimize import minimize_scalar

    w2 = weight / load_N ** 2

    def cost(b):
        sums = hist @ (LEVELS ** b)
        A = np.sum(w2 * sums * load_N) / np.sum(w2 * sums * sums)
        return np.sum(w2 * (A * sums - load_N) ** 2), A

    grid = np.linspace(*b_bounds, 40)
    k = int(np.argmin([cost(b)[0] for b in grid]))
    sol = minimize_scalar(lambda b: cost(b)[0], bounds=(grid[max(k - 1, 0)],
                                                         grid[min(k + 1, 39)]),
                          method="bounded", options={"xatol": 1e-8})
    return float(cost(sol.x)[1]), float(sol.x)


def fit_candidate(name, hist, load_N):
    """(A, b) of candidate ``name`` on the training patches."""
    start = fit_power(hist, load_N, objective="l1").params
    if name == "l1":
        return start["A"], start["b"]
    if name == "l1 relative":
        return weighted_l1_power(hist, load_N, 1.0 / load_N)
    A, b = start["A"], start["b"]
    for _ in range(2):
        n_eff = effective_sensels(hist, b)
        if name == "l1 n_eff-trim":
            n_eff = np.minimum(n_eff, np.median(n_eff))
        if name == "relative n_eff":
            A, b = weighted_relative_power(hist, load_N, n_eff)
        else:
            A, b = weighted_l1_power(hist, load_N, np.sqrt(n_eff) / load_N)
    return A, b


CANDIDATES = ("l1", "l1 relative", "l1 n_eff", "relative n_eff", "l1 n_eff-trim")


def shares(A, b, hist, load_N):
    """Share of unsaturated patches whose load ``A hist @ levels**b`` is within 5 %."""
    clean = hist[:, 255] == 0
    return float(np.mean(np.abs(A * (hist[clean] @ LEVELS ** b) / load_N[clean] - 1) <= 0.05))


def seed_scores(member, seed, sizes, candidates):
    """Per held-out size, the shares of the truth and of each candidate on one seed."""
    out = {}
    for n_test in sizes:
        train, test = family_sessions(dataclasses.replace(member, n_test=n_test), seed)
        hist, load = points_to_arrays([p for p in points_from_frames(train.raw.values,
                                                                     train.load_N)
                                       if p.histogram[255] == 0])
        test_hist, test_load = points_to_arrays(points_from_frames(test.raw.values,
                                                                   test.load_N))
        hist, test_hist = hist.astype(float), test_hist.astype(float)
        table = true_force_table_N(train.sensor)
        clean = test_hist[:, 255] == 0
        row = {"truth": float(np.mean(np.abs(test_hist[clean] @ table / test_load[clean] - 1)
                                      <= 0.05))}
        if n_test == sizes[0]:
            fits = {}
            for name in candidates:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    fits[name] = fit_candidate(name, hist, load)
        for name in candidates:
            row[name] = shares(*fits[name], test_hist, test_load)
        out[n_test] = row
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--members", default=",".join(FAMILY))
    parser.add_argument("--sizes", default="36,150", help="held-out patches per session")
    parser.add_argument("--candidates", default=",".join(CANDIDATES))
    args = parser.parse_args()
    start = time.perf_counter()
    sizes = [int(s) for s in args.sizes.split(",")]
    names = args.candidates.split(",")
    print(f"worst of {args.seeds} sessions' share within 5 % / the true law's worst "
          "(median share in brackets)")
    lines = {n_test: [] for n_test in sizes}
    for member in args.members.split(","):
        runs = [seed_scores(FAMILY[member], seed, sizes, names) for seed in range(args.seeds)]
        for n_test in sizes:
            truth = np.array([r[n_test]["truth"] for r in runs])
            row = f"{member:<17}{truth.min():>6.2f} ({np.median(truth):.2f})"
            for name in names:
                v = np.array([r[n_test][name] for r in runs])
                row += f"{v.min() / truth.min():>14.2f} ({np.median(v):.2f})"
            lines[n_test].append(row)
    for n_test in sizes:
        print(f"\n{n_test} held-out patches\n{'member':<17}{'truth':>13}"
              + "".join(f"{n:>21}" for n in names))
        print("\n".join(lines[n_test]))
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
