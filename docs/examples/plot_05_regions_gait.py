"""
Regions and gait of a recording
===============================

Everything that describes a recording is a method of ``recording.tactile`` (registered by
:mod:`tactilecal.analysis`): force, contact area, centre of force, peak and mean pressure
per frame, regions, high-pressure zones, profiles, and the figures (:doc:`/analysis`).

This example reads the real F-Scan walk of the footPress project (both insoles, 60 x 21
sensels, 205 frames at 0.032 s, in kPa). The real exports are not part of the repository:
they are looked for in ``../shared/realdata`` next to it, or in ``$TACTILECAL_REALDATA``.
Without them, the example writes stand-ins with :func:`tactilecal.io.write_tekscan`: a pad
pressed on an F-Scan-sized sensor (:func:`tactilecal.simulate.ramp_hold`), converted to kPa
by a 1-point calibration of 5.94 kPa per count like the left insole's. That is a press,
not a step, and the example says so.
"""

# %%
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import tactilecal as tc

# the build runs this script in docs/examples: ../../.. is the folder beside the repository
realdata = Path(os.environ.get("TACTILECAL_REALDATA", "../../../shared/realdata"))
paths = {"left": realdata / "footPress_FrasP01L.asf",
         "right": realdata / "footPress_FrasP01R.asf"}
if not all(path.is_file() for path in paths.values()):
    from tactilecal.io import write_tekscan
    from tactilecal.simulate import make_sensor, ramp_hold

    print(f"{realdata} has no footPress exports: reading simulated stand-ins (a press, "
          "not a walk) written by write_tekscan")
    folder = Path(tempfile.mkdtemp())
    for seed, side in enumerate(paths):
        raw = ramp_hold(make_sensor("FSCAN", seed=seed), frame_rate_hz=31.25, seed=seed).raw
        kpa = (raw * 5.94).assign_attrs(raw.attrs, units="kPa")
        paths[side] = folder / f"{side}.asf"
        write_tekscan(kpa.isel(frame=slice(0, 205)), paths[side])
walk = {side: tc.read_tekscan(path) for side, path in paths.items()}
left = walk["left"]
print(left.sizes, left.attrs["units"])

# %%
# Per frame
# ---------
# ``frame_summary`` gives every per-frame quantity at once (the table of ``tactilecal
# analyze``); ``overview`` its headline numbers.
summary = left.tactile.frame_summary()
print(summary)
print(tc.analysis.overview(left.tactile.frame_table()))

# %%
# Force and contact area against time, the peak frame marked; the centre-of-force path.
force_time = left.tactile.plot_force_time(summary=summary)
cof_path = left.tactile.plot_cof_path(summary=summary)

# %%
# Both feet on one time axis
# --------------------------
# Each foot's total force, on the recordings' own time stamps.
fig, ax = plt.subplots(figsize=(6, 3), layout="constrained")
for side, rec in walk.items():
    ax.plot(rec["time"], rec.tactile.force(), label=side)
ax.set(xlabel="time [s]", ylabel="force [N]")
ax.legend()

# %%
# Regions
# -------
# ``select_region`` keeps a box ``(row0, row1, col0, col1)`` (stops excluded) or a boolean
# mask; every other method then describes the region. Here the front and the back half of
# the insole: their forces add up to the whole.
rows = left.sizes["row"]
front = left.tactile.select_region((0, rows // 2, 0, left.sizes["col"]))
back = left.tactile.select_region((rows // 2, rows, 0, left.sizes["col"]))
peak = tc.analysis.peak_frame(summary)  # the file's frame number
print(f"frame {peak}: front {float(front.tactile.force().sel(frame=peak)):.1f} N + back "
      f"{float(back.tactile.force().sel(frame=peak)):.1f} N = "
      f"{float(left.tactile.force().sel(frame=peak)):.1f} N")

# %%
# High-pressure zones: the connected regions above a level, frame by frame, ranked by
# force; and the peak-pressure map they come from.
zones = left.tactile.high_pressure_zones(level_kPa=200.0)
print(zones[zones["frame"] == zones["frame"].iloc[0]].head())
peak_map = left.tactile.plot_pressure_map()
