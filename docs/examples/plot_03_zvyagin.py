"""
Zvyagin's method and its figures
================================

Zvyagin (2022, *Sensors* 22(19):7290) calibrates from the uneven high-pressure zones of
dead-weight patches: it finds, for every pair of patches, the power law that both obey,
fits ``A = alpha b^beta`` to those laws and chooses the law of least energy. It runs
through the same door as every static method, ``calibrate(points, method="zvyagin")``;
its intermediate results are ``cal.method_result``, with the paper's figures as methods
(:doc:`/zvyagin`).

The data are the bundled session ``a`` of ``tactilecal demo`` (a simulated 5051 with the
true law ``f = 0.0035 raw^1.16`` N per sensel).
"""

# %%
import tactilecal as tc
from tactilecal.demo import bundle_path

points = tc.load_points(bundle_path() / "session-a" / "manifest.csv")
cal = tc.calibrate(points, method="zvyagin")
print(cal.summary())

# %%
# The steps, as the paper's figures
# ---------------------------------
# The mean discrepancy ``d(I)`` over the separation domain (Figure 7): its minimum I* splits
# each patch's sensels into low- and high-pressure zones.
z = cal.method_result
d_map = z.plot_d_map()

# %%
# Every pair of patches: the number of roots of eq. (12) above the threshold (Figure 8).
pairs = z.plot_pair_chart()

# %%
# The (A, b) laws of the usable pairs and the fitted ``A = alpha b^beta`` (Figure 9).
ab = z.plot_ab_scatter()

# %%
# The energy ``E(b0)`` along that curve: the chosen law.
energy = z.plot_energy()

# %%
# The calibration curves (Figure 10) and each patch's error (Figure 11).
curves = z.plot_calibration_curves()
patch_errors = z.plot_patch_errors()

# %%
# Against other methods
# ---------------------
# ``compare_calibrations`` puts calibrations side by side as the paper's Table 2 and
# Figure 10 do.
power = tc.calibrate(points, method="power")
comparison = tc.calibration.compare_calibrations([cal, power], names=["zvyagin", "power"])
print(comparison.table())
side_by_side = comparison.plot()
