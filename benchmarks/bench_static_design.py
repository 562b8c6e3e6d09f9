"""Benchmark: what each family member's training session gives a static fit (issue 12).

Per member of :data:`tactilecal.simulate.FAMILY`, over ``--seeds`` training sessions (45
patches, :func:`family_sessions`), from the simulation's truth:

- loaded sensels per patch (true force > 0) and Kish's effective number of sensels
  ``n_eff = (sum f)**2 / sum f**2`` over the true force map;
- the share of the sensor's area under the pad;
- the true law's relative error on the unsaturated training patches (``hist @ true table /
  load - 1``) and the share within 5 %: the floor set by gain spread and noise, before any
  fit;
- the largest reading and the share of the load carried by sensels above raw 128;
- the share of patches with more than 2 % of their load on dead sensels (lost to any law);
- the share of candidate patches that saturate when drawn (the session keeps
  ``saturated_share`` of them and redraws the rest), from one batch of 400 draws.

Usage: ``python benchmarks/bench_static_design.py [--seeds 20] [--members a,b]``
"""

import argparse
import time

import numpy as np

from tactilecal.calibration import points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.simulate import FAMILY, family_sessions, true_force_table_N
from tactilecal.simulate._deadweight import ContactModel, _base_relief, _draw_patches


def session_figures(member, seed):
    """Figures of one training session (one value per patch, or per session)."""
    train, _ = family_sessions(member, seed)
    force = train.force_N
    n_eff = force.sum(axis=(1, 2)) ** 2 / (force ** 2).sum(axis=(1, 2))
    hist, load = points_to_arrays(points_from_frames(train.raw.values, train.load_N))
    error = hist.astype(float) @ true_force_table_N(train.sensor) / load - 1
    raw = train.raw.values
    side_mm = train.pad_side_cm * 10.0
    sensor = train.sensor
    area = side_mm ** 2 / (sensor.rows * sensor.row_spacing_mm * sensor.cols
                           * sensor.col_spacing_mm)
    high = np.where(raw > 128, force, 0).sum(axis=(1, 2)) / force.sum(axis=(1, 2))
    return {"loaded": (force > 0).sum(axis=(1, 2)), "n_eff": n_eff, "area": area,
            "abs_error": np.abs(error[~train.saturated]),
            "within": np.abs(error[~train.saturated]) <= 0.05,
            "max_raw": raw.max(axis=(1, 2)), "high": high,
            "saturated": train.saturated,
            "dead": force[:, sensor.dead].sum(axis=1) / force.sum(axis=(1, 2)) > 0.02}


def saturating_draws(member, seed=0, n=400):
    """Share of ``n`` candidate patches that hold a reading at 255 when drawn."""
    sensor = member.sensor(seed)
    rng = np.random.default_rng(seed)
    contact = ContactModel()
    base = _base_relief(sensor, contact, rng)
    batch = _draw_patches(sensor, base, contact, member.masses_kg, member.pad_sides_cm, n, rng)
    return float(np.mean(batch["saturated"]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--members", default=",".join(FAMILY))
    args = parser.parse_args()
    start = time.perf_counter()
    print("medians over every training patch of the seeds (10th-90th percentile in brackets)")
    print(f"{'member':<17}{'loaded sensels':>19}{'n_eff':>19}{'pad/sensor area':>17}"
          f"{'truth |err| %':>19}{'truth within 5%':>16}{'max raw':>9}"
          f"{'force >128':>11}{'sat. draws':>11}{'sat. kept':>10}{'dead >2%':>9}")
    for name in args.members.split(","):
        member = FAMILY[name]
        runs = [session_figures(member, seed) for seed in range(args.seeds)]
        cat = {k: np.concatenate([np.atleast_1d(r[k]) for r in runs]) for k in runs[0]}

        def cell(key, scale=1.0, fmt=".1f", width=19, cat=cat):
            lo, mid, hi = np.quantile(cat[key] * scale, [0.1, 0.5, 0.9])
            return f"{f'{mid:{fmt}} ({lo:{fmt}}-{hi:{fmt}})':>{width}}"

        print(f"{name:<17}{cell('loaded', fmt='.0f')}{cell('n_eff')}"
              f"{cell('area', fmt='.2f', width=17)}{cell('abs_error', 100)}"
              f"{np.mean(cat['within']):>16.2f}{int(np.max(cat['max_raw'])):>9d}"
              f"{np.median(cat['high']):>11.2f}{saturating_draws(member):>11.2f}"
              f"{np.mean(cat['saturated']):>10.2f}{np.mean(cat['dead']):>9.2f}", flush=True)
    print(f"{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
