"""Censored fits (issue 12): a patch with a sensel at 255 is a lower bound of its load."""

import numpy as np
import pytest
from scipy import optimize

from tactilecal import calibrate
from tactilecal.calibration import points_from_frames
from tactilecal.calibration._fit import Fit, FitData
from tactilecal.calibration._models import LEVELS
from tactilecal.calibration._powerfit import _censored_median
from tactilecal.calibration.methods import MODULES
from tactilecal.calibration.methods._censored import refit_censored
from tactilecal.simulate import family_sessions, true_force_table_N


def test_censored_median_is_the_minimum_of_its_one_sided_cost():
    rng = np.random.default_rng(0)
    for _ in range(20):
        ratio, weight = rng.normal(1, 0.1, 30), rng.uniform(0.5, 2, 30)
        censored = rng.random(30) < 0.3

        def cost(a, ratio=ratio, weight=weight, censored=censored):
            r = a - ratio
            return np.sum(weight * np.where(censored, np.maximum(r, 0), np.abs(r)))

        best = _censored_median(ratio, weight, censored)
        # a piecewise-linear convex cost is smallest at one of its kinks
        assert cost(best) == pytest.approx(min(cost(a) for a in ratio), rel=1e-12)


def test_censored_median_without_censoring_is_the_weighted_median():
    ratio, weight = np.array([3.0, 1.0, 2.0, 5.0]), np.array([1.0, 1.0, 1.0, 4.0])
    expected = np.quantile(ratio, 0.5, weights=weight, method="inverted_cdf")
    assert _censored_median(ratio, weight, np.zeros(4, bool)) == expected


@pytest.mark.parametrize("method", ["linear", "polynomial", "linear-offset"])
def test_linear_censored_fit_is_the_minimum_of_the_one_sided_cost(method):
    """The refit loop's fixed point against a direct minimisation of the convex cost."""
    train, _ = family_sessions("5051-saturating", seed=3)
    points = points_from_frames(train.raw.values, train.load_N)
    hist = np.array([p.histogram for p in points], dtype=float)
    load = np.asarray(train.load_N, dtype=float)
    censored = hist[:, 255] > 0
    assert censored.sum() >= 5
    module = MODULES[method]
    fit = module.fit(FitData(hist, load, censored=censored), module.Options())

    design = {"linear": lambda: (hist @ LEVELS)[:, None],
              "polynomial": lambda: hist @ (LEVELS[:, None] ** np.arange(1, 4)),
              "linear-offset": lambda: np.column_stack([hist @ LEVELS,
                                                        -hist[:, 1:].sum(axis=1)])}[method]()
    scale = np.abs(design).max(axis=0)

    def cost(x):
        r = (design / scale) @ x - load
        return np.sum(np.where(censored, np.maximum(r, 0), r) ** 2)

    direct = optimize.minimize(cost, np.linalg.lstsq(design / scale, load, rcond=None)[0],
                               method="BFGS", options={"gtol": 1e-10})
    assert cost(_coefficients(method, fit) * scale) == pytest.approx(direct.fun, rel=1e-6)


def _coefficients(method, fit):
    if method == "linear":
        return np.array([fit.params["A"]])
    if method == "polynomial":
        return np.array(fit.params["coefficients"])
    return np.array([fit.params["K"], fit.params["K"] * fit.params["offset"]])


@pytest.mark.parametrize("method", ["power", "polynomial", "lut", "piecewise", "zvyagin"])
def test_censored_fits_predict_held_out_patches_as_well_as_the_truth(method):
    """On 40 % saturated patches the censored law predicts as well as the true one."""
    train, test = family_sessions("5051-saturating", seed=2)
    points = points_from_frames(train.raw.values, train.load_N)
    hist = np.array([p.histogram for p in points_from_frames(test.raw.values, test.load_N)],
                    dtype=float)
    load = np.asarray(test.load_N, dtype=float)
    clean = hist[:, 255] == 0

    def share(table):
        return np.mean(np.abs(hist[clean] @ table / load[clean] - 1) <= 0.05)

    options = {"mode": "robust", "sensel_area_mm2": 1.6129} if method == "zvyagin" else {}
    truth = share(true_force_table_N(train.sensor))
    censored = share(calibrate(points, method=method, saturated="censored",
                               **options).force_table())
    assert truth > 0.9
    assert censored >= 0.95 * truth  # measured 1.00 of 1.00 for each method


def test_a_censored_refit_that_never_settles_says_so():
    """A law that over-predicts the saturated patch exactly when it is left out cycles."""
    hist = np.zeros((3, 256))
    hist[:, 10] = 1
    hist[2, 255] = 1
    load = np.array([1.0, 1.0, 5.0])

    def flip_flop(data):  # in the set: predicts 4 < 5; out of it: 6 > 5
        return Fit("power", {"A": 4.0 / 265 if len(data.load_N) == 3 else 6.0 / 265, "b": 1.0})

    with pytest.raises(ValueError, match=r"the set of over-predicted saturated patches did not "
                                         r"settle in 50 refits"):
        refit_censored(flip_flop, FitData(hist, load, censored=np.array([False, False, True])))
