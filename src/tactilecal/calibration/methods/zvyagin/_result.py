"""Result of the Zvyagin procedure: every intermediate, a summary and a JSON round trip."""

from dataclasses import dataclass, field

import numpy as np

from tactilecal._result import ShortRepr
from tactilecal._units import pressure_to_kPa
from tactilecal.calibration.methods.zvyagin import _plots
from tactilecal.calibration.methods.zvyagin._fit import saturation_pressure_MPa

__all__ = ["ZvyaginResult", "PAIR_CATEGORIES", "summarise_d_map"]

#: One character per pair in the chart of Figure 8.
PAIR_CATEGORIES = {
    "V": "valid: root Y > 3 and both raw-sum errors < max_relerr (the paper's green/cyan)",
    "O": "valid but an outlier of the robust power-law fit (robust mode)",
    "R": "root Y > 3 but a raw-sum error >= max_relerr (the paper's orange)",
    "N": "no root Y > 3",
    "X": "a patch left out (empty frame or saturated in robust mode)",
    "-": "the patch with itself",
}


def summarise_d_map(d_map, ranges, separation):
    """Compact form of d_{T}(I) for storage: profiles, slices at I1*, size of the flat minimum.

    ``profile_Im`` is the minimum of d over the other three components for each value of Im;
    ``I3_I4_at_I1`` is min over I2 of d at I1 = I1* (Figure 7), ``I2_I3_at_I1`` min over I4.
    """
    k1 = int(np.searchsorted(ranges[0], separation[0]))
    at_i1 = d_map[k1]
    d_min = float(d_map.min())
    return {
        "ranges": [[int(r[0]), int(r[-1])] for r in ranges],
        "n_vectors": int(d_map.size),
        "profiles": [np.round(d_map.min(axis=tuple(a for a in range(4) if a != m)), 5)
                     for m in range(4)],
        "I1": int(separation[0]),
        "I3_I4_at_I1": np.round(at_i1.min(axis=0), 4),
        "I2_I3_at_I1": np.round(at_i1.min(axis=2), 4),
        "n_within_5pct": int(np.sum(d_map <= d_min * 1.05)),
    }


def _as_array(x, dtype=float):
    return np.array([np.nan if v is None else v for v in x], dtype=dtype) if dtype is float \
        else np.asarray(x, dtype=dtype)


@dataclass(repr=False)
class ZvyaginResult(ShortRepr):
    """Everything the Zvyagin (2022) procedure computed, patch by patch and pair by pair.

    Attributes mirror the paper: ``separation`` (I*), ``d_min`` (d_{T}(I*)), ``counts``
    (n_1..n_5 per patch at I*), ``pairs`` (every pair i < j: roots, (A, b), category),
    ``pair_matrix`` (Figure 8), ``grey`` (patches pairing with almost nothing),
    ``power_law`` (alpha, beta, R2, eq. 14), ``final`` ((A0, b0) and E, eq. 15),
    ``p_s_MPa`` (eq. 16), ``error_pct`` (per patch, Figure 11) and ``share_table`` (share
    of pairs giving (A, b) per load combination).

    Examples
    --------
    >>> from tactilecal.calibration import calibrate, points_from_frames
    >>> from tactilecal.simulate import deadweight_session, make_sensor
    >>> s = deadweight_session(make_sensor("5051", seed=0), n_patches=30, seed=0)  # b = 1.16
    >>> res = calibrate(points_from_frames(s.raw, s.load_N), method="zvyagin").method_result
    >>> res.mode, res.separation, round(res.b0, 2)
    ('robust', (8, 14, 44, 159), 1.15)
    >>> res.category_counts()
    {'N': 61, 'O': 34, 'R': 42, 'V': 298}
    """

    mode: str
    options: dict
    labels: list
    load_N: np.ndarray
    loaded_cells: np.ndarray
    raw_sum: np.ndarray
    raw_relerr: np.ndarray
    saturated_cells: np.ndarray
    usable: np.ndarray
    excluded: dict
    group: np.ndarray
    group_names: list
    separation: tuple
    d_min: float
    d_map: np.ndarray | None
    domain_ranges: tuple | None
    counts: np.ndarray
    pairs: dict
    pair_matrix: np.ndarray
    partner_share: np.ndarray
    grey: np.ndarray
    power_law: dict
    final: dict
    predicted_N: np.ndarray
    share_table: list
    sensel_area_mm2: float
    d_summary: dict = field(default=None)

    def __post_init__(self):
        if self.d_summary is None and self.d_map is not None:
            self.d_summary = summarise_d_map(self.d_map, self.domain_ranges, self.separation)

    # --- headline numbers -------------------------------------------------------------
    @property
    def A0(self):
        """Final A0 in newtons per sensel (eq. 15)."""
        return self.final["A0"]

    @property
    def b0(self):
        """Final b0 (eq. 15)."""
        return self.final["b0"]

    @property
    def alpha(self):
        """Return alpha of A = alpha * b**beta (eq. 14)."""
        return self.power_law["alpha"]

    @property
    def beta(self):
        """Return beta of A = alpha * b**beta (eq. 14)."""
        return self.power_law["beta"]

    @property
    def p_s_MPa(self):
        """Saturation pressure p_s = A0 * 255**b0 / S_sensel in MPa (eq. 16).

        In MPa as the paper gives it (Table 2); :attr:`p_s_kPa` is the same pressure in
        the kPa of the rest of the toolkit (``CalibrationResult.saturation_pressure_kPa``).
        """
        return saturation_pressure_MPa(self.A0, self.b0, self.sensel_area_mm2)

    @property
    def p_s_kPa(self):
        """Saturation pressure p_s of eq. 16 in kPa (1000 x :attr:`p_s_MPa`)."""
        return float(pressure_to_kPa(self.p_s_MPa, "MPa"))

    def _repr_fields(self):
        return [("mode", self.mode),
                ("patches used", f"{int(np.sum(self.usable))} of {len(self.labels)}"),
                ("separation", self.separation), ("d_min", self.d_min),
                ("pairs", len(self.pairs["b"])), ("alpha", self.alpha), ("beta", self.beta),
                ("A0", self.A0), ("b0", self.b0), ("p_s_kPa", self.p_s_kPa)]

    @property
    def error_pct(self):
        """Per-patch discrepancy (calibrated - applied) / applied in percent (Figure 11)."""
        return 100.0 * (self.predicted_N - self.load_N) / self.load_N

    def valid_pairs(self, *, inliers_only=False):
        """Return the indices into ``pairs`` of the pairs that gave (A, b) (categories V and O)."""
        keep = ("V",) if inliers_only else ("V", "O")
        return np.nonzero(np.isin(self.pairs["category"], keep))[0]

    def terminal_points(self):
        """Return the (A, b) pairs with the smallest and largest b (T1 and T2 of Figure 9).

        Taken among the pairs the power law was fitted to (in robust mode the trimmed
        pairs, category "O", are left out: their b can reach 10 with A near 1e-23).
        """
        idx = self.valid_pairs(inliers_only=True)
        b = self.pairs["b"][idx]
        lo, hi = idx[np.argmin(b)], idx[np.argmax(b)]
        return {name: {"b": float(self.pairs["b"][k]), "A": float(self.pairs["A"][k]),
                       "patches": [self.labels[self.pairs["i"][k]],
                                   self.labels[self.pairs["j"][k]]]}
                for name, k in (("T1", lo), ("T2", hi))}

    def category_counts(self):
        """Count the pairs per category letter (see :data:`PAIR_CATEGORIES`)."""
        upper = self.pair_matrix[np.triu_indices(len(self.labels), k=1)]
        letters, n = np.unique(upper, return_counts=True)
        return {str(k): int(v) for k, v in zip(letters, n, strict=True)}

    def within(self, pct):
        """Share of usable patches whose absolute error is below ``pct`` percent."""
        return float(np.mean(np.abs(self.error_pct[self.usable]) < pct))

    def summary(self):
        """Describe the result in a few lines: the Table 2 row, the pairs and the validation."""
        pl, cc = self.power_law, self.category_counts()
        lines = [
            f"Zvyagin (2022), {self.mode} mode: {int(self.usable.sum())} of "
            f"{len(self.labels)} patches used",
            f"I* = {self.separation}, d(I*) = {self.d_min:.3f} raw units per sensel",
            f"pairs: {sum(cc.values())} ({', '.join(f'{k} {v}' for k, v in cc.items())}); "
            f"grey patches: {len(self.grey)}",
            f"power law A = {pl['alpha']:.5g} * b^{pl['beta']:.4f}, R2 = {pl['r2']:.3f}",
            f"A0 = {self.A0:.5g} N, b0 = {self.b0:.4f}, p_s = {self.p_s_MPa:.3f} MPa",
            f"patches within 5%: {self.within(5):.0%}, within 10%: {self.within(10):.0%}",
        ]
        lines += [f"left out {self.labels[k]}: {why}" for k, why in self.excluded.items()]
        return "\n".join(lines)

    # --- figures: the paper's Figures 7-11 and E(b0), drawn by ``_plots`` ----------------
    plot_d_map = _plots.plot_d_map
    plot_pair_chart = _plots.plot_pair_chart
    plot_ab_scatter = _plots.plot_ab_scatter
    plot_calibration_curves = _plots.plot_calibration_curves
    plot_patch_errors = _plots.plot_patch_errors
    plot_energy = _plots.plot_energy
    save_figures = _plots.save_figures

    # --- JSON -------------------------------------------------------------------------
    def to_details(self, *, max_pairs=20000):
        """JSON-ready dict of every intermediate (the ``details`` of a CalibrationResult).

        Parameters
        ----------
        max_pairs : int
            At most this many pairs with a root Y > 3 are stored with their (A, b) (every
            one up to that number; beyond it an evenly spaced subset, flagged by
            ``pairs_stored``). The pair chart and all counts always cover every pair.
        """
        p = self.pairs
        keep = np.nonzero((p["n_roots"] > 0) & (p["category"] != "X"))[0]
        n_with_root = keep.size
        if keep.size > max_pairs:
            keep = keep[np.linspace(0, keep.size - 1, max_pairs).round().astype(int)]
        pl = {k: v for k, v in self.power_law.items() if k != "inlier"}
        fin = {k: v for k, v in self.final.items() if k not in ("b_grid", "E_grid")}
        return {
            "method": "zvyagin", "mode": self.mode, "options": self.options,
            "separation": list(self.separation), "d_min": self.d_min, "d_map": self.d_summary,
            "power_law": pl, "final": fin,
            "E_curve": {"b": np.round(self.final["b_grid"], 6),
                        "E": self.final["E_grid"]},
            "p_s_MPa": self.p_s_MPa, "sensel_area_mm2": self.sensel_area_mm2,
            "terminal_points": self.terminal_points(),
            "patches": {
                "label": self.labels, "load_N": self.load_N,
                "loaded_cells": self.loaded_cells, "raw_sum": self.raw_sum,
                "raw_relerr": np.round(self.raw_relerr, 6),
                "saturated_cells": self.saturated_cells, "counts": self.counts,
                "usable": self.usable,
                "excluded": {str(k): v for k, v in self.excluded.items()},
                "group": self.group, "partner_share": np.round(self.partner_share, 4),
                "predicted_N": self.predicted_N, "error_pct": self.error_pct,
            },
            "load_groups": self.group_names,
            "grey": self.grey,
            "pairs_stored": f"{keep.size} of {n_with_root} pairs with a root Y > 3",
            "pairs": {"i": p["i"][keep], "j": p["j"][keep], "n_roots": p["n_roots"][keep],
                      "A": [float(f"{v:.7g}") for v in p["A"][keep]],
                      "b": np.round(p["b"][keep], 7),
                      "category": "".join(p["category"][keep])},
            "pair_matrix": ["".join(row) for row in self.pair_matrix],
            "pair_categories": PAIR_CATEGORIES,
            "category_counts": self.category_counts(),
            "share_table": self.share_table,
        }

    @classmethod
    def from_details(cls, details):
        """Rebuild a result from :meth:`to_details` output (e.g. a calibration JSON).

        The full d map is not stored; its compact summary (``d_summary``) is. Pairs without a
        root (and pairs with excluded patches) are only in ``pair_matrix``.
        """
        pt, pr = details["patches"], details["pairs"]
        n = len(pt["label"])
        chart = np.array([list(row) for row in details["pair_matrix"]], dtype="<U1")
        chart = chart.reshape(n, n)
        pairs = {"i": np.asarray(pr["i"], dtype=np.int64), "j": np.asarray(pr["j"], dtype=np.int64),
                 "n_roots": np.asarray(pr["n_roots"], dtype=np.int64),
                 "A": _as_array(pr["A"]), "b": _as_array(pr["b"]),
                 "category": np.array(list(pr["category"]), dtype="<U1")}
        pairs["Y"] = 3.0 ** pairs["b"]
        fin = dict(details["final"])
        fin["b_range"] = tuple(fin["b_range"])
        fin["b_grid"] = _as_array(details["E_curve"]["b"])
        fin["E_grid"] = _as_array(details["E_curve"]["E"])
        pl = dict(details["power_law"])
        pl["inlier"] = pairs["category"][np.isin(pairs["category"], ("V", "O"))] == "V"
        return cls(
            mode=details["mode"], options=details["options"], labels=list(pt["label"]),
            load_N=_as_array(pt["load_N"]), loaded_cells=_as_array(pt["loaded_cells"], int),
            raw_sum=_as_array(pt["raw_sum"], int), raw_relerr=_as_array(pt["raw_relerr"]),
            saturated_cells=_as_array(pt["saturated_cells"], int),
            usable=_as_array(pt["usable"], bool),
            excluded={int(k): v for k, v in pt["excluded"].items()},
            group=_as_array(pt["group"], int), group_names=list(details["load_groups"]),
            separation=tuple(details["separation"]), d_min=details["d_min"], d_map=None,
            domain_ranges=None, counts=np.asarray(pt["counts"], dtype=np.int64).reshape(n, 5),
            pairs=pairs, pair_matrix=chart, partner_share=_as_array(pt["partner_share"]),
            grey=_as_array(details["grey"], int), power_law=pl, final=fin,
            predicted_N=_as_array(pt["predicted_N"]), share_table=details["share_table"],
            sensel_area_mm2=details["sensel_area_mm2"], d_summary=details["d_map"],
        )
