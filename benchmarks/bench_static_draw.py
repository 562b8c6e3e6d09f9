"""Benchmark: how much of a worst-session ratio is the draw of held-out patches (issue 12).

Issue 12's goal compares the worst session's share of held-out patches within 5 % for a
method with the true law's worst session, over 8 sessions of 36 held-out patches. On a
member whose shares are far from 1 (``9500-b1.4``: about half the patches), one patch is
0.028 of the share and the two worst sessions need not be the same session. This script
separates the draw from the method:

- per seed, the sensor and the 45 training patches of :func:`family_sessions` are fitted once
  by each method; the held-out patches are the benchmark's own 36 (block 0) plus
  ``--blocks - 1`` further blocks of 36 from an independent session of the same sensor
  (seed ``10**6 + seed``), so each seed has many equally likely 36-patch draws;
- the *per-session ratio* is the method's share over the truth's share on all held-out blocks
  of that seed (nearly free of the draw), and on block 0 alone;
- the *worst-of-k ratio* is ``min(method shares) / min(truth shares)`` over k sessions: over
  disjoint runs of k consecutive seeds with block 0 (the issue's protocol, no choice of seeds),
  and over ``--draws`` random picks of one block per seed (fits fixed: the spread is the
  draw of held-out patches alone).

Usage: ``python benchmarks/bench_static_draw.py [--member 9500-b1.4] [--seeds 160]
[--blocks 10] [--methods power,zvyagin,piecewise,lut] [--equilibrate 100,300,700]
[--save scores.npz]``
"""

import argparse
import time
import warnings

import numpy as np

from tactilecal import calibrate
from tactilecal.calibration import equilibrate, points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration._powerfit import _censored_median
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N, uniform_load
from tactilecal.simulate._deadweight import deadweight_session

PATCHES = 36
"""Held-out patches per session (issue 12's sessions)."""


def held_out_blocks(member, seed, train, test, n_blocks, transform=None):
    """Histograms (n_blocks, 36, 256) and loads (n_blocks, 36) of the held-out blocks.

    ``transform`` (e.g. :meth:`Equilibration.apply`) is applied to the frames first.
    """
    extra = deadweight_session(train.sensor, n_patches=PATCHES * (n_blocks - 1),
                               masses_kg=member.masses_kg, pad_sides_cm=member.pad_sides_cm,
                               saturated_share=member.saturated_share, blank_frame_share=0.0,
                               seed=10**6 + seed) if n_blocks > 1 else None
    hists, loads = [], []
    for session in (test, extra):
        if session is None:
            continue
        points = points_from_frames(frames_of(session, transform), session.load_N)
        hists.append(np.array([p.histogram for p in points], dtype=float))
        loads.append(np.asarray(session.load_N, dtype=float))
    return (np.concatenate(hists).reshape(n_blocks, PATCHES, 256),
            np.concatenate(loads).reshape(n_blocks, PATCHES))


def frames_of(session, transform=None):
    """A session's frames, through ``transform`` when one is given."""
    return session.raw.values if transform is None else transform(session.raw.values)


def sensor_equilibration(sensor, pressures_kPa, seed):
    """The sensor's equilibration from simulated uniform loads (5 frames per level).

    What a lab does before calibrating (Gillis 2013, sec. 3.5; ``tactilecal equilibrate``):
    :func:`uniform_load` at ``pressures_kPa`` then :func:`equilibrate`.
    """
    frames = uniform_load(sensor, pressures_kPa, seed=seed).raw.values
    return equilibrate(np.split(frames, len(pressures_kPa))).apply


def block_shares(table_N, hist, load_N):
    """Per block, the share of unsaturated patches predicted within 5 % of their load."""
    clean = hist[..., 255] == 0
    good = (np.abs(hist @ table_N / load_N - 1) <= 0.05) & clean
    return good.sum(axis=1) / clean.sum(axis=1)


def seed_scores(member, seed, methods, n_blocks, equilibrate_kPa=None):
    """Shares (n_blocks,) per block of the truth and of each method on one seed.

    With ``equilibrate_kPa`` the methods fit and predict equilibrated frames; the truth
    stays the unit-gain law on the raw readings (issue 12's reference).
    """
    train, test = family_sessions(member, seed)
    hist, load = held_out_blocks(member, seed, train, test, n_blocks)
    scores = {"truth": block_shares(true_force_table_N(train.sensor), hist, load)}
    transform = None
    if equilibrate_kPa:
        transform = sensor_equilibration(train.sensor, equilibrate_kPa, 4 * 10**6 + seed)
        hist, load = held_out_blocks(member, seed, train, test, n_blocks, transform)
    points = points_from_frames(frames_of(train, transform), train.load_N)
    for name in methods:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                table = session_ceiling(member, train, transform) if name == "ceiling" \
                    else force_table_N(name, points)
                scores[name] = block_shares(table, hist, load)
        except ValueError:
            scores[name] = np.zeros(n_blocks)  # a refused session counts as 0
    return scores


def force_table_N(name, points):
    """Force table of method ``name`` (with its defaults) fitted to ``points``.

    ``power:<candidate>`` is a candidate weighting of the power law's fit from
    ``bench_static_weights.py`` (fitted on the unsaturated points).
    """
    if not name.startswith("power:"):
        return calibrate(points, method=name).force_table()
    from bench_static_weights import LEVELS, fit_candidate

    hist, load = points_to_arrays([p for p in points if p.histogram[255] == 0])
    A, b = fit_candidate(name.removeprefix("power:"), hist.astype(float), load)
    return A * LEVELS ** b


def session_ceiling(member, train, transform=None, n_patches=450):
    """Not a method: the power law at the true b, scaled on 450 patches of the training session.

    The same seed gives the same base relief (drawn first), so these patches are the training
    session's with ten times as many placements; A is their l1 scale (the S-weighted median
    of F / S, as the power method profiles it). What no fit to this session can beat.
    """
    from bench_static_weights import LEVELS

    big = deadweight_session(train.sensor, n_patches=n_patches, masses_kg=member.masses_kg,
                             pad_sides_cm=member.pad_sides_cm,
                             saturated_share=member.saturated_share, blank_frame_share=0.0,
                             seed=train.seed)
    hist, load = points_to_arrays(points_from_frames(frames_of(big, transform), big.load_N))
    keep = hist[:, 255] == 0
    sums = hist[keep].astype(float) @ LEVELS ** member.b
    return _censored_median(load[keep] / sums, sums, np.zeros(keep.sum(), bool)) \
        * LEVELS ** member.b


def worst_ratios(method, truth, k, rng=None, n_draws=0):
    """Worst-of-k ratios over disjoint runs of k seeds: block 0, or random blocks per seed."""
    n_runs = method.shape[0] // k
    m, t = (x[:n_runs * k].reshape(n_runs, k, -1) for x in (method, truth))
    if not n_draws:
        return m[:, :, 0].min(axis=1) / t[:, :, 0].min(axis=1)
    pick = rng.integers(0, m.shape[2], size=(n_draws, n_runs, k))
    runs, seeds = np.arange(n_runs)[None, :, None], np.arange(k)[None, None, :]
    return (m[runs, seeds, pick].min(axis=2) / t[runs, seeds, pick].min(axis=2)).ravel()


def describe(values):
    """min / 10 % / median / 90 % / max and the share >= 0.95, as one string."""
    q = np.quantile(values, [0, 0.1, 0.5, 0.9, 1])
    return (" ".join(f"{v:5.2f}" for v in q) + f"   {np.mean(values >= 0.95):5.2f}"
            + f"  (n={len(values)})")


def report(scores, args):
    """Print the per-session and worst-of-k distributions of every method."""
    rng = np.random.default_rng(0)
    truth = scores["truth"]
    print(f"{args.member}: {truth.shape[0]} seeds x {truth.shape[1]} blocks of {PATCHES} "
          "held-out patches; quantiles min / 10 % / median / 90 % / max, then share >= 0.95")
    print(f"truth's share within 5 %, all blocks per seed: {describe(truth.mean(axis=1))}")
    print(f"truth's share within 5 %, block 0:             {describe(truth[:, 0])}")
    first = args.methods.split(",")[0]
    for name in args.methods.split(","):
        m = scores[name]
        print(f"\n{name}")
        print(f"  share within 5 %, all blocks per seed: {describe(m.mean(axis=1))}")
        print(f"  per-session ratio, all blocks pooled: {describe(m.mean(1) / truth.mean(1))}")
        print(f"  per-session ratio, block 0:           {describe(m[:, 0] / truth[:, 0])}")
        below, above = np.mean(m[:, 0] < truth[:, 0]), np.mean(m[:, 0] > truth[:, 0])
        print(f"  sessions where method < truth on block 0: {below:.2f}, > truth: {above:.2f}")
        if name != first:
            diff = m.mean(1) - scores[first].mean(1)
            print(f"  pooled share minus {first}'s, per seed: mean {diff.mean():+.3f} "
                  f"+- {2 * diff.std(ddof=1) / np.sqrt(diff.size):.3f} (2 se); better in "
                  f"{np.mean(diff > 0):.2f}, worse in {np.mean(diff < 0):.2f} of the seeds")
        for k in (k for k in (8, 20) if k <= m.shape[0]):
            print(f"  worst-of-{k:<2} block 0, disjoint seed runs: "
                  f"{describe(worst_ratios(m, truth, k))}")
            print(f"  worst-of-{k:<2} random blocks ({args.draws} draws):   "
                  f"{describe(worst_ratios(m, truth, k, rng, args.draws))}")
            pooled = worst_ratios(m.mean(1, keepdims=True), truth.mean(1, keepdims=True), k)
            print(f"  worst-of-{k:<2} of pooled shares:          {describe(pooled)}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--member", default="9500-b1.4", choices=list(FAMILY))
    parser.add_argument("--seeds", type=int, default=160)
    parser.add_argument("--blocks", type=int, default=10,
                        help="blocks of 36 held-out patches per seed (block 0 = the benchmark's)")
    parser.add_argument("--methods", default="power,zvyagin,piecewise,lut",
                        help="comma-separated methods, each with its defaults, "
                             "power:<candidate> of bench_static_weights.py (e.g. 'power:l1 "
                             "n_eff') or 'ceiling' (the true b scaled on 450 patches of the "
                             "training session); the others are compared seed by seed with "
                             "the first")
    parser.add_argument("--draws", type=int, default=200,
                        help="random picks of one block per seed for the worst-of-k spread")
    parser.add_argument("--equilibrate", default="", metavar="KPA,KPA",
                        help="equilibrate each sensor from uniform loads at these pressures "
                             "before fitting and predicting (the truth stays on raw readings)")
    parser.add_argument("--save", default=None, help="write the per-block shares to this .npz")
    parser.add_argument("--load", default=None, help="report from a saved .npz instead")
    args = parser.parse_args()
    start = time.perf_counter()
    if args.load:
        scores = dict(np.load(args.load))
    else:
        member = FAMILY[args.member]
        names = ["truth", *args.methods.split(",")]
        levels = [float(v) for v in args.equilibrate.split(",")] if args.equilibrate else None
        runs = [seed_scores(member, seed, names[1:], args.blocks, levels)
                for seed in range(args.seeds)]
        scores = {n: np.array([r[n] for r in runs]) for n in names}
        if args.save:
            np.savez(args.save, **scores)
    report(scores, args)
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
