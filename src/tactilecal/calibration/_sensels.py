"""Non-working sensels and equilibration (per-sensel gains from uniform loads).

Gillis (2013), sec. 3.5: equilibration gives every sensel the same output under a uniform
load, at one or several load levels; non-working sensels must be told apart from sensels
that read zero because they are not loaded, reported, and left out of averages.
"""

from dataclasses import dataclass, field

import numpy as np
from scipy import ndimage

from tactilecal._errors import TactilecalError
from tactilecal._jsonutil import to_jsonable
from tactilecal._provenance import provenance_of
from tactilecal._result import SavedResult
from tactilecal._validate import check_number, check_type, require_keys
from tactilecal.calibration._histogram import check_range

__all__ = ["NonWorkingSensels", "find_dead_sensels", "Equilibration", "equilibrate",
           "load_equilibration"]

_NEIGHBOURS = np.array([[1, 1, 1], [1, 0, 1], [1, 1, 1]])


def _as_frames(raw, name="raw"):
    values = np.asarray(getattr(raw, "values", raw), dtype=float)
    if values.ndim == 2:
        values = values[None]
    if values.ndim != 3:
        raise TactilecalError(f"{name} has {values.ndim} dimensions; expected 3 (frame, row, col)")
    check_range(values, f"{name}: ")
    return values


def _frame_blocks(raw, chunk_frames):
    """Frames of any real dtype, not copied or loaded, and the bounds of blocks to read.

    A dask array (a recording larger than memory) is read block by block along its own
    chunks, each computed once; an array in memory in ``chunk_frames`` frames, so that a
    uint8 movie is never converted to float64 whole.
    """
    values = raw.data if hasattr(raw, "dims") else raw  # a DataArray's numpy or dask array
    if not type(values).__module__.startswith("dask."):
        values = np.asarray(values)
    if values.ndim == 2:
        values = values[None]
    if values.ndim != 3:
        raise TactilecalError(f"raw has {values.ndim} dimensions; expected 3 (frame, row, col)")
    if hasattr(values, "chunks") and not isinstance(values, np.ndarray):
        bounds = np.cumsum((0, *values.chunks[0])).tolist()
    else:
        bounds = [*range(0, len(values), max(int(chunk_frames), 1)), len(values)]
    return values, bounds


@dataclass(repr=False, eq=False)
class NonWorkingSensels(SavedResult):
    """Sensels that never respond although their neighbours do.

    Saved as ``"format": "tactilecal-non-working-sensels/1"`` (and inside a calibration
    JSON as ``details["non_working_sensels"]``).

    Attributes
    ----------
    mask : numpy.ndarray of bool
        (rows, cols), True for a non-working sensel.
    evidence_frames : numpy.ndarray of int
        (rows, cols), frames in which the sensel's neighbours responded.
    n_frames : int
        Frames examined.

    Examples
    --------
    >>> import tempfile, pathlib, tactilecal
    >>> from tactilecal.simulate import deadweight_session, make_sensor
    >>> session = deadweight_session(make_sensor("5051", n_dead=3, seed=0), n_patches=30, seed=0)
    >>> dead = find_dead_sensels(session.raw)  # only the dead sensel under a pad shows
    >>> dead.sensels, np.argwhere(session.sensor.dead).tolist()
    ([[20, 23]], [[8, 1], [20, 23], [34, 10]])
    >>> path = pathlib.Path(tempfile.mkdtemp()) / "non_working.json"
    >>> dead.to_json(path)
    >>> tactilecal.load(path).report()
    'non-working sensels: 1 found over 30 frames at (row, col) (20, 23); masked'
    """

    FORMAT_KIND = "non-working-sensels"
    DESCRIPTION = "a non-working sensels JSON"

    mask: np.ndarray
    evidence_frames: np.ndarray
    n_frames: int = 0

    @property
    def sensels(self):
        """List of ``[row, col]`` of the non-working sensels."""
        return np.argwhere(self.mask).tolist()

    def report(self):
        """One line saying how many sensels were found and where."""
        where = ", ".join(f"({r}, {c})" for r, c in self.sensels[:20])
        more = " ..." if self.mask.sum() > 20 else ""
        return (f"non-working sensels: {int(self.mask.sum())} found over {self.n_frames} frames"
                + (f" at (row, col) {where}{more}; masked" if self.mask.any() else ""))

    def summary(self):
        """Return :meth:`report`'s line (how many non-working sensels, and where)."""
        return self.report()

    def _repr_fields(self):
        return [("shape", self.mask.shape), ("n_sensels", int(self.mask.sum())),
                ("sensels", self.sensels), ("n_frames", self.n_frames)]

    def _to_dict(self):
        """JSON-ready summary (the sensels, how many frames showed each, the frame shape)."""
        return to_jsonable({"sensels": self.sensels, "n_frames": self.n_frames,
                            "evidence_frames": self.evidence_frames[self.mask].tolist(),
                            "shape": list(self.mask.shape)})

    @classmethod
    def _from_dict(cls, data, source):
        """Rebuild from :meth:`to_dict` output."""
        require_keys(data, ("sensels", "n_frames", "evidence_frames", "shape"), source,
                     expected=cls.DESCRIPTION)
        where = f"key '{{}}' of {source}"
        sensels = check_type(data["sensels"], list, where.format("sensels"),
                             expected="a list of [row, col]")
        evidence = check_type(data["evidence_frames"], list, where.format("evidence_frames"),
                              expected="a list of counts")
        if len(evidence) != len(sensels) or not all(
                isinstance(rc, list) and len(rc) == 2 for rc in sensels):
            raise TactilecalError(f"{where.format('sensels')} holds {len(sensels)} entries and "
                                  f"evidence_frames {len(evidence)}; expected one [row, col] and "
                                  "one count per sensel")
        for k, (row, col) in enumerate(sensels):
            for value in (row, col):
                check_number(value, f"{where.format('sensels')}, entry {k}", minimum=0,
                             integer=True)
        n_frames = check_number(data["n_frames"], where.format("n_frames"), minimum=0,
                                integer=True)
        rows_cols = np.array(sensels, dtype=int).reshape(-1, 2)
        shape = tuple(check_number(v, where.format("shape"), minimum=0, integer=True)
                      for v in check_type(data["shape"], list, where.format("shape"),
                                          expected="[rows, cols]"))
        if len(shape) != 2 or (len(rows_cols) and np.any(rows_cols.max(axis=0) >= shape)):
            raise TactilecalError(f"{where.format('shape')} is {list(shape)}; expected [rows, "
                                  "cols] holding every listed sensel")
        mask = np.zeros(shape, dtype=bool)
        frames = np.zeros(shape, dtype=int)
        mask[tuple(rows_cols.T)] = True
        frames[tuple(rows_cols.T)] = evidence
        return cls(mask=mask, evidence_frames=frames, n_frames=int(n_frames))


def find_dead_sensels(raw, *, neighbour_share=1.0, min_frames=1, chunk_frames=2048):
    """Detect non-working sensels across a set of frames.

    A sensel is non-working when it reads 0 in every frame although, in at least
    ``min_frames`` frames, at least ``neighbour_share`` of its existing 8 neighbours read
    more than 0 (so an unloaded sensel at the edge of a patch is not mistaken for a dead one).

    The default (all neighbours, one frame) was chosen by measurement: on 8 simulated 5051
    sensors with 6 dead sensels each under 150 dead-weight patches it found 32 of the 48
    dead sensels with no false detection, where 75 % of the neighbours found 36 but also
    15 working sensels at the sensor's edge (a one-off study, in the git history).

    Parameters
    ----------
    raw : array_like, xarray.DataArray or dask array, shape (n, rows, cols)
        Raw frames (NaN for sensels outside the sensor shape), any real dtype; a dask
        array (or a DataArray over one) is read block by block, never whole.
    neighbour_share : float
        Share (0..1] of the existing neighbours that must respond (default all).
    min_frames : int
        Frames of such evidence needed.
    chunk_frames : int
        Frames processed at once (a dask array: its own blocks of frames).

    Returns
    -------
    NonWorkingSensels

    Raises
    ------
    ValueError
        If ``neighbour_share`` is outside (0, 1] or ``min_frames`` < 1.

    Examples
    --------
    >>> frames = np.full((2, 5, 5), 20.0); frames[:, 2, 2] = 0; frames[1, 0, 0] = 0
    >>> find_dead_sensels(frames).sensels
    [[2, 2]]
    """
    if not 0 < neighbour_share <= 1:
        raise TactilecalError(f"neighbour_share={neighbour_share}; expected a share in (0, 1]")
    if int(min_frames) < 1:
        raise TactilecalError(f"min_frames={min_frames}; expected an integer >= 1")
    values, bounds = _frame_blocks(raw, chunk_frames)
    exists = np.isfinite(np.asarray(values[0], dtype=float))
    n_exist = ndimage.convolve(exists.astype(int), _NEIGHBOURS, mode="constant")
    ever = np.zeros(exists.shape, bool)
    evidence = np.zeros(exists.shape, int)
    kernel = _NEIGHBOURS[None]
    for start, stop in zip(bounds[:-1], bounds[1:], strict=True):
        block = np.asarray(values[start:stop])
        check_range(block, f"frames {start}..{stop - 1}: ")
        responding = block > 0  # NaN > 0 is False
        ever |= responding.any(axis=0)
        n_resp = ndimage.convolve(responding.astype(int), kernel, mode="constant")
        evidence += (n_resp >= neighbour_share * np.maximum(n_exist, 1)).sum(axis=0)
    mask = exists & ~ever & (evidence >= min_frames) & (n_exist > 0)
    found = NonWorkingSensels(mask=mask, evidence_frames=evidence, n_frames=len(values))
    found.provenance = provenance_of([raw])
    return found


# ---------------------------------------------------------------------- equilibration
@dataclass(repr=False, eq=False)
class Equilibration(SavedResult):
    """Per-sensel gains that equalise the raw output under a uniform load.

    Saved as ``"format": "tactilecal-equilibration/1"``.

    ``apply`` multiplies every reading by its sensel's gain (0 stays 0, 255 stays 255 as a
    saturated reading cannot be corrected, results are clipped to 255, NaN where the gain
    is unknown: sensels that never responded).

    Attributes
    ----------
    gain : numpy.ndarray
        (rows, cols) gains, NaN for non-working sensels and sensels outside the shape.
    levels : list of dict
        Per load level: frames, mean raw, coefficient of variation before and after.

    Examples
    --------
    >>> from tactilecal.simulate import make_sensor, uniform_load
    >>> sensor = make_sensor("9500", gain_spread=0.1, seed=0)  # 3 dead sensels
    >>> raw, _ = uniform_load(sensor, [10.0, 20.0], frames_per_level=5)
    >>> eq = equilibrate([raw[:5], raw[5:]])  # two load levels
    >>> [(round(lv["cv_before"], 3), round(lv["cv_after"], 3)) for lv in eq.levels]
    [(0.098, 0.005), (0.096, 0.002)]
    >>> eq.gain.shape, int(np.isnan(eq.gain).sum())
    ((14, 14), 3)
    """

    FORMAT_KIND = "equilibration"
    DESCRIPTION = "an equilibration JSON"

    gain: np.ndarray
    levels: list = field(default_factory=list)

    def apply(self, raw):
        """Return equilibrated frames (float, same shape as ``raw``)."""
        values = np.asarray(getattr(raw, "values", raw), dtype=float)
        if values.shape[-2:] != self.gain.shape:
            raise TactilecalError(f"frames have shape {values.shape[-2:]}; expected "
                                  f"{self.gain.shape} (the equilibration's sensor)")
        check_range(values)
        out = np.clip(values * self.gain, 0.0, 255.0)
        return np.where(values == 255, 255.0, out)

    def plot_gains(self, ax=None):
        """Draw the gain of every sensel as a map (NaN: no gain, drawn blank).

        Returns
        -------
        matplotlib.axes.Axes

        Examples
        --------
        >>> eq = Equilibration(gain=np.array([[1.0, 1.1], [0.9, np.nan]]))
        >>> eq.plot_gains().get_title()
        'gain per sensel (1 = unchanged)'
        """
        if ax is None:
            from matplotlib.figure import Figure

            ax = Figure(figsize=(5.0, 4.2), layout="constrained").add_subplot()
        spread = float(np.nanmax(np.abs(self.gain - 1.0))) if np.isfinite(self.gain).any() \
            else 0.1
        image = ax.imshow(self.gain, cmap="RdBu_r", vmin=1 - spread, vmax=1 + spread,
                          origin="upper", interpolation="nearest")
        ax.figure.colorbar(image, ax=ax, shrink=0.8, label="gain")
        ax.set(title="gain per sensel (1 = unchanged)", xlabel="column", ylabel="row")
        return ax

    def summary(self):
        """Describe the gains and each load level's spread before and after (text)."""
        working = np.isfinite(self.gain)
        lines = [f"Equilibration of {self.gain.shape[0]} x {self.gain.shape[1]} sensels: "
                 f"{int(working.sum())} with a gain"
                 + (f", from {np.nanmin(self.gain):.4g} to {np.nanmax(self.gain):.4g}"
                    if working.any() else "")]
        lines += [f"  level {lv.get('level', k)}: {lv.get('n_frames')} frames, mean raw "
                  f"{_num(lv.get('mean_raw')):.4g}, coefficient of variation "
                  f"{_num(lv.get('cv_before')):.3g} -> {_num(lv.get('cv_after')):.3g}"
                  for k, lv in enumerate(self.levels)]
        return "\n".join(lines)

    def _repr_fields(self):
        working = np.isfinite(self.gain)
        span = (float(np.nanmin(self.gain)), float(np.nanmax(self.gain))) if working.any() \
            else None
        return [("shape", self.gain.shape), ("sensels with a gain", int(working.sum())),
                ("gain range", span), ("levels", len(self.levels))]

    def _to_dict(self):
        """JSON-ready dictionary: the ``gain`` table (null: no gain) and the ``levels``."""
        return to_jsonable({"gain": self.gain, "levels": self.levels})

    @classmethod
    def _from_dict(cls, data, source):
        """Rebuild from :meth:`to_dict` output."""
        return cls(gain=_gain_table(data.get("gain"), source),
                   levels=check_type(data.get("levels", []), list, f"key 'levels' of {source}",
                                     expected="a list"))


def _num(value):
    """Return a level's number for text (NaN for null, as JSON stores NaN)."""
    return float("nan") if value is None else float(value)


def _gain_table(rows, source):
    """Return the ``gain`` key as an array: positive gains, NaN for null (non-working).

    Filled row by row (no second list of lists); a row of floats and nulls is checked in
    NumPy, any other value (and every value the check refuses) by
    :func:`~tactilecal._validate.check_number`, which names its row and column.
    """
    where = f"key 'gain' of {source}"
    check_type(rows, list, where, expected="a list of rows")
    if not rows or not all(isinstance(row, list) and len(row) == len(rows[0]) for row in rows):
        raise TactilecalError(f"{where} is not a table; expected rows of equal length")
    gain = np.empty((len(rows), len(rows[0])))
    plain = {float, type(None)}
    for i, row in enumerate(rows):
        if set(map(type, row)) <= plain:
            gain[i] = row  # None is NaN
            suspect = np.flatnonzero(~(gain[i] > 0) | np.isinf(gain[i])).tolist()
        else:
            suspect = range(len(row))
        for j in suspect:
            value = check_number(row[j], f"{where}, row {i} col {j}", minimum=0.0,
                                 min_inclusive=False, allow_none=True)
            gain[i, j] = np.nan if value is None else value
    return gain


def load_equilibration(path):
    """Read an equilibration JSON written by :meth:`Equilibration.to_json`.

    The same as ``Equilibration.from_json(path)``.

    Raises
    ------
    ValueError, TypeError
        Not JSON, not an equilibration, or a gain that is not a positive number or null;
        the message names the file and the key.
    """
    return Equilibration.from_json(path)


def equilibrate(levels):
    """Compute per-sensel gains from uniform-load frames at one or several load levels.

    For each level ``l`` the per-sensel mean raw reading ``m_l`` over its frames is
    compared with the level's mean over the working sensels ``M_l``; the gain is the
    least-squares slope through the origin over the levels,
    ``g = sum_l M_l m_l / sum_l m_l**2`` (one level: ``g = M / m``), the I-Scan
    equilibration of Gillis (2013), sec. 3.5. Saturated means (255) are left out of a
    sensel's sum; sensels that never respond get NaN (non-working).

    Parameters
    ----------
    levels : sequence of array_like or xarray.DataArray
        One (n, rows, cols) set of raw frames per uniform load level.

    Returns
    -------
    Equilibration

    Raises
    ------
    ValueError
        If no level is given, shapes differ, or a level has no loaded sensel.

    Examples
    --------
    >>> sens = np.array([[0.9, 1.0], [1.1, 1.0]])
    >>> eq = equilibrate([50 * sens[None], 100 * sens[None]])
    >>> eq.apply(50 * sens[None]).round(6).tolist()
    [[[50.0, 50.0], [50.0, 50.0]]]
    """
    if getattr(levels, "ndim", 1) == 3:  # one (n, rows, cols) array: not n levels of a frame
        raise TactilecalError(f"levels is one array of shape {tuple(levels.shape)}; its frames "
                              "would each be taken as a load level of their own; expected a "
                              "list with one (n, rows, cols) array per load level, e.g. "
                              "equilibrate([frames]) for one level")
    if len(levels) == 0:
        raise TactilecalError("levels is empty; expected uniform-load frames at one level or more")
    means, counts = [], []
    for k, level in enumerate(levels):
        frames = _as_frames(level, f"level {k}")
        counts.append(len(frames))
        if means and frames.shape[1:] != means[0].shape:
            raise TactilecalError(f"level {k} has frames of shape {frames.shape[1:]}; expected "
                                  f"{means[0].shape} like level 0")
        means.append(frames.mean(axis=0))
    m = np.stack(means)
    valid = np.isfinite(m) & (m > 0) & (m < 255)
    M = np.array([np.nanmean(np.where(v, lvl, np.nan)) if v.any() else np.nan
                  for lvl, v in zip(m, valid, strict=True)])
    if np.isnan(M).any():
        raise TactilecalError(f"level {int(np.flatnonzero(np.isnan(M))[0])} has no loaded, "
                              "unsaturated sensel; expected a uniform load on the sensor")
    mz = np.where(valid, m, 0.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        gain = (M[:, None, None] * mz).sum(axis=0) / (mz ** 2).sum(axis=0)
    gain = np.where(valid.any(axis=0), gain, np.nan)
    report = [{"level": k, "n_frames": counts[k], "mean_raw": float(M[k]),
               "cv_before": _cv(m[k], valid[k]), "cv_after": _cv(m[k] * gain, valid[k])}
              for k in range(len(levels))]
    eq = Equilibration(gain=gain, levels=report)
    eq.provenance = provenance_of(levels)
    return eq


def _cv(values, valid):
    v = values[valid]
    return float(v.std() / v.mean()) if v.size else float("nan")
