"""The compiled I* search and pair solver (issue 16) against a plain solver of the equations.

``tests/zvyagin_reference.py`` writes Zvyagin's search and pair stage directly from the
paper (every separation's class counts, each pair's quartic by :func:`numpy.roots`), sharing
no code with the package; every result of :func:`zvyagin_fit` must be the same with it and
with the package's functions, to 1e-9 relative (the roots come from different algorithms:
root isolation and Newton's method, or the package's companion matrices for ill-conditioned
pairs, against numpy.roots; both are exact to rounding, ~1e-14, once a double root split by
rounding is put at its mean).
"""

import hashlib
import importlib.util
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from tactilecal.calibration import points_from_frames
from tactilecal.calibration._points import points_to_arrays
from tactilecal.calibration.methods.zvyagin import Options, _calibrate
from tactilecal.calibration.methods.zvyagin._approx import class_counts
from tactilecal.calibration.methods.zvyagin._approx import search_separation as new_search
from tactilecal.calibration.methods.zvyagin._kernels import pair_roots
from tactilecal.calibration.methods.zvyagin._pairs import (
    polynomial_roots,
    quartic_coefficients,
    roots_above,
    solve_pairs,
)
from tactilecal.simulate import deadweight_session, make_sensor

_SPEC = importlib.util.spec_from_file_location(
    "zvyagin_reference", Path(__file__).with_name("zvyagin_reference.py"))
ref = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(ref)

RTOL = 1e-9
#: (sensor model, A_N, b, masses kg, pad sides cm, patches, share with a 255, seed)
SESSIONS = [("5051", 0.0035, 1.16, (2, 5, 10), (1, 2, 3), 150, 0.2, 1),
            ("5051", 0.0035, 1.30, (2, 5, 10), (1, 2, 3), 120, 0.0, 2),
            ("9500", 0.016, 1.40, (5, 10, 20), (3, 4, 5), 90, 0.0, 3),
            ("5051", 0.0035, 1.16, (2, 5, 10, 20), (1, 2, 3), 100, 0.4, 4)]


@cache
def _session(model, a_n, b, masses_kg, pad_sides_cm, n_patches, saturated_share, seed):
    sensor = make_sensor(model, A_N=a_n, b=b, seed=seed)
    s = deadweight_session(sensor, n_patches=n_patches, masses_kg=masses_kg,
                           pad_sides_cm=pad_sides_cm, saturated_share=saturated_share,
                           seed=100 + seed)
    return points_to_arrays(points_from_frames(s.raw, s.load_N))


_SEARCHES = {}


def _reference_search(histograms, *, domain="strict"):
    """The plain search, once per distinct histograms and domain (both modes search alike)."""
    h = np.ascontiguousarray(histograms)
    key = (h.shape, h.dtype.str, hashlib.blake2b(h.tobytes()).hexdigest(), domain)
    if key not in _SEARCHES:
        _SEARCHES[key] = ref.search_separation(h, domain=domain)
    separation, d_min, d_map = _SEARCHES[key]
    return separation, d_min, d_map.copy()


def _fit(monkeypatch, h, f, reference, *, mode, saturated):
    """Zvyagin's procedure as ``calibrate`` runs it for each saturation treatment."""
    if saturated == "drop":  # calibrate leaves the saturated patches out
        h, f = h[h[:, 255] == 0], f[h[:, 255] == 0]
    censored = h[:, 255] > 0 if saturated == "censored" else None
    with monkeypatch.context() as m:
        if reference:
            m.setattr(_calibrate, "search_separation", _reference_search)
            m.setattr(_calibrate, "solve_pairs", ref.solve_pairs)
        return _calibrate.zvyagin_fit(h, f, Options(mode=mode), censored=censored,
                                      sensel_area_mm2=1.6129)


def _assert_same(new, old):
    assert new.separation == old.separation
    np.testing.assert_allclose(new.d_min, old.d_min, rtol=1e-12)
    np.testing.assert_allclose(new.d_map, old.d_map, rtol=1e-5)  # float32 sums
    for key in ("i", "j", "n_roots", "category"):
        np.testing.assert_array_equal(new.pairs[key], old.pairs[key], err_msg=key)
    for key in ("Y", "b", "A"):
        np.testing.assert_allclose(new.pairs[key], old.pairs[key], rtol=RTOL, err_msg=key)
    for key in ("alpha", "beta", "r2", "r2_all"):
        np.testing.assert_allclose(new.power_law[key], old.power_law[key], rtol=RTOL,
                                   err_msg=key)
    np.testing.assert_array_equal(new.power_law["inlier"], old.power_law["inlier"])
    for key in ("A0", "b0", "E", "curve_A0", "curve_b0"):
        if key in old.final:
            np.testing.assert_allclose(new.final[key], old.final[key], rtol=RTOL, err_msg=key)
    np.testing.assert_allclose(new.predicted_N, old.predicted_N, rtol=RTOL)
    np.testing.assert_array_equal(new.grey, old.grey)
    np.testing.assert_array_equal(new.partner_share,
                                  ref.partner_share(old.pairs, old.usable, len(old.labels)))
    assert new.share_table == ref.pair_share_table(old.group, old.group_names, old.pairs,
                                                   old.usable)


def _saturation_cases():
    """Each session with each saturation rule it can test; the 150-patch session is slow (the
    100-patch session, 40 % saturated, runs every rule fast)."""
    for s in SESSIONS:
        for sat in ("keep", "drop", "censored") if s[6] else ("keep",):
            marks = [pytest.mark.slow] if s[5] == 150 else []
            yield pytest.param(s, sat, marks=marks)


@pytest.mark.parametrize(("session", "saturated"), list(_saturation_cases()),
                         ids=lambda v: f"{v[0]}-b{v[2]}-{v[5]}p" if isinstance(v, tuple) else v)
@pytest.mark.parametrize("mode", ["faithful", "robust"])
def test_same_results_as_the_plain_solver(monkeypatch, session, saturated, mode):
    h, f = _session(*session)
    new = _fit(monkeypatch, h, f, False, mode=mode, saturated=saturated)
    old = _fit(monkeypatch, h, f, True, mode=mode, saturated=saturated)
    _assert_same(new, old)
    assert np.sum(new.pairs["category"] == "V") >= 50  # the comparison covers real pairs


def test_same_search_on_the_closed_domain():
    h, _ = _session(*SESSIONS[0])
    sep, d_min, d_map = new_search(h, domain="closed")
    sep_old, d_old, map_old = ref.search_separation(h, domain="closed")
    assert sep == sep_old
    assert d_min == pytest.approx(d_old, rel=1e-12)
    np.testing.assert_allclose(d_map, map_old, rtol=1e-5)


@pytest.mark.parametrize(("n_patches", "several_roots"), [
    (120, 10), pytest.param(250, 40, marks=pytest.mark.slow)])
@pytest.mark.parametrize(("b_min", "root_choice"), [(1.0, "smallest"), (0.5, "best-fit")])
def test_pairs_equal_the_plain_solver(b_min, root_choice, n_patches, several_roots):
    """Every pair of one large session compared: 7,140 pairs of 120 patches (31 and 76 with
    several roots above the threshold), 31,125 of 250 in the slow run (61 and 228)."""
    sensor = make_sensor("5051", seed=4)
    s = deadweight_session(sensor, n_patches=n_patches, seed=5)
    h, f = points_to_arrays(points_from_frames(s.raw, s.load_N))
    counts = class_counts(h, (6, 17, 50, 150))
    relerr = np.linspace(0.0, 0.2, h.shape[0])
    new = solve_pairs(counts, f, relerr, histograms=h, root_choice=root_choice, b_min=b_min)
    old = ref.solve_pairs(counts, f, relerr, histograms=h, root_choice=root_choice,
                          b_min=b_min)
    for key in ("i", "j", "n_roots", "category"):
        np.testing.assert_array_equal(new[key], old[key], err_msg=key)
    for key in ("Y", "b", "A"):
        np.testing.assert_allclose(new[key], old[key], rtol=RTOL, err_msg=key)
    assert np.sum(new["n_roots"] > 1) > several_roots  # several roots above the threshold


def _kernel(counts, load):
    i, j = np.array([0]), np.array([1])
    roots, n_roots, flagged = np.empty((1, 4)), np.empty(1, np.int64), np.empty(1, bool)
    pair_roots(np.asarray(counts, float), np.asarray(load, float), i, j, 3.0, roots,
               n_roots, flagged)
    return roots[0], int(n_roots[0]), bool(flagged[0])


@pytest.mark.parametrize(("counts", "why"), [
    ([[3, 0, 0, 0, 0], [0, 1, 0, 0, 0]], "root at the threshold: 3 - Y"),
    ([[16, 0, 1, 0, 0], [0, 8, 0, 0, 0]], "double root: (Y - 4)**2"),
    ([[0, 9, 0, 1, 0], [0, 0, 6, 0, 0]], "double root at the threshold: Y (Y - 3)**2"),
])
def test_ill_conditioned_pairs_go_to_the_companion_matrix(counts, why):
    counts = np.array(counts)
    load = np.ones(2)
    _roots, _n, flagged = _kernel(counts, load)
    assert flagged, why
    want = roots_above(polynomial_roots(quartic_coefficients(counts, load, np.array([0]),
                                                             np.array([1]))))
    got = solve_pairs(counts, load, np.zeros(2))
    assert got["n_roots"][0] == np.sum(~np.isnan(want))
    np.testing.assert_allclose(got["Y"][0], want[0, 0], rtol=1e-6, equal_nan=True)


@pytest.mark.parametrize(("roots", "n_above"), [
    ([3.5, 5.0, 7.0, 11.0], 4), ([1.0, 2.0, 4.0, 9.0], 2), ([-1.0, 0.5, 2.0, 2.9], 0),
    ([3.2, -2.0, 100.0, 0.1], 2), ([20.0, 20.5, 21.0, 1.5], 3),
])
def test_kernel_finds_known_real_roots(roots, n_above):
    """Quartics built from their roots (load 1 and 0: c = n_i - 0 * n_j = n_i)."""
    c = np.polynomial.polynomial.polyfromroots(roots)
    counts = np.vstack([c, np.zeros(5)])
    got, n, flagged = _kernel(counts, [0.0, 1.0])
    assert not flagged and n == n_above
    want = np.sort([r for r in roots if r > 3.0])
    np.testing.assert_allclose(got[:n], want, rtol=1e-12)
    assert np.isnan(got[n:]).all()


def test_kernel_steps_past_a_flat_point():
    """Pair of a 600-patch session: -(Y**4 - 8 Y**3 + 1), one root > 3 (7.998); the first
    bisection of (3, 9) lands on Y = 6 where p' = 0 (a former bug returned 6)."""
    got, n, flagged = _kernel([[1, 1, 8, 35, 16], [2, 1, 8, 27, 17]], [49.04, 49.04])
    want = np.roots([-1.0, 8.0, 0.0, 0.0, -1.0]).real.max()
    assert not flagged and n == 1
    assert got[0] == pytest.approx(want, rel=1e-12)


def test_a_load_that_is_not_finite_fails_as_before():
    counts = np.array([[10, 5, 2, 1, 0], [20, 5, 1, 0, 0], [5, 5, 5, 5, 1]])
    load = np.array([1.0, np.nan, 2.0])
    _roots, _n, flagged = _kernel(counts[:2], load[:2])
    assert flagged
    with np.errstate(invalid="ignore"), pytest.raises(np.linalg.LinAlgError, match="infs or NaNs"):
        ref.solve_pairs(counts, load, np.zeros(3))
    with np.errstate(invalid="ignore"), pytest.raises(np.linalg.LinAlgError, match="infs or NaNs"):
        solve_pairs(counts, load, np.zeros(3))


def test_a_root_on_the_threshold_does_not_count():
    """Patches 19 and 47 of SESSIONS[1] (10 kg each, equal Q(3) = 7221): an exact root Y = 3,
    which rounding puts at 3.0000000000000013; the paper's Y > 3 leaves it out."""
    load = 98.09199728999998
    c = load * np.array([1, 28, 93, 52, 1.0]) - load * np.array([4, 15, 64, 63, 1.0])
    roots = polynomial_roots(c[None])
    assert np.nanmin(np.abs(roots.real - 3.0)) < 1e-12  # the root is there
    assert np.isnan(roots_above(roots, 3.0)).all()


def test_a_double_root_split_by_rounding_is_put_at_its_mean():
    """Y (Y - 2)**2 (Y + 1) / Y: the companion matrix gives 2 -+ ~4e-8, their mean 2."""
    got = roots_above(polynomial_roots(np.array([[4.0, 0.0, -3.0, 1.0]])), 3.0 ** 0.5)
    np.testing.assert_allclose(got[0, :2], [2.0, 2.0], rtol=1e-14)
    assert np.isnan(got[0, 2])
