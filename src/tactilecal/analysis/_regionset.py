"""Named regions of a sensor: boxes, polygons, masks from files, as boolean sensel masks.

A region is a boolean mask over the sensor's ``(row, col)`` grid; :class:`Regions` keeps
several by name, in order. They are made from specifications (:meth:`Regions.from_specs`):
a box of sensel indices, a polygon of sensel coordinates, a mask (an array or a file), or
the text forms the command line takes (``--region NAME=SPEC``), or found in the recording
(:func:`tactilecal.analysis._contacts.split_contacts`).
"""

import re
from pathlib import Path

import numpy as np

from tactilecal._errors import TactilecalError
from tactilecal._validate import parse_number, read_text

__all__ = ["Regions", "region_mask", "parse_region_option"]

_BOX_TEXT = re.compile(r"^\s*(\d*)\s*:\s*(\d*)\s*,\s*(\d*)\s*:\s*(\d*)\s*$")
_SPEC_HELP = ("a box 'R0:R1,C0:C1' (0-based sensel indices, stops excluded), a polygon "
              "'poly:R,C;R,C;R,C' (vertices in sensel coordinates) or a mask file (.csv, "
              ".txt or .npy)")


class Regions:
    """Named regions of a sensor, each a boolean ``(rows, cols)`` mask, in order.

    Parameters
    ----------
    masks : dict
        Region name -> boolean array of shape ``(rows, cols)``. Regions may overlap (a box
        inside a larger one); those found by ``split_contacts`` never do and cover the
        whole sensor, so their forces add up to the total.
    how : dict, optional
        Region name -> how it was made (shown in reports).

    Examples
    --------
    >>> import numpy as np
    >>> r = Regions.from_specs({"left": (0, 2, 0, 1), "right": "0:2,1:2"}, shape=(2, 2))
    >>> r.names, [int(m.sum()) for m in r.masks], r.is_partition()
    (['left', 'right'], [2, 2], True)
    """

    def __init__(self, masks, *, how=None):
        masks = {str(name): np.asarray(mask) for name, mask in dict(masks).items()}
        if not masks:
            raise TactilecalError("no regions; expected at least one named region")
        shapes = {mask.shape for mask in masks.values()}
        for name, mask in masks.items():
            if mask.dtype != bool or mask.ndim != 2 or len(shapes) > 1:
                raise TactilecalError(f"region {name!r} has dtype {mask.dtype} and shape "
                                      f"{mask.shape}; expected boolean masks of one shape "
                                      f"(rows, cols), found shapes {sorted(shapes)}")
        self._masks = masks
        self.how = {name: (how or {}).get(name, "mask") for name in masks}

    @classmethod
    def from_specs(cls, specs, *, shape):
        """Make regions from ``{name: spec}`` on a sensor of ``shape`` (see :func:`region_mask`).

        Examples
        --------
        >>> Regions.from_specs({"top": (0, 1, 0, 3)}, shape=(2, 3)).masks[0].tolist()
        [[True, True, True], [False, False, False]]
        """
        masks, how = {}, {}
        for name, spec in dict(specs).items():
            masks[name], how[name] = region_mask(spec, shape, name=name)
        return cls(masks, how=how)

    @staticmethod
    def parse_option(text):
        """Split a ``--region NAME=SPEC`` value into ``(name, spec)``.

        Examples
        --------
        >>> Regions.parse_option("heel=40:60,0:21")
        ('heel', '40:60,0:21')
        """
        return parse_region_option(text)

    @property
    def names(self):
        """Region names, in order."""
        return list(self._masks)

    @property
    def masks(self):
        """The masks stacked, ``(n_regions, rows, cols)``, in the order of :attr:`names`."""
        return np.stack(list(self._masks.values()))

    @property
    def shape(self):
        """The sensor's ``(rows, cols)``."""
        return next(iter(self._masks.values())).shape

    def __getitem__(self, name):
        return self._masks[name]

    def __iter__(self):
        return iter(self._masks)

    def __len__(self):
        return len(self._masks)

    def items(self):
        """``(name, mask)`` pairs, in order."""
        return self._masks.items()

    def is_partition(self):
        """Return True when every sensel is in exactly one region (forces then add up)."""
        return bool((self.masks.sum(axis=0) == 1).all())

    def labels(self):
        """Return an int ``(rows, cols)`` map: 0 outside every region, k in the k-th.

        Raises
        ------
        TactilecalError
            If regions overlap (a sensel would need two labels).
        """
        stack = self.masks
        if (stack.sum(axis=0) > 1).any():
            raise TactilecalError(f"regions {self.names} overlap; expected disjoint regions for "
                                  "a label map")
        return (stack * np.arange(1, len(stack) + 1)[:, None, None]).sum(axis=0)

    def to_dict(self):
        """Return a JSON-ready description: each region's sensels (row, col lists) and origin."""
        return {name: {"how": self.how[name], "sensels": int(mask.sum()),
                       "rows": np.nonzero(mask)[0].tolist(), "cols": np.nonzero(mask)[1].tolist()}
                for name, mask in self.items()}

    def __repr__(self):
        parts = ", ".join(f"{name}: {int(mask.sum())} sensels ({self.how[name]})"
                          for name, mask in self.items())
        return f"Regions({parts}; sensor {self.shape[0]} x {self.shape[1]})"


def region_mask(spec, shape, *, name="region"):
    """Return ``(mask, how)`` for one region specification on a sensor of ``shape``.

    Parameters
    ----------
    spec : tuple, array_like, str or os.PathLike
        - a box ``(row_start, row_stop, col_start, col_stop)`` of 0-based sensel indices,
          stops excluded (Python slices), or its text ``"R0:R1,C0:C1"`` (an empty bound is
          the sensor's edge: ``"40:,0:"``);
        - a polygon: a sequence of at least 3 ``(row, col)`` vertices in sensel coordinates
          (sensel ``(i, j)`` has its centre at ``(i, j)``), or the text
          ``"poly:R,C;R,C;R,C"``; a sensel belongs to it when its centre is inside or on
          the edge;
        - a boolean mask of ``shape``, or a file holding one: ``.npy`` (booleans or 0/1),
          ``.csv``/``.txt`` (``rows`` lines of ``cols`` values 0 or 1, separated by commas
          or blanks).
    shape : tuple of int
        ``(rows, cols)`` of the sensor.
    name : str
        The region's name, for messages.

    Returns
    -------
    (numpy.ndarray of bool, str)

    Raises
    ------
    TactilecalError
        An empty box or one outside the sensor, a polygon holding no sensel centre, a mask
        of another shape or with values other than 0/1, an unreadable mask file.

    Examples
    --------
    >>> mask, how = region_mask("poly:0,0;0,2;2,0", (3, 3))
    >>> mask.astype(int).tolist(), how
    ([[1, 1, 1], [1, 1, 0], [1, 0, 0]], 'polygon of 3 vertices')
    """
    rows, cols = (int(n) for n in shape)
    if isinstance(spec, str) and _BOX_TEXT.match(spec):
        bounds = _BOX_TEXT.match(spec).groups()
        spec = tuple(int(b) if b else edge for b, edge in zip(bounds, (0, rows, 0, cols),
                                                              strict=True))
    if isinstance(spec, str) and spec.strip().lower().startswith("poly:"):
        spec = _polygon_text(spec, name)
    if isinstance(spec, str | Path):
        return _mask_file(Path(spec), (rows, cols), name), f"mask file {Path(spec).name}"
    array = np.asarray(spec)
    if array.dtype == bool:
        return _checked_mask(array, (rows, cols), f"region {name!r} mask"), "mask"
    if array.shape == (4,) and np.issubdtype(array.dtype, np.integer):
        return _box(tuple(int(v) for v in array), rows, cols, name)
    if array.ndim == 2 and array.shape[1] == 2 and len(array) >= 3:
        return _polygon(np.asarray(array, float), rows, cols, name)
    raise TactilecalError(f"region {name!r} is {spec!r}; expected {_SPEC_HELP}, a box tuple "
                          "(r0, r1, c0, c1) or a boolean mask")


def parse_region_option(text):
    """Split a ``--region NAME=SPEC`` value into ``(name, spec)``.

    Examples
    --------
    >>> parse_region_option("heel=40:60,0:21")
    ('heel', '40:60,0:21')
    """
    name, sep, spec = str(text).partition("=")
    if not sep or not name.strip() or not spec.strip():
        raise TactilecalError(f"--region {text!r}; expected NAME=SPEC where SPEC is {_SPEC_HELP}")
    return name.strip(), spec.strip()


def _box(box, rows, cols, name):
    r0, r1, c0, c1 = box
    if not (0 <= r0 < r1 <= rows and 0 <= c0 < c1 <= cols):
        raise TactilecalError(f"region {name!r}: box {box} is empty or outside the {rows} x "
                              f"{cols} sensels; expected 0 <= row_start < row_stop <= {rows} and "
                              f"0 <= col_start < col_stop <= {cols}")
    mask = np.zeros((rows, cols), dtype=bool)
    mask[r0:r1, c0:c1] = True
    return mask, f"box rows {r0}..{r1 - 1}, columns {c0}..{c1 - 1}"


def _polygon_text(text, name):
    vertices = []
    for k, pair in enumerate(filter(None, text.split(":", 1)[1].split(";")), 1):
        parts = pair.split(",")
        if len(parts) != 2:
            raise TactilecalError(f"region {name!r}: polygon vertex {k} is {pair!r}; expected "
                                  "'ROW,COL'")
        vertices.append([parse_number(p, f"region {name!r}: polygon vertex {k}") for p in parts])
    if len(vertices) < 3:
        raise TactilecalError(f"region {name!r}: polygon has {len(vertices)} vertices; expected "
                              "at least 3 ('poly:R,C;R,C;R,C')")
    return vertices


def _polygon(vertices, rows, cols, name):
    """Sensels whose centre lies inside or on the polygon (crossing-number rule)."""
    if not np.isfinite(vertices).all():
        raise TactilecalError(f"region {name!r}: polygon vertices {vertices.tolist()} are not "
                              "all finite; expected (row, col) numbers")
    r, c = np.mgrid[0:rows, 0:cols].astype(float)
    inside = np.zeros((rows, cols), dtype=bool)
    on_edge = np.zeros((rows, cols), dtype=bool)
    for (r1, c1), (r2, c2) in zip(vertices, np.roll(vertices, -1, axis=0), strict=True):
        crosses = (r1 > r) != (r2 > r)
        with np.errstate(divide="ignore", invalid="ignore"):
            c_at = c1 + (r - r1) * (c2 - c1) / (r2 - r1)
        inside ^= crosses & (c < c_at)
        cross = (r2 - r1) * (c - c1) - (c2 - c1) * (r - r1)
        within = ((np.minimum(r1, r2) <= r) & (r <= np.maximum(r1, r2))
                  & (np.minimum(c1, c2) <= c) & (c <= np.maximum(c1, c2)))
        on_edge |= within & np.isclose(cross, 0.0, atol=1e-9)
    mask = inside | on_edge
    if not mask.any():
        raise TactilecalError(f"region {name!r}: polygon {vertices.tolist()} holds no sensel "
                              f"centre of the {rows} x {cols} sensor; expected vertices in "
                              "sensel coordinates (row, col)")
    return mask, f"polygon of {len(vertices)} vertices"


def _mask_file(path, shape, name):
    if not path.is_file():
        raise FileNotFoundError(f"region {name!r}: mask file {path} does not exist; expected "
                                f"{_SPEC_HELP}")
    if path.suffix.lower() == ".npy":
        try:
            values = np.load(path, allow_pickle=False)
        except ValueError as exc:
            raise TactilecalError(f"region {name!r}: {path} is not a NumPy .npy array ({exc}); "
                                  "expected a boolean or 0/1 array") from None
    else:
        lines = [line for line in read_text(path, expected="a mask of 0/1 values").splitlines()
                 if line.strip()]
        values = [[parse_number(v, f"line {i} of {path.name}", minimum=0, maximum=1,
                                integer=True) for v in re.split(r"[,;\s]+", line.strip())]
                  for i, line in enumerate(lines, 1)]
        widths = sorted({len(v) for v in values})
        if len(widths) > 1:
            raise TactilecalError(f"{path}: rows have {widths} values; expected {shape[1]} in "
                                  "every row")
        values = np.array(values)
    values = np.asarray(values)
    if values.dtype != bool:
        if not np.isin(values, (0, 1)).all():
            raise TactilecalError(f"region {name!r}: {path} holds values other than 0 and 1; "
                                  "expected a mask of 0/1")
        values = values.astype(bool)
    return _checked_mask(values, shape, f"region {name!r}: {path.name}")


def _checked_mask(values, shape, what):
    if values.shape != tuple(shape):
        raise TactilecalError(f"{what} has shape {values.shape}; expected {tuple(shape)} "
                              "(rows, cols of the sensor)")
    if not values.any():
        raise TactilecalError(f"{what} selects no sensel; expected at least one True")
    return values
