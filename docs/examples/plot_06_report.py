"""
The HTML report
===============

``write_report`` (``tactilecal report`` on the command line) writes one self-contained
HTML page for the lab book: every input's provenance (path, size, SHA-256), the numbers and
the figures, each with a sentence on how to read it (:doc:`/analysis`).

This example reports the real F-Scan walk of the footPress project (left insole), already
in kPa: F-Scan applied the 1-point calibration that the file's header records. Without the
real exports (``../shared/realdata`` next to the repository, or ``$TACTILECAL_REALDATA``)
it reports a stand-in written by :func:`tactilecal.io.write_tekscan` from
:func:`tactilecal.simulate.ramp_hold` data, and says so.
"""

# %%
import os
import re
import tempfile
from pathlib import Path

from tactilecal.report import write_report

# the build runs this script in docs/examples: ../../.. is the folder beside the repository
realdata = Path(os.environ.get("TACTILECAL_REALDATA", "../../../shared/realdata"))
path = realdata / "footPress_FrasP01L.asf"
folder = Path(tempfile.mkdtemp())
if not path.is_file():
    from tactilecal.io import write_tekscan
    from tactilecal.simulate import make_sensor, ramp_hold

    print(f"{path} not found: reporting a simulated stand-in written by write_tekscan")
    raw = ramp_hold(make_sensor("FSCAN", seed=0), frame_rate_hz=31.25, seed=0).raw
    path = folder / "stand-in.asf"
    write_tekscan((raw * 5.94).assign_attrs(raw.attrs, units="kPa").isel(
        frame=slice(0, 205)), path)

# %%
# Write the report
# ----------------
out = write_report([path], folder / "walk.html", title="F-Scan walk, left insole")
html = out.read_text()
print(f"{out.name}: {len(html) / 1e6:.2f} MB, {html.count('<img')} figures")

# %%
# Its sections
# ------------
for heading in re.findall(r"<h2>(.*?)</h2>", html):
    print("-", re.sub(r"<.*?>", "", heading))
