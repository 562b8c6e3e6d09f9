"""
Static calibration from dead weights
====================================

A static calibration turns raw readings into force per sensel. Its input is a set of
calibration points: frames recorded under known loads (dead weights on pads, or a loading
machine's holds), listed in a manifest CSV (``file, frame, mass_kg`` or ``load_N``; see
:doc:`/static-calibration`). Each point is reduced to the histogram of its raw readings,
so every method fits from the same 256 numbers per frame.

This example uses the two dead-weight sessions bundled with the package (the data of
``tactilecal demo``: a simulated 5051 with the true law ``f = 0.0035 raw^1.16`` N per
sensel, 5 % gain spread, read noise and three dead sensels): it calibrates on session ``a``
and checks on the held-out session ``b``. :doc:`/choosing-a-method` says which method to
pick.
"""

# %%
# Points from a manifest
# ----------------------
import tactilecal as tc
from tactilecal.demo import bundle_path

session_a = bundle_path() / "session-a" / "manifest.csv"
session_b = bundle_path() / "session-b" / "manifest.csv"
print(session_a.read_text().splitlines()[:3])
points = tc.load_points(session_a)
held_out = tc.load_points(session_b)
print(len(points), "calibration points,", len(held_out), "held-out points")

# %%
# The default method: a power law fitted to whole frames
# -------------------------------------------------------
cal = tc.calibrate(points, method="power")
print(cal.summary())

# %%
# Checked on the held-out session: the share of its (unsaturated) points predicted within
# 5 % of the applied load, and the median error.
check = tc.validate(cal, held_out)
print({key: round(check.metrics[key], 3) for key in ("within_5pct", "median_abs_error_pct")})

# %%
# Every method on the same points
# -------------------------------
# The same calibration points fit every method; the held-out session ranks them.
for method in tc.calibration.METHODS:
    result = tc.calibrate(points, method=method)
    metrics = tc.validate(result, held_out).metrics
    print(f"{method:>14}: within 5 % {metrics['within_5pct']:6.1%}, "
          f"median |error| {metrics['median_abs_error_pct']:5.2f} %")

# %%
# The fitted law and the points it was fitted to
# ----------------------------------------------
curve = cal.plot_curve()
errors = cal.plot_points()

# %%
# A calibration is saved as JSON with its provenance and read back by ``tactilecal.load``;
# ``cal.apply(recording, units="kPa")`` converts a raw recording.
import tempfile
from pathlib import Path

path = Path(tempfile.mkdtemp()) / "cal.json"
cal.to_json(path)
print(tc.load(path).params == cal.params)
