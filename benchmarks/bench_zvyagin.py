"""Zvyagin (2022) accuracy and speed study on simulated dead-weight sessions.

Run: ``python benchmarks/bench_zvyagin.py [--quick]``

1. Accuracy: calibrate on one session, validate on another (other seed, same sensor), for
   the faithful and robust modes and the static ``power`` method on the same points; with
   and without saturated patches in the calibration session.
2. What each robust choice changes, one at a time, on the same data.
3. The (A, b) power law (R2) and the share of valid pairs per load combination.
4. Speed: the whole procedure for 150 patches against a plain Python loop over the domain
   evaluating eq. (8) (timed on a subset and extrapolated), and 1,000 patches.
Times are noisy on shared cores: ratios are measured in the same run.
"""

import sys
import time
import warnings

import numpy as np

from tactilecal.calibration import calibrate, points_from_frames, validate
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration.methods.zvyagin import zvyagin_fit
from tactilecal.calibration.methods.zvyagin._approx import patch_discrepancy, separation_domain
from tactilecal.simulate import deadweight_session, make_sensor

QUICK = "--quick" in sys.argv
N_SENSORS = 2 if QUICK else 4
TRUE_A, TRUE_B = 0.0035, 1.16


def sessions(k, saturated_share):
    sensor = make_sensor("5051", A_N=TRUE_A, b=TRUE_B, seed=10 + k)
    cal = deadweight_session(sensor, n_patches=150, seed=100 + k,
                             saturated_share=saturated_share)
    val = deadweight_session(sensor, n_patches=150, seed=200 + k)
    return (points_from_frames(cal.raw, cal.load_N), points_from_frames(val.raw, val.load_N))


def accuracy():
    print("1. calibrate on one session (150 patches), validate on another (150, other seed)")
    print(f"   truth A = {TRUE_A}, b = {TRUE_B}; {N_SENSORS} simulated sensors; mean over them")
    print(f"   {'calibration session':<24} {'method':<21} {'A0':>9} {'b0':>7} "
          f"{'within 5%':>9} {'median |e| %':>12}")
    print("   (power: the static method; by default it leaves saturated points out)")
    for share in (0.0, 0.2):
        res = {}
        for k in range(N_SENSORS):
            cal_pts, val_pts = sessions(k, share)
            for name, kw in (("zvyagin faithful", {"method": "zvyagin"}),
                             ("zvyagin robust", {"method": "zvyagin", "mode": "robust"}),
                             ("power", {"method": "power"}),
                             ("power keep saturated", {"method": "power",
                                                       "keep_saturated": True})):
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    cal = calibrate(cal_pts, **kw)
                s = validate(cal, val_pts)["summary"]
                res.setdefault(name, []).append((cal.params["A"], cal.params["b"],
                                                 s["within_5pct"], s["median_abs_error_pct"]))
        for name, v in res.items():
            v = np.array(v)
            print(f"   {f'{share:.0%} saturated patches':<24} {name:<21} {v[:, 0].mean():>9.5f} "
                  f"{v[:, 1].mean():>7.4f} {v[:, 2].mean():>9.1%} {v[:, 3].mean():>12.2f}")


VARIANTS = {
    "faithful": {},
    "+ best-fit root": {"root_choice": "best-fit"},
    "+ trim 5% of b each end": {"outliers": "trim"},
    "+ MAD clip of log A": {"outliers": "mad", "b_range": "inliers"},
    "+ drop saturated": {"saturated": "drop"},
    "robust": {"mode": "robust"},
    "robust, drop saturated": {"mode": "robust", "saturated": "drop"},
}


def choices():
    print("\n2. one choice at a time (20% saturated patches in the calibration session)")
    print(f"   {'variant':<26} {'A0':>9} {'b0':>7} {'|b0-b|':>7} {'within 5%':>9} "
          f"{'R2':>6} {'multi-root pairs':>16}")
    rows = {k: [] for k in VARIANTS}
    for k in range(N_SENSORS):
        cal_pts, val_pts = sessions(k, 0.2)
        h, f = points_to_arrays(cal_pts)
        hv, fv = points_to_arrays(val_pts)
        for name, opt in VARIANTS.items():
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                r = zvyagin_fit(h, f, **opt)
            err = (r.A0 * (hv @ np.arange(256.0) ** r.b0) - fv) / fv
            rows[name].append((r.A0, r.b0, abs(r.b0 - TRUE_B), np.mean(np.abs(err) < 0.05),
                               r.power_law["r2"], np.sum(r.pairs["n_roots"] > 1)))
    for name, v in rows.items():
        v = np.array(v)
        print(f"   {name:<26} {v[:, 0].mean():>9.5f} {v[:, 1].mean():>7.4f} "
              f"{v[:, 2].mean():>7.4f} {v[:, 3].mean():>9.1%} {v[:, 4].mean():>6.3f} "
              f"{v[:, 5].mean():>16.1f}")


def pairs_and_power_law():
    print("\n3. power law through the (A, b) pairs and pair effectiveness (first sensor)")
    cal_pts, _ = sessions(0, 0.0)
    h, f = points_to_arrays(cal_pts)
    for mode in ("faithful", "robust"):
        r = zvyagin_fit(h, f, mode=mode)
        pl = r.power_law
        print(f"   {mode:<8}: A = {pl['alpha']:.5g} b^{pl['beta']:.3f}, R2 = {pl['r2']:.3f} "
              f"(same line on every valid pair: {pl['r2_all']:.3f}); pairs "
              f"{r.category_counts()}; grey patches {len(r.grey)}")
    print(f"   {'loads':<16} {'pairs':>6} {'root > 3':>9} {'valid':>6} {'share':>6}")
    diff, same = [0, 0], [0, 0]
    for row in r.share_table:
        print(f"   {row['loads']:<16} {row['pairs']:>6} {row['with_root']:>9} "
              f"{row['valid']:>6} {row['share']:>6.1%}")
        a, b = row["loads"].split(" - ")
        acc = same if a == b else diff
        acc[0] += row["valid"]
        acc[1] += row["pairs"]
    print(f"   different weights: {diff[0] / diff[1]:.1%} valid; equal weights: "
          f"{same[0] / same[1]:.1%} valid (paper: 25-34% vs 11-23%)")


def plain_loop_seconds_per_vector(h, n_vectors):
    """Baseline: a plain Python loop over I evaluating eq. (5)-(8) with numpy per vector."""
    ranges = separation_domain()
    vectors = []
    for i1 in ranges[0]:
        for i2 in ranges[1]:
            for i3 in ranges[2]:
                for i4 in ranges[3]:
                    vectors.append((i1, i2, i3, i4))
                    if len(vectors) == n_vectors:
                        break
                if len(vectors) == n_vectors:
                    break
            if len(vectors) == n_vectors:
                break
        if len(vectors) == n_vectors:
            break
    t0 = time.perf_counter()
    best = np.inf
    for vec in vectors:
        best = min(best, patch_discrepancy(h, vec).mean())
    return (time.perf_counter() - t0) / n_vectors


def best_of(func, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - t0)
    return min(times), out


def speed():
    print("\n4. speed")
    sensor = make_sensor("5051", seed=1)
    s = deadweight_session(sensor, n_patches=150, seed=2)
    h, f = points_to_arrays(points_from_frames(s.raw, s.load_N))
    n_domain = int(np.prod([len(r) for r in separation_domain()]))
    t150, res = best_of(lambda: zvyagin_fit(h, f), 3)
    n_sub = 2000 if QUICK else 5000
    per_vec = plain_loop_seconds_per_vector(h, n_sub)
    loop_total = per_vec * n_domain
    print(f"   150 patches, whole procedure (I search over {n_domain} vectors + "
          f"{len(res.pairs['i'])} pairs + power law + E): {t150:.2f} s (best of 3)")
    print(f"   plain Python loop evaluating eq. (8): timed on {n_sub} vectors, "
          f"{per_vec * 1e6:.0f} us per vector -> {loop_total:.0f} s extrapolated to the domain")
    print(f"   ratio plain loop / ours: {loop_total / t150:.0f}x")
    big = deadweight_session(sensor, n_patches=1000, seed=3)
    hb, fb = points_to_arrays(points_from_frames(big.raw, big.load_N))
    t1000, rb = best_of(lambda: zvyagin_fit(hb, fb), 1)
    print(f"   1000 patches ({len(rb.pairs['i'])} pairs): {t1000:.2f} s "
          f"= {t1000 / t150:.1f}x the 150-patch time")


if __name__ == "__main__":
    accuracy()
    choices()
    pairs_and_power_law()
    speed()
