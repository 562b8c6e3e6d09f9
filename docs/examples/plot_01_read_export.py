"""
Read a Tekscan export
=====================

A Tekscan ASCII export (``.csv`` from I-Scan, ``.asf`` from F-Scan) becomes one
:class:`xarray.DataArray` with dims ``("frame", "row", "col")``, a ``time`` coordinate in
seconds and the sensor's description in ``attrs`` (see :doc:`/data-model`).

This example reads the real I-Scan movie of the pressuRe project (a finger on a 6900
sensor, 309 frames of 28 x 28 raw readings). The real exports are not part of the
repository: they are looked for in ``../shared/realdata`` next to it, or in
``$TACTILECAL_REALDATA``. Without them, the example writes a stand-in of the same shape with
:func:`tactilecal.io.write_tekscan` from :func:`tactilecal.simulate.ramp_hold` data and says
so.
"""

# %%
# Find the export, or write a stand-in
# ------------------------------------
import os
import tempfile
from pathlib import Path

import tactilecal as tc

# the build runs this script in docs/examples: ../../.. is the folder beside the repository
realdata = Path(os.environ.get("TACTILECAL_REALDATA", "../../../shared/realdata"))
path = realdata / "pressuRe_iscan_test.csv"
if not path.is_file():
    from tactilecal.io import write_tekscan
    from tactilecal.simulate import make_sensor, ramp_hold

    print(f"{path} not found: reading a simulated stand-in written by write_tekscan")
    stand_in = ramp_hold(make_sensor("6900", seed=0), frame_rate_hz=10.0, seed=1).raw
    path = Path(tempfile.mkdtemp()) / "simulated_iscan.csv"
    write_tekscan(stand_in, path)

# %%
# Read it
# -------
# One call reads header, frames and times; every header line is kept as a
# ``tekscan_<KEY>`` attribute and the sensor's geometry is parsed into named attributes.
rec = tc.read_tekscan(path)
print(rec.sizes)
for key in ("sensor_type", "units", "sensel_area_mm2", "row_spacing_mm",
            "seconds_per_frame", "noise_threshold"):
    print(f"{key:>18}: {rec.attrs.get(key)}")

# %%
# What it holds
# -------------
# ``recording.tactile`` (registered by :mod:`tactilecal.analysis`, which the top-level names
# load) summarises it as ``tactilecal info`` does.
summary = rec.tactile.describe()
print({key: summary[key] for key in ("frames", "duration_s", "units")})

# %%
# Each sensel's largest reading over the recording (raw readings, 0..255), and the total
# raw reading of every frame against time.
peak_map = rec.tactile.plot_pressure_map()

import matplotlib.pyplot as plt

fig, ax = plt.subplots(figsize=(6, 3), layout="constrained")
ax.plot(rec["time"], rec.sum(("row", "col")))
ax.set(xlabel="time [s]", ylabel="sum of raw readings")
